"""The one driver: every path (uniform, knots, adaptive, reversible, order
4, RK4, Verlet) has the same features, measured against exact solutions of
y'' = -y (y = cos t from (1, 0)) and against counters around fun."""

import numpy as np
import pytest

import splinestep
from splinestep import controllers, driver, problems


def oscillator(t, y, yp):
    return -y


def zero_control(t, y, yp):
    return 0.0


# Each path: a callable (fun, t_span, **kwargs) -> result.
PATHS = {
    "uniform": lambda f, span, **kw: splinestep.solve(f, span, 1.0, 0.0, 0.01, **kw),
    "knots": lambda f, span, **kw: splinestep.solve(
        f, span, 1.0, 0.0, knots=np.linspace(*span, round(abs(span[1] - span[0]) / 0.01) + 1),
        **kw),
    "newton": lambda f, span, **kw: splinestep.solve(f, span, 1.0, 0.0, 0.01,
                                                     iteration="newton", **kw),
    "order 4": lambda f, span, **kw: splinestep.solve(f, span, 1.0, 0.0, 0.05, order=4, **kw),
    "adaptive": lambda f, span, **kw: splinestep.solve(f, span, 1.0, 0.0, rtol=1e-6,
                                                       atol=1e-8, **kw),
    "reversible": lambda f, span, **kw: splinestep.solve_reversible(
        f, span, 1.0, 0.0, 0.01, zero_control, **kw),
    "rk4": lambda f, span, **kw: splinestep.rk4(f, span, 1.0, 0.0, 0.01, **kw),
    "verlet": lambda f, span, **kw: splinestep.verlet(f, span, 1.0, 0.0, 0.01, **kw),
}
EVENT_PATHS = list(PATHS)


def counted(f):
    calls = [0]

    def wrapped(t, y, yp):
        calls[0] += 1
        return f(t, y, yp)
    return wrapped, calls


@pytest.mark.parametrize("path", list(PATHS))
def test_every_path_returns_the_same_keys_and_counts_every_call(path):
    fun, calls = counted(oscillator)
    res = PATHS[path](fun, (0.0, 2.0))
    assert res.success and res.status == 0
    assert set(res) == set(splinestep.result.DEFAULTS)
    assert res.nfev == calls[0]
    bvp = splinestep.solve_bvp(oscillator, np.linspace(0, 1, 11), 0.0, 1.0)
    assert set(bvp) == set(res)


BACKWARD = {
    "uniform": lambda y0, yp0, t_eval: splinestep.solve(oscillator, (3.0, 0.0), y0, yp0, 0.01,
                                                        t_eval=t_eval),
    "adaptive": lambda y0, yp0, t_eval: splinestep.solve(oscillator, (3.0, 0.0), y0, yp0,
                                                         rtol=1e-7, atol=1e-9, t_eval=t_eval),
    "reversible": lambda y0, yp0, t_eval: splinestep.solve_reversible(
        oscillator, (3.0, 0.0), y0, yp0, 0.01, zero_control, t_eval=t_eval),
    "rk4": lambda y0, yp0, t_eval: splinestep.rk4(oscillator, (3.0, 0.0), y0, yp0, 0.01,
                                                  t_eval=t_eval),
    "verlet": lambda y0, yp0, t_eval: splinestep.verlet(oscillator, (3.0, 0.0), y0, yp0, 0.01,
                                                        t_eval=t_eval),
}


@pytest.mark.parametrize("path", list(BACKWARD))
def test_t_eval_backward(path):
    """Backward from t = 3 to 0 with values at t_eval: the error against
    cos t is the method's (h = 0.01: the spline's h^2 t / 24 ~ 1e-5, RK4's
    below 1e-9)."""
    t_eval = np.linspace(3.0, 0.0, 7)
    res = BACKWARD[path](np.cos(3.0), -np.sin(3.0), t_eval)
    assert res.success and np.array_equal(res.t, t_eval)
    error = np.max(np.abs(res.y[0] - np.cos(t_eval)))
    assert error < (1e-9 if path == "rk4" else 3e-5)


