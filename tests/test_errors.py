"""Bad input is refused with the argument's name; a run that fails part way
stops, says where and why, and returns only the steps it completed."""

import warnings

import numpy as np
import pytest
from numba import njit

import splinestep
from splinestep import problems

f = lambda t, y, yp: -y


@pytest.mark.parametrize("kwargs, name", [
    (dict(t_span=(1, 1)), "t_span"),
    (dict(t_span=(0, np.inf)), "t_span"),
    (dict(t_span=(0, np.nan)), "t_span"),
    (dict(t_span=5), "t_span"),
    (dict(h=0.0), "h"),
    (dict(h=-0.1), "h"),
    (dict(h=np.nan), "h"),
    (dict(h=np.inf), "h"),
    (dict(h=None, knots=[0, 0.5, 0.5, 1]), "knots"),
    (dict(h=None, knots=[0, 0.7, 0.5, 1]), "knots"),
    (dict(h=None, knots=[0, 0.5, 0.9]), "knots"),
    (dict(h=None, knots=[0.1, 0.5, 1.0]), "knots"),
    (dict(h=0.1, knots=[0, 1]), "knots"),
    (dict(h=None, rtol=0.0), "rtol"),
    (dict(h=None, atol=[1e-6, 1e-6]), "atol"),
    (dict(h=None, atol=-1.0), "atol"),
    (dict(h=None, first_step=0.0), "first_step"),
    (dict(h=None, max_step=float("nan")), "max_step"),
    (dict(h=None, max_steps=0), "max_steps"),
    (dict(h=None, order=4), "order"),
    (dict(order=3), "order"),
    (dict(reuse_jacobian="yes"), "reuse_jacobian"),
    (dict(h=None, iteration="global"), "global"),
    (dict(y0=[1.0, 2.0]), "y0 and yp0"),
    (dict(y0=np.nan), "y0"),
    (dict(yp0=np.inf), "yp0"),
    (dict(iteration="secant"), "iteration"),
    (dict(tol=0.0), "tol"),
    (dict(tol=-1e-8), "tol"),
    (dict(max_iter=0), "max_iter"),
    (dict(iterations=0), "iterations"),
    (dict(t_eval=[0.5, 0.2]), "t_eval"),
    (dict(t_eval=[0.5, 2.0]), "t_eval"),
    (dict(args=[1.0]), "args"),
])
def test_solve_rejects_bad_input(kwargs, name):
    call = dict(fun=f, t_span=(0, 1), y0=1.0, yp0=0.0, h=0.1)
    call.update(kwargs)
    with pytest.raises(ValueError, match=name):
        splinestep.solve(call.pop("fun"), call.pop("t_span"), call.pop("y0"),
                         call.pop("yp0"), **call)


@pytest.mark.parametrize("kwargs, name", [
    (dict(t_span=(1, 1)), "t_span"), (dict(h=0.0), "h"), (dict(h=-3.0), "h"),
    (dict(yp0=[0.0, 1.0]), "y0 and yp0"), (dict(t_eval=[-1.0]), "t_eval")])
def test_rk4_rejects_bad_input(kwargs, name):
    call = dict(t_span=(0, 1), y0=1.0, yp0=0.0, h=0.1)
    call.update(kwargs)
    with pytest.raises(ValueError, match=name):
        splinestep.rk4(f, call.pop("t_span"), call.pop("y0"), call.pop("yp0"), **call)


def blows_up(t, y, yp):
    """A right-hand side that fails (NaN) from t = 0.55 on."""
    return -y if t < 0.55 else np.full_like(y, np.nan)


blows_up_compiled = njit(blows_up)


@pytest.mark.parametrize("solver", ["spline", "rk4"])
@pytest.mark.parametrize("fun", [blows_up, blows_up_compiled], ids=["python", "compiled"])
def test_failure_part_way_returns_completed_steps(solver, fun):
    if solver == "spline":
        res = splinestep.solve(fun, (0, 1), 1.0, 0.0, 0.1)
    else:
        res = splinestep.rk4(fun, (0, 1), 1.0, 0.0, 0.1)
    assert res.status == -1 and not res.success
    assert "not finite" in res.message and "Step 6 " in res.message
    assert "t = 0.5" in res.message and "t = 0.6" in res.message
    assert res.nstep == 5
    assert np.allclose(res.t, np.arange(6) * 0.1, atol=1e-15)
    assert np.all(np.isfinite(res.y)) and np.all(np.isfinite(res.ypp))


