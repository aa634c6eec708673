"""What the solvers return: one result type with the same keys from every
entry point (:func:`new_result`), and the dense outputs."""

import numpy as np
from numba.extending import register_jitable


class OdeResult(dict):
    """Result of an integration, in the style of scipy's ``OdeResult``: a
    dict whose keys are also attributes.  (Not scipy's class itself, so
    not an instance of ``scipy.optimize.OptimizeResult``, and its repr
    lists ``repr`` of each value: importing scipy.optimize would add a
    third of a second to importing the package.)

    Attributes
    ----------
    t : ndarray, shape (k,)
        Times of the reported values (the knots, or ``t_eval``).
    y, yp, ypp : ndarray, shape (m, k)
        Solution, its first and its second derivative at ``t``.
    sol : SplineSolution, HermiteSolution or None
        The dense output when asked for (``dense_output=True``; the default of
        :func:`splinestep.solve_reversible`, always for
        :func:`splinestep.solve_bvp`): the C2 cubic spline, or for order 4 or
        6 the quintic Hermite through the knots; otherwise None.
    nfev : int
        Number of evaluations of the right-hand side (finite-difference
        Jacobian evaluations included).
    njev : int
        Number of evaluations of the user-supplied ``jac``.
    niter : int
        Total number of implicit iterations (fixed-point sweeps or Newton
        updates) over all steps.
    nstep : int
        Number of steps accepted (a run stopped by a terminal event ends
        with the step that holds it, cut at the event).
    n_rejected, n_failed : int
        Error-controlled knots: steps rejected by the error estimate, and
        steps whose equation could not be solved (both retried smaller); 0
        on the other paths.
    t_events, y_events, yp_events : list of ndarray or None
        For each event function, the times of its zeros and y, y' there
        (shapes (k,), (k, m), (k, m)); None when no events were given.
    local_error, local_error_yp : float
        Spline stepper: the largest estimated local error of one step in y
        and in y' (max norm), from the jumps of the spline's third
        derivative (:mod:`splinestep.check`); NaN for fewer than 2 steps and
        for the baselines (RK4, Verlet) and global runs.
    t_local_error : float
        The knot where ``local_error`` is largest.
    error_estimate : float
        :func:`splinestep.solve_bvp`: the estimated error of y on the
        returned mesh (by mesh halving); NaN elsewhere.
    rho : ndarray or None
        Time-reversible steps: the control variable of each step; None
        otherwise.
    method : str
        The method: "spline", "rk4" or "verlet".
    order : int
        The order of the method (2, 4 or 6 for the spline).
    path : {"compiled", "plain"}
        How the compiled loop called ``fun``: directly ("compiled", a
        ``numba.njit`` fun) or through the interpreter ("plain"; always for
        global and boundary value solves, which run in Python).
    status : int
        0 if the end of the span was reached, 1 if a terminal event stopped
        the run, -1 if the run failed.
    message : str
        Human-readable description of the outcome.
    success : bool
        ``status >= 0``: the end of the span, or a terminal event, was
        reached (as scipy's ``solve_ivp``).
    """

    def __getattr__(self, name):
        try:
            return self[name]
        except KeyError as error:
            raise AttributeError(name) from error

    __setattr__ = dict.__setitem__
    __delattr__ = dict.__delitem__

    def __dir__(self):
        return list(self.keys())

    def __repr__(self):
        first = [k for k in ("message", "success", "status") if k in self]
        keys = first + [k for k in self if k not in first]
        width = max((len(k) for k in keys), default=0)
        return "\n".join(f"{k:>{width}}: {self[k]!r}".replace("\n", "\n" + " " * (width + 2))
                         for k in keys) or "OdeResult()"


# Every result's keys and the value of each where it does not apply.
DEFAULTS = dict(t=None, y=None, yp=None, ypp=None, sol=None, t_events=None, y_events=None,
                yp_events=None, nfev=0, njev=0, niter=0, nstep=0, n_rejected=0, n_failed=0,
                local_error=np.nan, local_error_yp=np.nan, t_local_error=np.nan,
                error_estimate=np.nan, rho=None,
                method="spline", order=2, path="plain", status=0, message="", success=True)


