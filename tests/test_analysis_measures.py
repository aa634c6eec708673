"""The measurement helpers the notebooks call (splinestep.analysis:
long_time for notebook 08, adaptive for 07, error_location for 02), each
against a closed form or an independent computation."""

import numpy as np
import pandas as pd
import pytest

import splinestep
from splinestep import problems
from splinestep.analysis import adaptive, error_location, long_time
from splinestep.problems import kepler

MU = 0.6


def test_fitted_growth_tells_a_bounded_error_from_a_linear_drift():
    orbit = np.unique(np.round(np.logspace(0, 4, 33)))
    bounded = 1e-6 * (1.5 + np.sin(orbit))
    exponent, _, _ = long_time.fitted_growth(orbit, bounded, 100)
    assert abs(exponent) < 0.1
    drifting = 1e-8 + 2e-9 * (orbit - 1)
    exponent, drift, start = long_time.fitted_growth(orbit, drifting, 100)
    assert exponent > 0.9
    assert drift == pytest.approx(2e-9, rel=1e-9) and start == pytest.approx(1e-8, rel=1e-6)


@pytest.mark.parametrize("h", [0.02, 0.01])
def test_modified_invariants_are_conserved_where_the_energy_is_not(h):
    """Over one orbit of the ellipse the spline's energy error is O(h^2); its
    modified energy H~ and modified angular momentum are conserved to
    O(h^4) and to the step equation's tolerance: far smaller.  (The run
    ends on a whole step: a shortened last step would change h, and with it
    the modified invariants.)"""
    ellipse = problems.cannonball(MU)
    period = problems.orbit_elements(MU)["period"]
    t_end = h * np.floor(period / h)
    res = splinestep.solve(ellipse.fun, (0.0, t_end), ellipse.y0, ellipse.yp0, h,
                           args=ellipse.args)
    energy = kepler.energy(MU)(res.y, res.yp)
    modified = long_time.modified_energy(res.y, res.yp, MU, h)
    momentum = long_time.modified_momentum(res.y, res.yp, MU, h)
    energy_error = np.ptp(energy)
    assert 1e-2 * h ** 2 < energy_error < 10 * h ** 2
    assert np.ptp(modified) < 1e-3 * energy_error
    assert np.ptp(momentum) < 1e-12


def test_invariants_per_orbit_keeps_the_largest_error_of_each_sampled_orbit():
    ellipse = problems.cannonball(MU)
    period = problems.orbit_elements(MU)["period"]
    t = np.linspace(0.0, 3 * period, 601)[:-1]
    res = splinestep.solve(ellipse.fun, (0.0, t[-1]), ellipse.y0, ellipse.yp0, 0.01,
                           args=ellipse.args, t_eval=t)
    table = long_time.invariants_per_orbit("spline", res.t, res.y, res.yp, ellipse.y0,
                                           ellipse.yp0, MU, period, [0, 2])
    assert list(table.orbit) == [1, 3]
    in_third = (t >= 2 * period) & (t < 3 * period)
    h0 = kepler.energy(MU)(ellipse.y0[:, None], ellipse.yp0[:, None])[0]
    direct = np.max(np.abs(kepler.energy(MU)(res.y[:, in_third], res.yp[:, in_third]) - h0))
    assert table.energy_error.iloc[1] == direct


def test_true_local_error_of_a_step_is_fourth_order():
    """y'' = -y: one step from exact values misses by h^4 y''''/24 to
    leading order (notebook 05): at t = 1, cos(1) h^4 / 24."""
    oscillator = problems.harmonic()
    for h in (0.1, 0.05):
        error = adaptive.true_local_errors(oscillator, [1.0, 1.0 + h])[0]
        assert error == pytest.approx(np.cos(1.0) * h ** 4 / 24, rel=0.1)


def test_first_orbit_above_a_level_or_a_curve():
    """The orbit (from 1) at which a growing error first exceeds a number or
    another run's error orbit by orbit; 0 when it never does."""
    growing = np.array([1.0, 2.0, 3.0, 4.0])
    assert adaptive.first_orbit_above(growing, 2.5) == 3
    assert adaptive.first_orbit_above(growing, [2.0, 2.0, 2.0, 2.0]) == 3
    assert adaptive.first_orbit_above(growing, 5.0) == 0