@pytest.mark.parametrize("path", EVENT_PATHS)
def test_a_terminal_event_stops_the_run_where_it_fires(path):
    """y = cos t crosses zero at pi/2: the run ends there, having computed
    nothing much past it (it would run to t = 100)."""
    def zero(t, y, yp):
        return y[0]
    zero.terminal = True
    fun, calls = counted(oscillator)
    res = PATHS[path](fun, (0.0, 100.0), events=zero)
    assert res.status == 1 and res.success
    assert res.t_events[0].shape == (1,)
    assert abs(res.t_events[0][0] - np.pi / 2) < 1e-4
    assert res.t[-1] == res.t_events[0][0]
    assert res.nfev == calls[0]
    if path == "adaptive":
        # The tolerance is spread over the whole span (0, 100), so the steps
        # to pi/2 are those of a 100-long run; none is taken past the event.
        assert res.nfev < 4 * (res.nstep + res.n_rejected + res.n_failed) + 50
    else:
        assert res.nfev < 2000   # a full run to t = 100 takes 2e4 or more


def test_events_of_a_composition_are_of_its_order():
    """Order 4: the zeros of cos t located on the quintic Hermite are as
    accurate as the run itself (|y'| = 1 there, so a time error is a value
    error), and halving h divides their error by about 2^4."""
    def zero(t, y, yp):
        return y[0]
    errors = []
    for h in (0.1, 0.05):
        res = splinestep.solve(oscillator, (0.0, 10.0), 1.0, 0.0, h, order=4, events=zero)
        exact = np.pi / 2 + np.pi * np.arange(3)
        errors.append(np.max(np.abs(res.t_events[0] - exact)))
        own = np.max(np.abs(res.y[0] - np.cos(res.t))[res.t < 9.0])
        assert errors[-1] < 2 * own
    assert abs(np.log2(errors[0] / errors[1]) - 4) < 0.2


def test_rk4_and_verlet_backward_keep_their_order():
    """Backward from t = 2 to 0.5: the errors there fall as h^4 and h^2
    (not at t = 0, where cos has no slope and a phase error does not show)."""
    for solver, order in ((splinestep.rk4, 4), (splinestep.verlet, 2)):
        errors = [abs(solver(oscillator, (2.0, 0.5), np.cos(2.0), -np.sin(2.0), h).y[0, -1]
                      - np.cos(0.5)) for h in (0.02, 0.01)]
        assert abs(np.log2(errors[0] / errors[1]) - order) < 0.1


def test_plain_fun_values_that_go_wrong_later_are_named():
    """Complex values, None and a wrong-shape jac after t0: each is a failed
    run whose message says what fun (or jac) returned, and where."""
    def complex_later(t, y, yp):
        return -y + (1j if t > 0.25 else 0)
    res = splinestep.solve(complex_later, (0, 1), 1.0, 0.0, 0.1)
    assert res.status == -1 and "complex values at t = 0.3" in res.message
    assert res.nstep == 2

    def none_later(t, y, yp):
        return None if t > 0.25 else -y
    res = splinestep.solve(none_later, (0, 1), 1.0, 0.0, 0.1)
    assert res.status == -1 and "fun returned None at t = 0.3" in res.message

    def jac_later(t, y, yp):
        return (-np.eye(1), np.zeros((1, 1))) if t < 0.25 else (np.eye(2), np.eye(2))
    res = splinestep.solve(oscillator, (0, 1), 1.0, 0.0, 0.1, iteration="newton",
                           jac=jac_later, reuse_jacobian=False)
    assert res.status == -1 and "jac did not return two arrays of shape (1, 1)" in res.message
    assert "singular" not in res.message


def test_global_sweep_checks_every_value_and_counts_every_call():
    """iteration="global": jac is checked at t0 as on every other path, and
    a value of fun or jac that goes wrong inside the trajectory Newton (here
    from the 41st call on, after the 11-knot guess sweep) is a failed run
    that names it and where, with every call counted."""
    two = lambda t, y, yp: np.array([-y[0] + 0.1 * y[1], -y[1]])
    for jac in (lambda t, y, yp: (np.eye(1), np.eye(1)), lambda t, y, yp: np.eye(2),
                lambda t, y, yp: (np.eye(2) * 1j, np.eye(2)), lambda t, y, yp: None):
        with pytest.raises(ValueError, match="jac must return a pair"):
            splinestep.solve(two, (0, 1), [1.0, 1.0], [0.0, 0.0], 0.1, iteration="global",
                             jac=jac)
    for bad, said in ((1e-3j, "fun returned complex values at t = 0.6"),
                      (None, "fun returned None at t = 0.6")):
        calls = []

        def later(t, y, yp):
            calls.append(t)
            return -y if len(calls) <= 40 else (None if bad is None else -y + bad)
        res = splinestep.solve(later, (0, 1), 1.0, 0.0, 0.1, iteration="global")
        assert res.status == -1 and said in res.message and "Newton iteration 1" in res.message
        assert res.nfev == len(calls) == 41
    jac_calls = []

    def jac_later(t, y, yp):
        jac_calls.append(t)
        return (-np.eye(1), np.zeros((1, 1))) if len(jac_calls) < 5 else (np.eye(2),) * 2
    res = splinestep.solve(oscillator, (0, 1), 1.0, 0.0, 0.1, iteration="global", jac=jac_later)
    assert res.status == -1 and "jac did not return two arrays of shape (1, 1)" in res.message
    assert res.njev == len(jac_calls) == 5


