"""The derived constants of splinestep.analysis.family (Newmark's family and
its alpha members on the oscillator) against numeric measurements: the
amplification matrix against theory's 2 x 2 and against steps taken with the
family's formulas, the stability limits against a scan of the spectral
radius, the series against the numeric period error and damping ratio, and
the spectral radius at infinite step."""

import numpy as np
import pytest
import sympy as sp

from splinestep.analysis import family, theory

R = sp.Rational
EPS = np.finfo(float).eps
NEWMARK = family.MEMBERS
ALPHA = {"HHT a = 1/10": family.hht_parameters(R(1, 10)),
         "HHT a = 1/3": family.hht_parameters(R(1, 3)),
         "generalized-alpha rho = 0": family.generalized_alpha_parameters(0),
         "generalized-alpha rho = 4/5": family.generalized_alpha_parameters(R(4, 5))}
FIRST_ORDER = {"Newmark beta = 1/5, gamma = 3/5": (R(1, 5), R(3, 5), 0, 0)}
ALL = {**NEWMARK, **ALPHA, **FIRST_ORDER}


def terms(series, count):
    """The first ``count`` nonzero terms of a polynomial in Omega, as
    (power, coefficient), lowest power first."""
    poly = sp.Poly(series, family.Omega)
    found = sorted((m[0], c) for m, c in zip(poly.monoms(), poly.coeffs()))
    return found[:count]


@pytest.mark.parametrize("beta", [R(1, 6), R(1, 4), R(1, 12), R(0)])
def test_newmark_matrix_is_theorys_two_by_two_and_a_zero_eigenvalue(beta):
    A = family.amplification_matrix(beta, R(1, 2))
    M = theory.amplification(beta).subs(theory.x, family.Omega)
    lam = family.lam
    assert sp.simplify(A.det()) == 0
    assert sp.simplify(A.charpoly(lam).as_expr() - lam * M.charpoly(lam).as_expr()) == 0
    x = 0.7
    three = np.sort_complex(np.linalg.eigvals(family.amplification_matrices(x, beta, R(1, 2))))
    two = np.sort_complex(np.linalg.eigvals(np.array(M.subs(family.Omega, x), dtype=float)))
    assert np.abs(three[np.argmin(np.abs(three))]) < 1e-15
    assert np.allclose(np.delete(three, np.argmin(np.abs(three))), two, rtol=0, atol=1e-14)


def test_an_alpha_member_has_no_zero_eigenvalue():
    a = R(1, 10)
    A = family.amplification_matrix(*family.hht_parameters(a))
    # det A = det M0 / det M1 = -Omega^2 a (beta - a) / (1 + beta (1 - a) Omega^2),
    # beta - a = (1 - a)^2 / 4: the spurious root moves off 0 once Omega > 0
    Omega = family.Omega
    expected = -a * (1 - a) ** 2 * Omega ** 2 / (4 + (1 - a) * (1 + a) ** 2 * Omega ** 2)
    assert sp.simplify(A.det() - expected) == 0
    assert A.det().subs(Omega, 1) == R(-81, 5089)


def steps(params, omega, h, xi, state, count=10):
    """``count`` steps of the family's formulas (the module docstring of
    ``family``) on y'' = -omega^2 y - 2 xi omega y', in floating point,
    from (y, y', a); returns (y, h y', h^2 a) at the end."""
    beta, gamma, alpha_m, alpha_f = (float(c) for c in params)
    y, v, a = state
    for _ in range(count):
        y_known = y + h * v + h * h * (0.5 - beta) * a        # y_{n+1} - beta h^2 a_{n+1}
        v_known = v + h * (1 - gamma) * a
        # the acceleration equation is linear in a_{n+1}
        rhs = (-omega ** 2 * ((1 - alpha_f) * y_known + alpha_f * y)
               - 2 * xi * omega * ((1 - alpha_f) * v_known + alpha_f * v) - alpha_m * a)
        a_new = rhs / ((1 - alpha_m) + (1 - alpha_f) * (omega ** 2 * beta * h * h
                                                        + 2 * xi * omega * gamma * h))
        y, v, a = y_known + beta * h * h * a_new, v_known + gamma * h * a_new, a_new
    return np.array([y, h * v, h * h * a])


@pytest.mark.parametrize("xi", [R(0), R(1, 20)])
@pytest.mark.parametrize("name", sorted(ALL))
def test_matrix_power_is_ten_steps(name, xi):
    params, omega, h = ALL[name], 3.0, 0.2
    A = family.amplification_matrix(*params, xi=xi).subs(family.Omega, R(3, 5))
    powers = [np.array(A ** k, dtype=float) for k in range(11)]
    state = np.array([1.0, -0.5, 0.3])
    exact = powers[10] @ (state * [1, h, h * h])
    computed = steps(params, omega, h, float(xi), state)
    # each step's rounding (a few eps of the state) is carried by the
    # remaining powers of A: their norms bound the growth
    growth = max(np.linalg.norm(P, 2) for P in powers)
    assert growth < 5
    assert np.max(np.abs(computed - exact)) <= 1e-12 * np.max(np.abs(exact))
    assert np.max(np.abs(computed - exact)) <= 10 * 10 * EPS * growth * np.linalg.norm(state)