def test_orbits_changing_sign_finds_runs_of_orbits():
    signed = pd.Series([1.0, -1.0, 1.0, 2.0, -3.0, 1.0, 1.0, 2.0, -1.0, 3.0, -1.0, 2.0]
                       ).groupby(np.repeat([1, 2, 3, 4, 5, 6], 2))
    assert adaptive.orbits_changing_sign(signed) == ["1-1", "3-3", "5-6"]


def test_closed_form_ratios_of_the_ellipse():
    """r runs from 1 to 5 on the ellipse mu = 0.6: (5 / 1)^2 and (4.5 / 1)^2."""
    ratios = error_location.closed_form_ratios(MU)
    assert ratios["acceleration_ratio_apsides"][0] == pytest.approx(25.0, rel=1e-12)
    assert ratios["acceleration_ratio_arcs"][0] == pytest.approx(20.25, rel=1e-12)


def test_error_histories_against_the_exact_orbit():
    problem = problems.cannonball(MU)
    res = problem.solve("spline", h=0.05)
    frame = error_location.error_histories({MU: {"spline": res}})
    exact, _ = problems.kepler_exact(res.t, MU)
    assert frame.position_error.iloc[0] == 0.0
    assert np.allclose(frame.position_error, np.hypot(*(res.y - exact)), rtol=0, atol=1e-15)
    energy = 0.5 * np.sum(res.yp ** 2, axis=0) - MU / np.hypot(*res.y)
    assert np.allclose(frame.energy_error, np.abs(energy - energy[0]), rtol=0, atol=1e-15)


def test_trajectories_and_their_separation_from_the_exact_orbit():
    from types import SimpleNamespace
    t = np.linspace(0.0, 5.0, 51)
    exact, _ = problems.kepler_exact(t, MU)
    shifted = exact + np.array([[0.01], [0.0]])
    runs = {MU: {"spline": SimpleNamespace(t=t, y=exact), "rk4": SimpleNamespace(t=t, y=shifted)}}
    frame = error_location.trajectories(runs, stride=10)
    assert list(frame.t) == list(t[::10])
    assert np.allclose(frame.x_rk4 - frame.x_exact, 0.01, rtol=0, atol=1e-15)
    assert np.array_equal(frame.y_spline, exact[1, ::10])
    extent = max(np.ptp(exact[0]), np.ptp(exact[1]))
    assert error_location.largest_separation(runs)[MU] == pytest.approx(0.01 / extent, rel=1e-9)


def test_reproducible_round_keeps_the_digits_another_cpu_reproduces():
    """DOP853's evaluations per orbit on two machines (notebook 08): 190 and
    200 at two digits, 200 at the digits that a 5 % spread reproduces; a
    count that reproduces exactly keeps two digits."""
    assert [float(f"{v:.1e}") for v in (194.99, 195.61)] == [190.0, 200.0]
    for value in (194.99, 195.61):
        assert long_time.reproducible_round(value, long_time.ADAPTIVE_SPREAD) == 200.0
    assert long_time.reproducible_round(9248.46) == 9200.0
    # 9248.46 within 0.1 % reaches 9257.7, which rounds to 9300 at two digits
    assert long_time.reproducible_round(9248.46, 0.001) == 9000.0
    assert long_time.reproducible_round(4214.89, 0.05) == 4000.0


def test_fixed_step_runs_in_threads_are_the_runs_made_alone():
    ellipse = problems.cannonball(MU)
    t = np.arange(0.0, 200.0, 0.5)
    runs = long_time.fixed_step_runs(ellipse, 200.0, 0.01, t)
    assert list(runs) == ["spline", "spline, 1 sweep", "Verlet"]
    alone = {"spline": splinestep.solve(ellipse.fun, (0.0, 200.0), ellipse.y0, ellipse.yp0, 0.01,
                                        args=ellipse.args, t_eval=t),
             "spline, 1 sweep": splinestep.solve(ellipse.fun, (0.0, 200.0), ellipse.y0,
                                                 ellipse.yp0, 0.01, args=ellipse.args, t_eval=t,
                                                 iterations=1),
             "Verlet": splinestep.verlet(ellipse.fun, (0.0, 200.0), ellipse.y0, ellipse.yp0,
                                         0.01, args=ellipse.args, t_eval=t)}
    for name, res in alone.items():
        assert np.array_equal(runs[name].y, res.y) and np.array_equal(runs[name].yp, res.yp)
        assert runs[name].nfev == res.nfev
    # one sweep evaluates F once per step, the iterated spline about twice
    assert runs["spline, 1 sweep"].nfev < 0.6 * runs["spline"].nfev


