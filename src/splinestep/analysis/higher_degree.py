"""The report's suggestion built as written: splines of higher degree with
more continuity at the knots, collocating the ODE at every knot and
stepping one knot at a time.

On [t_i, t_i + h] the spline of degree k is

    p(tau) = sum_{j < k} D_j tau^j / j!  +  g tau^k,

where D_j = p^{(j)}(t_i) continue the previous piece (continuity of the
derivatives 0..k-1 at the knot: the spline is C^{k-1}) and the one free
coefficient g is fixed by collocating y'' = F(t, y, y') at t_i + h.  With
z = p''(h) as the unknown (g = (z - B_2) / (k (k - 1) h^(k-2)), B_j the
part of p^{(j)}(h) that does not involve g):

    p(h)  = B_0 + h^2 (z - B_2) / (k (k - 1)),
    p'(h) = B_1 + h (z - B_2) / (k - 1),
    z     = F(t_i + h, p(h), p'(h)),

solved by the fixed-point sweep.  k = 3 is the report's cubic method (the
coefficients h^2/6 and h/2 of ``splinestep.spline``).  For k >= 4 the
derivatives D_3 .. D_{k-1} at the knots are extra state: their recurrence
has roots that the ODE does not have (``notebooks/06_higher_degree`` derives
them); for k = 5 and 6 (the degrees measured) one lies outside the unit
circle, and the method diverges however small h is (Loscalzo and Talbot 1967 found the same for
first-order equations).

This module steps in plain numpy: it exists to show that behaviour, not
for speed.
"""

import math
import numbers

import numpy as np

from .. import _base
from ..result import OdeResult

MIN_DEGREE = 3


def solve_degree(fun, t_span, y0, yp0, h, degree, *, derivatives=None, args=(), tol=1e-12,
                 max_iter=50):
    """Step y'' = F(t, y, y') with the C^{k-1} spline of degree k = ``degree``.

    Parameters
    ----------
    fun : callable
        ``fun(t, y, yp, *args) -> y''`` (a plain or compiled function).
    t_span : (float, float)
        t0 < tf.
    y0 : float or array_like, shape (m,)
        Initial value.
    yp0 : float or array_like, shape (m,)
        Initial first derivative.
    h : float
        Uniform step; the last step is shortened to end at tf.
    degree : int
        k >= 3.
    derivatives : array_like, shape (k - 3, m), optional
        y''', ..., y^{(k-1)} at t0: the spline's first piece needs them for
        k >= 4 (required then; the exact values for a problem with an exact
        solution, so that the method starts on the solution).
    args : tuple
        Extra arguments of ``fun``.
    tol : float
        Convergence test of the sweep: the change of z is at most ``tol``
        times max(1, |z|) (max norm).
    max_iter : int
        Sweeps allowed per step.

    Returns
    -------
    OdeResult
        ``t``, ``y``, ``yp``, ``ypp`` at the knots, ``derivatives`` (the
        D_j, shape (k, m, n + 1)), ``nfev``, ``niter``, ``nstep``,
        ``status`` (0, or -1 when a step's sweep does not converge or the
        solution stops being finite: the steps before it are returned),
        ``message``, ``success``.

    References
    ----------
    .. [1] F. R. Loscalzo, T. D. Talbot, "Spline function approximations
       for solutions of ordinary differential equations", SIAM J. Numer.
       Anal. 4 (1967) 433-445.
    """
    t0, tf = _base.check_span(t_span)
    y0, yp0 = _base.check_state(y0, yp0)
    h, n, _ = _base.check_grid(t0, tf, h, None)
    args = _base.check_args(args)
    if not callable(fun):
        raise ValueError("fun must be callable")
    if not (isinstance(degree, numbers.Integral) and not isinstance(degree, bool)
            and degree >= MIN_DEGREE):
        raise ValueError(f"degree must be an integer >= {MIN_DEGREE}, got {degree!r}")
    if not (isinstance(tol, numbers.Real) and np.isfinite(tol) and tol > 0):
        raise ValueError(f"tol must be positive and finite, got {tol!r}")
    if not (isinstance(max_iter, numbers.Integral) and max_iter >= 1):
        raise ValueError(f"max_iter must be an integer >= 1, got {max_iter!r}")
    k, m = int(degree), y0.size
    extra = k - MIN_DEGREE
    if extra and derivatives is None:
        raise ValueError(f"derivatives (y''' ... y^({k - 1}) at t0, shape ({extra}, {m})) "
                         f"is required for degree {k}")
    derivatives = (np.empty(0) if derivatives is None
                   else _base._real_array(derivatives, "derivatives"))
    if derivatives.size != extra * m or not np.all(np.isfinite(derivatives)):
        raise ValueError(f"derivatives must be {extra} x {m} finite numbers for degree {k}")
    derivatives = derivatives.reshape(extra, m)
    fun_value = _base.check_fun(fun, t0, y0, yp0, args)

    D = np.vstack([y0, yp0, fun_value, derivatives])
    steps = t0 + h * np.arange(n + 1)
    steps[-1] = tf
    history = [D.copy()]
    nfev, niter, status, message = 1, 0, 0, None
    for i in range(n):
        dt = steps[i + 1] - steps[i]
        # shift[j, l] = dt^(l - j) / (l - j)!: the Taylor shift of D_l to p^{(j)}(dt)
        shift = np.array([[dt ** (l - j) / math.factorial(l - j) if l >= j else 0.0
                           for l in range(k)] for j in range(k)])
        base = shift @ D                        # B_j, j < k
        # p^{(j)}(h) = B_j + g k!/(k-j)! h^(k-j), with g from z
        g_weight = np.array([math.factorial(k) / math.factorial(k - j) * dt ** (k - j)
                             for j in range(k)])
        z = D[2].copy()
        for _ in range(max_iter):
            g = (z - base[2]) / g_weight[2]
            y_new, yp_new = base[0] + g_weight[0] * g, base[1] + g_weight[1] * g
            with np.errstate(all="ignore"):
                value = _base.as_vector(fun(steps[i + 1], y_new, yp_new, *args))
            nfev += 1
            niter += 1
            if value.shape != (m,) or not np.all(np.isfinite(value)) \
                    or not np.all(np.isfinite(y_new)):
                status, message = -1, "the solution is no longer finite"
                break
            change = np.max(np.abs(value - z))
            z = value
            if change <= tol * max(1.0, np.max(np.abs(z))):
                break
        else:
            status, message = -1, f"the sweep did not converge in {max_iter} iterations"
        if status:
            message = (f"Step {i + 1} (from t = {_base.short(steps[i])} to t = "
                       f"{_base.short(steps[i + 1])}) failed: {message}. Returning the "
                       f"{i} steps completed before it.")
            break
        g = (z - base[2]) / g_weight[2]
        D = base + g_weight[:, None] * g
        D[2] = z
        history.append(D.copy())
    D_all = np.stack(history, axis=-1)          # (k, m, steps + 1)
    return OdeResult(
        t=steps[:D_all.shape[-1]].copy(), y=D_all[0], yp=D_all[1], ypp=D_all[2],
        derivatives=D_all, sol=None, nfev=nfev, njev=0, niter=niter, nstep=D_all.shape[-1] - 1,
        status=status, success=status == 0, path="plain",
        message=message or "The solver successfully reached the end of the integration interval.")
