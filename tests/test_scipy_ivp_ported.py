"""Tests of scipy's ``solve_ivp`` (scipy/integrate/_ivp/tests/test_ivp.py)
ported to the second-order signature, run on every path of
:func:`splinestep.solve` that takes events: uniform steps (fixed-point and
Newton), given knots, the order-4 composition and adaptive knots.

scipy's harmonic oscillator u' = (u_2, -u_1) from (1, 0) is y'' = -y from
y = 1, y' = 0, with zeros of y at pi/2 + k pi.  Each test names the scipy
test it ports; where this package differs from scipy the test says so.
"""

import numpy as np
import pytest

import splinestep

PATHS = {
    "uniform": dict(h=0.01),
    "newton": dict(h=0.01, iteration="newton"),
    "knots": dict(knots=np.linspace(0.0, 20.0, 2001)),
    "order 4": dict(h=0.05, order=4),
    "adaptive": dict(rtol=1e-6, atol=1e-8),
}
SPAN = (0.0, 20.0)
# The events are located on the run's dense output (the cubic, or the quintic
# of a composition): errors of order h^2 y''''... at order 2, far less at 4.
EVENT_TOL = {"uniform": 1e-4, "newton": 1e-4, "knots": 1e-4, "order 4": 1e-5,
             "adaptive": 1e-6}


def oscillator(t, y, yp):
    return -y


def zero_of_y(t, y, yp):
    return y[0]


def event_copy(offset=0.0, **attributes):
    """A fresh event function y + offset with ``attributes`` (terminal, direction)."""
    def g(t, y, yp):
        return y[0] + offset
    for name, value in attributes.items():
        setattr(g, name, value)
    return g


@pytest.mark.parametrize("path", PATHS)
@pytest.mark.parametrize("n_events", [3, 4])
def test_event_terminal_integer(path, n_events):
    """scipy test_event_terminal_integer: terminal = n stops at the n-th zero."""
    res = splinestep.solve(oscillator, SPAN, 1.0, 0.0, events=event_copy(terminal=n_events),
                           **PATHS[path])
    assert res.status == 1
    assert len(res.t_events[0]) == len(res.y_events[0]) == n_events
    exact = np.pi / 2 + np.pi * np.arange(n_events)
    assert np.max(np.abs(res.t_events[0] - exact)) < EVENT_TOL[path]
    assert res.t[-1] == res.t_events[0][-1]


@pytest.mark.parametrize("path", PATHS)
def test_terminal_count_not_reached_lists_each_zero_once(path):
    """A terminal count larger than the zeros in the span: every zero once,
    status 0 (the fixed-step path listed each zero twice)."""
    res = splinestep.solve(oscillator, (0.0, 10.0), 1.0, 0.0, events=event_copy(terminal=4),
                           **{k: (v[v <= 10.0] if k == "knots" else v)
                              for k, v in PATHS[path].items()})
    assert res.status == 0
    exact = np.pi / 2 + np.pi * np.arange(3)
    assert res.t_events[0].size == 3
    assert np.max(np.abs(res.t_events[0] - exact)) < EVENT_TOL[path]


@pytest.mark.parametrize("path", PATHS)
def test_a_terminal_event_that_never_fires_leaves_the_others_once(path):
    """Two events, one terminal that never fires: the other's zeros once each."""
    never = event_copy(2.0, terminal=True)                 # |y| <= 1: no zero
    res = splinestep.solve(oscillator, SPAN, 1.0, 0.0, events=[zero_of_y, never],
                           **PATHS[path])
    assert res.status == 0
    exact = np.pi / 2 + np.pi * np.arange(6)      # the zeros in (0, 20)
    assert res.t_events[0].size == 6 and res.t_events[1].size == 0
    assert np.max(np.abs(res.t_events[0] - exact)) < EVENT_TOL[path]
    assert res.y_events[1].shape == (0,)          # scipy's shape for no zeros
    assert res.y_events[0].shape == (6, 1)


@pytest.mark.parametrize("path", PATHS)
def test_event_terminal_iv(path):
    """scipy test_event_terminal_iv: terminal None and 0 are not terminal;
    -1 and 3.5 are refused."""
    runs = [splinestep.solve(oscillator, SPAN, 1.0, 0.0, events=event_copy(terminal=t),
                             **PATHS[path]) for t in (None, 0, False)]
    for res in runs:
        assert res.status == 0 and res.t_events[0].size == 6
        np.testing.assert_array_equal(res.t_events[0], runs[0].t_events[0])
    for bad in (-1, 3.5):
        with pytest.raises(ValueError, match="terminal"):
            splinestep.solve(oscillator, SPAN, 1.0, 0.0, events=event_copy(terminal=bad),
                             **PATHS[path])


