"""The adaptive driver: the spline step with knots chosen by a controller.

:func:`splinestep.solve` calls :func:`run` when neither ``h`` nor ``knots``
is given.  The loop walks from t0 to tf with :func:`splinestep.step.spline_step`,
asks :mod:`splinestep.controllers` whether to keep each step and how large
to make the next, and stores the accepted knots; the spline over them is
the solution.  A step whose equation has no solution at the current size
(the sweep diverges, Newton fails) is a rejected step, retried smaller.
"""

import numpy as np
from numba import njit

from . import _base, _compile
from ._base import BAD_SHAPE, FD_STEP, NON_FINITE, OK, as_vector, wrong_length
from .controllers import FAILED_FACTOR, error_norm, step_factor
from .result import OdeResult, SplineSolution
from .step import step_state, spline_step

from .status import STEP_TOO_SMALL, TOO_MANY_STEPS


@njit(cache=True)
def store_knot(T, Y, YP, YPP, n, t, y, yp, ypp):
    """Store a knot at row ``n`` of the growing arrays (doubled when full);
    returns the arrays."""
    if n == T.shape[0]:
        m = Y.shape[1]
        T2 = np.empty(2 * n)
        Y2 = np.empty((2 * n, m))
        YP2 = np.empty((2 * n, m))
        YPP2 = np.empty((2 * n, m))
        T2[:n] = T
        Y2[:n] = Y
        YP2[:n] = YP
        YPP2[:n] = YPP
        T, Y, YP, YPP = T2, Y2, YP2, YPP2
    T[n] = t
    Y[n] = y
    YP[n] = yp
    YPP[n] = ypp
    return T, Y, YP, YPP


def _adaptive_loop(fun, args, jac, t0, tf, y0, yp0, rtol, atol, first_step, max_step, mode,
                   n_iter, until_converged, tol, reuse, max_steps):
    """Integrate from t0 to tf choosing the knots.

    Returns (status, last_status, n_knots, nfev, njev, niter, n_rejected,
    n_failed, T, Y, YP, YPP): ``status`` is OK, a step status (the first
    evaluation failed), STEP_TOO_SMALL (``last_status`` then says why the
    last attempt failed) or TOO_MANY_STEPS.
    """
    m = y0.shape[0]
    T = np.empty(256)
    Y = np.empty((256, m))
    YP = np.empty((256, m))
    YPP = np.empty((256, m))
    y = y0.copy()
    yp = yp0.copy()
    ypp = np.empty(m)
    z = np.empty(m)
    y_new = np.empty(m)
    yp_new = np.empty(m)
    jerk = np.empty(m)
    jerk_new = np.empty(m)
    work, lu, piv, info = step_state(m, 1)
    nfev = 0
    njev = 0
    niter = 0
    n_rejected = 0
    n_failed = 0
    direction = 1.0 if tf > t0 else -1.0
    g = as_vector(fun(t0, y, yp, *args))
    nfev += 1
    if wrong_length(g, m):
        return (BAD_SHAPE, BAD_SHAPE, 0, nfev, njev, niter, 0, 0, T, Y, YP, YPP)
    for k in range(m):
        ypp[k] = g[k]
        if not abs(g[k]) < np.inf:
            return (NON_FINITE, NON_FINITE, 0, nfev, njev, niter, 0, 0, T, Y, YP, YPP)
    T, Y, YP, YPP = store_knot(T, Y, YP, YPP, 0, t0, y, yp, ypp)
    n_knots = 1
    span = abs(tf - t0)
    # y''' at t0 from one difference of F along the Taylor line: the first
    # step's estimate compares its interval's third derivative with it.
    delta = FD_STEP * max(1.0, abs(t0), span) * direction
    for k in range(m):
        y_new[k] = y[k] + delta * yp[k] + 0.5 * delta * delta * ypp[k]
        yp_new[k] = yp[k] + delta * ypp[k]
    g = as_vector(fun(t0 + delta, y_new, yp_new, *args))
    nfev += 1
    for k in range(m):
        jerk[k] = (g[k] - ypp[k]) / delta
    dt_prev = 0.0
    # The first step: scipy's rule of thumb, 1 % of |y| / |y'| in the scaled norm.
    if first_step > 0.0:
        dt = first_step
    else:
        d0 = 0.0
        d1 = 0.0
        for k in range(m):
            scale = atol[k] + rtol * abs(y[k])
            d0 += (y[k] / scale) ** 2
            d1 += (yp[k] / scale) ** 2
        d0 = np.sqrt(d0 / m)
        d1 = np.sqrt(d1 / m)
        dt = 1e-6 if (d0 < 1e-5 or d1 < 1e-5) else 0.01 * d0 / d1
    dt = min(dt, max_step, span)
    t = t0
    after_reject = False
    last_status = OK
    nstep = 0
    while direction * (tf - t) > 0.0:
        if nstep >= max_steps:
            return (TOO_MANY_STEPS, last_status, n_knots, nfev, njev, niter, n_rejected,
                    n_failed, T, Y, YP, YPP)
        min_step = 16.0 * np.finfo(np.float64).eps * max(abs(t), span)
        if dt < min_step:
            return (STEP_TOO_SMALL, last_status, n_knots, nfev, njev, niter, n_rejected,
                    n_failed, T, Y, YP, YPP)
        remaining = abs(tf - t)
        if dt >= remaining or remaining - dt < min_step:
            dt = remaining
        t_new = tf if dt == remaining else t + direction * dt
        signed = t_new - t
        status, fe, je, it = spline_step(fun, args, jac, t_new, signed, y, yp, ypp, z, y_new,
                                         yp_new, mode, n_iter, until_converged, tol, reuse, work,
                                         lu, piv, info, 0)
        nfev += fe
        njev += je
        niter += it
        nstep += 1
        last_status = status
        if status != OK:
            n_failed += 1
            dt *= FAILED_FACTOR
            after_reject = True
            continue
        for k in range(m):
            jerk_new[k] = (z[k] - ypp[k]) / signed
        norm = error_norm(signed, dt_prev, jerk_new, jerk, y, yp, y_new, yp_new, rtol, atol)
        factor = step_factor(norm, after_reject)
        if not norm <= 1.0:
            n_rejected += 1
            dt *= min(factor, 1.0)
            after_reject = True
            continue
        after_reject = False
        t = t_new
        for k in range(m):
            y[k] = y_new[k]
            yp[k] = yp_new[k]
            ypp[k] = z[k]
            jerk[k] = jerk_new[k]
        T, Y, YP, YPP = store_knot(T, Y, YP, YPP, n_knots, t, y, yp, ypp)
        n_knots += 1
        dt_prev = signed
        dt = min(abs(signed) * factor, max_step)
    return (OK, last_status, n_knots, nfev, njev, niter, n_rejected, n_failed, T, Y, YP, YPP)


