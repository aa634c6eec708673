"""Time-reversible variable steps (Hairer and Soderlind, 2005).

An error-controlled step size depends on the error estimate, which is not
symmetric in time: stepping back does not retrace the steps, and the
bounded energy error of a fixed step is lost (notebook 07 shows the drift).
Hairer and Soderlind keep it by making the step size itself the output of a
symmetric recursion.  With a step-size function s(y) (the steps are
proportional to s: small where s is small, so that the density of steps is
proportional to 1/s) and G = -(d/dt) ln s along the solution, a control variable rho
follows the leapfrog recursion

    rho_{1/2} = rho_0 + eps G(y_0) / 2,    rho_0 = 1,
    h_n = eps / rho_{n+1/2},       (y_n, y'_n) -> (y_{n+1}, y'_{n+1}) by the spline step,
    rho_{n+3/2} = rho_{n+1/2} + eps G(y_{n+1})

(the increments change sign backwards in time), so that
rho ~ s(y_0) / s(y) and h ~ eps s(y) / s(y_0).  The step and the
recursion are both symmetric, so the whole map is: run backwards, it retraces
its knots.  For the Kepler problem s = r^(3/2) (steps proportional to the
local orbital time scale) gives G = -(3/2) (q . q') / |q|^2.

References
----------
.. [1] E. Hairer, G. Soderlind, "Explicit, time reversible, adaptive step
   size control", SIAM J. Sci. Comput. 26 (2005) 1838-1851.
"""

import numpy as np
from numba import typeof

from . import _base, _compile
from ._base import OK
from .adaptive import store_knot
from .result import OdeResult, SplineSolution
from .step import FIXED_POINT, NEWTON, step_state, spline_step


from .status import RHO_NOT_POSITIVE, TOO_MANY_STEPS


def _reversible_loop(fun, args, jac, control, control_args, t0, tf, y0, yp0, ypp0, eps, rho0,
                     mode, n_iter, tol, max_steps):
    """The knots from t0 to tf at the steps eps / rho (module docstring).
    Returns (status, n_knots, nfev, njev, niter, T, Y, YP, YPP, RHO)."""
    m = y0.shape[0]
    T = np.empty(256)
    Y = np.empty((256, m))
    YP = np.empty((256, m))
    YPP = np.empty((256, m))
    RHO = np.empty(256)
    y = y0.copy()
    yp = yp0.copy()
    ypp = ypp0.copy()
    z = np.empty(m)
    y_new = np.empty(m)
    yp_new = np.empty(m)
    work, lu, piv, info = step_state(m, 1)
    T, Y, YP, YPP = store_knot(T, Y, YP, YPP, 0, t0, y, yp, ypp)
    n_knots = 1
    nfev = 0
    njev = 0
    niter = 0
    direction = 1.0 if tf > t0 else -1.0
    # Backwards in time the control's increments change sign: rho follows
    # the same function of the state in both directions.
    rho = rho0 + 0.5 * direction * eps * control(t0, y, yp, *control_args)
    t = t0
    while direction * (tf - t) > 0.0:
        if n_knots > max_steps:
            return (TOO_MANY_STEPS, n_knots, nfev, njev, niter, T, Y, YP, YPP, RHO)
        if not rho > 0.0:
            return (RHO_NOT_POSITIVE, n_knots, nfev, njev, niter, T, Y, YP, YPP, RHO)
        h = eps / rho
        t_new = tf if h >= abs(tf - t) else t + direction * h
        status, fe, je, it = spline_step(fun, args, jac, t_new, t_new - t, y, yp, ypp, z, y_new,
                                         yp_new, mode, n_iter, True, tol, True, work, lu, piv,
                                         info, 0)
        nfev += fe
        njev += je
        niter += it
        if status != OK:
            return (status, n_knots, nfev, njev, niter, T, Y, YP, YPP, RHO)
        if n_knots - 1 == RHO.shape[0]:
            RHO2 = np.empty(2 * RHO.shape[0])
            RHO2[:RHO.shape[0]] = RHO
            RHO = RHO2
        RHO[n_knots - 1] = rho
        t = t_new
        for k in range(m):
            y[k] = y_new[k]
            yp[k] = yp_new[k]
            ypp[k] = z[k]
        T, Y, YP, YPP = store_knot(T, Y, YP, YPP, n_knots, t, y, yp, ypp)
        n_knots += 1
        rho += direction * eps * control(t, y, yp, *control_args)
    return (OK, n_knots, nfev, njev, niter, T, Y, YP, YPP, RHO)


# Types after (fun, args, jac, control, control_args): t0, tf, y0, yp0, ypp0,
# eps, rho0, mode, n_iter, tol, max_steps.
_LOOP_TYPES = (_compile.FLOAT, _compile.FLOAT, _compile.VECTOR, _compile.VECTOR,
               _compile.VECTOR, _compile.FLOAT, _compile.FLOAT, _compile.INT, _compile.INT,
               _compile.FLOAT, _compile.INT)


