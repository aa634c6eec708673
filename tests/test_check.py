"""The step-too-large check (splinestep.check): it warns on runs whose
error is a sizeable fraction of the solution and stays silent on accurate
ones, forwards and backwards.  Errors against exact solutions or a Radau
solve at rtol = atol = 1e-12."""

import warnings

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import splinestep
from splinestep.problems.nonlinear import rational


def warned(fun, t_span, y0, yp0, h, **kwargs):
    """(result, whether the run warned that its step is too large)."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        res = splinestep.solve(fun, t_span, y0, yp0, h, **kwargs)
    return res, any("too large" in str(w.message) for w in caught)


def van_der_pol(t, y, yp):
    return 10.0 * (1.0 - y * y) * yp - y


def test_van_der_pol_mu_10_at_h_0_05_is_caught():
    """Newton at h = 0.05 over (0, 30) from (2, 0): the error is more than a
    tenth of the amplitude (2) and the run says so; at h = 0.005 the error
    is below 1 % of it and the run is silent."""
    sol = solve_ivp(lambda t, u: [u[1], 10.0 * (1 - u[0] ** 2) * u[1] - u[0]], (0.0, 30.0),
                    [2.0, 0.0], method="Radau", rtol=1e-12, atol=1e-12, dense_output=True)
    for h, error_above, error_below, expected in ((0.05, 0.2, np.inf, True),
                                                  (0.005, 0.0, 0.02, False)):
        res, flagged = warned(van_der_pol, (0.0, 30.0), 2.0, 0.0, h, iteration="newton")
        error = np.max(np.abs(res.y[0] - sol.sol(res.t)[0]))
        assert error_above < error < error_below
        assert flagged is expected
        assert ("too large" in res.message) is expected


@pytest.mark.parametrize("t_span", [(0.0, 20.0), (20.0, 0.0)])
def test_an_oscillator_run_off_by_more_than_half_is_caught_both_ways(t_span):
    """y'' = -y at h = 1 (omega h = 1, stable): the phase error after 20
    units is 0.5 of the amplitude, and no single step's estimate says so;
    their sum does.  At h = 0.05 (error 2e-3) the run is silent."""
    for h, expected in ((1.0, True), (0.05, False)):
        res, flagged = warned(lambda t, y, yp: -y, t_span, 1.0, 0.0, h)
        error = abs(res.y[0, -1] - np.cos(20.0))     # 20 units after y = 1, y' = 0
        assert bool(error > 0.3) is expected
        assert flagged is expected


def test_a_growing_mode_taken_accurately_is_not_flagged():
    """scipy's rational problem backwards over [5, 1] at h = 1 (error 1.4e-3
    of the solution) grows by 1.2898 per step where the linearised equation
    grows by 1.2884: an accuracy of 0.1 % in the growth rate, not an
    instability, which a check of the growth alone would call one."""
    problem = rational()
    res, flagged = warned(problem.fun, (5.0, 1.0), problem.y0, problem.yp0, 1.0)
    error = np.max(np.abs(res.y[0] - res.t / (res.t + 10.0)))
    assert error < 2e-3 * np.max(np.abs(res.y))
    assert not flagged


def test_false_alarms_and_misses_over_runs_of_known_error():
    """splinestep.analysis.alarms: 59 fixed-step runs of eleven problems,
    forwards and backwards, against exact or Radau references.  Of the 34
    runs whose error is below 1 % of the solution's scale, two warn: a
    damped chain under a ground-motion record stepped at the record's
    interval and at half of it, whose samples kink the forcing at the knots
    (the jump of the third derivative reads each kink as a large fourth
    derivative).  Of the 13 runs off by more than 10 %, at most 4 go
    unflagged (the damped oscillator backwards at h = 0.5, the Kepler orbit
    at T/1000 and T/4000 and the cannonball mu = 0.6 at h = 0.32, whose
    error is made at a periapsis passage and then amplified by the orbit's
    drift)."""
    from splinestep.analysis import alarms
    rows = alarms.runs()
    false_alarms, accurate, misses, inaccurate = alarms.tally(rows)
    assert accurate >= 30 and inaccurate >= 12
    assert false_alarms == 2 and misses <= 4
    assert {r["h"] for r in rows if r["warned"] and r["relative_error"] < 0.01
            and r["problem"].startswith("chain")} == {0.005, 0.01}


def test_verdicts_name_each_run_by_its_error_and_warning():
    """alarms.verdicts on rows at each side of the two thresholds (1 % and
    10 % of the scale), and tally's counts from the same rows."""
    from splinestep.analysis import alarms
    rows = [dict(status=0, relative_error=e, warned=w)
            for e, w in ((0.009, True), (0.009, False), (0.011, True), (0.099, False),
                         (0.11, False), (0.11, True))]
    rows.append(dict(status=-1, relative_error=np.nan, warned=False))
    assert alarms.verdicts(rows) == ["false alarm", "right", "between", "between", "miss",
                                     "right", "run failed"]
    assert alarms.tally(rows) == (1, 2, 1, 2)


def test_a_chaotic_damped_run_is_flagged():
    """The Ueda oscillator y'' = -0.05 y' - y^3 + 7.5 cos t from (1, 0) over
    (0, 300) at h = 0.05 is chaotic: the run strays about as far from the
    true solution (DOP853 at 1e-12) as the solution's size, and warns, although
    its Jacobian, frozen at any state, contracts (eigenvalue real parts
    -0.025): a check that trusted the frozen Jacobians' damping would let
    it pass."""
    def ueda(t, y, yp):
        return -0.05 * yp - y ** 3 + 7.5 * np.cos(t)
    res, flagged = warned(ueda, (0.0, 300.0), 1.0, 0.0, 0.05)
    reference = solve_ivp(lambda t, u: [u[1], -0.05 * u[1] - u[0] ** 3 + 7.5 * np.cos(t)],
                          (0.0, 300.0), [1.0, 0.0], method="DOP853", rtol=1e-12, atol=1e-12,
                          dense_output=True)
    error = np.max(np.abs(res.y[0] - reference.sol(res.t)[0]))
    assert error > 0.5 * np.max(np.abs(res.y))
    assert flagged
