"""The one driver: a step, a step-size controller, and everything else once.

Every front door (:func:`splinestep.solve`, :func:`splinestep.solve_reversible`,
:func:`splinestep.rk4`, :func:`splinestep.verlet`) validates its arguments,
chooses a step (:class:`Method`) and a controller
(:class:`splinestep.controllers.Control`) and calls :func:`run`, which runs
the compiled loop :func:`_drive`.  The loop asks the controller for the next
knot, takes the step, lets the controller judge it (error control), and for
every path alike:

- locates the events on the accepted step's interpolant as the step is
  taken (a terminal event ends the run at its zero, whose state becomes the
  last knot);
- fills ``t_eval`` from the same interpolant (:func:`dense_state`);
- stores the knots for dense output (when they are wanted);
- keeps the largest estimated local error of the spline steps (the jump
  of the third derivative, :mod:`splinestep.controllers`);
- counts every evaluation of fun and jac and honours ``max_steps`` (a
  fixed grid of more steps is refused by the front door);
- checks each value fun returns (the steps return a status).

The steps share one protocol: from (y, y', y'') at t to t_new they leave
y_new, y'_new and z = y''(t_new) in the work buffers and return (status,
nfev, njev, niter).  :data:`SPLINE` is one spline step (the sweep inlined:
it is the hot path that ``make bench`` holds against C), :data:`COMPOSED`
a symmetric composition of spline steps (:func:`step.composed_step`),
:data:`RK4` and :data:`VERLET` the baselines (:mod:`splinestep._explicit`).
A new method is a new kind here and one branch of the step dispatch in
:func:`_drive`.  Spline steps by the fixed-point sweep under the constant
or the error controller (the commonest runs) take :func:`_sweep_drive`, the
same loop without the other branches and with its vectors apart: it
compiles in less than half the time (``benchmarks/compile_time.py``) and
runs within a few per cent of the separate loops of before the one driver
(``make bench``; the one driver took 15 to 30 % more); its results equal :func:`_drive`'s to the last bit
(``tests/test_driver.py``).  RK4 and Verlet on a grid likewise take
:func:`_explicit_drive`, without the spline steps' branches.  The price:
a type that runs on every path compiles three loops, 40 to 45 % more
CPU time in all than the one driver took.

Settings travel as named tuples (``step.Method`` with its ``Iteration``,
``controllers.Control`` with its ``Vectors``, :class:`Saving`), and the loop
returns one (:class:`Run`), so the compiled code has ten named arguments
instead of twenty positional ones.  The method, its iteration and the
controller are chosen at run time, so numba compiles (and caches) one loop
per family of paths (the sweep's, the explicit baselines', every other) and
per type of ``fun``, ``args``, ``jac`` and ``control``; a compiled ``fun``
whose ``args`` are numbers or float arrays, and every plain one, reach the
loop through adapters of one type (:mod:`splinestep._compile`), so a new
``fun`` compiles no loop, only its adapter; and no two compiled
loops share a name (loops specialised by closure constants share their
symbol names, which a process loading two of them from the disk cache, each
compiled by another process, may link to the wrong one).  The run-time
choice costs nothing measurable per evaluation (``make bench``).  The
records the sweep's loop reads at every step hold numbers only (a
composition's weights travel in ``Method`` to its step), and its vectors
live in one buffer: an array passed
into a helper inside the loop, or an array rebound inside it (the knot
arrays grow outside the stepping loop), costs reference counting at every
step.
"""

import os
from collections import namedtuple

import numpy as np
from numba import njit
from numba.extending import register_jitable

from . import _compile
from ._base import FD_STEP, evaluate, wrong_length
from ._explicit import rk4_step, verlet_step
from .controllers import (CONSTANT, ERROR, REVERSIBLE, first_size, judge, noise_weights,
                          propose)
from .result import HermiteSolution, SplineSolution, new_result, quintic_coefficients
from .status import (BAD_SHAPE, EVENT_FAILED, EXCEEDED, OK, OUT_OF_MEMORY, TERMINAL_EVENT,
                     message)
from .members import CUBIC, HERMITE, QUINTIC
from .step import (FIXED_POINT, SPLINE as SPLINE_SCHEME, Iteration, Method, State,
                   _value_status, composed_step, local_errors, newton_call, step_state,
                   sweep_step)

# The methods (steps) the driver takes: one step of a member of Newmark's
# family (the spline's by default), a composition of them, the baselines.
SPLINE, COMPOSED, RK4, VERLET = 0, 1, 2, 3
# The interpolant of a step, for t_eval and events (splinestep.members):
# the spline's cubic, the quintic Hermite through both knots' (y, y', y'')
# (a composition's, of its order, and the other members'), and the cubic
# Hermite of (y, y') and of (y', y'') (the baselines').


@njit(cache=True)
def dense_kind(kind, scheme):
    """The interpolant of the steps of method ``kind`` taking the member
    ``scheme`` (a :class:`splinestep.members.Scheme`)."""
    if kind == SPLINE:
        return scheme.interpolant
    return QUINTIC if kind == COMPOSED else HERMITE

Saving = namedtuple("Saving", "t_eval store events max_knots")
Saving.__doc__ = """What the driver keeps: values at ``t_eval`` (may be
empty), every knot when ``store`` (else the first only), at most
``max_knots`` of them (what the free memory holds, :func:`max_knots`: the
run stops with OUT_OF_MEMORY at that many, not with a MemoryError that
would lose it), and the key of the events' tracker
(:mod:`splinestep.events`), negative for none."""