@pytest.mark.parametrize("path", PATHS)
def test_event_direction(path):
    """scipy test_events (directions): y falls through zero at pi/2 + 2k pi
    and rises at 3pi/2 + 2k pi; a direction that is not a finite number is
    refused (scipy would silently find nothing for nan)."""
    falls = splinestep.solve(oscillator, SPAN, 1.0, 0.0, events=event_copy(direction=-1),
                             **PATHS[path])
    rises = splinestep.solve(oscillator, SPAN, 1.0, 0.0, events=event_copy(direction=2.5),
                             **PATHS[path])
    assert np.max(np.abs(falls.t_events[0] - (np.pi / 2 + 2 * np.pi * np.arange(3)))) \
        < EVENT_TOL[path]
    assert np.max(np.abs(rises.t_events[0] - (3 * np.pi / 2 + 2 * np.pi * np.arange(3)))) \
        < EVENT_TOL[path]
    for bad in (np.nan, np.inf, "up"):
        with pytest.raises(ValueError, match="direction"):
            splinestep.solve(oscillator, SPAN, 1.0, 0.0, events=event_copy(direction=bad),
                             **PATHS[path])


@pytest.mark.parametrize("events", [1.0, [1.0], "g"])
def test_events_must_be_callables(events):
    with pytest.raises(ValueError, match="events"):
        splinestep.solve(oscillator, SPAN, 1.0, 0.0, h=0.01, events=events)


@pytest.mark.parametrize("path", PATHS)
def test_t_eval_early_event(path):
    """scipy test_t_eval_early_event: a terminal event before the first t_eval
    point returns no points, status 1, and the event time exactly."""
    def early(t, y, yp):
        return t - 7.0
    early.terminal = True
    kwargs = dict(PATHS[path])
    if "knots" in kwargs:
        kwargs["knots"] = np.linspace(5.0, 9.0, 401)
    res = splinestep.solve(oscillator, (5.0, 9.0), 1.0, 0.0, events=early,
                           t_eval=np.linspace(7.5, 9.0, 16), **kwargs)
    assert res.success and res.status == 1
    assert res.t.size == 0 and res.y.shape == (1, 0)
    assert res.t_events[0].size == 1
    assert res.t_events[0][0] == pytest.approx(7.0, abs=1e-12)


@pytest.mark.parametrize("setting, value", [
    ("iterations", True), ("max_iter", True), ("tol", True), ("rtol", True),
    ("y0", True), ("max_steps", True)])
def test_booleans_are_not_numbers(setting, value):
    """iterations=True, rtol=True, y0=True ...: a ValueError naming the
    argument, not a silent 1."""
    kwargs = dict(y0=1.0, h=None if setting in ("rtol",) else 0.1)
    kwargs[setting] = value
    y0 = kwargs.pop("y0")
    with pytest.raises(ValueError, match=setting):
        splinestep.solve(oscillator, (0.0, 1.0), y0, 0.0, **kwargs)


@pytest.mark.parametrize("solver", ["solve", "rk4", "verlet"])
@pytest.mark.parametrize("h", [1e-10, 1e-300, 1e-5 / 3])
def test_a_grid_of_more_than_max_steps_is_refused_before_it_starts(solver, h):
    """h = 1e-10 over (0, 1) would be 10^10 steps and h = 1e-300 overflows:
    both are a ValueError at once, as is a grid one step over max_steps."""
    kwargs = dict(max_steps=3 * 10**5 - 1) if h == 1e-5 / 3 else {}  # 300,000 steps
    with pytest.raises(ValueError, match="max_steps"):
        getattr(splinestep, solver)(oscillator, (0.0, 1.0), 1.0, 0.0, h, **kwargs)


def test_max_steps_bounds_given_knots_and_allows_exactly_max_steps():
    with pytest.raises(ValueError, match="max_steps"):
        splinestep.solve(oscillator, (0.0, 1.0), 1.0, 0.0, knots=np.linspace(0, 1, 12),
                         max_steps=10)
    res = splinestep.solve(oscillator, (0.0, 1.0), 1.0, 0.0, 0.1, max_steps=10)
    assert res.success and res.nstep == 10