def test_max_steps_stops_every_variable_controller():
    for res in (splinestep.solve(oscillator, (0, 10), 1.0, 0.0, rtol=1e-10, max_steps=50),
                splinestep.solve_reversible(oscillator, (0, 10), 1.0, 0.0, 0.01, zero_control,
                                            max_steps=50)):
        assert res.status == -1 and "max_steps = 50" in res.message and res.nstep <= 50


def test_the_driver_settings_are_records():
    """The compiled loop takes a few named records, not twenty positional
    numbers: its signature is fun, args, jac, control, control_args, the
    step, the controller and its arrays, what to save, and the start."""
    ctrl, vectors = controllers.constant(1.0, 0.5, 2, np.empty(0), 10)
    assert ctrl.kind == controllers.CONSTANT and ctrl.max_steps == 10
    assert all(np.isscalar(value) for value in ctrl)   # numbers only: no refcounting
    step = driver.method(driver.RK4)
    assert step.kind == driver.RK4 and step.weights.shape == (1,)
    assert all(np.isscalar(v) for value in step.iteration      # the member's scheme too
               for v in (value if isinstance(value, tuple) else (value,)))
    assert driver._drive.__code__.co_argcount == 10


def test_unknown_options_are_named():
    with pytest.raises(ValueError, match="rtoll"):
        splinestep.solve(oscillator, (0, 1), 1.0, 0.0, rtoll=1e-3)
    with pytest.raises(ValueError, match="h_max"):
        splinestep.solve_reversible(oscillator, (0, 1), 1.0, 0.0, 0.1, zero_control, h_max=1)


def test_a_raising_event_is_raised():
    def bad(t, y, yp):
        if t > 0.5:
            raise RuntimeError("event broke")
        return 1.0
    with pytest.raises(RuntimeError, match="event broke"):
        splinestep.solve(oscillator, (0, 1), 1.0, 0.0, 0.1, events=bad)


def test_problems_still_solve_on_every_method():
    problem = problems.cannonball(0.6)
    for method in ("spline", "rk4"):
        assert problem.solve(method).success


def test_solve_bvp_counts_every_call():
    fun, calls = counted(oscillator)
    res = splinestep.solve_bvp(fun, np.linspace(0, 1, 11), 0.0, 1.0)
    assert res.success and res.nfev == calls[0]


def test_a_recovered_refusal_is_not_the_reason_of_a_later_failure():
    """An adaptive run that meets None once, retries smaller and goes on,
    then fails on NaN values, says NaN (not finite), not None."""
    seen = []

    def flaky(t, y, yp):
        if 1.0 < t < 1.2 and not seen:
            seen.append(t)
            return None
        return -y if t < 2.0 else np.full(1, np.nan)
    res = splinestep.solve(flaky, (0, 5), 1.0, 0.0, rtol=1e-6)
    assert seen and res.status == -1
    assert "None" not in res.message and "not finite" in res.message


def test_the_check_survives_a_jac_that_fails_at_the_end():
    """A jac that returns None after t = 0.5 is not used by the steps of a
    run with a kept matrix (built at t0); the step-size check after the run
    must not raise on it."""
    def jac(t, y, yp):
        return (-np.eye(1), np.zeros((1, 1))) if t < 0.5 else None
    res = splinestep.solve(oscillator, (0, 1), 1.0, 0.0, 0.01, iteration="newton", jac=jac)
    assert res.success


def test_the_size_in_the_warning_includes_the_last_knot():
    """y'' = y at h = 2 (Newton): the message's max |y| is the largest |y|
    at the knots, the last included (it grows at every step)."""
    with pytest.warns(UserWarning):
        res = splinestep.solve(lambda t, y, yp: y, (0, 30), 1.0, 0.0, 2.0, iteration="newton")
    assert f"max |y| = {np.max(np.abs(res.y)):.3g}" in res.message