def new_result(**values):
    """The one result builder: an :class:`OdeResult` with every key of
    :data:`DEFAULTS`, ``values`` given (an unknown key is a programming
    error) and ``success`` from ``status``."""
    unknown = set(values) - set(DEFAULTS)
    if unknown:
        raise KeyError(f"not result keys: {sorted(unknown)}")
    result = OdeResult(DEFAULTS, **values)
    result.success = result.status >= 0
    return result


class SplineSolution:
    """The C2 cubic spline that the stepper builds, as a callable.

    ``sol(t)`` returns y(t); ``sol(t, nu)`` its ``nu``-th derivative
    (``nu`` in 0..3).  Results have shape (m,) for scalar ``t`` and (m, k)
    for an array of k times, as scipy's ``OdeSolution``.

    Parameters
    ----------
    knots : ndarray, shape (n + 1,)
    y, yp, ypp : ndarray, shape (n + 1, m)
        Values, first and second derivatives at the knots.
    """

    def __init__(self, knots, y, yp, ypp):
        h = np.diff(knots)[:, None]
        a, b, c = y[:-1], yp[:-1], 0.5 * ypp[:-1]
        d = (ypp[1:] - ypp[:-1]) / (6.0 * h)
        # Imported here: scipy.interpolate takes a fifth of a second to import.
        from scipy.interpolate import PPoly
        # PPoly wants the highest power first: shape (4, n, m).
        self.ppoly = PPoly(np.stack([d, c, b, a]), knots, extrapolate=False)
        self.t_min, self.t_max = min(knots[0], knots[-1]), max(knots[0], knots[-1])

    def __call__(self, t, nu=0):
        degree = self.ppoly.c.shape[0] - 1
        if not (isinstance(nu, (int, np.integer)) and not isinstance(nu, (bool, np.bool_))
                and 0 <= nu <= degree):
            raise ValueError(f"nu must be an integer from 0 to {degree} (the interpolant's "
                             f"degree; higher derivatives are zero), got {nu!r}")
        t = np.asarray(t, dtype=float)
        if np.any((t < self.t_min) | (t > self.t_max)):
            raise ValueError(
                f"t must lie in the integration span [{self.t_min}, {self.t_max}]")
        return np.moveaxis(self.ppoly(t, nu), -1, 0)


@register_jitable
def quintic_coefficients(dt, p0, v0, a0, p1, v1, a1):
    """The s^3, s^4, s^5 coefficients of the quintic with value, slope and
    second derivative (p0, v0, a0) at s = 0 and (p1, v1, a1) at s = dt
    (numbers in compiled code, arrays in Python)."""
    # What the quadratic Taylor part leaves at s = dt, in value, slope and
    # second derivative; the three coefficients solve a 3 x 3 system.
    rp = p1 - p0 - dt * (v0 + 0.5 * dt * a0)
    rv = (v1 - v0 - dt * a0) * dt
    ra = (a1 - a0) * dt * dt
    return ((10.0 * rp - 4.0 * rv + 0.5 * ra) / dt ** 3,
            (-15.0 * rp + 7.0 * rv - ra) / dt ** 4,
            (6.0 * rp - 3.0 * rv + 0.5 * ra) / dt ** 5)


class HermiteSolution(SplineSolution):
    """The quintic Hermite interpolant through the knots' values and first
    two derivatives: the dense output of a composed (order 4 or 6) run,
    accurate to O(h^6) between knots in y (its nu-th derivative to
    O(h^(6 - nu))), so y and y' to the run's order.  Called as
    :class:`SplineSolution` (``nu`` in 0..5); continuous with its first two
    derivatives at the knots.
    """

    def __init__(self, knots, y, yp, ypp):
        h = np.diff(knots)[:, None]
        p0, v0, a0, p1, v1, a1 = y[:-1], yp[:-1], ypp[:-1], y[1:], yp[1:], ypp[1:]
        c3, c4, c5 = quintic_coefficients(h, p0, v0, a0, p1, v1, a1)
        from scipy.interpolate import PPoly
        self.ppoly = PPoly(np.stack([c5, c4, c3, 0.5 * a0, v0, p0]), knots, extrapolate=False)
        self.t_min, self.t_max = min(knots[0], knots[-1]), max(knots[0], knots[-1])
