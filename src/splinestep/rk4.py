"""The report's baseline: classical fourth-order Runge-Kutta on the
equivalent first-order system u = (y, y'), u' = (y', F(t, y, y'))."""

import numpy as np

from . import _base, _compile
from ._base import BAD_SHAPE, NON_FINITE, OK, as_vector, wrong_length

# Butcher tableau of the classical method: stage j (j = 2, 3, 4) is taken
# at t + NODES[j-2] h from the state advanced by the previous stage; the
# stages are combined with weights FIRST_WEIGHT, then STAGE_WEIGHTS.
NODES = (0.5, 0.5, 1.0)
FIRST_WEIGHT = 1.0 / 6.0
STAGE_WEIGHTS = (1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0)


# Compiled once per signature and cached on disk by splinestep._compile, for
# compiled and plain-Python right-hand sides alike.
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
    y = y0.copy()
    yp = yp0.copy()
    ypp = np.empty(m)
    y_stage = np.empty(m)
    v = np.empty(m)          # velocity of the current stage
    a = np.empty(m)          # acceleration of the current stage
    sum_v = np.empty(m)
    sum_a = np.empty(m)
    y_new = np.empty(m)
    yp_new = np.empty(m)
    ypp_new = np.empty(m)
    nfev = 0
    n_eval = 0

    g = as_vector(fun(t0, y, yp, *args))
    nfev += 1
    if wrong_length(g, m):
        return (BAD_SHAPE, 0, t0, t0, nfev, 0, 0, 0, 0, 0, T, Y, YP, YPP, YE, YPE, YPPE)
    for k in range(m):
        ypp[k] = g[k]
        if not abs(g[k]) < np.inf:
            return (NON_FINITE, 0, t0, t0, nfev, 0, 0, 0, 0, 0, T, Y, YP, YPP, YE, YPE, YPPE)
    T[0] = t0
    for k in range(m):
        Y[0, k] = y[k]
        YP[0, k] = yp[k]
        YPP[0, k] = ypp[k]
    n_knots = 1
    while n_eval < ne and t_eval[n_eval] <= t0:
        for k in range(m):
            YE[n_eval, k] = y[k]
            YPE[n_eval, k] = yp[k]
            YPPE[n_eval, k] = ypp[k]
        n_eval += 1

    t = t0
    for i in range(n):
        t_new = t0 + (i + 1) * h if i + 1 < n else tf
        dt = t_new - t
        # Stage 1 is (y', y'') at t; stage j+1 advances by NODES[j] dt with stage j.
        for k in range(m):
            v[k] = yp[k]
            a[k] = ypp[k]
            sum_v[k] = FIRST_WEIGHT * v[k]
            sum_a[k] = FIRST_WEIGHT * a[k]
        status = OK
        for j in range(4):
            if j < 3:
                c = NODES[j] * dt
                for k in range(m):
                    y_stage[k] = y[k] + c * v[k]
                    v[k] = yp[k] + c * a[k]
                g = as_vector(fun(t + c, y_stage, v, *args))
            else:
                # y'' at the new knot: the first stage of the next step.
                for k in range(m):
                    y_new[k] = y[k] + dt * sum_v[k]
                    yp_new[k] = yp[k] + dt * sum_a[k]
                g = as_vector(fun(t_new, y_new, yp_new, *args))
            nfev += 1
            if wrong_length(g, m):
                status = BAD_SHAPE
                break
            for k in range(m):
                if not abs(g[k]) < np.inf:
                    status = NON_FINITE
                a[k] = g[k]
            if status != OK:
                break
            if j < 3:
                for k in range(m):
                    sum_v[k] += STAGE_WEIGHTS[j] * v[k]
                    sum_a[k] += STAGE_WEIGHTS[j] * a[k]
        if status != OK:
            return (status, i + 1, t, t_new, nfev, 0, 0, i, n_knots, n_eval,
                    T, Y, YP, YPP, YE, YPE, YPPE)
        for k in range(m):
            ypp_new[k] = a[k]
        while n_eval < ne and t_eval[n_eval] <= t_new:
            # Cubic Hermite basis on s = (t - t_i) / dt, and its derivative.
            s = (t_eval[n_eval] - t) / dt
            h00 = (1.0 + 2.0 * s) * (1.0 - s) ** 2
            h10 = s * (1.0 - s) ** 2 * dt
            h01 = s * s * (3.0 - 2.0 * s)
            h11 = s * s * (s - 1.0) * dt
            d00 = 6.0 * s * (s - 1.0) / dt
            d10 = (1.0 - s) * (1.0 - 3.0 * s)
            d11 = s * (3.0 * s - 2.0)
            for k in range(m):
                YE[n_eval, k] = h00 * y[k] + h10 * yp[k] + h01 * y_new[k] + h11 * yp_new[k]
                YPE[n_eval, k] = h00 * yp[k] + h10 * ypp[k] + h01 * yp_new[k] + h11 * ypp_new[k]
                YPPE[n_eval, k] = (d00 * (yp[k] - yp_new[k]) + d10 * ypp[k]
                                   + d11 * ypp_new[k])
            n_eval += 1
        for k in range(m):
            y[k] = y_new[k]
            yp[k] = yp_new[k]
            ypp[k] = ypp_new[k]
        t = t_new
        if store_knots:
            T[n_knots] = t
            for k in range(m):
                Y[n_knots, k] = y[k]
                YP[n_knots, k] = yp[k]
                YPP[n_knots, k] = ypp[k]
            n_knots += 1
    return (OK, -1, t, t, nfev, 0, 0, n, n_knots, n_eval, T, Y, YP, YPP, YE, YPE, YPPE)


# Types of the loop's arguments after (fun, args): t0, h, n, tf, y0, yp0,
# t_eval, store_knots.
_LOOP_TYPES = (_compile.FLOAT, _compile.FLOAT, _compile.INT, _compile.FLOAT, _compile.VECTOR,
               _compile.VECTOR, _compile.VECTOR, _compile.BOOL)


def rk4(fun, t_span, y0, yp0, h, *, t_eval=None, args=()):
    """Classical fourth-order Runge-Kutta for y'' = F(t, y, y').

    The report's comparison method: RK4 on the first-order system
    u = (y, y'), with the same uniform step as the spline method (it
    evaluates F four times per step, at the ends and twice at the midpoint).

    Parameters
    ----------
    fun : callable
        ``fun(t, y, yp, *args) -> y''``; the loop runs compiled and calls a
        ``numba.njit`` function directly, a plain one through the
        interpreter.
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
    path = _base.choose_path(fun, None, args)
    _base.check_fun(fun, t0, y0, yp0, args)
    with _compile.loop_callables(path, fun, None, args) as (loop_fun, _, loop_args):
        fun_type, args_type, _ = _compile.loop_types(loop_fun, None, loop_args)
        loop = _compile.compiled(_rk4_loop, (fun_type, args_type) + _LOOP_TYPES)
        out = loop(loop_fun, loop_args, t0, h, n, tf, y0, yp0,
                   np.empty(0) if t_eval is None else t_eval, t_eval is None)
    result, _ = _base.build_result(out, t_eval, 0)
    result.path = path
    return result
