"""Events located on the spline, checked against closed forms: the apsides
and the r = a crossings of a Kepler ellipse (Kepler's equation), the zeros
of a pendulum (complete elliptic integral), a ball hitting the ground (a
quadratic, which the cubic spline reproduces exactly); and backward
integration."""

import math

import numpy as np
import pytest
from scipy.special import ellipk

import splinestep
from splinestep import problems


def fitted_order(steps, errors):
    return np.polyfit(np.log(steps), np.log(errors), 1)[0]


# The report's ellipse: mu = 0.6, launched at periapsis r = 1 with speed 1.
MU = 0.6
A = 1.0 / (2.0 / 1.0 - 1.0 / MU)            # vis-viva: a = 3
ECC = 1.0 - 1.0 / A                          # periapsis r = a (1 - e) = 1
MEAN_MOTION = math.sqrt(MU / A**3)


def radial_velocity(t, y, yp, mu):
    return y[0] * yp[0] + y[1] * yp[1]       # r r' : zero at the apsides


def r_minus_a(t, y, yp, mu):
    return math.hypot(y[0], y[1]) - A


def kepler_times(eccentric_anomalies):
    """Times from periapsis by Kepler's equation M = E - e sin E."""
    return np.array([(E - ECC * math.sin(E)) / MEAN_MOTION for E in eccentric_anomalies])


def ellipse_events(h):
    apoapsis = lambda *a: radial_velocity(*a)   # noqa: E731
    apoapsis.direction = -1                      # r r' goes + to -: apoapsis
    periapsis = lambda *a: radial_velocity(*a)  # noqa: E731
    periapsis.direction = 1
    problem = problems.cannonball(MU)
    return problem.solve("spline", h=h, events=[apoapsis, periapsis, r_minus_a],
                         dense_output=True)


def test_kepler_event_times_converge_at_order_2_to_keplers_equation():
    period = 2 * math.pi / MEAN_MOTION
    exact = [np.array([period / 2]), np.array([period]),
             kepler_times([math.pi / 2, 3 * math.pi / 2, 5 * math.pi / 2])]
    steps = [0.04, 0.02, 0.01, 0.005]
    errors = []
    for h in steps:
        res = ellipse_events(h)
        assert res.status == 0
        assert [t.size for t in res.t_events] == [1, 1, 3]
        errors.append(max(np.max(np.abs(t - e)) for t, e in zip(res.t_events, exact)))
        # Each event time is a root of the dense output, to rounding.
        for g, times in zip([radial_velocity, radial_velocity, r_minus_a], res.t_events):
            for t in times:
                assert abs(g(t, res.sol(t), res.sol(t, 1), MU)) < 1e-10
        for times, ys, yps in zip(res.t_events, res.y_events, res.yp_events):
            assert np.allclose(ys, res.sol(times).T, atol=1e-13)
            assert np.allclose(yps, res.sol(times, 1).T, atol=1e-13)
    assert 1.9 < fitted_order(steps, errors) < 2.1


def test_pendulum_zero_crossings_against_the_elliptic_integral():
    theta0 = 1.0
    period = 4 * ellipk(math.sin(theta0 / 2) ** 2)
    exact = period / 4 + period / 2 * np.arange(4)

    def angle(t, y, yp):
        return y[0]

    steps = [0.02, 0.01, 0.005]
    errors = []
    for h in steps:
        res = splinestep.solve(lambda t, y, yp: -math.sin(y[0]), (0, 2 * period), theta0, 0.0,
                               h, events=angle)
        assert res.t_events[0].size == 4
        errors.append(np.max(np.abs(res.t_events[0] - exact)))
    assert 1.9 < fitted_order(steps, errors) < 2.1
    # The linearised period error (omega h)^2 / 24 (omega < 1 here), twice over.
    assert errors[-1] < 2 * steps[-1] ** 2 / 24 * exact[-1]


def ground(t, y, yp):
    return y[0]


ground.terminal = True
ground.direction = -1


@pytest.mark.parametrize("t_eval", [None, np.linspace(0, 5, 51)])
def test_terminal_event_stops_where_the_ball_lands(t_eval):
    g, height, speed = 9.81, 10.0, 5.0
    landing = (speed + math.sqrt(speed**2 + 2 * g * height)) / g
    res = splinestep.solve(lambda t, y, yp: -g, (0, 5), height, speed, 0.01, events=ground,
                           t_eval=t_eval, dense_output=True)
    assert res.status == 1 and res.success and "termination event" in res.message
    # The solution is a quadratic, which the cubic spline holds exactly.
    assert res.t_events[0] == pytest.approx([landing], abs=1e-12)
    assert abs(res.y_events[0][0, 0]) < 1e-12
    assert res.yp_events[0][0, 0] == pytest.approx(speed - g * landing, abs=1e-12)
    assert res.t[-1] <= landing + 1e-15
    if t_eval is None:
        assert res.t[-1] == res.t_events[0][0] and res.y[0, -1] == res.y_events[0][0, 0]
    else:
        assert res.t.size == np.sum(t_eval <= landing)
    assert res.sol.t_max == pytest.approx(landing, abs=1e-15)


