"""A run that blows up past its member's stability limit is a failure
(status -1), with the time, the step, the estimated omega h and the limit in
its message; and no run that does not blow up is called one.

The estimated omega h is the undamped oscillation on which one step grows
as much as the linearised step does; on y'' = -omega^2 y it is omega h
itself, to the bisection's rounding."""

import math
import warnings

import numpy as np
import pytest

import splinestep
from splinestep import problems
from splinestep.check import BLOWN_UP, omega_h_of_growth
from splinestep.members import MEMBERS, amplification


def _quiet(*args, **kwargs):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return splinestep.solve(*args, **kwargs)


@pytest.mark.parametrize("method, omega_h", [("spline", 3.5), ("spline", 4.0), ("spline", 6.0),
                                             ("fox-goodwin", 2.6), ("fox-goodwin", 3.2)])
def test_a_run_past_the_stability_limit_fails_and_names_omega_h(method, omega_h):
    limit = MEMBERS[method].stability_limit
    res = _quiet(lambda t, y, yp: -y, (0.0, 400.0 * omega_h), 1.0, 0.0, omega_h,
                 iteration="newton", method=method)
    assert res.status == -1 and not res.success
    assert "blew up" in res.message and "t = 0 " in res.message
    assert f"estimated omega h = {omega_h:.3g}, past its stability limit omega h = " \
           f"{limit:.4g}" in res.message
    assert np.max(np.abs(res.y)) > BLOWN_UP


@pytest.mark.parametrize("method", ["spline", "fox-goodwin"])
def test_omega_h_of_growth_inverts_the_amplification_factor(method):
    sc = MEMBERS[method].scheme()
    limit = MEMBERS[method].stability_limit
    for omega_h in (1.001 * limit, 1.5 * limit, 10.0 * limit):
        matrix = amplification(np.array([[-omega_h ** 2]]), np.zeros((1, 1)), 1.0, sc)
        rho = np.max(np.abs(np.linalg.eigvals(matrix)))
        assert omega_h_of_growth(rho, sc, limit) == pytest.approx(omega_h, rel=1e-9)
    assert math.isnan(omega_h_of_growth(0.99, sc, limit))
    assert math.isnan(omega_h_of_growth(2.0, MEMBERS["average-acceleration"].scheme(),
                                        math.inf))


def test_just_inside_the_limit_is_not_a_failure():
    """At omega h = 3.4 (inside sqrt(12)) the spline's run is bounded: at
    most a warning about its accuracy, never a failure."""
    res = _quiet(lambda t, y, yp: -y, (0.0, 200.0), 1.0, 0.0, 3.4, iteration="newton")
    assert res.status == 0 and np.max(np.abs(res.y)) <= 1.0 + 1e-9


def test_an_equation_that_grows_is_not_a_failure():
    """y'' = y grows by e^20 over (0, 20): the step follows the equation's
    growth, which is not the step's instability.  (The relative error of a
    second-order step on e^t grows like h^2 t / 12 to leading order.)"""
    res = _quiet(lambda t, y, yp: y, (0.0, 20.0), 1.0, 1.0, 0.1)
    assert res.status == 0
    assert res.y[0, -1] == pytest.approx(math.exp(20.0), rel=0.1 ** 2 * 20.0 / 12.0)


@pytest.mark.parametrize("iteration", ["fixed-point", "newton"])
def test_no_false_failure_on_the_report_and_test_problems(iteration):
    cases = [problems.cannonball(mu) for mu in problems.CANNONBALL_MU]
    cases += [problems.rigid_body(), problems.harmonic(3.0), problems.eccentric(0.9),
              problems.chain(50)]
    for problem in cases:
        res = _quiet(problem.fun, problem.t_span, problem.y0, problem.yp0, problem.h,
                     args=problem.args, iteration=iteration)
        assert res.status == 0, (problem, res.message)


def test_no_false_failure_on_a_damped_chain_under_a_ground_motion_record():
    """A Rayleigh-damped chain of 10 storeys driven by a ground acceleration
    given as a record at dt = 0.01 (piecewise linear), stepped at the
    record's dt: omega_max h is 0.3, far inside the limit; the run is a
    success."""
    m = 10
    stiffness = (2 * np.eye(m) - np.eye(m, k=1) - np.eye(m, k=-1)) * 400.0
    stiffness[-1, -1] = 400.0
    damping = 0.05 * np.eye(m) + 0.002 * stiffness
    rng = np.random.default_rng(7)
    t_record = np.arange(0.0, 20.0001, 0.01)
    record = np.convolve(rng.normal(size=t_record.size), np.ones(25) / 25, "same") * 3.0

    def fun(t, y, yp):
        return -stiffness @ y - damping @ yp - np.interp(t, t_record, record)

    res = splinestep.solve(fun, (0.0, 20.0), np.zeros(m), np.zeros(m), 0.01)
    assert res.status == 0 and "blew up" not in res.message
    omega_max = math.sqrt(np.linalg.eigvalsh(stiffness).max())
    assert omega_max * 0.01 < 0.5


