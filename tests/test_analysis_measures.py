"""The measurement helpers the notebooks call (splinestep.analysis:
long_time for notebook 08, adaptive for 09, error_location for 02), each
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
    leading order (notebook 06): at t = 1, cos(1) h^4 / 24."""
    oscillator = problems.harmonic()
    for h in (0.1, 0.05):
        error = adaptive.true_local_errors(oscillator, [1.0, 1.0 + h])[0]
        assert error == pytest.approx(np.cos(1.0) * h ** 4 / 24, rel=0.1)


def test_matched_uniform_runs_reach_the_adaptive_error():
    orbit = problems.eccentric(0.5)
    period = orbit.t_span[1]
    work = adaptive.work_precision(orbit, period, [200, 800, 3200], [1e-4])
    assert set(work.method) == {"uniform, 1 sweep", "uniform, iterated",
                                "adaptive, 1 sweep", "adaptive, iterated"}
    matched = adaptive.matched_uniform_runs(orbit, period, work)
    # An order-2 step scaled to the adaptive run's error reaches it within 30 %.
    assert len(matched) > 0
    assert np.all(np.abs(matched.uniform_error / matched.adaptive_error - 1) < 0.3)


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


def test_adaptive_over_uniform_reads_the_ratio_at_equal_error():
    """Uniform runs that need exactly twice the adaptive evaluations at
    every error: adaptive / uniform is 0.5 wherever both curves reach."""
    from splinestep.analysis import tolerance
    errors = np.geomspace(1e-8, 1e-3, 6)
    adaptive_rows = pd.DataFrame(dict(problem="p", nfev=1e3 * errors ** -0.5, error=errors))
    uniform_rows = pd.DataFrame(dict(problem="p", nfev=2e3 * errors[1:] ** -0.5,
                                     error=errors[1:]))
    table = tolerance.adaptive_over_uniform(adaptive_rows, uniform_rows)
    assert table.loc["p", "least"] == pytest.approx(0.5, rel=1e-9)
    assert table.loc["p", "most"] == pytest.approx(0.5, rel=1e-9)


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
