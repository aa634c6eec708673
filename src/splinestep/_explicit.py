"""The explicit baselines' stepping loop: classical RK4 and velocity
Verlet share one compiled loop (the knot walk, the output at ``t_eval``, the
status checks) and differ only in their step (:func:`_rk4_step`,
:func:`_verlet_step`), both inlined into the loop (numba
``inline="always"``): as calls, they cost each method 1.3 to 1.5 times the
time per evaluation (``make bench``)."""

import numpy as np
from numba import njit

from . import _base, _compile
from ._base import BAD_SHAPE, NON_FINITE, OK, as_vector, wrong_length

# Butcher tableau of the classical method: stage j (j = 2, 3, 4) is taken
# at t + NODES[j-2] h from the state advanced by the previous stage; the
# stages are combined with weights FIRST_WEIGHT, then STAGE_WEIGHTS.
NODES = (0.5, 0.5, 1.0)
FIRST_WEIGHT = 1.0 / 6.0
STAGE_WEIGHTS = (1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0)


# The methods of the loop.
RK4, VERLET = 0, 1


# Compiled once per signature and cached on disk by splinestep._compile, for
# compiled and plain-Python right-hand sides alike.
def _explicit_loop(fun, args, method, t0, h, n, tf, y0, yp0, t_eval, store_knots):
    """Step from t0 to tf with ``method`` (RK4 or VERLET); same return
    tuple as ``spline._spline_loop``'s first item.

    Between steps, values at ``t_eval`` come from cubic Hermite
    interpolation of (y, y') and of (y', y'') at the two ends of the step.
    Its error is O(h^4): below Verlet's error, but of the order of RK4's own
    (on the ellipse at h = 0.0321, 25 % above RK4's energy error in the first
    orbit), so that RK4 is measured at its own steps (``t_eval`` on them).
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

    status = _checked(as_vector(fun(t0, y, yp, *args)), ypp, m)
    nfev += 1
    if status != OK:
        return (status, 0, t0, t0, nfev, 0, 0, 0, 0, 0, T, Y, YP, YPP, YE, YPE, YPPE)
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
        if method == RK4:
            status, evals = _rk4_step(fun, args, t, t_new, dt, y, yp, ypp, y_stage, v, a,
                                      sum_v, sum_a, y_new, yp_new)
        else:
            status, evals = _verlet_step(fun, args, t_new, dt, y, yp, ypp, v, a, y_new, yp_new)
        nfev += evals
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


@njit(cache=True, inline="always")
def _checked(g, a, m):
    """Copy the value ``g`` of fun into ``a``; the status it implies."""
    if wrong_length(g, m):
        return BAD_SHAPE
    status = OK
    for k in range(m):
        if not abs(g[k]) < np.inf:
            status = NON_FINITE
        a[k] = g[k]
    return status


@njit(cache=True, inline="always")
def _rk4_step(fun, args, t, t_new, dt, y, yp, ypp, y_stage, v, a, sum_v, sum_a, y_new, yp_new):
    """One RK4 step on u = (y, y'), u' = (y', F): y_new, yp_new, and y'' at
    t_new in ``a``.  Returns (status, evaluations of F made: 4 unless one
    failed)."""
    m = y.shape[0]
    # Stage 1 is (y', y'') at t; stage j+1 advances by NODES[j] dt with stage j.
    for k in range(m):
        v[k] = yp[k]
        a[k] = ypp[k]
        sum_v[k] = FIRST_WEIGHT * v[k]
        sum_a[k] = FIRST_WEIGHT * a[k]
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
        status = _checked(g, a, m)
        if status != OK:
            return status, j + 1
        if j < 3:
            for k in range(m):
                sum_v[k] += STAGE_WEIGHTS[j] * v[k]
                sum_a[k] += STAGE_WEIGHTS[j] * a[k]
    return OK, 4


@njit(cache=True, inline="always")
def _verlet_step(fun, args, t_new, dt, y, yp, ypp, v, a, y_new, yp_new):
    """One velocity-Verlet step: y_new, yp_new, and y'' at t_new in ``a``;
    one evaluation of F.  F's y' argument is the predictor y' + dt y''
    (O(dt^2) off, so the step keeps order 2 when F depends on y').
    Returns (status, 1)."""
    m = y.shape[0]
    for k in range(m):
        y_new[k] = y[k] + dt * yp[k] + (0.5 * dt * dt) * ypp[k]
        v[k] = yp[k] + dt * ypp[k]
    status = _checked(as_vector(fun(t_new, y_new, v, *args)), a, m)
    for k in range(m):
        yp_new[k] = yp[k] + (0.5 * dt) * (ypp[k] + a[k])
    return status, 1

# Types of the loop's arguments after (fun, args): method, t0, h, n, tf, y0,
# yp0, t_eval, store_knots.
LOOP_TYPES = (_compile.INT, _compile.FLOAT, _compile.FLOAT, _compile.INT, _compile.FLOAT, _compile.VECTOR,
               _compile.VECTOR, _compile.VECTOR, _compile.BOOL)




def run(method, fun, t_span, y0, yp0, h, t_eval, args, max_steps=_base.MAX_STEPS):
    """Validate the arguments, run the loop with ``method`` on the compiled
    or plain path, and return the :class:`OdeResult`."""
    t0, tf = _base.check_span(t_span)
    y0, yp0 = _base.check_state(y0, yp0)
    h, n, _ = _base.check_grid(t0, tf, h, None, _base.check_max_steps(max_steps))
    t_eval = _base.check_t_eval(t_eval, t0, tf)
    args = _base.check_args(args)
    if not callable(fun):
        raise ValueError("fun must be callable")
    path = _base.choose_path(fun, None, args)
    _base.check_fun(fun, t0, y0, yp0, args)
    with _compile.loop_callables(path, fun, None, args) as (loop_fun, _, loop_args):
        fun_type, args_type, _ = _compile.loop_types(loop_fun, None, loop_args)
        loop = _compile.compiled(_explicit_loop, (fun_type, args_type) + LOOP_TYPES)
        out = loop(loop_fun, loop_args, method, t0, h, n, tf, y0, yp0,
                   np.empty(0) if t_eval is None else t_eval, t_eval is None)
    result, _ = _base.build_result(out, t_eval, 0)
    result.path = path
    return result