# Types after (fun, args, jac): t0, tf, y0, yp0, rtol, atol, first_step,
# max_step, mode, n_iter, until_converged, tol, reuse, max_steps.
_LOOP_TYPES = (_compile.FLOAT, _compile.FLOAT, _compile.VECTOR, _compile.VECTOR, _compile.FLOAT,
               _compile.VECTOR, _compile.FLOAT, _compile.FLOAT, _compile.INT, _compile.INT,
               _compile.BOOL, _compile.FLOAT, _compile.BOOL, _compile.INT)


def run(loop_fun, loop_args, loop_jac, *settings):
    """Run the compiled adaptive loop (see :func:`_adaptive_loop`) with
    ``settings`` = (t0, tf, y0, yp0, rtol, atol, first_step, max_step, mode,
    n_iter, until_converged, tol, reuse, max_steps)."""
    loop = _compile.compiled(
        _adaptive_loop, _compile.loop_types(loop_fun, loop_jac, loop_args) + _LOOP_TYPES)
    return loop(loop_fun, loop_args, loop_jac, *settings)


def build_result(out, t0, t_eval, max_iter, max_steps):
    """The :class:`OdeResult` of an adaptive run (knots, or values at
    ``t_eval`` from the spline) and its knot values (T, Y, YP, YPP)."""
    (status, last_status, n_knots, nfev, njev, niter, n_rejected, n_failed,
     T, Y, YP, YPP) = out
    T, Y, YP, YPP = T[:n_knots], Y[:n_knots], YP[:n_knots], YPP[:n_knots]
    m = Y.shape[1]
    t_end = T[-1] if n_knots else t0
    if status == OK:
        message = "The solver successfully reached the end of the integration interval."
    elif n_knots == 0:
        message = (f"The initial evaluation at t = {_base.short(t0)} failed: "
                   f"{_base.failure(status, max_iter, m)}.")
    elif status == TOO_MANY_STEPS:
        message = (f"The run stopped at t = {_base.short(t_end)} after max_steps = "
                   f"{max_steps} step attempts; returning the {n_knots - 1} steps accepted.")
    else:
        why = ("its error estimate was too large" if last_status == OK
               else f"its equation could not be solved ({_base.failure(last_status, max_iter, m)})")
        message = (f"The step size fell below the rounding floor at t = {_base.short(t_end)}: "
                   f"the last step tried was rejected because {why}. Returning the "
                   f"{n_knots - 1} steps accepted before it.")
    if t_eval is None:      # the knots (values (m, k), as scipy)
        t, y, yp, ypp = T, Y.T, YP.T, YPP.T
    elif n_knots < 2:       # nothing to evaluate the spline on
        t, y, yp, ypp = T[:0], Y[:0].T, YP[:0].T, YPP[:0].T
    else:                   # the spline at the requested times it reached
        direction = 1.0 if T[-1] >= T[0] else -1.0
        t = t_eval[direction * (t_eval - T[-1]) <= 0]
        sol = SplineSolution(T, Y, YP, YPP)
        y, yp, ypp = (sol(t, nu) for nu in range(3))
    result = OdeResult(
        t=t.copy(), y=np.array(y), yp=np.array(yp), ypp=np.array(ypp), sol=None,
        nfev=int(nfev), njev=int(njev), niter=int(niter), nstep=int(n_knots - 1),
        n_rejected=int(n_rejected), n_failed=int(n_failed), status=0 if status == OK else -1,
        message=message, success=status == OK)
    return result, (T, Y, YP, YPP)