def test_first_step_beyond_the_span_is_refused():
    """scipy test_first_step: 'first_step exceeds bounds'."""
    with pytest.raises(ValueError, match="first_step"):
        splinestep.solve(oscillator, (0.0, 1.0), 1.0, 0.0, first_step=2.0)
    res = splinestep.solve(oscillator, (0.0, 1.0), 1.0, 0.0, first_step=1.0)
    assert res.success


def test_rtol_below_what_float64_reaches_warns_and_is_raised():
    """scipy's common.validate_tol: rtol < 100 eps warns and becomes 100 eps;
    the run is then the same as one asked for 100 eps."""
    with pytest.warns(UserWarning, match="rtol"):
        low = splinestep.solve(oscillator, (0.0, 0.01), 1.0, 0.0, rtol=1e-16, atol=1e-12)
    floor = splinestep.solve(oscillator, (0.0, 0.01), 1.0, 0.0, rtol=100 * np.finfo(float).eps,
                             atol=1e-12)
    np.testing.assert_array_equal(low.y, floor.y)


def test_scalar_t_eval_is_refused():
    """scipy refuses a t_eval that is not 1-D; so does this package now."""
    with pytest.raises(ValueError, match="t_eval"):
        splinestep.solve(oscillator, (0.0, 1.0), 1.0, 0.0, 0.1, t_eval=0.5)


@pytest.mark.parametrize("solver", ["solve", "rk4", "verlet"])
def test_empty_state_and_empty_span_are_refused_by_name(solver):
    """scipy test_empty and test_zero_interval accept both; this package
    refuses them with a ValueError naming the argument (website/scipy.md)."""
    with pytest.raises(ValueError, match="y0"):
        getattr(splinestep, solver)(oscillator, (0.0, 1.0), [], [], 0.1)
    with pytest.raises(ValueError, match="t_span"):
        getattr(splinestep, solver)(oscillator, (4.0, 4.0), 1.0, 0.0, 0.1)


@pytest.mark.parametrize("order, degree", [(2, 3), (4, 5)])
def test_dense_output_derivative_order_is_checked(order, degree):
    """sol(t, nu) for nu in 0..degree (the cubic's, the quintic's); nu = 1.5
    was truncated to 1 and nu = 4 on the cubic returned zeros."""
    res = splinestep.solve(oscillator, (0.0, 1.0), 1.0, 0.0, 0.01, order=order,
                           dense_output=True)
    assert abs(res.sol(0.5, degree - 1)[0] - np.cos(0.5 + (degree - 1) * np.pi / 2)) < 1e-2
    for bad in (1.5, degree + 1, -1, True):
        with pytest.raises(ValueError, match="nu"):
            res.sol(0.5, bad)


def test_status_codes_are_one_table_of_distinct_codes():
    """One status table: every code means one thing on every path ('max_steps
    reached' is one code for the fixed, adaptive and reversible loops), and
    every code a step can fail with has its sentence."""
    from splinestep import status
    assert len(set(status.CODES.values())) == len(status.CODES)
    assert status.OK == 0
    step_codes = {v for k, v in status.CODES.items() if 0 < v < 10}
    assert step_codes == set(status.FAILURES)


