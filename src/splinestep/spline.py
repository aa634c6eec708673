"""Cubic-spline time stepping for y'' = F(t, y, y').

On each interval [t_i, t_{i+1}] (h = t_{i+1} - t_i) the solution is the cubic

    s_i(t) = a_i + b_i (t - t_i) + c_i (t - t_i)^2 + d_i (t - t_i)^3,

continuous with its first two derivatives at the knots and satisfying the
ODE at every knot.  With z = y''(t_{i+1}) = 2 c_{i+1} the unknown of the step,

    d_i     = (z - y''_i) / (6 h)                        (report eq. 8)
    a_{i+1} = y_i + h y'_i + h^2 (y''_i / 3 + z / 6)      (eq. 6)
    b_{i+1} = y'_i + h (y''_i + z) / 2                     (eq. 7)
    z       = F(t_{i+1}, a_{i+1}, b_{i+1})                 (eq. 9, with c = y''/2)

which is Newmark's method with beta = 1/6, gamma = 1/2 (the "linear
acceleration" method).  The step equation is solved by the report's
fixed-point iteration (start from d_i = 0, i.e. z = y''_i) or by Newton's
method.
"""

import warnings

import numpy as np

from . import _base, _compile, adaptive, check
from .events import check_events, locate
from ._base import BAD_SHAPE, NON_FINITE, OK, as_vector, wrong_length
from .result import HermiteSolution, SplineSolution
from .step import (FIXED_POINT, NEWTON, YP_WEIGHT, Y_WEIGHT, composed_step, local_errors,
                   newton_call, quintic, step_state, sweep_step)

ITERATIONS = ("fixed-point", "newton", "global")

# Symmetric compositions raising the order of a symmetric one-step method
# (weights of the sub-steps, each a multiple of the step): Yoshida's triple
# jump for order 4 and his 7-stage solution A for order 6.
_CBRT2 = 2.0 ** (1.0 / 3.0)
_YOSHIDA6 = (0.784513610477560, 0.235573213359357, -1.17767998417887)
COMPOSITIONS = {
    2: (1.0,),
    4: (1.0 / (2.0 - _CBRT2), -_CBRT2 / (2.0 - _CBRT2), 1.0 / (2.0 - _CBRT2)),
    6: _YOSHIDA6 + (1.0 - 2.0 * sum(_YOSHIDA6),) + _YOSHIDA6[::-1],
}


def composition(order):
    """(weights, slots) of the composition of ``order``: the sub-steps'
    sizes as fractions of the step, and for each the index of its distinct
    size (sub-steps of one size share a kept Newton matrix)."""
    weights = np.array(COMPOSITIONS[order])
    distinct = list(dict.fromkeys(weights.tolist()))
    return weights, np.array([distinct.index(w) for w in weights.tolist()], dtype=np.int64)