def test_a_control_that_is_not_finite_is_named():
    res = splinestep.solve_reversible(oscillator, (0, 1), 1.0, 0.0, 0.1,
                                      lambda t, y, yp: np.nan if t > 0.3 else 0.0)
    assert res.status == -1 and "not finite" in res.message


@pytest.mark.parametrize("name", ["tol", "max_iter"])
def test_solve_bvp_refuses_booleans(name):
    with pytest.raises(ValueError, match=name):
        splinestep.solve_bvp(oscillator, np.linspace(0, 1, 11), 0.0, 1.0, **{name: True})


def test_the_step_size_warning_points_at_the_caller():
    with pytest.warns(UserWarning) as caught:
        splinestep.solve(oscillator, (0, 30), 1.0, 0.0, 2.5, iteration="newton")
    with pytest.warns(UserWarning) as caught_reversible:
        splinestep.solve_reversible(oscillator, (0, 30), 1.0, 0.0, 2.5, zero_control,
                                    iteration="newton")
    assert caught[0].filename == caught_reversible[0].filename == __file__


def _events_of(problem):
    def crossing(t, y, yp, *args):
        return y[1] - 0.5
    crossing.terminal = False
    return [crossing]


@pytest.mark.parametrize("case", ["uniform", "adaptive", "t_eval", "events", "knots"])
def test_the_sweep_loop_is_the_driver_to_the_last_bit(monkeypatch, case):
    """Runs of the fixed-point sweep take their own compiled loop
    (driver._sweep_drive, the driver without the other steps' branches, its
    vectors apart): every number of its result equals the whole driver's
    (driver._drive) bit for bit, on a uniform and an adaptive run, with
    t_eval, with events and on given knots."""
    p = problems.cannonball(0.5)
    span = (0.0, 3.0)
    options = {"uniform": dict(h=0.01), "adaptive": dict(rtol=1e-6, atol=1e-9),
               "t_eval": dict(h=0.01, t_eval=np.linspace(0.0, 3.0, 7)),
               "events": dict(h=0.01, events=_events_of(p)),
               "knots": dict(knots=3.0 * np.linspace(0.0, 1.0, 301) ** 1.5)}[case]

    def run():
        h = options.pop("h", None) if "h" in options else None
        res = splinestep.solve(p.fun, span, p.y0, p.yp0, h, args=p.args, **options)
        if h is not None:
            options["h"] = h
        return res

    own = run()
    monkeypatch.setattr(driver, "_sweep_drive", driver._drive)
    whole = run()
    assert own.success and whole.success
    for key in ("t", "y", "yp", "ypp", "nfev", "nstep", "niter", "n_rejected", "local_error"):
        assert np.array_equal(np.asarray(own[key]), np.asarray(whole[key]), equal_nan=True), key
    if case == "events":
        assert own.t_events[0].size > 0
        assert np.array_equal(own.t_events[0], whole.t_events[0])
        assert np.array_equal(own.y_events[0], whole.y_events[0])


@pytest.mark.parametrize("solver", ["rk4", "verlet"])
@pytest.mark.parametrize("case", ["uniform", "t_eval", "events"])
def test_the_explicit_loop_is_the_driver_to_the_last_bit(monkeypatch, solver, case):
    """RK4 and Verlet take their own compiled loop (driver._explicit_drive,
    the driver without the spline steps' branches): every number of the
    result equals the whole driver's bit for bit."""
    p = problems.cannonball(0.5)
    options = {"uniform": {}, "t_eval": dict(t_eval=np.linspace(0.0, 3.0, 7)),
               "events": dict(events=_events_of(p))}[case]

    def run():
        return getattr(splinestep, solver)(p.fun, (0.0, 3.0), p.y0, p.yp0, 0.01, args=p.args,
                                           **options)

    own = run()
    monkeypatch.setattr(driver, "_explicit_drive", driver._drive)
    whole = run()
    assert own.success and whole.success
    for key in ("t", "y", "yp", "ypp", "nfev", "nstep"):
        assert np.array_equal(np.asarray(own[key]), np.asarray(whole[key])), key
    if case == "events":
        assert own.t_events[0].size > 0
        assert np.array_equal(own.y_events[0], whole.y_events[0])