def solve_reversible(fun, t_span, y0, yp0, eps, control, *, rho0=1.0, args=(),
                     iteration="fixed-point", tol=1e-12, max_iter=50, jac=None,
                     max_steps=10**7):
    """Integrate y'' = F(t, y, y') with the spline step at the time-reversible
    step sizes of Hairer and Soderlind.

    Parameters
    ----------
    fun, t_span, y0, yp0, args, iteration, tol, max_iter, jac
        As for :func:`splinestep.solve` (forward or backward in time).
    eps : float
        The step at the start (rho_0 = 1); the steps scale with it.
    control : callable
        ``control(t, y, yp, *args) -> G``, minus the time derivative of the
        logarithm of the step-size function s along the solution (see the module
        docstring); for Kepler with s = r^(3/2), -1.5 (y . yp) / |y|^2.
    rho0 : float
        The control variable at the start (the first step is about
        eps / rho0).  To retrace a run backwards from its knot k, start
        there with rho0 = rho[k - 1] + eps G(y_k) / 2.
    max_steps : int
        The run stops (status -1) after this many steps.

    Returns
    -------
    OdeResult
        As :func:`splinestep.solve` at its knots, with ``sol`` the spline and
        ``rho`` the control variable at the half steps.
    """
    t0, tf = _base.check_span(t_span, backward=True)
    y0, yp0 = _base.check_state(y0, yp0)
    args = _base.check_args(args)
    if not (isinstance(eps, (int, float)) and np.isfinite(eps) and eps > 0):
        raise ValueError(f"eps must be positive and finite, got {eps!r}")
    if not callable(control):
        raise ValueError("control must be callable")
    if iteration not in ("fixed-point", "newton"):
        raise ValueError(f"iteration must be 'fixed-point' or 'newton', got {iteration!r}")
    if not (isinstance(max_steps, (int, np.integer)) and max_steps >= 1):
        raise ValueError(f"max_steps must be an integer >= 1, got {max_steps!r}")
    if not (isinstance(rho0, (int, float)) and np.isfinite(rho0) and rho0 > 0):
        raise ValueError(f"rho0 must be positive and finite, got {rho0!r}")
    mode = FIXED_POINT if iteration == "fixed-point" else NEWTON
    path = _base.choose_path(fun, jac, args)
    ypp0 = _base.check_fun(fun, t0, y0, yp0, args)
    try:
        float(control(t0, y0.copy(), yp0.copy(), *args))
    except Exception as error:
        raise ValueError(f"control must return a number at t0; it raised "
                         f"{type(error).__name__}: {error}") from error
    with _compile.loop_callables(path, fun, jac, args) as (loop_fun, loop_jac, loop_args), \
            _compile.scalar_callable(path, control, args) as (loop_control, control_args):
        fun_type, args_type, jac_type = _compile.loop_types(loop_fun, loop_jac, loop_args)
        control_type = _compile.function_type(loop_control, tuple(typeof(control_args)))
        loop = _compile.compiled(_reversible_loop, (fun_type, args_type, jac_type, control_type,
                                                    typeof(control_args)) + _LOOP_TYPES)
        (status, n_knots, nfev, njev, niter, T, Y, YP, YPP, RHO) = loop(
            loop_fun, loop_args, loop_jac, loop_control, control_args, t0, tf, y0, yp0, ypp0,
            float(eps), float(rho0), mode, int(max_iter), float(tol), int(max_steps))
    T, Y, YP, YPP = T[:n_knots], Y[:n_knots], YP[:n_knots], YPP[:n_knots]
    t_end = _base.short(T[-1])
    if status == OK:
        message = "The solver successfully reached the end of the integration interval."
    elif status == TOO_MANY_STEPS:
        message = f"max_steps = {max_steps} reached at t = {t_end}."
    elif status == RHO_NOT_POSITIVE:
        message = (f"The control variable rho is not positive at t = {t_end}: eps is too "
                   "large for this control.")
    else:
        message = (f"Step {n_knots} (from t = {t_end}) failed: "
                   f"{_base.failure(status, max_iter, y0.size)}.")
    return OdeResult(t=T.copy(), y=Y.T.copy(), yp=YP.T.copy(), ypp=YPP.T.copy(),
                     sol=SplineSolution(T, Y, YP, YPP) if T.size >= 2 else None,
                     rho=RHO[:n_knots - 1].copy(), nfev=int(nfev) + 1, njev=int(njev),
                     niter=int(niter), nstep=T.size - 1, status=0 if status == OK else -1,
                     message=message, success=status == OK, path=path, order=2,
                     t_events=None, y_events=None, yp_events=None)