# Compiled once per signature and cached on disk by splinestep._compile, for
# compiled and plain-Python right-hand sides alike.
def _spline_loop(fun, args, jac, t0, h, n, knots, tf, y0, yp0, ypp0, jerk0, dt0, t_eval,
                 store_knots, mode, n_iter, until_converged, tol, reuse, weights, slots):
    """Step from t0 to tf, forwards or backwards (h and the knots carry the
    direction).  Compiled by numba for every ``fun``: a compiled one is
    called directly, a plain-Python one through ``_compile.python_callbacks``.  Component
    loops over preallocated buffers keep the step free of temporary arrays.

    ``ypp0`` (y'' at t0) and ``jerk0`` (the third derivative on the step
    of size ``dt0`` that ended at t0) are empty for a fresh start; a run
    continued from an earlier one passes them, so that it continues the same
    spline and the same error estimate.

    Returns ``(common, estimate)``: ``common`` is (status, fail_step, t_last,
    t_fail, nfev, njev, niter, nstep, n_knots, n_eval, T, Y, YP, YPP, YE,
    YPE, YPPE), see ``_base.build_result``; ``estimate`` is (err_y, t_err_y,
    err_yp, y_scale, yp_scale, y_at_err, yp_at_err, y, yp, ypp, jerk, dt):
    the largest estimated local errors of y and y' (max norm over components
    and steps, see ``step.local_errors``), the knot where that of y is largest and the
    state there, the largest |y| and |y'| met, and the state, second and
    third derivative and step size at the last knot reached.
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
    y = y0.copy()            # a_i
    yp = yp0.copy()          # b_i
    ypp = np.zeros(m)        # 2 c_i
    jerk = np.zeros(m)       # 6 d on the last interval
    z = np.empty(m)          # the unknown y''_{i+1} = 2 c_{i+1}
    work, lu, piv, info = step_state(m, np.max(slots) + 1)  # buffers, kept Newton matrices
    sub = (np.empty(m), np.empty(m), np.empty(m))  # a composition's sub-step starts
    composed = weights.shape[0] > 1
    y_new = np.empty(m)
    yp_new = np.empty(m)
    y_at_err = y0.copy()
    yp_at_err = yp0.copy()
    nfev = 0
    njev = 0
    niter = 0
    n_eval = 0
    direction = 1.0 if tf >= t0 else -1.0
    err_y = 0.0
    err_yp = 0.0
    t_err_y = t0
    y_scale = 0.0
    yp_scale = 0.0
    for k in range(m):
        y_scale = max(y_scale, abs(y[k]))
        yp_scale = max(yp_scale, abs(yp[k]))
    have_jerk = jerk0.shape[0] == m
    dt_prev = dt0
    if have_jerk:
        for k in range(m):
            jerk[k] = jerk0[k]

    status = OK
    if ypp0.shape[0] == m:
        for k in range(m):
            ypp[k] = ypp0[k]
    else:
        g = as_vector(fun(t0, y, yp, *args))
        nfev += 1
        if wrong_length(g, m):
            status = BAD_SHAPE
        else:
            for k in range(m):
                ypp[k] = g[k]
                if not abs(g[k]) < np.inf:
                    status = NON_FINITE
    if status != OK:
        return ((status, 0, t0, t0, nfev, njev, niter, 0, 0, 0,
                 T, Y, YP, YPP, YE, YPE, YPPE),
                (err_y, t_err_y, err_yp, y_scale, yp_scale, y_at_err, yp_at_err,
                 y, yp, ypp, jerk, dt_prev))
    T[0] = t0
    for k in range(m):
        Y[0, k] = y[k]
        YP[0, k] = yp[k]
        YPP[0, k] = ypp[k]
    n_knots = 1
    while n_eval < ne and direction * (t_eval[n_eval] - t0) <= 0.0:
        for k in range(m):
            YE[n_eval, k] = y[k]
            YPE[n_eval, k] = yp[k]
            YPPE[n_eval, k] = ypp[k]
        n_eval += 1

    t = t0
    for i in range(n):
        if knots.shape[0] > 0:
            t_new = knots[i + 1]
        elif i + 1 < n:
            t_new = t0 + (i + 1) * h
        else:
            t_new = tf
        dt = t_new - t
        if composed:
            status, fe, je, it = composed_step(fun, args, jac, t, t_new, weights, slots, y, yp,
                                               ypp, z, y_new, yp_new, mode, n_iter,
                                               until_converged, tol, reuse, work, lu, piv, info,
                                               sub)
        elif mode == FIXED_POINT:   # the hot path, inlined
            status, fe, je, it = sweep_step(fun, args, t_new, dt, y, yp, ypp, z, y_new, yp_new,
                                            n_iter, until_converged, tol, work)
        else:
            status, fe, je, it = newton_call(fun, args, jac, t_new, dt, y, yp, ypp, z, y_new,
                                             yp_new, n_iter, until_converged, tol, reuse, work,
                                             lu, piv, info, 0)
        nfev += fe
        njev += je
        niter += it
        if status != OK:
            return ((status, i + 1, t, t_new, nfev, njev, niter, i, n_knots, n_eval,
                     T, Y, YP, YPP, YE, YPE, YPPE),
                    (err_y, t_err_y, err_yp, y_scale, yp_scale, y_at_err, yp_at_err,
                     y, yp, ypp, jerk, dt_prev))
        # Report at the requested times inside (t, t_new] from the cubic
        # itself, or for a composed step from the quintic through the knots'
        # values and first two derivatives (of the composition's order).
        while n_eval < ne and direction * (t_eval[n_eval] - t_new) <= 0.0:
            s = t_eval[n_eval] - t
            for k in range(m):
                if composed:
                    YE[n_eval, k], YPE[n_eval, k], YPPE[n_eval, k] = quintic(
                        s, dt, y[k], yp[k], ypp[k], y_new[k], yp_new[k], z[k])
                else:
                    d = (z[k] - ypp[k]) / (6.0 * dt)
                    YE[n_eval, k] = y[k] + s * (yp[k] + s * (0.5 * ypp[k] + s * d))
                    YPE[n_eval, k] = yp[k] + s * (ypp[k] + 3.0 * s * d)
                    YPPE[n_eval, k] = ypp[k] + 6.0 * s * d
            n_eval += 1
        # Local error estimate: y''' is constant on each interval, so its
        # jump at the knot t over the mean of the two steps estimates y''''.
        ey = 0.0
        eyp = 0.0
        for k in range(m):
            new_jerk = (z[k] - ypp[k]) / dt
            if have_jerk:
                est_y, est_yp = local_errors(new_jerk, jerk[k], dt, dt_prev)
                ey = max(ey, est_y)
                eyp = max(eyp, est_yp)
            jerk[k] = new_jerk
        if ey > err_y:
            err_y = ey
            t_err_y = t
            for k in range(m):
                y_at_err[k] = y[k]
                yp_at_err[k] = yp[k]
        err_yp = max(err_yp, eyp)
        have_jerk = True
        dt_prev = dt
        for k in range(m):
            y[k] = y_new[k]
            yp[k] = yp_new[k]
            ypp[k] = z[k]
            y_scale = max(y_scale, abs(y[k]))
            yp_scale = max(yp_scale, abs(yp[k]))
        t = t_new
        if store_knots:
            T[n_knots] = t
            for k in range(m):
                Y[n_knots, k] = y[k]
                YP[n_knots, k] = yp[k]
                YPP[n_knots, k] = ypp[k]
            n_knots += 1
    return ((OK, -1, t, t, nfev, njev, niter, n, n_knots, n_eval,
             T, Y, YP, YPP, YE, YPE, YPPE),
            (err_y, t_err_y, err_yp, y_scale, yp_scale, y_at_err, yp_at_err,
             y, yp, ypp, jerk, dt_prev))


def solve(fun, t_span, y0, yp0, h=None, *, knots=None, t_eval=None, args=(), events=None,
          iteration="fixed-point", iterations=None, tol=1e-12, max_iter=50,
          jac=None, dense_output=False, order=2, rtol=1e-3, atol=1e-6, first_step=None,
          max_step=np.inf, max_steps=_base.MAX_STEPS, reuse_jacobian=True):
    """Solve y'' = F(t, y, y') by cubic-spline time stepping.

    Each step extends a C2 cubic spline by one knot and satisfies the ODE at
    the new knot; the implicit unknown (the third-derivative coefficient
    d_i, equivalently y'' at the new knot) is found by fixed-point
    iteration, as in the report, or by Newton's method.

    Parameters
    ----------
    fun : callable
        ``fun(t, y, yp, *args) -> y''``, with y and yp arrays of shape (m,);
        it returns an array of shape (m,), a list or a tuple of m numbers,
        or a number when m = 1.  The stepping loop runs compiled; a
        ``numba.njit`` ``fun`` is called from it directly, a plain one
        through the interpreter (see the README's "The fast path"); a
        compiled ``fun`` that returns a tuple spares an array allocation
        per evaluation.
    t_span : (float, float)
        Interval of integration (t0, tf); tf < t0 integrates backwards.
    y0, yp0 : float or array_like, shape (m,)
        Initial value and initial first derivative (real).
    h : float, optional
        Uniform step (positive; the direction comes from ``t_span``).  When
        the span is not a multiple of h, the last step is shortened to end
        exactly at tf; a last step shorter than 1e-9 h is merged into the
        one before, and an h larger than the span gives one step.
    knots : array_like, optional
        Knots t0 = knots[0], ..., knots[-1] = tf, strictly monotonic
        (instead of h).
    t_eval : array_like, optional
        Times in t_span, sorted in the direction of integration, at which to
        report the solution, evaluated from the spline; the knots are then
        not stored.
    args : tuple, optional
        Extra arguments passed to ``fun``, ``jac`` and the events.  Numbers
        are passed as floats and numeric arrays as float arrays.
    events : callable or list of callables, optional
        Functions ``g(t, y, yp, *args)`` whose zeros are located on the
        spline, with the optional attributes ``terminal`` and ``direction``
        of scipy's ``solve_ivp`` (see :mod:`splinestep.events`).
    iteration : {"fixed-point", "newton", "global"}
        How the step equation is solved.  "fixed-point" is the report's
        scheme; it converges when h^2/6 |dF/dy| + h/2 |dF/dy'| < 1.
        "newton" uses Newton's method with an LU solve of
        I - h^2/6 dF/dy - h/2 dF/dy' (exact ``jac``, or finite differences
        at m evaluations of F), the matrix kept across iterations and steps
        and rebuilt when convergence slows (``reuse_jacobian``).  On a linear
        problem its first iteration solves the step equation to rounding
        error, and a second one confirms it, so a converged step costs 2
        iterations.  "global" solves the equations of all knots together by
        Newton's method with a sparse LU (:mod:`splinestep.bvp`), starting
        from one sweep per step; it gives the stepwise solution.
    iterations : int, optional
        Exactly this many iterations per step, with no convergence test
        (the report's "a few times").  By default iterate until converged.
    tol : float
        Convergence test: the change of the step's increments (of y and y'
        at the new knot) is at most ``tol`` times the size of the state
        (max norm).
    max_iter : int
        Iterations allowed per step before the run fails (when
        ``iterations`` is None).
    jac : callable, optional
        ``jac(t, y, yp, *args) -> (dF/dy, dF/dyp)``, two (m, m) arrays, used
        by Newton's method (finite differences otherwise); unused, with a
        warning, by the fixed-point iteration.
    dense_output : bool
        Return the spline itself as ``sol`` (for ``order`` 4 or 6 the quintic
        :class:`HermiteSolution` through the knots, of the run's order).
    order : {2, 4, 6}
        2: the report's method.  4 and 6: each step of size h is a symmetric
        composition of spline steps (Yoshida's triple jump, 3 sub-steps; his
        7-stage solution A) [3]_; symmetric like the spline step, so the
        long-time behaviour is kept.  Events are located on the cubic through
        the knots (second order between knots).
    rtol, atol : float, and float or array_like of shape (m,)
        Adaptive knots (neither ``h`` nor ``knots`` given): the estimated
        local errors of y and y' of each step, from the jump of the spline's
        third derivative (:mod:`splinestep.controllers`), must be at most
        atol + rtol |y| (scipy's scaled RMS norm).  ``res.t`` holds the knots
        chosen; ``res.n_rejected`` and ``res.n_failed`` count the steps
        rejected by the estimate and those whose equation could not be
        solved (both retried smaller).
    first_step, max_step : float
        Adaptive knots: the first step (chosen from y0, yp0 by default) and
        the largest step.
    max_steps : int
        The most steps a run may take (default 10**8).  A fixed grid (``h``
        or ``knots``) of more steps is refused before it starts (ValueError);
        adaptive knots stop after this many step attempts (status -1).
    reuse_jacobian : bool
        Newton: keep the matrix and its LU factors while the iteration
        converges fast (simplified Newton [4]_); False rebuilds it at every
        iteration (full Newton).

    Returns
    -------
    OdeResult
        ``t`` (k,), ``y``, ``yp``, ``ypp`` (m, k), ``sol``, ``t_events``,
        ``y_events``, ``yp_events``, ``nfev``, ``njev``, ``niter``,
        ``nstep``, ``local_error``, ``local_error_yp``, ``t_local_error``
        (a uniform run's own estimate: that of a spline step of size h, which
        for ``order`` 4 or 6 overstates the local error; NaN for adaptive and
        global runs), ``order``,
        ``path``, ``status`` (0 reached the end, 1 a terminal event, -1
        failed), ``message``, ``success``; adaptive runs also
        ``n_rejected``, ``n_failed``.  A failed run returns the steps
        completed before the failure and says in ``message`` which step
        failed and why.

    Warns
    -----
    UserWarning
        When the run's own error estimate says that the step is far too
        large for the solution (see :mod:`splinestep.check`); the message
        then says so too.

    References
    ----------
    .. [1] N. M. Newmark, "A method of computation for structural dynamics",
       J. Eng. Mech. Div. ASCE 85 (1959) 67-94.
    .. [2] E. L. Wilson, I. Farhoomand, K. J. Bathe, "Nonlinear dynamic
       analysis of complex structures", Earthquake Eng. Struct. Dyn. 1 (1973)
       241-252 (the linear acceleration method).
    .. [3] H. Yoshida, "Construction of higher order symplectic integrators",
       Phys. Lett. A 150 (1990) 262-268; E. Hairer, C. Lubich, G. Wanner,
       "Geometric Numerical Integration", 2nd ed., Springer (2006), Sec. II.4
       and V.3.
    .. [4] E. Hairer, G. Wanner, "Solving Ordinary Differential Equations II",
       2nd ed., Springer (1996), Sec. IV.8.

    Examples
    --------
    >>> import numpy as np, splinestep
    >>> res = splinestep.solve(lambda t, y, yp: -y, (0, np.pi), 1.0, 0.0, h=np.pi / 100)
    >>> bool(abs(res.y[0, -1] + 1) < 1e-3)
    True
    """
    t0, tf = _base.check_span(t_span, backward=True)
    y0, yp0 = _base.check_state(y0, yp0)
    _base.check_max_steps(max_steps)
    adaptive = h is None and knots is None
    if not adaptive:
        h, n, knots = _base.check_grid(t0, tf, h, knots, max_steps)
    t_eval = _base.check_t_eval(t_eval, t0, tf)
    args = _base.check_args(args)
    if iteration not in ITERATIONS:
        raise ValueError(f"iteration must be one of {ITERATIONS}, got {iteration!r}")
    if order not in COMPOSITIONS:
        raise ValueError(f"order must be one of {tuple(COMPOSITIONS)}, got {order!r}")
    if not isinstance(reuse_jacobian, (bool, np.bool_)):
        raise ValueError(f"reuse_jacobian must be True or False, got {reuse_jacobian!r}")
    if adaptive:
        rtol, atol, first_step, max_step, max_steps = _base.check_tolerances(
            rtol, atol, first_step, max_step, max_steps, y0.size)
        if first_step > abs(tf - t0):
            raise ValueError(f"first_step = {first_step:g} exceeds the span "
                             f"{abs(tf - t0):g} of t_span")
        if order != 2:
            raise ValueError(f"order={order} needs h or knots: the adaptive knots control "
                             "the error of the order-2 step")
        if iteration == "global":
            raise ValueError('iteration="global" needs h or knots')
    if iteration == "global":
        if order != 2 or events is not None or iterations is not None:
            raise ValueError('iteration="global" takes neither order > 2, events nor '
                             "iterations")
        from .bvp import solve_global
        return solve_global(fun, t0, tf, y0, yp0, h, n, knots, t_eval, args, tol, max_iter,
                            jac, dense_output)
    if not (_base.is_real(tol) and np.isfinite(tol) and tol > 0):
        raise ValueError(f"tol must be positive and finite, got {tol!r}")
    if not (_base.is_integer(max_iter) and max_iter >= 1):
        raise ValueError(f"max_iter must be an integer >= 1, got {max_iter!r}")
    if iterations is not None and not (_base.is_integer(iterations) and iterations >= 1):
        raise ValueError(f"iterations must be None or an integer >= 1, got {iterations!r}")
    if not callable(fun):
        raise ValueError("fun must be callable")
    if jac is not None and not callable(jac):
        raise ValueError("jac must be callable or None")
    mode = FIXED_POINT if iteration == "fixed-point" else NEWTON
    if jac is not None and mode == FIXED_POINT:
        warnings.warn("jac is not used by the fixed-point iteration; pass "
                      "iteration=\"newton\" to use it", UserWarning, stacklevel=2)
        jac = None
    events = check_events(events, args)
    path = _base.choose_path(fun, jac, args)
    _base.check_fun(fun, t0, y0, yp0, args)
    if jac is not None:
        _base.check_jac(jac, t0, y0, yp0, args)

    until_converged = iterations is None
    n_iter = max_iter if until_converged else iterations
    if adaptive:
        return _solve_adaptive(fun, jac, args, path, t0, tf, y0, yp0, t_eval, events, mode,
                               int(n_iter), until_converged, float(tol),
                               bool(reuse_jacobian), rtol, atol, first_step, max_step,
                               max_steps, dense_output)
    weights, slots = composition(order)
    settings = (mode, int(n_iter), until_converged, float(tol), bool(reuse_jacobian), weights,
                slots)
    store_knots = bool(t_eval is None or dense_output or events)
    t_eval_all = _EMPTY if t_eval is None else t_eval
    with _compile.loop_callables(path, fun, jac, args) as (loop_fun, loop_jac, loop_args):
        loop = _compile.compiled(
            _spline_loop, _compile.loop_types(loop_fun, loop_jac, loop_args) + _LOOP_TYPES)
        # Without a terminal event the run is one piece and its events are
        # located afterwards; with one, piece by piece as the run goes, and
        # only there (locating them again would list every zero twice).
        located = any(ev.max_count for ev in events)
        if not located:
            out, estimate = loop(loop_fun, loop_args, loop_jac, t0, h, n, knots, tf, y0, yp0,
                                 _EMPTY, _EMPTY, 0.0, t_eval_all, store_knots, *settings)
            terminal = None
        else:
            out, estimate, terminal = _run_until_terminal(
                loop, loop_fun, loop_args, loop_jac, t0, h, n, knots, tf, y0, yp0, t_eval_all,
                events, settings)
    result, knot_values = _base.build_result(out, t_eval, n_iter)
    if events and not located:
        T, Y, YP, YPP = knot_values
        locate(events, T, Y, YP, YPP)
    if terminal is not None:
        result, knot_values = _cut_at(result, knot_values, t_eval, terminal)
    _attach_events(result, events, y0.size)
    if dense_output and knot_values[0].size >= 2:
        result.sol = (SplineSolution if order == 2 else HermiteSolution)(*knot_values)
    result.path = path
    result.order = order
    # For a composition the jumps measure the local error of a spline step of
    # size h, which overstates the composition's: the check still sees a step
    # far too large for the solution, and no reasonable one.
    check.report(result, estimate, fun, jac, args, h, t0, y0, yp0, Y_WEIGHT, YP_WEIGHT)
    return result


def _attach_events(result, events, m):
    """The events' zeros as scipy's ``t_events``, ``y_events`` (and
    ``yp_events``); None without events."""
    if not events:
        result.t_events = result.y_events = result.yp_events = None
        return
    result.t_events = [np.array(ev.times) for ev in events]
    # As scipy: (k, m) for k zeros, and shape (0,) for none.
    result.y_events = [np.array([s[0] for s in ev.states]) for ev in events]
    result.yp_events = [np.array([s[1] for s in ev.states]) for ev in events]


def _solve_adaptive(fun, jac, args, path, t0, tf, y0, yp0, t_eval, events, mode, n_iter,
                    until_converged, tol, reuse, rtol, atol, first_step, max_step, max_steps,
                    dense_output):
    """solve() with knots chosen by the error controller (splinestep.adaptive)."""
    with _compile.loop_callables(path, fun, jac, args) as (loop_fun, loop_jac, loop_args):
        out = adaptive.run(loop_fun, loop_args, loop_jac, t0, tf, y0, yp0, rtol, atol,
                           first_step, max_step, mode, n_iter, until_converged, tol, reuse,
                           max_steps)
    result, knot_values = adaptive.build_result(out, t0, t_eval, n_iter, max_steps)
    T, Y, YP, YPP = knot_values
    if events:
        index, t_ev, y_ev, yp_ev, ypp_ev, _ = locate(events, T, Y, YP, YPP)
        if index is not None:
            result, knot_values = _cut_at(result, knot_values, t_eval, (t_ev, y_ev, yp_ev,
                                                                        ypp_ev))
    _attach_events(result, events, y0.size)
    if dense_output and knot_values[0].size >= 2:
        result.sol = SplineSolution(*knot_values)
    result.path = path
    result.order = 2
    result.local_error = result.local_error_yp = result.t_local_error = np.nan
    return result


_EMPTY = np.empty(0)
# Types of the loop's arguments after (fun, args, jac): t0, h, n, knots, tf,
# y0, yp0, ypp0, jerk0, dt0, t_eval, store_knots, mode, n_iter,
# until_converged, tol, reuse, weights, slots.
_LOOP_TYPES = (_compile.FLOAT, _compile.FLOAT, _compile.INT, _compile.VECTOR, _compile.FLOAT,
               _compile.VECTOR, _compile.VECTOR, _compile.VECTOR, _compile.VECTOR,
               _compile.FLOAT, _compile.VECTOR, _compile.BOOL, _compile.INT, _compile.INT,
               _compile.BOOL, _compile.FLOAT, _compile.BOOL, _compile.VECTOR,
               _compile.INT_VECTOR)

# Steps in the first piece of a run with a terminal event; each later piece
# doubles, up to MAX_PIECE, so a run that stops early computes little past
# its event and a long run makes few calls.
FIRST_PIECE = 256
MAX_PIECE = 65536


def _run_until_terminal(loop, fun, args, jac, t0, h, n, knots, tf, y0, yp0, t_eval, events,
                        settings):
    """Run the loop piece by piece, each continuing the same spline (its
    knots, y'' and error estimate carried over), and look for the events'
    zeros after each piece; stop after the piece holding a terminal zero.

    Returns (out, estimate, terminal) as the loop would for the whole run,
    with ``terminal`` = (t, y, yp, ypp) of the terminal event or None.
    """
    direction = 1.0 if tf > t0 else -1.0
    pieces, ests = [], []
    start, size = 0, FIRST_PIECE
    t_a, y_a, yp_a, ypp_a, jerk_a, dt_a = t0, y0, yp0, _EMPTY, _EMPTY, 0.0
    g_first, terminal = None, None
    while True:
        stop = min(start + size, n)
        if knots.size:
            piece = knots[start:stop + 1]
        else:
            piece = t0 + np.arange(start, stop + 1) * h
            piece[0] = t_a
            if stop == n:
                piece[-1] = tf
        ahead = direction * (t_eval - t_a)
        mine = t_eval[((ahead > 0) | ((ahead == 0) & (start == 0)))
                      & (direction * (t_eval - piece[-1]) <= 0)]
        out, est = loop(fun, args, jac, t_a, h, stop - start, piece, piece[-1], y_a, yp_a,
                        ypp_a, jerk_a, dt_a, mine, True, *settings)
        pieces.append((start, out))
        ests.append(est)
        n_knots = out[8]
        index, t_ev, y_ev, yp_ev, ypp_ev, g_first = locate(
            events, out[10][:n_knots], out[11][:n_knots], out[12][:n_knots],
            out[13][:n_knots], g_first)
        if index is not None:
            terminal = (t_ev, y_ev, yp_ev, ypp_ev)
            break
        if out[0] != OK or stop == n:
            break
        y_a, yp_a, ypp_a, jerk_a, dt_a = est[7], est[8], est[9], est[10], est[11]
        t_a, start, size = piece[-1], stop, min(2 * size, MAX_PIECE)
    return _joined(pieces), _joined_estimate(ests), terminal


def _joined(pieces):
    """One loop output from consecutive pieces (the first knot of each later
    piece is the last of the one before)."""
    last = pieces[-1][1]
    offset = pieces[-1][0]
    status, fail_step, t_last, t_fail = last[0], last[1], last[2], last[3]
    if fail_step > 0:
        fail_step += offset
    totals = [sum(out[k] for _, out in pieces) for k in (4, 5, 6, 7)]
    rows = [[out[k][:out[8]] if j == 0 else out[k][1:out[8]] for j, (_, out)
             in enumerate(pieces)] for k in (10, 11, 12, 13)]
    T, Y, YP, YPP = (np.concatenate(parts) for parts in rows)
    evals = [np.concatenate([out[k][:out[9]] for _, out in pieces]) for k in (14, 15, 16)]
    return (status, fail_step, t_last, t_fail, *totals, T.size, evals[0].shape[0],
            T, Y, YP, YPP, *evals)


def _joined_estimate(ests):
    """The error estimate of consecutive pieces: the largest of each."""
    worst = max(ests, key=lambda e: e[0])
    return (worst[0], worst[1], max(e[2] for e in ests), max(e[3] for e in ests),
            max(e[4] for e in ests), worst[5], worst[6], *ests[-1][7:])


def _cut_at(result, knot_values, t_eval, terminal):
    """The result ended at a terminal event: knots (or t_eval points) up to
    it, and the event's own point as the last knot."""
    t_ev, y_ev, yp_ev, ypp_ev = terminal
    T, Y, YP, YPP = knot_values
    direction = 1.0 if T[-1] >= T[0] else -1.0
    keep = direction * (T - t_ev) < 0
    T = np.append(T[keep], t_ev)
    Y, YP, YPP = (np.vstack([v[keep], w]) for v, w in ((Y, y_ev), (YP, yp_ev), (YPP, ypp_ev)))
    if t_eval is None:
        result.t, result.y, result.yp, result.ypp = T.copy(), Y.T.copy(), YP.T.copy(), YPP.T.copy()
    else:
        keep_eval = direction * (result.t - t_ev) <= 0
        result.t = result.t[keep_eval]
        result.y, result.yp, result.ypp = (v[:, keep_eval] for v in
                                           (result.y, result.yp, result.ypp))
    result.status, result.success = 1, True
    result.message = f"A termination event occurred at t = {_base.short(t_ev)}."
    return result, (T, Y, YP, YPP)