STABILITY = [
    ("linear acceleration", 2 * sp.sqrt(3)),
    ("Fox-Goodwin", sp.sqrt(6)),
    ("central difference", sp.Integer(2)),
    ("average acceleration", sp.oo),
    *((name, sp.oo) for name in ALPHA),
    ("Newmark beta = 1/5, gamma = 3/5", sp.sqrt(10)),
]


@pytest.mark.parametrize("name, limit", STABILITY)
def test_stability_limit_against_a_scan_of_the_spectral_radius(name, limit):
    params = ALL[name]
    assert family.stability_limit(*params) == limit
    x = np.linspace(1e-3, 20, 40001)
    unstable = x[family.spectral_radius(x, *params) > 1 + 1e-9]
    if limit == sp.oo:
        far = np.geomspace(20, 1e8, 200)
        assert unstable.size == 0 and np.all(family.spectral_radius(far, *params) <= 1 + 1e-9)
    else:
        # the first unstable point of the grid is the first past the limit
        assert float(limit) < unstable[0] <= float(limit) + (x[1] - x[0])


@pytest.mark.parametrize("beta, gamma", [(R(1, 6), R(1, 2)), (R(0), R(3, 5)), (R(1, 10), R(3, 4)),
                                         (R(3, 10), R(3, 4))])
def test_newmark_stability_limit_formula(beta, gamma):
    expected = 1 / sp.sqrt(gamma / 2 - beta)
    assert sp.simplify(family.stability_limit(beta, gamma) - expected) == 0
    assert family.stability_limit(float(beta), float(gamma)) == family.stability_limit(beta, gamma)


def test_an_unstable_and_a_conditionally_stable_alpha_member():
    # gamma below 1/2 - alpha_m + alpha_f amplifies from the smallest step on
    assert family.stability_limit(R(1, 4), R(1, 2), R(1, 5), R(2, 5)) == 0
    assert family.spectral_radius(0.1, R(1, 4), R(1, 2), R(1, 5), R(2, 5)) > 1 + 1e-6
    limit = family.stability_limit(R(1, 6), R(1, 2), R(1, 4), R(1, 5))
    assert limit == sp.sqrt(10)
    radius = family.spectral_radius([0.999 * float(limit), 1.001 * float(limit)],
                                    R(1, 6), R(1, 2), R(1, 4), R(1, 5))
    assert radius[0] <= 1 and radius[1] > 1 + 1e-6


PERIOD_LEADING = {
    "linear acceleration": (2, R(1, 24)),
    "average acceleration": (2, R(1, 12)),
    "Fox-Goodwin": (4, R(-1, 480)),
    "central difference": (2, R(-1, 24)),
    # HHT: (2 + 6 a - 9 a^2)/24; generalized-alpha: (11 rho^2 - 14 rho + 11)/(24 (1 + rho)^2);
    # Newmark: (48 beta + 12 gamma^2 - 36 gamma + 11)/96
    "HHT a = 1/10": (2, R(251, 2400)),
    "HHT a = 1/3": (2, R(1, 8)),
    "generalized-alpha rho = 0": (2, R(11, 24)),
    "generalized-alpha rho = 4/5": (2, R(19, 216)),
    "Newmark beta = 1/5, gamma = 3/5": (2, R(83, 2400)),
}
DAMPING_LEADING = {
    # HHT: a (1 - a)^2 / 8; generalized-alpha: (1 - rho)^3 / (2 (1 + rho)^3);
    # Newmark: (gamma - 1/2) / 2
    "HHT a = 1/10": (3, R(81, 8000)),
    "HHT a = 1/3": (3, R(1, 54)),
    "generalized-alpha rho = 0": (3, R(1, 2)),
    "generalized-alpha rho = 4/5": (3, R(1, 1458)),
    "Newmark beta = 1/5, gamma = 3/5": (1, R(1, 20)),
}


def fitted_leading(measure, params, power, x):
    """The least-squares c of measure(x) = c x^power over the points x."""
    values = measure(x, *params)
    return np.sum(values * x ** power) / np.sum(x ** (2 * power))