def _read(path):
    """The text of ``path``, or '' where it cannot be read."""
    try:
        with open(path) as handle:
            return handle.read()
    except OSError:
        return ""


def _field_bytes(text, name):
    """The value in kB of the line ``name: value kB`` of ``text``, in bytes, or None."""
    for line in text.splitlines():
        if line.startswith(name + ":"):
            return int(line.split()[1]) * 1024
    return None


def _free_memory():
    """Bytes this process may still allocate, as far as the system tells:
    the smallest of the memory available (Linux's MemAvailable, else the
    free pages), what the address-space limit (``ulimit -v``) leaves above
    the process's size, and what its cgroup's limit leaves (cgroup v2);
    None if none is known."""
    limits = []
    available = _field_bytes(_read("/proc/meminfo"), "MemAvailable")
    if available is not None:
        limits.append(available)
    else:
        try:
            limits.append(os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
        except (AttributeError, ValueError, OSError):
            pass
    try:
        import resource
        soft = resource.getrlimit(resource.RLIMIT_AS)[0]
        if soft != resource.RLIM_INFINITY:
            limits.append(soft - (_field_bytes(_read("/proc/self/status"), "VmSize") or 0))
    except (ImportError, ValueError):
        pass
    maximum, current = _read("/sys/fs/cgroup/memory.max").strip(), \
        _read("/sys/fs/cgroup/memory.current").strip()
    if maximum.isdigit() and current.isdigit():
        limits.append(int(maximum) - int(current))
    return min(limits) if limits else None


def max_knots(m):
    """How many knots of ``m`` components (t, y, y', y'', rho) a fifth of
    the memory this process may still allocate holds (:func:`_free_memory`):
    the result copies them once more and its dense output
    (``dense_output=True``) takes about 4/3 of them again, and the rest is
    the caller's; unbounded where the system does not tell."""
    free = _free_memory()
    if free is None:
        return 2**62
    return max(2, (max(free, 0) // 5) // ((3 * m + 2) * 8))

Run = namedtuple("Run", "status last_status rate fail_step t_last t_fail nfev njev niter attempts "
                        "nstep n_rejected n_failed n_knots n_eval T K RHO E estimate "
                        "y_at_err yp_at_err y_end yp_end")
Run.__doc__ = """What the loop returns.  ``status`` (a code of
:mod:`splinestep.status`), ``last_status`` (the last step's own) and
``rate`` (its iteration's estimated contraction per iteration, when it
failed; NaN otherwise),
``fail_step`` (1-based index of the step that failed, 0 for the start),
``t_last`` (the last knot reached), ``t_fail`` (where the failed step was
headed), the counts, the knots ``T[:n_knots]`` with ``K`` (knot, (y, y',
y''), component) and ``RHO`` (the reversible control of the step ending at
each knot), the values at ``t_eval[:n_eval]`` in ``E`` ((y, y', y''),
time, component), and the local error estimate: ``estimate`` holds
(err_y, t_err, err_yp, y_scale, yp_scale, dt_at_err, dt_first, dt_last,
sum_y, sum_yp: the estimates summed over the steps),
with the state where err_y is largest and the final state."""

_E_Y, _E_T, _E_YP, _E_YSCALE, _E_YPSCALE, _E_DT, _E_FIRST, _E_LAST, _E_SUM_Y, _E_SUM_YP = range(10)


@register_jitable
def dense_state(kind, s, dt, p0, v0, a0, p1, v1, a1):
    """y, y', y'' at t + s on the step from t (p0, v0, a0) to t + dt (p1,
    v1, a1) from the step's interpolant ``kind``.  Numbers in compiled code,
    arrays (broadcast) in Python: :mod:`splinestep.events` locates zeros on
    the same polynomials the loop evaluates at ``t_eval``."""
    if kind == CUBIC:
        d = (a1 - a0) / (6.0 * dt)
        return (p0 + s * (v0 + s * (0.5 * a0 + s * d)), v0 + s * (a0 + 3.0 * s * d),
                a0 + 6.0 * s * d)
    if kind == QUINTIC:
        c3, c4, c5 = quintic_coefficients(dt, p0, v0, a0, p1, v1, a1)
        return (p0 + s * (v0 + s * (0.5 * a0 + s * (c3 + s * (c4 + s * c5)))),
                v0 + s * (a0 + s * (3.0 * c3 + s * (4.0 * c4 + s * 5.0 * c5))),
                a0 + s * (6.0 * c3 + s * (12.0 * c4 + s * 20.0 * c5)))
    # Cubic Hermite bases on u = s / dt, and the derivative of the first
    # two.  Its error is O(h^4): below Verlet's error, but of the order of
    # RK4's own, so RK4 is best measured at its own steps (t_eval on them).
    u = s / dt
    h00 = (1.0 + 2.0 * u) * (1.0 - u) ** 2
    h10 = u * (1.0 - u) ** 2 * dt
    h01 = u * u * (3.0 - 2.0 * u)
    h11 = u * u * (u - 1.0) * dt
    d00 = 6.0 * u * (u - 1.0) / dt
    d10 = (1.0 - u) * (1.0 - 3.0 * u)
    d11 = u * (3.0 * u - 2.0)
    return (h00 * p0 + h10 * v0 + h01 * p1 + h11 * v1,
            h00 * v0 + h10 * a0 + h01 * v1 + h11 * a1,
            d00 * (v0 - v1) + d10 * a0 + d11 * a1)


# Rows of the driver's vector buffer: the state at t, at t_new, the third
# derivative of the last step and of the new one, the state where the local
# error estimate is largest.
_Y, _YP, _YPP, _Y1, _YP1, _Z, _JERK, _JERK1, _Y_ERR, _YP_ERR = range(10)


@njit(cache=True)
def _grow(T, K, RHO, most):
    """The knot arrays with twice the rows (at most ``most``), the first
    ones copied."""
    n = T.shape[0]
    rows = min(2 * n, most)
    T2, K2, RHO2 = np.empty(rows), np.empty((rows,) + K.shape[1:]), np.empty(rows)
    T2[:n] = T
    K2[:n] = K
    RHO2[:n] = RHO
    return T2, K2, RHO2


@njit(cache=True, inline="always")
def _put(T, K, RHO, n, t, vec, rho):
    """Store the knot t with (y, y', y'') from ``vec`` at row ``n`` and the
    control variable of the step that ended there."""
    T[n] = t
    RHO[n] = rho
    for k in range(vec.shape[1]):
        K[n, 0, k] = vec[_Y, k]
        K[n, 1, k] = vec[_YP, k]
        K[n, 2, k] = vec[_YPP, k]


@njit(cache=True)
def _fill_eval(t_eval, n_eval, t, t_end, dt, kind, vec, E, direction):
    """Values at the requested times in (t, t_end] from the interpolant of
    the step of size dt from t held in ``vec`` (with dt = 0: at t itself,
    from the state); returns the new count."""
    m = vec.shape[1]
    while n_eval < t_eval.shape[0] and direction * (t_eval[n_eval] - t_end) <= 0.0:
        s = t_eval[n_eval] - t
        for k in range(m):
            if dt == 0.0:
                E[0, n_eval, k], E[1, n_eval, k], E[2, n_eval, k] = (
                    vec[_Y, k], vec[_YP, k], vec[_YPP, k])
            else:
                E[0, n_eval, k], E[1, n_eval, k], E[2, n_eval, k] = dense_state(
                    kind, s, dt, vec[_Y, k], vec[_YP, k], vec[_YPP, k], vec[_Y1, k],
                    vec[_YP1, k], vec[_Z, k])
        n_eval += 1
    return n_eval


@njit(cache=True, inline="always")
def _estimate(acc, y_new, yp_new, z, ypp, jerk1, jerk0, dt, dt_prev, t, have_jump, sc):
    """After the accepted spline step of size ``dt`` from the knot ``t`` to
    (``y_new``, ``yp_new``, ``z``), from y'' = ``ypp``: its third derivative
    into ``jerk1`` (``jerk0`` on the step before; one pass over the
    components for both) and the accumulators ``acc`` (a tuple indexed by _E_Y
    ... _E_SUM_YP) updated with the largest |y|, |y'| (the step's end
    included), the first and last steps, and (after the first step) the
    largest estimated local errors (see ``step.local_errors``) and their
    sums.  A tuple of numbers and one-dimensional vectors, not arrays to
    store into or rows of the loop's buffer: the loop keeps them in
    registers (stored at every step, they cost a sixth of the compiled
    sweep's time per evaluation in ``make bench``)."""
    e_y, e_t, e_yp, y_scale, yp_scale, e_dt, e_first, e_last, sum_y, sum_yp = acc
    if not have_jump:
        e_first = dt
    # The last step, or the one before when the last was cut short at tf.
    e_last = dt if not have_jump or abs(dt) >= abs(dt_prev) else dt_prev
    jump, y3 = 0.0, 0.0
    for k in range(y_new.shape[0]):
        jerk1[k] = (z[k] - ypp[k]) / dt
        y_scale = max(y_scale, abs(y_new[k]))
        yp_scale = max(yp_scale, abs(yp_new[k]))
        jump = max(jump, abs(jerk1[k] - jerk0[k]))
        y3 = max(y3, abs(jerk1[k]))
    if have_jump:
        # The estimates grow with the jump and the third derivative,
        # rounding included: those of the largest of each bound the
        # components' estimates (the largest of them for the spline, whose
        # estimates follow the jump alone).
        ey, eyp = local_errors(y3, jump, dt, dt_prev, sc)
        if ey > e_y:
            e_y, e_t, e_dt = ey, t, dt
        e_yp = max(e_yp, eyp)
        sum_y += ey
        sum_yp += eyp
    return e_y, e_t, e_yp, y_scale, yp_scale, e_dt, e_first, e_last, sum_y, sum_yp


@njit(cache=True, inline="always")
def _advance(vec, ev_out, at_event):
    """The end of the accepted step (or the terminal event's state) becomes
    the start of the next; so does its third derivative."""
    for k in range(vec.shape[1]):
        if at_event:
            vec[_Y1, k], vec[_YP1, k], vec[_Z, k] = ev_out[0, k], ev_out[1, k], ev_out[2, k]
        vec[_Y, k], vec[_YP, k], vec[_YPP, k] = vec[_Y1, k], vec[_YP1, k], vec[_Z, k]
        vec[_JERK, k] = vec[_JERK1, k]


@njit(cache=True, error_model="numpy")
def _taylor_jerk(fun, args, t0, tf, vec):
    """The third derivative at t0 from one difference of F along the Taylor
    line, into the row _JERK (the error controller's first step compares
    its interval's third derivative with it); returns OK, or BAD_SHAPE for
    a value of the wrong length (one evaluation either way).  The
    difference step is sqrt(eps) times the larger of 1 and the smaller of
    |t0| and the span, within the span: relative to the span alone, its
    truncation error, which the first step's estimate cannot go below,
    would grow with the span (a 300-orbit run could not take its first
    step); relative to |t0| alone, with |t0| (a start at t0 = 1e7 over a
    span of 10 could not either)."""
    m = vec.shape[1]
    direction = 1.0 if tf > t0 else -1.0
    span = abs(tf - t0)
    delta = min(FD_STEP * max(1.0, min(abs(t0), span)), span) * direction
    for k in range(m):
        vec[_Y1, k] = vec[_Y, k] + delta * vec[_YP, k] + 0.5 * delta * delta * vec[_YPP, k]
        vec[_YP1, k] = vec[_YP, k] + delta * vec[_YPP, k]
    g = evaluate(fun, args, t0 + delta, vec[_Y1], vec[_YP1])
    if wrong_length(g, m):
        return BAD_SHAPE
    for k in range(m):
        vec[_JERK, k] = (g[k] - vec[_YPP, k]) / delta
    return OK


@njit(cache=True)
def _start(ctrl, saving, t0, y0, yp0, ypp0):
    """The buffers of a run: ``vec`` (rows _Y ... _YP_ERR) holding the
    start, the knot arrays T, K (knot, (y, y', y''), component) and RHO
    (n + 1 rows for a constant grid, 256 doubled as needed otherwise, 1 when
    the knots are not stored) holding the first knot, E (3, len(t_eval), m)
    and ``acc``."""
    m = y0.shape[0]
    vec = np.zeros((10, m))
    vec[_Y], vec[_YP], vec[_YPP], vec[_Y_ERR], vec[_YP_ERR] = y0, yp0, ypp0, y0, yp0
    rows = 1
    if saving.store:
        rows = min(ctrl.n + 1 if ctrl.kind == CONSTANT else 256, saving.max_knots)
    T, K, RHO = np.empty(rows), np.empty((rows, 3, m)), np.zeros(rows)
    _put(T, K, RHO, 0, t0, vec, np.nan)
    y_scale, yp_scale = 0.0, 0.0
    for k in range(m):
        y_scale = max(y_scale, abs(y0[k]))
        yp_scale = max(yp_scale, abs(yp0[k]))
    acc = (0.0, t0, 0.0, y_scale, yp_scale, 0.0, 0.0, 0.0, 0.0, 0.0)
    return vec, T, K, RHO, np.empty((3, saving.t_eval.shape[0], m)), acc


@register_jitable
def _begin(fun, args, control, control_args, ctrl, t0, kind, vec, E, t_eval):
    """At the first knot, before the first step: the values at the requested
    times equal to t0, the third derivative there for the error
    controller's first step (one evaluation of F), the reversible control
    variable's start.  Returns (status, nfev, n_eval, rho).  Compiled
    within the driver (its branches typed with the driver's own types); a
    driver run as plain Python calls it as plain Python."""
    direction = 1.0 if ctrl.tf > t0 else -1.0
    status, nfev, rho = OK, 0, 0.0
    n_eval = _fill_eval(t_eval, 0, t0, t0, 0.0, kind, vec, E, direction)
    if ctrl.kind == ERROR:
        status, nfev = _taylor_jerk(fun, args, t0, ctrl.tf, vec), 1
    if ctrl.kind == REVERSIBLE:
        rho = ctrl.rho0 + 0.5 * direction * ctrl.eps * control(t0, vec[_Y], vec[_YP],
                                                               *control_args)
    return status, nfev, n_eval, rho


@njit(cache=True, inline="always")
def _within(status, y, bound):
    """``status``, or EXCEEDED when it is OK and some |y_k| exceeds
    ``bound`` (or is NaN) while the bound is finite."""
    if status == OK and bound < np.inf:
        for k in range(y.shape[0]):
            if not abs(y[k]) <= bound:
                return EXCEEDED
    return status


@njit(cache=True, inline="always")
def _jerk(z, ypp, dt, out):
    """The step's third derivative (z - y'') / dt into ``out``."""
    for k in range(z.shape[0]):
        out[k] = (z[k] - ypp[k]) / dt


def _drive(fun, args, jac, control, control_args, method, ctrl, vectors, saving, start):
    """Step from t0 to ctrl.tf (module docstring); ``start`` is (t0,
    y0, y'0, F there), F evaluated (and counted) by the front door,
    ``vectors`` the controller's arrays
    (:class:`splinestep.controllers.Vectors`).  Returns a :class:`Run`.
    The hot path (the sweep) keeps its vectors in one buffer and its
    settings in records of numbers: every array passed into the loop's
    helpers costs reference counting at every step."""
    # The step and the controller are chosen here, at run time: one compiled loop serves
    # every method, member and controller for a given type of fun.
    step_kind, control_kind, spline_steps = method.kind, ctrl.kind, method.kind <= COMPOSED
    sweep = step_kind == SPLINE and method.iteration.mode == FIXED_POINT
    (t0, y0, yp0, ypp0), (knots, atol, rtol) = start, vectors
    m, it, t_eval = y0.shape[0], method.iteration, saving.t_eval
    kind = dense_kind(method.kind, it.scheme)
    vec, T, K, RHO, E, acc = _start(ctrl, saving, t0, y0, yp0, ypp0)
    y, yp, ypp, y_new, yp_new, z = vec[_Y], vec[_YP], vec[_YPP], vec[_Y1], vec[_YP1], vec[_Z]
    kept = step_state(m, max(np.max(method.slots), np.max(method.inside_slots)) + 1,
                      spline_steps and it.mode != FIXED_POINT and not it.sparse)
    stage, ev_out, span = np.empty((4, m)), np.empty((3, m)), (min(t0, ctrl.tf), max(t0, ctrl.tf))
    work, velocity, jerk1, jerk0 = kept.work, stage[0], vec[_JERK1], vec[_JERK]
    # The records' numbers as plain locals: a field read from a record that
    # holds arrays is not free inside the loop.
    store, events = saving.store, saving.events
    s = State(y, yp, ypp, y_new, yp_new, z)
    sub = State(np.empty(m), np.empty(m), np.empty(m), y_new, yp_new, z)
    nfev, njev, niter, attempts, accepted, n_rejected, n_failed = 0, 0, 0, 0, 0, 0, 0
    direction = 1.0 if ctrl.tf > t0 else -1.0
    status, t, t_new, fail_step, last_status, n_eval = _value_status(ypp0, m), t0, t0, 0, OK, 0
    last_rate, dt_prev, done = np.nan, 0.0, False
    memory = (0.0, False)   # what the error controller keeps between steps (judge)
    n_knots, size, rho = 1, first_size(ctrl, atol, rtol, t0, y0, yp0), 0.0
    if status == OK:
        status, nfev, n_eval, rho = _begin(fun, args, control, control_args, ctrl, t0, kind,
                                           vec, E, t_eval)
    # The knot arrays grow outside the stepping loop: arrays rebound
    # inside it would cost reference counting at every step.
    while status == OK and not done:
        if store and n_knots == T.shape[0]:
            if t == ctrl.tf:   # the end reached with every row used: nothing more to store
                break
            if n_knots >= saving.max_knots:
                status, fail_step = OUT_OF_MEMORY, attempts + 1
                break
            T, K, RHO = _grow(T, K, RHO, saving.max_knots)
        while status == OK and not (store and n_knots == T.shape[0]):
            status, t_new, done = propose(ctrl, knots, t0, t, attempts, accepted, size, rho)
            if done or status != OK:
                fail_step = attempts + 1
                break
            dt = t_new - t
            if sweep:   # the hot path, inlined
                noise_weights(ctrl, vectors, it.scheme, dt, y, yp, work, memory[0])
                status, fe, je, ni, rate = sweep_step(fun, args, t_new, dt, y, yp, ypp, z,
                                                      y_new, yp_new, it, work)
            elif step_kind == SPLINE:
                status, fe, je, ni, rate = newton_call(fun, args, jac, t_new, dt, s, it, kept,
                                                       0)
            elif step_kind == COMPOSED:
                status, fe, je, ni, rate = composed_step(fun, args, jac, t, t_new, s, method,
                                                         kept, sub, span)
            elif step_kind == RK4:
                status, fe, je, ni, rate = rk4_step(fun, args, t, t_new, dt, y, yp, ypp, y_new,
                                                    yp_new, z, stage)
            else:
                status, fe, je, ni, rate = verlet_step(fun, args, t_new, dt, y, yp, ypp, y_new,
                                                       yp_new, z, velocity)
            nfev, njev, niter, attempts, last_status, last_rate = (
                nfev + fe, njev + je, niter + ni, attempts + 1, status, rate)
            if spline_steps and control_kind == ERROR:   # what judge reads (as _estimate)
                _jerk(z, ypp, dt, jerk1)
            if control_kind == ERROR:
                outcome = (status, rate if step_kind == SPLINE else np.nan)
                keep, size, memory = judge(ctrl, vectors, it.scheme, outcome, dt, dt_prev,
                                           (jerk1, jerk0), y, yp, y_new, yp_new, memory)
                if not keep:
                    n_rejected, n_failed = n_rejected + (status == OK), n_failed + (status != OK)
                    status = OK
                    continue
            status = _within(status, y_new, ctrl.y_max)
            if status != OK:
                fail_step = attempts
                break
            if spline_steps:
                largest = acc[_E_Y]
                acc = _estimate(acc, y_new, yp_new, z, ypp, jerk1, jerk0, dt, dt_prev, t,
                                accepted > 0, it.scheme)
                if acc[_E_Y] > largest:   # the state where the error of y is largest
                    vec[_Y_ERR], vec[_YP_ERR] = y, yp
            stop, t_end = 0, t_new
            if events >= 0.0:
                stop, t_ev = _compile.python_events(events, t, t_new, kind, vec[:6], ev_out)
                t_end = t_ev if stop == 1 else t_new
            if n_eval < t_eval.shape[0] and direction * (t_eval[n_eval] - t_end) <= 0.0:
                n_eval = _fill_eval(t_eval, n_eval, t, t_end, dt, kind, vec, E, direction)
            if stop == 2:
                status, fail_step = EVENT_FAILED, attempts
                break
            if stop == 1 and t_end == t:
                # A terminal zero at the step's start (where the last
                # step ended on it to rounding): the run ends at its
                # last knot, not at a second knot of the same time.
                status = TERMINAL_EVENT
                break
            _advance(vec, ev_out, stop == 1)
            t, dt_prev, accepted = t_end, dt, accepted + 1
            if store:
                _put(T, K, RHO, n_knots, t, vec, rho)
                n_knots += 1
            if stop == 1:
                status = TERMINAL_EVENT
            elif control_kind == REVERSIBLE:
                rho += direction * ctrl.eps * control(t, y, yp, *control_args)
    return Run(status, last_status, last_rate, -1 if status == OK else fail_step, t, t_new,
               nfev, njev, niter, attempts, accepted, n_rejected, n_failed, n_knots, n_eval, T,
               K, RHO, E, np.array(acc), vec[_Y_ERR].copy(), vec[_YP_ERR].copy(), y.copy(),
               yp.copy())


def _explicit_drive(fun, args, jac, control, control_args, method, ctrl, vectors, saving,
                    start):
    """:func:`_drive` for the explicit baselines (RK4, Verlet) on a given
    grid: the same helpers in the same order (the same numbers to the last
    bit, ``tests/test_driver.py``) without the spline steps' branches, so
    that a run of RK4 or Verlet compiles only its own step."""
    # The step and the controller are chosen here, at run time: one compiled
    # loop serves every method and controller for a given type of fun.
    step_kind, control_kind = method.kind, ctrl.kind
    t0, y0, yp0, ypp0 = start
    knots, atol, rtol = vectors.knots, vectors.atol, vectors.rtol
    m, t_eval = y0.shape[0], saving.t_eval
    kind = dense_kind(method.kind, method.iteration.scheme)
    vec, T, K, RHO, E, acc = _start(ctrl, saving, t0, y0, yp0, ypp0)
    y, yp, ypp, y_new, yp_new, z = vec[_Y], vec[_YP], vec[_YPP], vec[_Y1], vec[_YP1], vec[_Z]
    stage, ev_out = np.empty((4, m)), np.empty((3, m))
    velocity = stage[0]
    # The records' numbers as plain locals: a field read from a record that
    # holds arrays is not free inside the loop.
    store, events = saving.store, saving.events
    nfev, njev, niter, attempts, accepted, n_rejected, n_failed = 0, 0, 0, 0, 0, 0, 0
    direction = 1.0 if ctrl.tf > t0 else -1.0
    status, t, t_new, fail_step, last_status, n_eval = _value_status(ypp0, m), t0, t0, 0, OK, 0
    last_rate, dt_prev, done = np.nan, 0.0, False
    n_knots, size, rho = 1, first_size(ctrl, atol, rtol, t0, y0, yp0), 0.0
    if status == OK:
        status, nfev, n_eval, rho = _begin(fun, args, control, control_args, ctrl, t0, kind,
                                           vec, E, t_eval)
    # The knot arrays grow outside the stepping loop: arrays rebound
    # inside it would cost reference counting at every step.
    while status == OK and not done:
        if store and n_knots == T.shape[0]:
            if t == ctrl.tf:   # the end reached with every row used: nothing more to store
                break
            if n_knots >= saving.max_knots:
                status, fail_step = OUT_OF_MEMORY, attempts + 1
                break
            T, K, RHO = _grow(T, K, RHO, saving.max_knots)
        while status == OK and not (store and n_knots == T.shape[0]):
            status, t_new, done = propose(ctrl, knots, t0, t, attempts, accepted, size, rho)
            if done or status != OK:
                fail_step = attempts + 1
                break
            dt = t_new - t
            if step_kind == RK4:
                status, fe, je, ni, rate = rk4_step(fun, args, t, t_new, dt, y, yp, ypp, y_new,
                                                    yp_new, z, stage)
            else:
                status, fe, je, ni, rate = verlet_step(fun, args, t_new, dt, y, yp, ypp, y_new,
                                                       yp_new, z, velocity)
            nfev, njev, niter, attempts, last_status, last_rate = (
                nfev + fe, njev + je, niter + ni, attempts + 1, status, rate)
            if status != OK:
                fail_step = attempts
                break
            stop, t_end = 0, t_new
            if events >= 0.0:
                stop, t_ev = _compile.python_events(events, t, t_new, kind, vec[:6], ev_out)
                t_end = t_ev if stop == 1 else t_new
            if n_eval < t_eval.shape[0] and direction * (t_eval[n_eval] - t_end) <= 0.0:
                n_eval = _fill_eval(t_eval, n_eval, t, t_end, dt, kind, vec, E, direction)
            if stop == 2:
                status, fail_step = EVENT_FAILED, attempts
                break
            if stop == 1 and t_end == t:
                # A terminal zero at the step's start (where the last
                # step ended on it to rounding): the run ends at its
                # last knot, not at a second knot of the same time.
                status = TERMINAL_EVENT
                break
            _advance(vec, ev_out, stop == 1)
            t, dt_prev, accepted = t_end, dt, accepted + 1
            if store:
                _put(T, K, RHO, n_knots, t, vec, rho)
                n_knots += 1
            if stop == 1:
                status = TERMINAL_EVENT
    return Run(status, last_status, last_rate, -1 if status == OK else fail_step, t, t_new,
               nfev, njev, niter, attempts, accepted, n_rejected, n_failed, n_knots, n_eval, T,
               K, RHO, E, np.array(acc), vec[_Y_ERR].copy(), vec[_YP_ERR].copy(), y.copy(),
               yp.copy())




@njit(cache=True, inline="always")
def _to_rows(vec, y, yp, ypp, y_new, yp_new, z):
    """The sweep loop's own vectors into the rows of ``vec`` that the
    helpers shared with :func:`_drive` read (events, t_eval)."""
    for k in range(vec.shape[1]):
        vec[_Y, k], vec[_YP, k], vec[_YPP, k] = y[k], yp[k], ypp[k]
        vec[_Y1, k], vec[_YP1, k], vec[_Z, k] = y_new[k], yp_new[k], z[k]


def _sweep_drive(fun, args, jac, control, control_args, method, ctrl, vectors, saving, start):
    """:func:`_drive` for spline steps by the fixed-point sweep (order 2)
    under the constant or the error controller: the same helpers, in the
    same order, so the same numbers to the last bit
    (``tests/test_driver.py``), without the other steps' and the
    reversible controller's branches.  A run of this kind (the commonest)
    compiles this loop alone, and its state lives in vectors of its own,
    not in rows of one buffer: the compiler then knows that y and y_new do
    not overlap and keeps the sweep within a few per cent of the separate
    loops (``make bench``); they are copied into the buffer's rows only where a
    shared helper reads them (an event's search, a requested time)."""
    control_kind = ctrl.kind
    t0, y0, yp0, ypp0 = start
    knots, atol, rtol = vectors.knots, vectors.atol, vectors.rtol
    m, it, t_eval = y0.shape[0], method.iteration, saving.t_eval
    kind = dense_kind(method.kind, it.scheme)
    vec, T, K, RHO, E, acc = _start(ctrl, saving, t0, y0, yp0, ypp0)
    kept = step_state(m, 1, False)
    ev_out = np.empty((3, m))
    work = kept.work
    store, events = saving.store, saving.events
    nfev, njev, niter, attempts, accepted, n_rejected, n_failed = 0, 0, 0, 0, 0, 0, 0
    direction = 1.0 if ctrl.tf > t0 else -1.0
    status, t, t_new, fail_step, last_status, n_eval = _value_status(ypp0, m), t0, t0, 0, OK, 0
    last_rate, dt_prev, done = np.nan, 0.0, False
    memory = (0.0, False)   # what the error controller keeps between steps (judge)
    n_knots, size, rho = 1, first_size(ctrl, atol, rtol, t0, y0, yp0), 0.0
    if status == OK:
        status, nfev, n_eval, rho = _begin(fun, args, control, control_args, ctrl, t0, kind,
                                           vec, E, t_eval)
    y, yp, ypp, jerk0 = vec[_Y].copy(), vec[_YP].copy(), vec[_YPP].copy(), vec[_JERK].copy()
    y_new, yp_new, z, jerk1 = np.empty(m), np.empty(m), np.empty(m), np.empty(m)
    # The knot arrays grow outside the stepping loop: arrays rebound
    # inside it would cost reference counting at every step.
    while status == OK and not done:
        if store and n_knots == T.shape[0]:
            if t == ctrl.tf:   # the end reached with every row used: nothing more to store
                break
            if n_knots >= saving.max_knots:
                status, fail_step = OUT_OF_MEMORY, attempts + 1
                break
            T, K, RHO = _grow(T, K, RHO, saving.max_knots)
        while status == OK and not (store and n_knots == T.shape[0]):
            status, t_new, done = propose(ctrl, knots, t0, t, attempts, accepted, size, rho)
            if done or status != OK:
                fail_step = attempts + 1
                break
            dt = t_new - t
            noise_weights(ctrl, vectors, it.scheme, dt, y, yp, work, memory[0])
            status, fe, je, ni, rate = sweep_step(fun, args, t_new, dt, y, yp, ypp, z,
                                                  y_new, yp_new, it, work)
            nfev, njev, niter, attempts, last_status, last_rate = (
                nfev + fe, njev + je, niter + ni, attempts + 1, status, rate)
            if control_kind == ERROR:   # what judge reads (_estimate writes it too)
                _jerk(z, ypp, dt, jerk1)
                keep, size, memory = judge(ctrl, vectors, it.scheme, (status, rate), dt,
                                           dt_prev, (jerk1, jerk0), y, yp, y_new, yp_new, memory)
                if not keep:
                    n_rejected, n_failed = n_rejected + (status == OK), n_failed + (status != OK)
                    status = OK
                    continue
            status = _within(status, y_new, ctrl.y_max)
            if status != OK:
                fail_step = attempts
                break
            largest = acc[_E_Y]
            acc = _estimate(acc, y_new, yp_new, z, ypp, jerk1, jerk0, dt, dt_prev, t,
                            accepted > 0, it.scheme)
            if acc[_E_Y] > largest:   # the state where the error of y is largest
                vec[_Y_ERR], vec[_YP_ERR] = y, yp
            stop, t_end = 0, t_new
            if events >= 0.0:
                _to_rows(vec, y, yp, ypp, y_new, yp_new, z)
                stop, t_ev = _compile.python_events(events, t, t_new, kind, vec[:6], ev_out)
                t_end = t_ev if stop == 1 else t_new
            if n_eval < t_eval.shape[0] and direction * (t_eval[n_eval] - t_end) <= 0.0:
                _to_rows(vec, y, yp, ypp, y_new, yp_new, z)
                n_eval = _fill_eval(t_eval, n_eval, t, t_end, dt, kind, vec, E, direction)
            if stop == 2:
                status, fail_step = EVENT_FAILED, attempts
                break
            if stop == 1 and t_end == t:
                # A terminal zero at the step's start (where the last
                # step ended on it to rounding): the run ends at its
                # last knot, not at a second knot of the same time.
                status = TERMINAL_EVENT
                break
            # The end of the step (or the terminal event's state) becomes
            # the start of the next (as _advance does for _drive).
            for k in range(m):
                if stop == 1:
                    y_new[k], yp_new[k], z[k] = ev_out[0, k], ev_out[1, k], ev_out[2, k]
                y[k], yp[k], ypp[k], jerk0[k] = y_new[k], yp_new[k], z[k], jerk1[k]
            t, dt_prev, accepted = t_end, dt, accepted + 1
            if store:
                T[n_knots] = t
                RHO[n_knots] = rho
                for k in range(m):
                    K[n_knots, 0, k], K[n_knots, 1, k], K[n_knots, 2, k] = y[k], yp[k], ypp[k]
                n_knots += 1
            if stop == 1:
                status = TERMINAL_EVENT
    return Run(status, last_status, last_rate, -1 if status == OK else fail_step, t, t_new,
               nfev, njev, niter, attempts, accepted, n_rejected, n_failed, n_knots, n_eval, T,
               K, RHO, E, np.array(acc), vec[_Y_ERR].copy(), vec[_YP_ERR].copy(), y.copy(),
               yp.copy())


def method(kind, mode=FIXED_POINT, n_iter=1, until_converged=True, tol=1e-12, reuse=True,
           weights=(1.0,), slots=(0,), inside=(1.0,), inside_slots=(0,), scheme=SPLINE_SCHEME):
    """The :class:`splinestep.step.Method` record of a step (its Newton
    matrices built by the loop: see :func:`run`) of the member ``scheme``
    (a :class:`splinestep.members.Scheme`; the spline's by default)."""
    return Method(int(kind), Iteration(int(mode), int(n_iter), bool(until_converged), float(tol),
                                       bool(reuse), -1.0, False, scheme),
                  np.asarray(weights, dtype=float), np.asarray(slots, dtype=np.int64),
                  np.asarray(inside, dtype=float), np.asarray(inside_slots, dtype=np.int64))


def run(path, fun, jac, args, method, controller, output, start, control=None, matrices=None):
    """Run the compiled driver on the ``path`` ("compiled" or "plain") and
    return its :class:`Run` and the reason a plain fun's value was refused
    (None if none).  ``controller`` is (Control, Vectors) of
    :mod:`splinestep.controllers`, ``output`` (t_eval or None, store the knots?, a
    :class:`splinestep.events.Tracker` or None), ``start`` (t0, y0, yp0,
    F there), ``control`` the reversible controller's G(t, y, y'), if any,
    ``matrices`` the :class:`splinestep._linalg.Matrices` that builds
    Newton's matrices in Python (then ``jac`` is None), if any."""
    t_eval, store, events = output
    ctrl, vectors = controller
    t_eval = np.empty(0) if t_eval is None else t_eval
    start = (float(start[0]),) + tuple(start[1:])
    with _compile.loop_callables(path, fun, jac, args, start[1].shape[0]) as (
            loop_fun, loop_jac, loop_args, buffer), \
            _compile.scalar_callable(path, control, args) as (loop_control, control_args), \
            _compile.event_tracker(events) as key, \
            _compile.external_matrices(matrices) as matrices_key:
        if matrices is not None:
            method = method._replace(iteration=method.iteration._replace(
                matrices=matrices_key, sparse=bool(matrices.sparse)))
        saving = Saving(t_eval, bool(store), key, max_knots(start[1].shape[0]) if store else 1)
        drive = (_sweep_drive if method.kind == SPLINE and method.iteration.mode == FIXED_POINT
                 and ctrl.kind != REVERSIBLE else
                 _explicit_drive if method.kind >= RK4 and ctrl.kind == CONSTANT else _drive)
        loop = _compile.compiled_driver(drive, loop_fun, loop_jac, loop_args, loop_control,
                                        control_args, method, ctrl, vectors, saving, start)
        out = _compile.interruptible(
            lambda: loop(loop_fun, loop_args, loop_jac, loop_control, control_args, method,
                         ctrl, vectors, saving, start), buffer)
        reason = _compile.reason(loop_args, buffer)
    if events is not None and events.error is not None:
        raise events.error
    return out, reason


def result_of(out, t_eval, max_iter, ctrl, reason=None, *, path, order=2, method="spline",
              njev=0, dense_output=False, iteration=None, interpolant=None):
    """The one result builder of driver runs: the :class:`OdeResult` of the
    :class:`Run` ``out`` (knots, or values at ``t_eval``), with its message
    from :func:`splinestep.status.message`.  ``njev`` adds the front door's
    own calls of jac; the start's evaluation of fun is counted here;
    ``iteration`` is the spline steps' mode (FIXED_POINT or NEWTON),
    ``interpolant`` the member's (:mod:`splinestep.members`), which sets
    the class of ``sol`` (by ``order`` when None)."""
    n, m = out.n_knots, out.K.shape[2]
    if t_eval is None:
        t, (y, yp, ypp) = out.T[:n], (out.K[:n, j] for j in range(3))
    else:
        t, (y, yp, ypp) = t_eval[:out.n_eval], (out.E[j, :out.n_eval] for j in range(3))
    code = out.status
    status = 0 if code == OK else 1 if code == TERMINAL_EVENT else -1
    result = new_result(
        t=t.copy(), y=y.T.copy(), yp=yp.T.copy(), ypp=ypp.T.copy(), nfev=int(out.nfev) + 1,
        njev=int(out.njev) + njev, niter=int(out.niter), nstep=int(out.nstep),
        n_rejected=int(out.n_rejected), n_failed=int(out.n_failed),
        rho=out.RHO[1:n].copy() if ctrl.kind == REVERSIBLE else None,
        method=method, order=order, path=path, status=status,
        message=message(out, max_iter, m, ctrl.max_steps, reason,
                        sweep=iteration == FIXED_POINT, y_max=ctrl.y_max))
    if dense_output and n >= 2:
        knots = (out.T[:n], *(out.K[:n, j] for j in range(3)))
        quintic = order > 2 if interpolant is None else interpolant != CUBIC
        result.sol = (HermiteSolution if quintic else SplineSolution)(*knots)
    return result