def test_failure_part_way_with_t_eval_stops_reporting_at_last_knot():
    res = splinestep.solve(blows_up, (0, 1), 1.0, 0.0, 0.1, t_eval=np.linspace(0, 1, 21),
                           dense_output=True)
    assert res.status == -1
    assert res.t[-1] <= 0.5 + 1e-15 and res.t.size == 11
    assert np.all(np.isfinite(res.y))
    assert res.sol(0.45).shape == (1,)


def test_wrong_shape_later_in_the_run_is_a_failure_not_a_crash():
    def changes_shape(t, y, yp):
        return -y if t < 0.35 else np.zeros(3)
    res = splinestep.solve(changes_shape, (0, 1), [1.0, 2.0], [0.0, 0.0], 0.1)
    assert res.status == -1 and "Step 4 " in res.message
    assert "shape (3,) at t = 0.4 (expected shape (2,))" in res.message
    assert res.nstep == 3


@pytest.mark.parametrize("x", [2.5, 2.584])
def test_diverging_sweep_that_overflows_is_a_failure(x):
    """Past w h = sqrt(6) the sweep's iterates grow by (w h)^2/6 per
    iteration; given enough iterations they overflow.  An infinite iterate
    must end the step as a failure, not pass the relative convergence test
    (|change| <= tol * inf) as a converged step of size 1e308."""
    problem = problems.harmonic(1.0, t_span=(0.0, x), h=x)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = problem.solve(max_iter=10**6)
    assert res.status == -1 and "diverged" in res.message
    assert res.niter < 10**5  # ended at the overflow, not at max_iter
    assert np.all(np.isfinite(res.y)) and res.t.tolist() == [0.0]


def test_nonconvergence_names_step_and_time():
    # w h = 3 > sqrt(6): the sweep multiplies the error by -1.5 each time.
    res = splinestep.solve(lambda t, y, yp: -900.0 * y, (0, 1), 1.0, 0.0, 0.1, max_iter=30)
    assert res.status == -1
    assert res.message.startswith("Step 1 (from t = 0 to t = 0.1) failed")
    assert "diverged (its change grew in two iterations in a row)" in res.message
    assert res.niter <= 4   # given up at once, not after max_iter = 30 sweeps
    assert "smaller h" in res.message and 'iteration="newton"' in res.message
    assert res.nstep == 0 and res.t.tolist() == [0.0]


@pytest.mark.parametrize("call", [
    lambda: splinestep.solve(f, (False, True), 1.0, 0.0, 0.1),
    lambda: splinestep.rk4(f, (0, np.True_), 1.0, 0.0, 0.1),
    lambda: splinestep.solve(f, (0, 1), 1.0, 0.0, 0.1, order=4.0),
], ids=["t_span", "t_span rk4", "order"])
def test_booleans_and_floats_are_not_counts_or_times(call):
    with pytest.raises(ValueError, match="t_span must be a pair of numbers|order must be one"):
        call()


def test_compiled_fun_that_may_return_none_is_refused_at_the_start():
    @njit
    def sometimes_none(t, y, yp):
        if t > 0.55:
            return None
        return -y
    for solver in (splinestep.solve, splinestep.rk4):
        with pytest.raises(ValueError, match="fun is compiled with a value that may be None"):
            solver(sometimes_none, (0, 1), 1.0, 0.0, 0.1)


def forcing(t, y, yp, on):
    return -y + on


def test_a_jump_of_f_ends_an_adaptive_run_with_the_remedy_that_works():
    """y'' = -y + H(t - 1/2), y(0) = 1, y'(0) = 0: the error-controlled run
    stops at the jump and says what to do; done so (two runs, each with F
    on its side of the jump), y(1) agrees with the exact
    1 + (cos 1/2 - 1) cos 1/2 - sin^2 1/2 within the tolerance."""
    jumps = lambda t, y, yp: -y + (1.0 if t > 0.5 else 0.0)
    res = splinestep.solve(jumps, (0, 1), 1.0, 0.0, rtol=1e-6)
    assert res.status == -1 and "at t = 0.5" in res.message
    assert "end t_span at the jump" in res.message
    before = splinestep.solve(forcing, (0, 0.5), 1.0, 0.0, rtol=1e-6, args=(0.0,))
    after = splinestep.solve(forcing, (0.5, 1.0), before.y[:, -1], before.yp[:, -1],
                             rtol=1e-6, args=(1.0,))
    exact = 1 + (np.cos(0.5) - 1) * np.cos(0.5) - np.sin(0.5) ** 2
    assert before.success and after.success
    assert abs(after.y[0, -1] - exact) < 1e-6