def test_drift_summary_prints_what_reproduces():
    drift = pd.DataFrame([
        dict(method="spline", orbits=10000, energy_exponent=-0.001, final_energy_error=6.496e-6,
             momentum_exponent=0.0004, final_momentum_error=9.92e-6),
        dict(method="Verlet", orbits=10000, energy_exponent=0.0137, final_energy_error=3.64e-6,
             momentum_exponent=np.nan, final_momentum_error=3.1e-13),
        dict(method="DOP853, rtol 1e-04", orbits=1000, energy_exponent=0.884,
             final_energy_error=0.0048, momentum_exponent=0.83, final_momentum_error=0.0087)])
    table = long_time.drift_summary(drift)
    assert list(table.loc["spline"]) == ["10,000", "+0.00", "6.5e-06", "+0.00", "1e-05"]
    assert list(table.loc["Verlet"]) == ["10,000", "+0.01", "3.6e-06", "conserved", "3e-13"]
    assert list(table.loc["DOP853, rtol 1e-04"]) == ["1,000", "+0.9", "~1e-02", "+0.8", "~1e-02"]


def test_crossing_interpolates_between_sampled_orbits():
    orbit = np.array([1.0, 10.0, 100.0, 1000.0])
    error = 1e-3 * orbit          # a linear drift: exact in log-log
    assert long_time.crossing(orbit, error, 0.3) == pytest.approx(300.0, rel=1e-12)
    assert long_time.crossing(orbit, error, 1e-4) == 1.0
    assert np.isnan(long_time.crossing(orbit, error, 2.0))
    # the first crossing of an error that saturates and oscillates
    assert long_time.crossing(orbit, [0.1, 2.0, 0.5, 3.0], 1.0) == pytest.approx(
        10 ** (np.log(10) / np.log(20)), rel=1e-12)


def test_accumulated_estimate_reads_the_checks_sum():
    """On y'' = -y (y'''' = cos t) the check's estimates summed over k
    periods at the step h are h^3/24 and h^2/12 times the integral of
    |cos t|, 4k: 0.0167 and 0.333 for k = 100, h = 0.1, above 0.3 in y'."""
    oscillator = problems.harmonic()
    with pytest.warns(UserWarning, match="sum to"):
        res = splinestep.solve(oscillator.fun, (0.0, 200 * np.pi), oscillator.y0,
                               oscillator.yp0, 0.1, args=oscillator.args)
    found = long_time.accumulated_estimate(res)
    assert found["sum_y"] == pytest.approx(0.1 ** 3 / 24 * 400, rel=0.03)
    assert found["sum_yp"] == pytest.approx(0.1 ** 2 / 12 * 400, rel=0.03)
    assert (found["fraction"], found["y_scale"], found["yp_scale"]) == (0.3, 1.0, 1.0)
    shorter = splinestep.solve(oscillator.fun, (0.0, 100 * np.pi), oscillator.y0,
                               oscillator.yp0, 0.1, args=oscillator.args)
    assert long_time.accumulated_estimate(shorter) is None


def test_the_check_estimates_a_composed_step_as_one_cubic_step():
    """Order 4 on the ellipse at h = 0.08: the check's sums are those of the
    report's method at the same step (notebook 10), not of the composition."""
    ellipse = problems.cannonball(MU)
    t_end = 400 * problems.orbit_elements(MU)["period"]
    sums = {}
    for order in (2, 4):
        with pytest.warns(UserWarning, match="sum to"):
            res = splinestep.solve(ellipse.fun, (0.0, t_end), ellipse.y0, ellipse.yp0, 0.08,
                                   args=ellipse.args, order=order)
        sums[order] = long_time.accumulated_estimate(res)["sum_yp"]
    assert sums[4] == pytest.approx(sums[2], rel=0.05)
    assert 0.4 < sums[2] < 0.6