def check_leading(measure, params, series):
    """The series' leading coefficient c Omega^p against the c fitted to
    the measure on Omega up to where the next term d Omega^q is 1/1000 of
    it (at most 0.2); the tolerance is twice the bias that the next term
    gives the fit plus the measure's rounding: the pair's eigenvalues are
    about 2 Omega apart, so that their rounding is eps / Omega and the
    ratio divides by Omega again, eps / Omega^2 in the measure."""
    (p, c), (q, d) = terms(series, 2)
    x = np.linspace(0.5, 1, 6) * min(0.2, float(abs(c / d) / 1000) ** (1 / (q - p)))
    fitted = fitted_leading(measure, params, p, x)
    bias = abs(d) * np.sum(x ** (p + q)) / np.sum(x ** (2 * p))
    rounding = 10 * EPS / np.min(x) ** (p + 2)
    tolerance = 2 * bias + rounding
    assert tolerance < 0.01 * abs(c)               # the check resolves c to 1 %
    assert abs(fitted - float(c)) <= tolerance
    return fitted


@pytest.mark.parametrize("name", sorted(PERIOD_LEADING))
def test_period_error_series_against_the_measured_period_error(name):
    params = ALL[name]
    series = family.period_error_series(*params, order=8)
    assert terms(series, 1)[0] == PERIOD_LEADING[name]
    check_leading(family.period_error, params, series)


@pytest.mark.parametrize("name", sorted(DAMPING_LEADING))
def test_damping_series_against_the_measured_damping_ratio(name):
    params = ALL[name]
    series = family.damping_series(*params, order=7)
    assert terms(series, 1)[0] == DAMPING_LEADING[name]
    check_leading(family.damping_ratio, params, series)


@pytest.mark.parametrize("name", sorted(NEWMARK))
def test_gamma_half_newmark_members_do_not_damp(name):
    params = NEWMARK[name]
    assert family.damping_series(*params, order=9) == 0
    x = np.geomspace(0.005, 0.9 * min(3.0, float(family.stability_limit(*params))), 200)
    # |lambda| = 1 to rounding: the pair's eigenvalues are 2 sin(Omega)
    # apart (rounding eps / Omega), and the ratio divides by Omega again
    assert np.all(np.abs(family.damping_ratio(x, *params)) <= 100 * EPS / x ** 2)


@pytest.mark.parametrize("name", sorted(ALPHA))
def test_alpha_members_are_second_order(name):
    params = ALL[name]
    period = family.period_error_series(*params, order=4)
    damping = family.damping_series(*params, order=4)
    assert terms(period, 1)[0][0] == 2 and terms(damping, 1)[0][0] == 3
    x = np.geomspace(0.01, 0.04, 5)
    slope_period = np.polyfit(np.log(x), np.log(np.abs(family.period_error(x, *params))), 1)[0]
    slope_damping = np.polyfit(np.log(x), np.log(family.damping_ratio(x, *params)), 1)[0]
    assert abs(slope_period - 2) < 0.01 and abs(slope_damping - 3) < 0.01


def test_first_order_member_damps_at_first_order():
    params = FIRST_ORDER["Newmark beta = 1/5, gamma = 3/5"]
    x = np.geomspace(0.01, 0.04, 5)
    slope = np.polyfit(np.log(x), np.log(family.damping_ratio(x, *params)), 1)[0]
    assert abs(slope - 1) < 0.01


def test_oscillatory_range_ends_at_the_limit_for_newmark():
    # beyond Omega_crit the principal roots are real: no period, no damping
    for name, limit in [("linear acceleration", 2 * np.sqrt(3)), ("central difference", 2.0)]:
        params = NEWMARK[name]
        inside, outside = family.period_error([0.99 * limit, 1.01 * limit], *params)
        assert np.isfinite(inside) and np.isnan(outside)
        assert np.isnan(family.damping_ratio(1.01 * limit, *params))
    assert np.all(np.isfinite(family.period_error(np.geomspace(1e-2, 1e4, 50),
                                                  *family.hht_parameters(R(1, 3)))))


@pytest.mark.parametrize("rho", [R(0), R(1, 2), R(4, 5), R(1)])
def test_generalized_alpha_rho_infinity_is_its_rho(rho):
    params = family.generalized_alpha_parameters(rho)
    assert family.rho_infinity(*params) == rho
    # the three roots meet at -rho at infinity: they approach it as Omega^(-2/3)
    assert abs(family.spectral_radius(1e6, *params) - float(rho)) < 2e-4


@pytest.mark.parametrize("name, expected", [
    ("average acceleration", sp.Integer(1)),
    ("linear acceleration", 2 + sp.sqrt(3)),
    ("Fox-Goodwin", 5 + 2 * sp.sqrt(6)),
    ("central difference", sp.oo),
    ("HHT a = 1/10", R(9, 11)),                     # (1 - a) / (1 + a)
    ("HHT a = 1/3", R(1, 2)),
])
def test_rho_infinity_of_the_other_members(name, expected):
    params = ALL[name]
    value = family.rho_infinity(*params)
    assert value == expected if expected == sp.oo else sp.simplify(value - expected) == 0
    radius = family.spectral_radius(1e6, *params)
    if expected == sp.oo:
        assert radius > 1e11                        # grows as Omega^2
    else:
        assert abs(radius - float(expected)) < 2e-4
