"""Each measured property has a metric that can fail: shown here on cases
where the property does not hold."""

import dataclasses

import numpy as np
import pytest

from splinestep import problems
from splinestep.analysis import diagnostics


@pytest.mark.parametrize("x", [0.5, 1.5, 2.5])
def test_amplitude_factor_sees_rk4_damping(x):
    """RK4 damps on the oscillator: the metric gives |R(ix)| < 1, not 1."""
    problem = problems.harmonic(1.0, t_span=(0.0, 400 * x), h=x)
    rho, theta = diagnostics.recurrence_fit(problem.solve("rk4").y[0])
    closed = np.sqrt(1 - x ** 6 / 72 + x ** 8 / 576)
    assert rho < 1 - 1e-4
    assert abs(rho - closed) < 1e-10


def test_amplitude_factor_of_a_damped_oscillator():
    """y'' = -y - 2 zeta y': the spline's samples decay, and the metric
    gives the decay per step of the exact solution to O(h^2)."""
    import splinestep
    zeta, h = 0.05, 0.01
    res = splinestep.solve(lambda t, y, yp: -y - 2 * zeta * yp, (0, 40), 1.0, 0.0, h)
    rho, theta = diagnostics.recurrence_fit(res.y[0])
    assert abs(rho - np.exp(-zeta * h)) < 1e-5 * h
    assert abs(theta - np.sqrt(1 - zeta ** 2) * h) < 1e-4 * h


def test_amplitude_factor_sees_growth_beyond_the_stability_limit():
    x = np.sqrt(12) * 1.05  # real eigenvalues: no rotation, growth
    problem = problems.harmonic(1.0, t_span=(0.0, 40 * x), h=x)
    res = problem.solve(iteration="newton")
    assert res.status == -1 and "blew up" in res.message
    rho, _ = diagnostics.recurrence_fit(res.y[0])
    assert rho > 1.1


def test_growth_ratio_bounded_on_kepler_and_growing_on_the_rigid_body():
    """The energy error: bounded on the cannonball (ratio near 1) and
    growing linearly on the rigid body (ratio near 8)."""
    kepler = dataclasses.replace(problems.cannonball(0.6), t_span=(0.0, 8 * 42.15))
    res = kepler.solve()
    e = kepler.invariants["energy"](res.y, res.yp)
    assert diagnostics.growth_ratio(res.t, e - e[0]) < 1.2
    body = dataclasses.replace(problems.rigid_body("consistent"), t_span=(0.0, 400.0))
    res = body.solve()
    e = body.invariants["energy"](res.y, res.yp)
    assert 6 < diagnostics.growth_ratio(res.t, e - e[0]) < 9


def test_work_interpolation_against_a_power_law():
    nfev = np.array([100.0, 200.0, 400.0, 800.0])
    error = 3.0 * nfev ** -2.0
    assert abs(diagnostics.work_to_reach(nfev, error, 3.0 * 300.0 ** -2) - 300.0) < 1e-9
    assert np.isnan(diagnostics.work_to_reach(nfev, error, 1.0))
    lo, hi = diagnostics.ratio_range((nfev, error), (nfev * 2, error))
    assert abs(lo - 4.0) < 1e-9 and abs(hi - 4.0) < 1e-9


def test_kepler_acceleration_derivatives_against_finite_differences():
    t = np.linspace(0.0, 42.15, 40001)
    x, v = problems.kepler_exact(t, 0.6)
    a, a1, a2 = problems.acceleration_derivatives(x, v, 0.6)
    dt = t[1] - t[0]
    fd1 = np.gradient(a, dt, axis=1)
    fd2 = np.gradient(fd1, dt, axis=1)
    inner = slice(10, -10)
    assert np.max(np.abs(fd1 - a1)[:, inner]) < 1e-5 * np.abs(a1).max()
    assert np.max(np.abs(fd2 - a2)[:, inner]) < 1e-4 * np.abs(a2).max()


def test_orbit_elements_and_curvature_of_the_ellipse():
    """a = 3, b^2 = 5: curvature a/b^2 at both apsides, b/a^2 at r = a."""
    elements = problems.orbit_elements(0.6)
    assert abs(elements["a"] - 3) < 1e-12 and abs(elements["eccentricity"] - 2 / 3) < 1e-12
    t = np.linspace(0.0, elements["period"], 20001)
    x, v = problems.kepler_exact(t, 0.6)
    a, _, _ = problems.acceleration_derivatives(x, v, 0.6)
    kappa = problems.path_curvature(v, a)
    assert abs(kappa[0] - 3 / 5) < 1e-12 and abs(kappa[10000] - 3 / 5) < 1e-9
    assert abs(kappa.min() - np.sqrt(5) / 9) < 1e-6