def test_terminal_event_of_a_long_run_stops_early():
    # A run of 10^6 steps whose event comes after 150: the pieces before the
    # event are computed, the rest is not.
    res = splinestep.solve(lambda t, y, yp: -9.81, (0, 1e4), 10.0, 5.0, 0.01, events=ground)
    assert res.status == 1 and res.nstep < 1000


def test_terminal_count_and_direction():
    crossing = lambda t, y, yp: y[0]   # noqa: E731
    up = lambda t, y, yp: y[0]         # noqa: E731
    up.direction = 1
    down = lambda t, y, yp: y[0]       # noqa: E731
    down.direction = -1
    down.terminal = 2
    res = splinestep.solve(lambda t, y, yp: -y, (0, 20), 1.0, 0.0, 0.001,
                           events=[crossing, up, down])
    # cos t: down at pi/2, 5 pi/2; up at 3 pi/2.  The run stops at the second down.
    assert res.status == 1
    assert np.allclose(res.t_events[2], [math.pi / 2, 5 * math.pi / 2], atol=1e-6)
    assert np.allclose(res.t_events[1], [3 * math.pi / 2], atol=1e-6)
    assert np.allclose(res.t_events[0], [math.pi / 2, 3 * math.pi / 2, 5 * math.pi / 2],
                       atol=1e-6)
    assert res.t[-1] == pytest.approx(5 * math.pi / 2, abs=1e-6)


def test_zero_at_the_initial_time_is_not_an_event():
    res = splinestep.solve(lambda t, y, yp: -9.81, (0, 1), 0.0, 3.0, 0.01, events=ground)
    landing = 2 * 3.0 / 9.81
    assert res.t_events[0] == pytest.approx([landing], abs=1e-12)


def test_events_reject_bad_attributes():
    bad = lambda t, y, yp: y[0]   # noqa: E731
    bad.terminal = -1
    with pytest.raises(ValueError, match="terminal"):
        splinestep.solve(lambda t, y, yp: -y, (0, 1), 1.0, 0.0, 0.1, events=bad)
    with pytest.raises(ValueError, match="events"):
        splinestep.solve(lambda t, y, yp: -y, (0, 1), 1.0, 0.0, 0.1, events=[1.0])


@pytest.mark.parametrize("iteration", ["fixed-point", "newton"])
def test_backward_run_retraces_the_forward_run(iteration):
    """The method is symmetric: stepping back from the end of a forward run
    returns to the start, to the iteration's tolerance."""
    problem = problems.cannonball(MU)
    forward = splinestep.solve(problem.fun, (0.0, 20.0), problem.y0, problem.yp0, 0.01,
                               args=problem.args, iteration=iteration)
    backward = splinestep.solve(problem.fun, (20.0, 0.0), forward.y[:, -1], forward.yp[:, -1],
                                0.01, args=problem.args, iteration=iteration,
                                dense_output=True)
    assert backward.status == 0 and backward.t[0] == 20.0 and backward.t[-1] == 0.0
    assert np.all(np.diff(backward.t) < 0)
    assert np.allclose(backward.y[:, ::-1], forward.y, atol=1e-10)
    assert np.allclose(backward.yp[:, ::-1], forward.yp, atol=1e-10)
    # Its error against the exact orbit is that of a forward run (order 2).
    exact_y, _ = problem.exact(np.array([0.0]))
    assert np.max(np.abs(backward.y[:, -1] - exact_y[:, 0])) < 1e-10
    assert np.allclose(backward.sol(10.0), forward.y[:, 1000], atol=1e-10)


def test_backward_with_t_eval_and_events():
    res = splinestep.solve(lambda t, y, yp: -y, (10.0, 0.0), math.cos(10), -math.sin(10), 0.001,
                           t_eval=[9.0, 5.0, 0.0], events=lambda t, y, yp: y[0])
    assert res.t.tolist() == [9.0, 5.0, 0.0]
    assert np.allclose(res.y[0], np.cos(res.t), atol=1e-5)
    zeros = (np.arange(7) + 0.5) * math.pi
    assert np.allclose(res.t_events[0], zeros[zeros < 10][::-1], atol=1e-5)
    with pytest.raises(ValueError, match="t_eval"):
        splinestep.solve(lambda t, y, yp: -y, (10.0, 0.0), 1.0, 0.0, 0.1, t_eval=[0.0, 5.0])


def test_events_on_a_run_that_fails_at_its_start():
    res = splinestep.solve(lambda t, y, yp: np.full_like(y, np.nan), (0, 1), 1.0, 0.0, 0.1,
                           events=ground)
    assert res.status == -1 and res.t_events[0].size == 0