def test_global_sweep_reports_its_solution_not_its_guess():
    """iteration="global" does not pass on the guess's step-size warning
    (one sweep per step on y'' = -100 y - 20 y' at h = 0.05 is off; the
    solution, the stepwise Newton's, is not), and a Newton iteration that
    fails returns the initial state only, with a hint that applies."""
    damped = lambda t, y, yp: -100 * y - 20 * yp
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        whole = splinestep.solve(damped, (0, 1), 1.0, 0.0, 0.05, iteration="global")
        stepwise = splinestep.solve(damped, (0, 1), 1.0, 0.0, 0.05, iteration="newton")
    assert np.max(np.abs(whole.y - stepwise.y)) < 1e-12
    res = splinestep.solve(lambda t, y, yp: -100 * y ** 3, (0, 1), 1.0, 0.0, 0.5,
                           iteration="global", dense_output=True)
    assert res.status == -1 and "smaller h" in res.message and "y_guess" not in res.message
    assert res.message.count("smaller h") == 1
    assert res.t.tolist() == [0.0] and res.y.tolist() == [[1.0]] and res.sol is None


def test_global_sweep_whose_starting_sweep_fails_keeps_nothing_of_it():
    """y'' = -100 y' - y at h = 0.1: one explicit sweep per step overflows
    by t = 27 where the method itself (stepwise Newton) decays; the global
    run returns its initial state, not the overflowing guess."""
    stiff = lambda t, y, yp: -100.0 * yp - y
    jac = lambda t, y, yp: (-np.eye(1), -100.0 * np.eye(1))
    with pytest.warns(UserWarning, match="The step is too large"):   # its first steps
        newton = splinestep.solve(stiff, (0, 50), 1.0, 0.0, 0.1, iteration="newton", jac=jac)
    assert newton.success and 0 < newton.y[0, -1] < 1
    with np.errstate(over="ignore", invalid="ignore"):   # the guess overflows
        res = splinestep.solve(stiff, (0, 50), 1.0, 0.0, 0.1, iteration="global", jac=jac,
                               t_eval=[1.0, 2.0], dense_output=True)
    assert res.status == -1 and "The starting sweep" in res.message
    assert res.t.tolist() == [0.0] and res.y.tolist() == [[1.0]] and res.sol is None


@pytest.mark.parametrize("bad", ["fun", "jac"])
def test_global_and_bvp_name_where_a_value_is_not_finite(bad):
    def fun(t, y, yp):
        return -y if bad == "jac" or t <= 0.5 else np.full_like(y, np.nan)

    def jac(t, y, yp):
        return (-np.eye(1) if bad == "fun" or t <= 0.5 else np.full((1, 1), np.nan),
                np.zeros((1, 1)))
    res = splinestep.solve(fun, (0, 2), 1.0, 0.0, 0.1, iteration="global", jac=jac)
    said = "not finite at t = 0.6 (the first such knot)"
    if bad == "fun":   # the starting sweep meets it first
        assert res.status == -1 and "not finite" in res.message and "t = 0.6" in res.message
    else:
        assert res.status == -1 and f"jac is {said}" in res.message
    bvp = splinestep.solve_bvp(fun, np.linspace(0, 2, 11), 1.0, 0.0, jac=jac)
    assert bvp.status == -1 and f"{bad} is {said}" in bvp.message


def test_reversible_run_merges_a_rounding_sliver_at_the_end():
    """Ten constant steps of 0.1 end at 1 - 1.1e-16: the tenth ends at tf,
    as on every other controller, and max_steps = 10 suffices."""
    zero = lambda t, y, yp: 0.0
    res = splinestep.solve_reversible(f, (0, 1), 1.0, 0.0, 0.1, zero, max_steps=10)
    assert res.success and res.nstep == 10 and res.t[-1] == 1.0
    assert np.min(np.diff(res.t)) > 0.09


def test_global_sweep_takes_an_empty_event_list_as_no_events():
    res = splinestep.solve(f, (0, 1), 1.0, 0.0, 0.1, iteration="global", events=[])
    assert res.success and res.t_events is None


def test_compiled_fun_returning_a_mixed_tuple_is_refused_at_the_start():
    @njit
    def mixed(t, y, yp):
        return (-y[0], 0)
    with pytest.raises(ValueError, match="a tuple of mixed types"):
        splinestep.solve(mixed, (0, 1), [1.0, 0.0], [0.0, 1.0], 0.1)


def test_the_type_check_reads_the_signature_the_run_uses():
    """A compiled fun once called with an integer t has a mixed-tuple
    signature too; the run calls it with a float t, where it returns two
    floats, and is not refused for the other signature."""
    @njit
    def time_and_rate(t, y, yp):
        return (t, -y[1])
    time_and_rate(1, np.ones(2), np.ones(2))   # compiles Tuple(int64, float64)
    assert splinestep.solve(time_and_rate, (0.0, 1.0), [1.0, 1.0], [0.0, 0.0], 0.1).success