def test_a_run_from_rest_is_not_judged_a_blow_up():
    """From rest the start's size is 0 and says nothing of the solution's:
    y1'' = -y1 + sin t beside y2'' = -1e4 y2, whose mode is past the limit
    at h = 0.04 (omega h = 4) but never excited, is accurate; it keeps the
    step-size warning and its status 0."""
    def fun(t, y, yp):
        return np.array([-y[0] + math.sin(t), -1e4 * y[1]])

    res = _quiet(fun, (0.0, 20.0), np.zeros(2), np.zeros(2), 0.04, iteration="newton")
    assert res.status == 0 and "blew up" not in res.message
    exact = 0.5 * (np.sin(res.t) - res.t * np.cos(res.t))   # resonance from rest
    assert np.max(np.abs(res.y[0] - exact)) < 1e-2 * np.max(np.abs(exact))
    assert np.all(res.y[1] == 0.0)


@pytest.mark.parametrize("start", [1e-6, 1e-3])
def test_a_small_start_that_grows_by_resonance_is_not_a_blow_up(start):
    """The same pair from y1(0) = 1e-6 or 1e-3: y1 grows thousands of times
    by resonance, accurately, beside the unexcited mode past the limit; one
    more step does not grow the final state as the linearised step would,
    so the run keeps its status 0."""
    def fun(t, y, yp):
        return np.array([-y[0] + math.sin(t), -1e4 * y[1]])

    res = _quiet(fun, (0.0, 20.0), np.array([start, 0.0]), np.zeros(2), 0.04,
                 iteration="newton")
    assert res.status == 0 and "blew up" not in res.message
    assert np.max(np.abs(res.y[0])) > BLOWN_UP * start


@pytest.mark.parametrize("adaptive", [False, True])
def test_y_max_stops_a_run_at_the_first_knot_beyond_it(adaptive):
    """With ``y_max`` a run stops, failed, at the first knot where |y|
    exceeds the bound, checked or not and from rest too: the same run
    without the bound shows where that knot is."""
    p = problems.chain(20, omega_h=4.0, periods=2.0)
    y0 = 1e-3 * np.sin(np.arange(20.0))
    grid = {} if adaptive else {"h": p.h}
    if adaptive:    # y'' = y grows as e^t: the error controller follows it
        fun, span, y0, yp0 = (lambda t, y, yp: y), (0.0, 30.0), 1e-3 * np.ones(2), np.zeros(2)
    else:           # past sqrt(12): the spline's step grows the fastest mode
        fun, span, yp0 = p.fun, p.t_span, np.zeros(20)
    kwargs = dict(args=() if adaptive else p.args, iteration="newton", check=False, **grid)
    free = _quiet(fun, span, y0, yp0, **kwargs)
    beyond = np.flatnonzero(np.max(np.abs(free.y), axis=0) > 1e3)[0]
    res = _quiet(fun, span, y0, yp0, y_max=1e3, **kwargs)
    assert res.status == -1 and not res.success
    assert res.t[-1] == free.t[beyond - 1]
    assert f"The run stopped at t = {free.t[beyond]:.10g}: |y| exceeded y_max = 1000" \
        in res.message
    assert np.array_equal(res.y, free.y[:, :beyond])


def test_a_bound_the_run_stays_below_changes_nothing():
    kwargs = dict(h=0.05, iteration="newton")
    free = splinestep.solve(lambda t, y, yp: -y, (0.0, 20.0), 1.0, 0.0, **kwargs)
    bounded = splinestep.solve(lambda t, y, yp: -y, (0.0, 20.0), 1.0, 0.0, y_max=1.0 + 1e-6,
                               **kwargs)
    assert bounded.status == 0 and np.array_equal(bounded.y, free.y)


@pytest.mark.parametrize("bad", [0, -1.0, "1", True, None, np.nan])
def test_y_max_must_be_a_positive_number(bad):
    with pytest.raises(ValueError, match="y_max must be a positive number"):
        splinestep.solve(lambda t, y, yp: -y, (0.0, 1.0), 0.1, 0.0, h=0.1, y_max=bad)


def test_y_max_below_the_start_is_refused():
    with pytest.raises(ValueError, match=r"y_max = 0.5 is below the largest \|y0\|, 1"):
        splinestep.solve(lambda t, y, yp: -y, (0.0, 1.0), [0.1, -1.0], [0.0, 0.0], h=0.1,
                         y_max=0.5)


def test_the_global_iteration_refuses_y_max():
    with pytest.raises(ValueError, match='iteration="global" takes no y_max'):
        splinestep.solve(lambda t, y, yp: y, (0.0, 10.0), 1.0, 0.0, h=0.1, iteration="global",
                         y_max=2.0)


def test_a_run_stopped_at_y_max_keeps_its_message_when_the_check_sees_a_blow_up():
    res = _quiet(lambda t, y, yp: -y, (0.0, 400.0), 1.0, 0.0, 4.0, iteration="newton",
                 y_max=1e6)
    assert res.status == -1 and "exceeded y_max = 1e+06" in res.message
    assert "blew up" not in res.message and np.max(np.abs(res.y)) <= 1e6


def test_the_chain_past_the_limit_fails_on_the_arnoldi_path():
    """The chain of 100 masses at omega_m h = 4 (beyond sqrt 12), Newton with
    the sparse K: above DENSE_UP_TO the check estimates the growth by
    Arnoldi steps (the equation's own growth then reads 1 + 2e-16), and the
    run's last step is shortened to end the span; the run, |y| about 1e64,
    is a failure whose estimated omega h is the step's."""
    p = problems.chain(100, omega_h=4.0, periods=3.125)
    res = _quiet(p.fun, p.t_span, p.y0, p.yp0, p.h, args=p.args, iteration="newton",
                 jac=p.jac)
    assert res.status == -1 and not res.success
    assert "blew up" in res.message and "estimated omega h = 4, past its stability limit" \
        in res.message
