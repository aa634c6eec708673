"""The reference solutions against independent closed forms."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from splinestep import problems
from splinestep.problems import euler_top, kepler

T = np.linspace(0, 50, 201)


def test_circular_orbit_is_cos_sin():
    x, v = problems.kepler_exact(T, 1.0)
    assert np.max(np.abs(x - [np.cos(T), np.sin(T)])) < 1e-12
    assert np.max(np.abs(v - [-np.sin(T), np.cos(T)])) < 1e-12


def test_elliptic_orbit_matches_classical_kepler_equation():
    mu = 0.6
    a, e = 3.0, 2.0 / 3.0  # from energy -0.1 and periapsis 1
    n = np.sqrt(mu / a ** 3)
    E = np.array([brentq(lambda E: E - e * np.sin(E) - n * t, 0, n * t + 1, xtol=1e-15, rtol=1e-15)
                  for t in T])
    x_ref = np.array([a * (np.cos(E) - e), a * np.sqrt(1 - e * e) * np.sin(E)])
    assert np.max(np.abs(problems.kepler_exact(T, mu)[0] - x_ref)) < 1e-12


def test_hyperbolic_orbit_matches_hyperbolic_kepler_equation():
    mu = 0.4
    a, e = 2.0, 1.5  # semi-major |a| = mu / (2 * 0.1), e = 1/mu - 1
    n = np.sqrt(mu / a ** 3)
    H = np.array([brentq(lambda H: e * np.sinh(H) - H - n * t, 0, 20, xtol=1e-15, rtol=1e-15)
                  for t in T])
    x_ref = np.array([a * (e - np.cosh(H)), a * np.sqrt(e * e - 1) * np.sinh(H)])
    assert np.max(np.abs(problems.kepler_exact(T, mu)[0] - x_ref)) < 1e-12


def test_parabolic_orbit_matches_barker_equation():
    mu, p = 0.5, 2.0  # p = h^2 / mu, periapsis p / 2 = 1
    # Barker: tan(f/2) + tan^3(f/2)/3 = 2 sqrt(mu / p^3) t, solved in closed form.
    m = 3 * np.sqrt(mu / p ** 3) * T
    D = np.cbrt(m + np.sqrt(m * m + 1)) - np.cbrt(np.sqrt(m * m + 1) - m)
    f = 2 * np.arctan(D)
    r = p / (1 + np.cos(f))
    x_ref = np.array([r * np.cos(f), r * np.sin(f)])
    assert np.max(np.abs(problems.kepler_exact(T, mu)[0] - x_ref)) < 1e-12




@pytest.mark.parametrize("mu", problems.CANNONBALL_MU)
def test_kepler_exact_conserves_invariants_and_solves_the_ode(mu):
    problem = problems.cannonball(mu)
    x, v = problem.exact(T)
    energy = problem.invariants["energy"](x, v)
    assert np.max(np.abs(energy - (0.5 - mu))) < 1e-13
    assert np.max(np.abs(problem.invariants["angular momentum"](x, v) - 1)) < 1e-13
    # v is the derivative of x: central difference of the exact solution.
    d = 1e-4
    xp, _ = problem.exact(T[1:] + d)
    xm, _ = problem.exact(T[1:] - d)
    assert np.max(np.abs((xp - xm) / (2 * d) - v[:, 1:])) < 1e-7


def test_report_energy_eq13_only_conserved_for_mu_1():
    for mu in problems.CANNONBALL_MU:
        x, v = problems.kepler_exact(T, mu)
        spread = np.ptp(kepler.energy_as_printed(x, v))
        assert (spread < 1e-12) == (mu == 1.0)


def euler_dop853(w0, t, moments=euler_top.MOMENTS):
    sol = solve_ivp(lambda s, w: euler_top.euler_rates(w, moments), (0, t[-1]), w0,
                    method="DOP853", t_eval=t, rtol=1e-13, atol=1e-15)
    return sol.y


@pytest.mark.parametrize("w0", [(1.0, 0.01, 0.01), (0.01, 0.02, 1.0), (-0.3, 0.5, -0.7),
                                (0.2, -0.9, 0.3)])
def test_euler_top_exact_matches_euler_equations(w0):
    t = np.linspace(0, 80, 321)
    w, wp = problems.euler_top_exact(t, w0)
    assert np.max(np.abs(w - euler_dop853(np.array(w0), t))) < 1e-10
    assert np.max(np.abs(wp - euler_top.euler_rates(w))) < 1e-15


def test_rigid_body_problem_initial_rates():
    consistent = problems.rigid_body("consistent")
    printed = problems.rigid_body("printed")
    assert np.allclose(consistent.yp0, [1e-4 / 3, -0.01, 0.01], rtol=1e-14, atol=0)
    assert np.all(printed.yp0 == 0)
    assert consistent.reference_kind == "exact"
    assert "DOP853" in printed.reference_kind
    # The second-order equations (eqs. 15-18, beta = 0) are satisfied by the exact motion.
    t = np.linspace(0, 20, 2001)
    w, wp = consistent.exact(t)
    dt = t[1] - t[0]
    wpp_fd = (wp[:, 2:] - wp[:, :-2]) / (2 * dt)
    rhs = np.array([consistent.fun.py_func(0.0, w[:, k], wp[:, k], *consistent.args)
                    for k in range(1, t.size - 1)]).T
    assert np.max(np.abs(wpp_fd - rhs)) < 1e-6


def test_printed_rates_change_the_energy_of_eq19():
    printed = problems.rigid_body("printed")
    t = np.linspace(0, 80, 801)
    w, wp = printed.reference(t)
    spread = np.ptp(printed.invariants["energy"](w, wp))
    assert 1e-5 < spread < 1e-3