def test_the_solver_imports_no_analysis_and_no_sympy():
    """The analysis (sympy theory, diagnostics, conjugacy, higher degrees,
    extrapolation) lives in splinestep.analysis, which the solver never
    imports: a fresh interpreter importing splinestep loads neither."""
    import subprocess
    import sys
    code = ("import sys, splinestep; "
            "print(any(m == 'sympy' or m.startswith('splinestep.analysis') for m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout.strip()
    assert out == "False"


# scipy's rational problem, u = t / (t + 10) with y1 = t u', has the same
# solution as the second-order equation y'' = -y' (1 - y) / 5,
# started from u(5) = 1/3, u'(5) = 2/45; scipy's error norm (the RMS over
# components of the error over atol + rtol |exact|) covers y and y'.
RTOL, ATOL = 1e-3, 1e-6
RATIONAL_PATHS = {
    "uniform": dict(h=0.1),
    "newton": dict(h=0.1, iteration="newton"),
    "knots": dict(knots=None),   # 41 uniform knots across the span, in its direction
    "order 4": dict(h=0.1, order=4),
    "adaptive": dict(rtol=RTOL, atol=ATOL),
}


def rational(t, y, yp):
    return -yp * (1.0 - y) / 5.0


def rational_exact(t):
    t = np.asarray(t, dtype=float)
    return t / (t + 10.0), 10.0 / (t + 10.0) ** 2


def scipy_error(t, y, yp):
    """scipy's compute_error on (y, y') at the times t."""
    u, up = rational_exact(t)
    e = np.vstack([(y - u) / (ATOL + RTOL * np.abs(u)), (yp - up) / (ATOL + RTOL * np.abs(up))])
    return np.linalg.norm(e, axis=0) / np.sqrt(e.shape[0])


def solve_rational(path, t_span, **extra):
    kwargs = dict(RATIONAL_PATHS[path])
    if "knots" in kwargs:
        kwargs["knots"] = np.linspace(*t_span, 41)
    return splinestep.solve(rational, t_span, 1.0 / 3.0, 2.0 / 45.0, **kwargs, **extra)


@pytest.mark.parametrize("t_span", [(5.0, 9.0), (5.0, 1.0)])
@pytest.mark.parametrize("path", RATIONAL_PATHS)
def test_integration(path, t_span):
    """scipy test_integration on the rational problem: the run starts at t0
    and ends at tf with status 0, no events, an error below 5 in scipy's
    norm at its knots and on its dense output (50 points and the middle),
    and a dense output that passes through the knots (backwards over
    [5, 1] the adaptive run's error ended at 5.55 in scipy's norm while
    rtol bounded each step's error; it bounds the global error now)."""
    res = solve_rational(path, t_span, dense_output=True)
    assert res.t[0] == t_span[0] and res.t[-1] == t_span[1]
    assert res.t_events is None and res.y_events is None
    assert res.success and res.status == 0
    assert np.all(scipy_error(res.t, res.y[0], res.yp[0]) < 5)
    for tc in (np.linspace(*t_span), np.array([sum(t_span) / 2])):
        assert np.all(scipy_error(tc, res.sol(tc)[0], res.sol(tc, 1)[0]) < 5)
    np.testing.assert_allclose(res.sol(res.t), res.y, rtol=1e-15, atol=1e-15)


@pytest.mark.parametrize("t_span", [(5.0, 9.0), (5.0, 1.0)])
def test_max_step(t_span):
    """scipy test_max_step: no step longer than max_step, the error within 5
    in scipy's norm; a negative max_step is refused, and so is one below
    the rounding floor of t_span (scipy runs and fails: its message says
    the step is below the spacing of the numbers; here no step is taken)."""
    res = solve_rational("adaptive", t_span, max_step=0.5, dense_output=True)
    assert res.t[0] == t_span[0] and res.t[-1] == t_span[1]
    assert np.all(np.abs(np.diff(res.t)) <= 0.5 + 1e-15)
    assert res.success and res.status == 0 and res.t_events is None
    assert np.all(scipy_error(res.t, res.y[0], res.yp[0]) < 5)
    tc = np.linspace(*t_span)
    assert np.all(scipy_error(tc, res.sol(tc)[0], res.sol(tc, 1)[0]) < 5)
    np.testing.assert_allclose(res.sol(res.t), res.y, rtol=1e-15, atol=1e-15)
    with pytest.raises(ValueError, match="max_step"):
        solve_rational("adaptive", t_span, max_step=-1)
    with pytest.raises(ValueError, match="max_step = 1e-20 is below the rounding floor"):
        solve_rational("adaptive", t_span, max_step=1e-20)


@pytest.mark.parametrize("t_span", [(5.0, 9.0), (5.0, 1.0)])
def test_first_step(t_span):
    """scipy test_first_step: the first step is first_step; -1 and a first
    step longer than the span are refused."""
    res = solve_rational("adaptive", t_span, max_step=0.5, first_step=0.1, dense_output=True)
    assert res.t[0] == t_span[0] and res.t[-1] == t_span[1]
    assert abs(res.t[1] - 5.0) == pytest.approx(0.1, rel=1e-12)
    assert res.success and res.status == 0
    assert np.all(scipy_error(res.t, res.y[0], res.yp[0]) < 5)
    np.testing.assert_allclose(res.sol(res.t), res.y, rtol=1e-15, atol=1e-15)
    for bad in (-1, 5):
        with pytest.raises(ValueError, match="first_step"):
            solve_rational("adaptive", t_span, first_step=bad)


# (t_span, t_eval, whether scipy's test checks the error there)
T_EVALS = [((5.0, 9.0), np.linspace(5.0, 9.0, 10), True),
           ((5.0, 1.0), np.linspace(5.0, 1.0, 10), True),
           ((5.0, 9.0), [5, 5.01, 7, 8, 8.01, 9], True),
           ((5.0, 1.0), [5, 4.99, 3, 1.5, 1.1, 1.01, 1], False),
           ((5.0, 9.0), [5.01, 7, 8, 8.01], True),
           ((5.0, 1.0), [4.99, 3, 1.5, 1.1, 1.01], False)]


@pytest.mark.parametrize("t_span, t_eval, checked", T_EVALS)
@pytest.mark.parametrize("path", RATIONAL_PATHS)
def test_t_eval(path, t_span, t_eval, checked):
    """scipy test_t_eval: the values come at exactly the requested times,
    within 5 in scipy's norm where scipy checks it, and do not change with
    dense_output (scipy test_t_eval_dense_output); times outside the span
    are refused."""
    res = solve_rational(path, t_span, t_eval=t_eval)
    np.testing.assert_array_equal(res.t, t_eval)
    assert res.success and res.status == 0 and res.t_events is None
    if checked:
        assert np.all(scipy_error(res.t, res.y[0], res.yp[0]) < 5)
    dense = solve_rational(path, t_span, t_eval=t_eval, dense_output=True)
    np.testing.assert_array_equal(dense.y, res.y)
    with pytest.raises(ValueError, match="t_eval"):
        solve_rational(path, (5.0, 9.0), t_eval=[4, 6])


@pytest.mark.parametrize("path", PATHS)
def test_duplicate_timestamps(path):
    """scipy test_duplicate_timestamps: an upward cannon hits the ground
    once, at 2 v0 / g, with the ground state as its event state, and its
    dense output is the parabola (the cubics and quintics hold a quadratic
    exactly).  scipy runs to tf = inf; this package needs a finite span."""
    g, v0 = 9.80665, 0.01

    def cannon(t, y, yp):
        return np.array([-g])

    def hit_ground(t, y, yp):
        return y[0]
    hit_ground.terminal = True
    hit_ground.direction = -1
    kwargs = dict(PATHS[path])
    if "knots" in kwargs:
        kwargs["knots"] = np.linspace(0.0, 1.0, 2001)
    if "h" in kwargs:
        kwargs["h"] = 0.05 * 0.001 / g
    res = splinestep.solve(cannon, (0.0, 1.0), 0.0, v0, events=hit_ground, dense_output=True,
                           **kwargs)
    assert res.success and res.status == 1
    assert np.all(np.diff(res.t) > 0)    # no knot twice (the zero falls on a knot)
    np.testing.assert_allclose(res.t_events, [[2 * v0 / g]], rtol=1e-9)
    np.testing.assert_allclose(res.y_events[0], [[0.0]], atol=1e-12)
    np.testing.assert_allclose(res.yp_events[0], [[-v0]], rtol=1e-9)
    # scipy evaluates sol at 0.01, past the event, by extrapolation; this
    # package's dense output refuses times outside the run (website/scipy.md).
    t = 0.001
    np.testing.assert_allclose([res.sol(t)[0], res.sol(t, 1)[0]],
                               [v0 * t - g * t ** 2 / 2, v0 - g * t], rtol=1e-9)
    with pytest.raises(ValueError, match="span"):
        res.sol(0.01)


@pytest.mark.parametrize("path", PATHS)
def test_integration_zero_rhs(path):
    """scipy test_integration_zero_rhs: F = 0 from y' = 0 keeps y at 1 to
    rounding (1e-15 relative) on every path."""
    kwargs = dict(PATHS[path])
    if "knots" in kwargs:
        kwargs["knots"] = np.linspace(0.0, 10.0, 101)
    res = splinestep.solve(lambda t, y, yp: np.zeros(3), (0.0, 10.0), np.ones(3), np.zeros(3),
                           **kwargs)
    assert res.success and res.status == 0
    np.testing.assert_allclose(res.y, 1.0, rtol=1e-15)


def test_args_single_value():
    """scipy test_args_single_value: args that is not a tuple is refused
    (scipy: a TypeError; here a ValueError naming args); args=(-1,) passes
    -1 to fun: y'' = -y from (1, 0) is cos t."""
    with pytest.raises(ValueError, match="args"):
        splinestep.solve(lambda t, y, yp, a: a * y, (0.0, 0.1), 1.0, 0.0, 0.001, args=-1)
    res = splinestep.solve(lambda t, y, yp, a: a * y, (0.0, 0.1), 1.0, 0.0, 0.001, args=(-1,))
    assert res.y[0, -1] == pytest.approx(np.cos(0.1), abs=1e-9)


@pytest.mark.parametrize("path", PATHS)
def test_args_reach_fun_and_events(path):
    """scipy test_args: args go to fun and to every event function: the
    zeros of cos t - a with a = 0.5 are pi/3 + 2 pi k and 5 pi/3 + 2 pi k."""
    def crossing(t, y, yp, a):
        return y[0] - a
    kwargs = dict(PATHS[path])
    if "knots" in kwargs:
        kwargs["knots"] = np.linspace(0.0, 10.0, 1001)
    res = splinestep.solve(lambda t, y, yp, a: -y, (0.0, 10.0), 1.0, 0.0, args=(0.5,),
                           events=crossing, **kwargs)
    exact = np.array([np.pi / 3, 5 * np.pi / 3, 7 * np.pi / 3])
    np.testing.assert_allclose(res.t_events[0], exact, atol=10 * EVENT_TOL[path])


@pytest.mark.parametrize("fill", [np.nan, np.inf])
@pytest.mark.parametrize("name", ["y0", "yp0"])
def test_initial_state_finiteness(fill, name):
    """scipy test_initial_state_finiteness (gh-17846), for y0 and y'0."""
    state = dict(y0=np.ones(3), yp0=np.zeros(3))
    state[name] = np.full(3, fill)
    with pytest.raises(ValueError, match=name):
        splinestep.solve(lambda t, y, yp: -y, (0.0, 10.0), state["y0"], state["yp0"], 0.1)


def only_inside(lo, hi):
    """A right-hand side that refuses any t outside [lo, hi], and counts."""
    def fun(t, y, yp):
        if not lo <= t <= hi:
            raise ValueError(f"fun evaluated at t = {t!r}, outside [{lo}, {hi}]")
        return 2.0 * y
    return fun


BOUND_PATHS = dict(PATHS, **{"order 6": dict(h=0.05, order=6)})


@pytest.mark.parametrize("path", BOUND_PATHS)
def test_tbound_respected_small_interval(path):
    """scipy test_tbound_respected_small_interval (gh-17341): over
    [0, 1e-4] fun is never called beyond 1e-4, by the run or by its checks;
    at orders 4 and 6 the first and last steps take compositions whose
    sub-steps stay inside the step."""
    small = 1e-4
    kwargs = dict(BOUND_PATHS[path])
    if "knots" in kwargs:
        kwargs["knots"] = np.linspace(0.0, small, 11)
    if "h" in kwargs:
        kwargs["h"] = small / 10
    res = splinestep.solve(only_inside(0.0, small), (0.0, small), 1.0, 0.0, **kwargs)
    assert res.success, res.message


@pytest.mark.parametrize("path", BOUND_PATHS)
def test_tbound_respected_oscillator(path):
    """scipy test_tbound_respected_oscillator (gh-9198): a constant
    right-hand side that refuses t > 205 over (100, 200), with dense
    output and a max_step of the whole span, backwards as well."""
    def constant(t, y, yp):
        if not 100.0 <= t <= 200.0:
            raise ValueError("called outside the interval")
        return np.array([1.73307544e-02, 6.49376470e-06, 0.0, 0.0])
    y0 = np.array([134.08298555, 138.82348612, 100.0, 0.0])
    for t_span in ((100.0, 200.0), (200.0, 100.0)):
        kwargs = dict(BOUND_PATHS[path])
        if "knots" in kwargs:
            kwargs["knots"] = np.linspace(*t_span, 101)
        if "h" in kwargs:
            kwargs["h"] = 1.0
        if path == "adaptive":
            kwargs["max_step"] = 100.0
        res = splinestep.solve(constant, t_span, y0, np.zeros(4), dense_output=True, **kwargs)
        assert res.success, res.message


@pytest.mark.parametrize("order", [4, 6])
@pytest.mark.parametrize("t_span, h", [((0.0, 1.0), 0.3), ((0.0, 1.0), 1.0), ((1.0, 0.0), 0.3),
                                       ((0.0, 10.0), 0.1)])
def test_compositions_call_fun_inside_the_span_only(order, t_span, h):
    """The triple jump's sub-steps reach t + 1.35 h and t - 0.35 h: with
    h = 0.3 over (0, 1), 22 of 103 calls were outside.  Every call is now
    inside, forwards and backwards."""
    lo, hi = min(t_span), max(t_span)
    times = []

    def fun(t, y, yp):
        times.append(t)
        return -y
    res = splinestep.solve(fun, t_span, 1.0, 0.0, h, order=order)
    assert res.success and times
    assert lo <= min(times) and max(times) <= hi


@pytest.mark.parametrize("order", [4, 6])
def test_end_steps_keep_the_order(order):
    """Runs of 8, 16 and 32 steps over (0, 1) on y'' = -y, whose first and
    last steps are taken by the inside composition (a quarter to a
    sixteenth of the run): the error at t = 1 falls at the order."""
    errors = [abs(splinestep.solve(oscillator, (0.0, 1.0), 1.0, 0.0, 1.0 / n, order=order).y[0, -1]
                  - np.cos(1.0)) for n in (8, 16, 32)]
    slopes = np.log2(np.array(errors[:-1]) / errors[1:])
    assert np.all(np.abs(slopes - order) < 0.3), slopes


def rational_event(which, direction=0.0, terminal=False):
    """scipy's event_rational_1 (y_0 - y_1^0.7), _2 (y_1^0.6 - y_0) and _3
    (t - 7.4) in the second-order variables, where y_0 = y and y_1 = t y'."""
    def g(t, y, yp):
        y1 = t * yp[0]
        return (y[0] - y1 ** 0.7, y1 ** 0.6 - y[0], t - 7.4)[which - 1]
    g.direction, g.terminal = direction, terminal
    return g


@pytest.mark.parametrize("path", RATIONAL_PATHS)
def test_events(path):
    """scipy test_events on the rational problem over [5, 8]: the zero of
    event 1 in (5.3, 5.7) and of event 2 in (7.3, 7.7), each once, with
    their directions (+1 keeps only event 1, -1 only event 2); a terminal
    event 3 at t = 7.4 ends the run (status 1) with the interpolant still
    within 5 in scipy's norm; each event's state a zero of it; the same
    zeros backwards over [8, 5], with the directions (as t decreases: -1
    keeps event 1, +1 event 2) and the terminal event.  scipy's y_events
    rows hold (y_0, y_1),
    here (y,) and yp_events (y',)."""
    start = {(5.0, 8.0): (1.0 / 3.0, 2.0 / 45.0), (8.0, 5.0): (4.0 / 9.0, 5.0 / 162.0)}

    def run(t_span, *events, **extra):
        kwargs = dict(RATIONAL_PATHS[path])
        if "knots" in kwargs:
            kwargs["knots"] = np.linspace(*t_span, 41)
        return splinestep.solve(rational, t_span, *start[t_span], events=list(events),
                                **kwargs, **extra)

    def zeros_are_events(res, events):
        for k, g in enumerate(events):
            for t, y, yp in zip(res.t_events[k], res.y_events[k], res.yp_events[k]):
                assert g(t, y, yp) == pytest.approx(0.0, abs=1e-8)

    for t_span in start:
        events = (rational_event(1), rational_event(2))
        res = run(t_span, *events)
        assert res.status == 0
        assert [len(t) for t in res.t_events] == [1, 1]
        assert 5.3 < res.t_events[0][0] < 5.7 and 7.3 < res.t_events[1][0] < 7.7
        assert res.y_events[0].shape == (1, 1) and res.y_events[1].shape == (1, 1)
        zeros_are_events(res, events)
    # Backwards, event 1 rises and event 2 falls as t decreases.
    for t_span, direction, counts in (((5.0, 8.0), 1.0, [1, 0]), ((5.0, 8.0), -1.0, [0, 1]),
                                      ((8.0, 5.0), -1.0, [1, 0]), ((8.0, 5.0), 1.0, [0, 1])):
        events = (rational_event(1, direction), rational_event(2, direction))
        res = run(t_span, *events)
        assert res.status == 0 and [len(t) for t in res.t_events] == counts
        assert [y.shape for y in res.y_events] == [(1, 1) if c else (0,) for c in counts]
        zeros_are_events(res, events)
    events = (rational_event(1), rational_event(2), rational_event(3, terminal=True))
    res = run((5.0, 8.0), *events, dense_output=True)
    assert res.status == 1 and [len(t) for t in res.t_events] == [1, 0, 1]
    assert 5.3 < res.t_events[0][0] < 5.7 and 7.3 < res.t_events[2][0] < 7.5
    assert res.t[-1] == pytest.approx(7.4, abs=1e-12)
    zeros_are_events(res, events)
    tc = np.linspace(res.t[0], res.t[-1])
    assert np.all(scipy_error(tc, res.sol(tc)[0], res.sol(tc, 1)[0]) < 5)
    u, up = rational_exact(res.t_events[0][0])
    np.testing.assert_allclose([res.y_events[0][0, 0], res.yp_events[0][0, 0]], [u, up],
                               rtol=RTOL, atol=ATOL)
    events = (rational_event(1), rational_event(2), rational_event(3, terminal=True))
    res = run((8.0, 5.0), *events, dense_output=True)
    assert res.status == 1 and [len(t) for t in res.t_events] == [0, 1, 1]
    assert 7.3 < res.t_events[1][0] < 7.7 and 7.3 < res.t_events[2][0] < 7.5
    zeros_are_events(res, events)
    tc = np.linspace(res.t[-1], res.t[0])
    assert np.all(scipy_error(tc, res.sol(tc)[0], res.sol(tc, 1)[0]) < 5)


# At rtol 0.1 the steps are about 0.3, and the step-too-large check says so
# (one step grows by 2.02 where e^t grows by 1.99); scipy's test is about rtol.
@pytest.mark.filterwarnings("ignore:The step is too large")
def test_array_rtol():
    """scipy test_array_rtol (gh-15482): rtol may be given per component;
    one below 100 eps warns and is raised, and the tighter rtol gives the
    smaller error.  y'' = y from (1, 1) is e^t, over (0, 1)."""
    def growth(t, y, yp):
        return y
    first = splinestep.solve(growth, (0.0, 1.0), [1.0, 1.0], [1.0, 1.0], rtol=[1e-1, 1e-1])
    with pytest.warns(UserWarning, match="At least one element of rtol"):
        second = splinestep.solve(growth, (0.0, 1.0), [1.0, 1.0], [1.0, 1.0],
                                  rtol=[1e-1, 1e-16])
    err1, err2 = (np.linalg.norm(r.y[:, -1] - np.e) for r in (first, second))
    assert err2 < err1
    with pytest.raises(ValueError, match="rtol"):
        splinestep.solve(growth, (0.0, 1.0), [1.0, 1.0], [1.0, 1.0], rtol=[1e-3, 1e-3, 1e-3])


@pytest.mark.parametrize("path", BOUND_PATHS)
def test_tbound_respected_larger_interval(path):
    """scipy test_tbound_respected_larger_interval (gh-8848): a radial
    equation in log r over (-17, 2) whose fun refuses t outside the span,
    with max_step 0.03, atol 1e-8, rtol 1e-5.  scipy's first-order system
    P' = r Q, Q' = -2 r ((-0.2 - V(r)) P + Q / r) with r = e^t is, with
    Q = P' / r, the second-order equation P'' = P' + r Q' =
    P' - 2 r^2 ((-0.2 - V) P + Q / r), from P = 1, P' = -11 e^-17."""
    def potential(r):
        return -11.0 / r + 10.0 * r / (0.05 + r * r)

    def radial(t, y, yp):
        if t < -17.0 or t > 2.0:
            raise ValueError("Function was evaluated outside interval")
        r = np.exp(t)
        q = yp[0] / r
        return np.array([yp[0] - 2.0 * r * r * ((-0.2 - potential(r)) * y[0] + q / r)])

    t0 = -17.0
    kwargs = dict(BOUND_PATHS[path])
    if "knots" in kwargs:
        kwargs["knots"] = np.linspace(t0, 2.0, 1001)
    if "h" in kwargs:
        kwargs["h"] = 0.03
    if path == "adaptive":
        kwargs = dict(max_step=0.03, atol=1e-8, rtol=1e-5)
    res = splinestep.solve(radial, (t0, 2.0), 1.0, -11.0 * np.exp(t0), **kwargs)
    assert res.success, res.message
