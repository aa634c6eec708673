"""The report's baseline: classical fourth-order Runge-Kutta on the
equivalent first-order system u = (y, y'), u' = (y', F(t, y, y'))."""

import numpy as np
from numba import njit

from . import _base
from ._base import BAD_SHAPE, NON_FINITE, OK

# Butcher tableau of the classical method: stage j (j = 2, 3, 4) is taken
# at t + NODES[j-2] h from the state advanced by the previous stage; the
# stages are combined with weights FIRST_WEIGHT, then STAGE_WEIGHTS.
NODES = (0.5, 0.5, 1.0)
FIRST_WEIGHT = 1.0 / 6.0
STAGE_WEIGHTS = (1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0)


# Not cache=True: numba's on-disk cache cannot key a loop on the function it
# is given (it recompiles every run) and pickles that function's type into its
# index, which breaks later processes.  The loop compiles once per process.
@njit
def _rk4_loop(fun, args, t0, h, n, tf, y0, yp0, t_eval, store_knots):
    """Step from t0 to tf; same return tuple as ``spline._spline_loop``.

    Between steps, values at ``t_eval`` come from cubic Hermite
    interpolation of (y, y') and of (y', y'') at the two ends of the step,
    accurate to O(h^4) like the method.
    """
    m = y0.shape[0]
    n_out = n + 1 if store_knots else 1
    T = np.empty(n_out)
    Y = np.empty((n_out, m))
    YP = np.empty((n_out, m))
    YPP = np.empty((n_out, m))
    ne = t_eval.shape[0]
    YE = np.empty((ne, m))
    YPE = np.empty((ne, m))
    YPPE = np.empty((ne, m))
    nfev = 0
    n_eval = 0

    y = y0.copy()
    yp = yp0.copy()
    ypp = np.asarray(fun(t0, y, yp, *args))
    nfev += 1
    if ypp.ndim != 1 or ypp.shape[0] != m:
        return (BAD_SHAPE, 0, t0, t0, nfev, 0, 0, 0, 0, 0, T, Y, YP, YPP, YE, YPE, YPPE)
    if not np.all(np.isfinite(ypp)):
        return (NON_FINITE, 0, t0, t0, nfev, 0, 0, 0, 0, 0, T, Y, YP, YPP, YE, YPE, YPPE)
    T[0] = t0
    Y[0] = y
    YP[0] = yp
    YPP[0] = ypp
    n_knots = 1
    while n_eval < ne and t_eval[n_eval] <= t0:
        YE[n_eval] = y
        YPE[n_eval] = yp
        YPPE[n_eval] = ypp
        n_eval += 1

    t = t0
    for i in range(n):
        t_new = t0 + (i + 1) * h if i + 1 < n else tf
        dt = t_new - t
        # Stages k_j = (velocity, acceleration) of u = (y, y').
        v = yp
        a = ypp
        sum_v = FIRST_WEIGHT * v
        sum_a = FIRST_WEIGHT * a
        status = OK
        for j in range(3):
            c = NODES[j] * dt
            y_stage = y + c * v
            v = yp + c * a
            a = np.asarray(fun(t + c, y_stage, v, *args))
            nfev += 1
            if a.ndim != 1 or a.shape[0] != m:
                status = BAD_SHAPE
                break
            if not np.all(np.isfinite(a)):
                status = NON_FINITE
                break
            sum_v = sum_v + STAGE_WEIGHTS[j] * v
            sum_a = sum_a + STAGE_WEIGHTS[j] * a
        if status == OK:
            y_new = y + dt * sum_v
            yp_new = yp + dt * sum_a
            # y'' at the new knot: the first stage of the next step.
            ypp_new = np.asarray(fun(t_new, y_new, yp_new, *args))
            nfev += 1
            if ypp_new.ndim != 1 or ypp_new.shape[0] != m:
                status = BAD_SHAPE
            elif not np.all(np.isfinite(ypp_new)):
                status = NON_FINITE
        if status != OK:
            return (status, i + 1, t, t_new, nfev, 0, 0, i, n_knots, n_eval,
                    T, Y, YP, YPP, YE, YPE, YPPE)
        while n_eval < ne and t_eval[n_eval] <= t_new:
            # Cubic Hermite basis on s = (t - t_i) / dt.
            s = (t_eval[n_eval] - t) / dt
            h00 = (1.0 + 2.0 * s) * (1.0 - s) ** 2
            h10 = s * (1.0 - s) ** 2
            h01 = s * s * (3.0 - 2.0 * s)
            h11 = s * s * (s - 1.0)
            d00 = 6.0 * s * (s - 1.0) / dt
            d10 = (1.0 - s) * (1.0 - 3.0 * s)
            d01 = -d00
            d11 = s * (3.0 * s - 2.0)
            YE[n_eval] = h00 * y + (h10 * dt) * yp + h01 * y_new + (h11 * dt) * yp_new
            YPE[n_eval] = h00 * yp + (h10 * dt) * ypp + h01 * yp_new + (h11 * dt) * ypp_new
            YPPE[n_eval] = d00 * yp + d10 * ypp + d01 * yp_new + d11 * ypp_new
            n_eval += 1
        y = y_new
        yp = yp_new
        ypp = ypp_new
        t = t_new
        if store_knots:
            T[n_knots] = t
            Y[n_knots] = y
            YP[n_knots] = yp
            YPP[n_knots] = ypp
            n_knots += 1
    return (OK, -1, t, t, nfev, 0, 0, n, n_knots, n_eval, T, Y, YP, YPP, YE, YPE, YPPE)


def rk4(fun, t_span, y0, yp0, h, *, t_eval=None, args=()):
    """Classical fourth-order Runge-Kutta for y'' = F(t, y, y').

    The report's comparison method: RK4 on the first-order system
    u = (y, y'), with the same uniform step as the spline method (it
    evaluates F four times per step, at the ends and twice at the midpoint).

    Parameters
    ----------
    fun : callable
        ``fun(t, y, yp, *args) -> y''``; a ``numba.njit`` function runs the
        loop compiled.
    t_span : (float, float)
        Interval of integration, t0 < tf.
    y0, yp0 : float or array_like, shape (m,)
        Initial value and first derivative.
    h : float
        Step.  The last step is shortened to end exactly at tf.
    t_eval : array_like, optional
        Sorted times at which to report the solution (cubic Hermite
        interpolation between steps); the steps are then not stored.
    args : tuple, optional
        Extra arguments passed to ``fun``.

    Returns
    -------
    OdeResult
        As :func:`splinestep.solve`; ``ypp`` holds F at the reported
        points (interpolated between steps), ``niter`` is 0.

    References
    ----------
    .. [1] E. Hairer, S. P. Norsett, G. Wanner, "Solving Ordinary
       Differential Equations I", 2nd ed., Springer (1993), Sec. II.1.
    """
    t0, tf = _base.check_span(t_span)
    y0, yp0 = _base.check_state(y0, yp0)
    h, n, _ = _base.check_grid(t0, tf, h, None)
    t_eval = _base.check_t_eval(t_eval, t0, tf)
    args = _base.check_args(args)
    if not callable(fun):
        raise ValueError("fun must be callable")
    loop = _base.select_loop(_rk4_loop, fun)
    out = loop(fun, args, t0, h, n, tf, y0, yp0,
               np.empty(0) if t_eval is None else t_eval, t_eval is None)
    result, _ = _base.build_result(out, t_eval, 0)
    return result
