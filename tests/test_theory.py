"""The derived constants of splinestep.analysis.theory against measurements made with
the package: local errors, period error, stability limit, the Verlet
conjugacy, the higher-degree splines, and Verlet's order."""

import warnings

import numpy as np
import sympy as sp

import splinestep
from splinestep import problems
from splinestep.analysis import conjugacy, diagnostics, theory
from splinestep.analysis.higher_degree import solve_degree


def test_local_error_constants_match_one_measured_step():
    err_y, err_yp = theory.local_errors()
    c_y = float(err_y.coeff(theory.h, 4).coeff(theory.Y[4]))
    c_yp = float(err_yp.coeff(theory.h, 3).coeff(theory.Y[4]))
    h = 0.01
    step = splinestep.solve(lambda t, y, yp: -y, (0.0, h), 1.0, 0.0, h, tol=1e-15)
    # y = cos t: y'''' = 1 at t = 0; the next terms are O(h) smaller
    assert abs((step.y[0, -1] - np.cos(h)) / h ** 4 - c_y) < 1e-2 * c_y
    assert abs((step.yp[0, -1] + np.sin(h)) / h ** 3 - c_yp) < 1e-2 * c_yp


def test_two_step_relation_order_and_period_error():
    rho, sigma, residual = theory.two_step()
    assert residual == 0
    C = theory.error_constants([rho.coeff(theory.zeta, j) for j in range(3)],
                               [sigma.coeff(theory.zeta, j) for j in range(3)])
    assert C[:4] == [0, 0, 0, 0] and C[4] == sp.Rational(-1, 12)
    cos_theta = sp.simplify(theory.amplification().trace() / 2)
    series = theory.period_error(cos_theta)
    x = 0.1
    problem = problems.harmonic(omega=1.0, t_span=(0.0, 400 * x), h=x)
    res = problem.solve(iteration="newton", tol=1e-15)
    measured = x / diagnostics.recurrence_fit(res.y[0])[1] - 1
    assert abs(measured - float(series.subs(theory.x, x))) < 1e-9
    assert theory.oscillator_period_error(x) == measured


def test_verlet_in_other_variables_is_the_same_relation():
    """Q = q - h^2 f(q)/6 turns the spline's relation into Verlet's: the
    difference simplifies to 0, and with sigma = zeta (Verlet's own
    relation in q) instead it would not."""
    assert theory.verlet_in_other_variables() == 0
    q0, q1, q2, f0, f1, f2 = sp.symbols("q0 q1 q2 f0 f1 f2")
    plain = theory.h ** 2 * f1 - (q0 - 2 * q1 + q2)
    spline = theory.h ** 2 * (f0 + 4 * f1 + f2) / 6 - (q0 - 2 * q1 + q2)
    assert sp.simplify(plain - spline) != 0


def test_derivations_typeset_as_latex():
    err_y, _ = theory.local_errors()
    assert theory.latex(err_y, "rev-lex") == (r"\frac{h^{4} y^{(4)}}{24} + \frac{7 h^{5} y^{(5)}}{360}"
                                              r" + \frac{h^{5} q y^{(4)}}{72}")
    assert theory.aligned([("a", theory.x ** 2 / 6), ("b", r"\sqrt{6}")]) == \
        r"\begin{aligned}a &= \frac{x^{2}}{6} \\ b &= \sqrt{6}\end{aligned}"


def test_constants_table_shows_each_value_to_its_digits():
    import pandas as pd
    frame = pd.DataFrame([("a", sp.Rational(1, 12), 0.0833300000669, 6),
                          ("b", 2 + sp.sqrt(3), 3.73655807545, 4),
                          ("c", 2 * sp.sqrt(3), 3.4641016151, 10),
                          ("d", sp.Integer(0), 1.50118600883e-09, 2)],
                         columns=["quantity", "exact", "measured", "digits"])
    table = theory.constants_table(frame)
    assert list(table["derived"]) == ["1/12", "2 + sqrt(3)", "2sqrt(3)", "0"]
    assert list(table["derived value"]) == ["0.0833333", "3.732", "3.464101615", "0"]
    assert list(table["measured"]) == ["0.0833300", "3.737", "3.464101615", "1.5e-09"]


def test_measured_step_matrix_is_the_derived_one_and_the_limits_are_found():
    derived = sp.lambdify(theory.x, theory.amplification())
    for x in (0.5, 2.0, 5.0, 15.0):
        measured = theory.oscillator_step_matrix(x, tol=1e-10)
        assert np.max(np.abs(measured - np.array(derived(x), float))) < 1e-12 * max(1, x * x)
    assert abs(theory.bisect(lambda v: v * v >= 2.0, 1.0, 2.0, steps=50) - np.sqrt(2)) < 1e-12
    assert theory.sweep_converges(2.4) and not theory.sweep_converges(2.5, max_iter=1000)


def test_verlet_on_the_modified_force_reproduces_the_spline():
    ellipse = problems.cannonball(0.6)
    h = ellipse.h
    n = int(round(10 * problems.orbit_elements(0.6)["period"] / h))
    t = h * np.arange(0, n + 1, 97)
    spline = splinestep.solve(ellipse.fun, (0.0, n * h), ellipse.y0, ellipse.yp0, h,
                              args=ellipse.args, t_eval=t)
    Q, P = conjugacy.to_verlet(t, spline.y, spline.yp, ellipse.fun, h, ellipse.args)
    force = conjugacy.modified_force(ellipse.fun, ellipse.jac, h, ellipse.args)
    verlet = splinestep.verlet(force, (0.0, n * h), Q[:, 0], P[:, 0], h, t_eval=t)
    assert np.max(np.abs(verlet.y - Q)) < 1e-9 and np.max(np.abs(verlet.yp - P)) < 1e-9
    plain = splinestep.verlet(ellipse.fun, (0.0, n * h), ellipse.y0, ellipse.yp0, h,
                              args=ellipse.args, t_eval=t)
    assert np.max(np.abs(plain.y - spline.y)) > 1e-3
    # conjugacy.compare (notebook 05) measures the same
    found = conjugacy.compare(ellipse, n, every=97)
    assert np.array_equal(found["spline"].y, spline.y)
    assert found["conjugate_gap"] == max(np.max(np.abs(verlet.y - Q)), np.max(np.abs(verlet.yp - P)))
    assert found["plain_gap"] == np.max(np.abs(plain.y - spline.y))
    # Verlet's exact angular momentum Q x P, in the spline's variables
    r = np.hypot(*spline.y)
    L = (1 + h * h * 0.6 / (6 * r ** 3)) * (spline.y[0] * spline.yp[1] - spline.y[1] * spline.yp[0])
    assert np.ptp(L) < 1e-12


def test_higher_degree_splines_roots_and_orders():
    f = lambda t, y, yp: -y  # noqa: E731
    cubic = solve_degree(f, (0.0, 5.0), 1.0, 0.0, 0.1, 3)
    assert np.max(np.abs(cubic.y - splinestep.solve(f, (0.0, 5.0), 1.0, 0.0, 0.1).y)) < 1e-13
    assert sp.factor(theory.characteristic_at_zero(5)) == sp.factor(
        theory.zeta * (theory.zeta - 1) ** 2 * (theory.zeta ** 2 + 4 * theory.zeta + 1))
    res = solve_degree(f, (0.0, 1.5), 1.0, 0.0, 0.05, 5, derivatives=[[0.0], [1.0]])
    e = np.abs(res.y[0] - np.cos(res.t))
    use = e > 1e-10
    factor = np.exp(np.polyfit(np.arange(e.size)[use], np.log(e[use]), 1)[0])
    assert abs(factor - (2 + np.sqrt(3))) < 0.01 * (2 + np.sqrt(3))
    errors = [np.max(np.abs(solve_degree(f, (0.0, 10.0), 1.0, 0.0, h, 4, derivatives=[[0.0]]).y[0]
                            - np.cos(np.arange(0.0, 10.0 + h / 2, h)))) for h in (0.1, 0.05)]
    assert 3.8 < np.log2(errors[0] / errors[1]) < 4.2


def test_verlet_is_second_order_with_damping():
    w = np.sqrt(1 - 0.0625)
    exact = np.exp(-2.5) * (np.cos(10 * w) + 0.25 / w * np.sin(10 * w))
    errors = [abs(splinestep.verlet(lambda t, y, yp: -y - 0.5 * yp, (0, 10), 1.0, 0.0, h).y[0, -1]
                  - exact) for h in (0.05, 0.025)]
    assert 1.9 < np.log2(errors[0] / errors[1]) < 2.1


def test_solve_degree_names_its_bad_arguments():
    import pytest
    f = lambda t, y, yp: -y  # noqa: E731
    for kwargs, name in ((dict(degree=2), "degree"), (dict(degree=4), "derivatives"),
                         (dict(degree=4, derivatives=[[0.0, 1.0]]), "derivatives"),
                         (dict(degree=4, derivatives="x"), "derivatives")):
        with pytest.raises(ValueError, match=name):
            solve_degree(f, (0.0, 1.0), 1.0, 0.0, 0.1, **kwargs)


def _ellipse_run(solver, orbits, h):
    ellipse = problems.cannonball(0.6)
    period = problems.orbit_elements(0.6)["period"]
    t = h * np.arange(int(round(orbits * period / h)) + 1)
    res = solver(ellipse.fun, (0.0, t[-1]), ellipse.y0, ellipse.yp0, h, args=ellipse.args,
                 t_eval=t)
    return t, res.y, ellipse.reference(t)[0], period


def test_phase_drift_measured_two_ways_agrees_and_both_methods_lag():
    """The polar angle's drift per orbit from the unwrapped angle error against
    the exact solution, and from the periapsis passages alone (period and turn
    of the periapsis): two independent measurements of one number.  Over 40
    orbits the orbit-averaged angle error still carries the within-orbit
    oscillation at O(1/orbits) of the drift, so they must agree to a few per
    cent; both methods lag, the spline by more."""
    drifts = {}
    for name, solver in (("spline", splinestep.solve), ("verlet", splinestep.verlet)):
        t, y, exact, period = _ellipse_run(solver, 40, 0.01)
        by_angle = diagnostics.phase_drift_from_angle(t, y, exact, period)
        by_passages, period_error, precession = diagnostics.phase_drift_from_passages(
            t, y, period)
        assert abs(by_passages / by_angle - 1) < 0.03
        assert by_angle < 0 and period_error > 0
        drifts[name] = (by_angle, precession)
    assert 1.4 < drifts["spline"][0] / drifts["verlet"][0] < 2.0
    # the periapsis turns by equal and opposite amounts (the conjugacy's phi is
    # radial, the two methods' error constants are opposite)
    assert abs(drifts["spline"][1] + drifts["verlet"][1]) < 0.05 * abs(drifts["spline"][1])


def test_phase_drift_scales_as_h_squared():
    """A second-order method's drift per orbit shrinks 4 times when h halves."""
    drift = {}
    for h in (0.02, 0.01):
        t, y, _, period = _ellipse_run(splinestep.solve, 10, h)
        drift[h] = diagnostics.phase_drift_from_passages(t, y, period)[0]

    assert abs(drift[0.02] / drift[0.01] - 4.0) < 0.1


def test_phase_drift_diagnostics_recover_a_known_drift():
    """On a synthetic orbit whose angle lags by exactly c per orbit and whose
    periapsis turns by p per orbit, both measurements return them."""
    period, c, p = 2.0, -3e-3, 1e-3
    t = np.linspace(0.0, 20 * period, 20 * 4000 + 1)
    mean_anomaly = 2 * np.pi * t / period
    e = 0.5
    E = mean_anomaly.copy()
    for _ in range(50):
        E = mean_anomaly + e * np.sin(E)
    r = 1 - e * np.cos(E)
    nu = 2 * np.arctan2(np.sqrt(1 + e) * np.sin(E / 2), np.sqrt(1 - e) * np.cos(E / 2))
    exact = np.vstack([r * np.cos(nu), r * np.sin(nu)])
    orbit_count = t / period
    # the computed orbit: period stretched so that the angle lags by (c - p) per
    # orbit through the timing, and turned by p per orbit
    stretch = 1 + (c - p) / (2 * np.pi)
    E2 = mean_anomaly * stretch
    for _ in range(50):
        E2 = mean_anomaly * stretch + e * np.sin(E2)
    r2 = 1 - e * np.cos(E2)
    nu2 = 2 * np.arctan2(np.sqrt(1 + e) * np.sin(E2 / 2), np.sqrt(1 - e) * np.cos(E2 / 2))
    turn = p * orbit_count * stretch
    y = np.vstack([r2 * np.cos(nu2 + turn), r2 * np.sin(nu2 + turn)])
    by_passages, _, precession = diagnostics.phase_drift_from_passages(t, y, period)
    assert abs(precession - p) < 1e-5
    assert abs(by_passages - c) < 2e-5
    assert abs(diagnostics.phase_drift_from_angle(t, y, exact, period) - c) < 2e-4


def test_starting_errors_must_be_of_order_p_plus_1():
    """Henrici's hypothesis on the starting values: y_0 off by h^2 (y_1 exact)
    costs one order, y_0 off by h^3 does not, and the package's start (y_0
    exact, y_1 one step) gives order 2; the two-step recurrence started as the
    package starts reproduces the package's run."""
    steps = np.array([0.1, 0.05, 0.025, 0.0125])

    def order(start):
        return theory.two_step_order(start, steps, 10.0)

    def package(h):
        return 1.0, splinestep.solve(lambda t, y, yp: -y, (0.0, h), 1.0, 0.0, h, tol=1e-15).y[0, 1]

    assert abs(order(package) - 2) < 0.05
    assert abs(order(lambda h: (1 + h ** 2, np.cos(h))) - 1) < 0.05
    assert abs(order(lambda h: (1 + h ** 3, np.cos(h))) - 2) < 0.05
    run = splinestep.solve(lambda t, y, yp: -y, (0.0, 10.0), 1.0, 0.0, 0.05, tol=1e-15)
    recurrence = theory.two_step_oscillator(1.0, run.y[0, 1], 0.05, run.nstep)
    assert np.max(np.abs(recurrence - run.y[0])) < 1e-12


def test_knots_satisfy_the_two_step_relation_with_f_evaluated_afresh():
    """The relation holds to rounding for converged steps, and visibly not for
    one sweep per step (so the check can fail)."""
    ellipse = problems.cannonball(0.6)
    assert ellipse.h == 0.01

    def residual(run):
        return theory.relation_residual(ellipse, run)

    assert residual(ellipse.solve(h=0.01, tol=1e-15, t_eval=None)) < 1e-14
    assert residual(ellipse.solve(h=0.01, iterations=1, t_eval=None)) > 1e-13


def test_one_sweep_costs_verlets_one_evaluation_per_step():
    ellipse = problems.cannonball(0.6)
    one = ellipse.solve(h=0.01, iterations=1)
    verlet = ellipse.solve("verlet", h=0.01)
    # The spline run also counts its step-size check: 2m + 1 evaluations at
    # each of three states (m = 2).
    assert one.nfev - 3 * (2 * 2 + 1) == verlet.nfev == one.nstep + 1


def test_energy_error_is_the_modified_energy_correction_and_does_not_drift():
    """Backward error analysis predicts the spline's energy error without the
    run's H: H - H0 = -(c - c0) + O(h^4), c = h^2 (|grad V|^2/24 + V_qq(v, v)/12)
    (section 4).  The neglected terms are h^2 times smaller than c times
    factors of order one on this orbit, so the prediction must hold to 10 h^2
    of the error (a wrong coefficient or sign leaves an error of its own size).
    And the largest error in the last of 300 orbits equals that in the first
    to 5 %: a drift like RK4's at equal work (linear, 1.5e-10 + 1.6e-11 (k - 1) in
    orbit k) would multiply it by 30."""
    from splinestep.problems import kepler
    mu, h = 0.6, 0.01
    ellipse = problems.cannonball(mu)
    period = problems.orbit_elements(mu)["period"]
    n = int(round(300 * period / h))
    per_orbit = int(period / h)
    steps = np.r_[np.arange(per_orbit), np.arange(n - per_orbit, n + 1)]
    res = splinestep.solve(ellipse.fun, (0.0, n * h), ellipse.y0, ellipse.yp0, h,
                           args=ellipse.args, t_eval=h * steps)
    y, v = res.y, res.yp
    r = np.hypot(*y)
    vqq = mu * (np.sum(v * v, axis=0) / r ** 3 - 3 * np.sum(y * v, axis=0) ** 2 / r ** 5)
    c = h * h * (mu ** 2 / r ** 4 / 24 + vqq / 12)
    H = kepler.energy(mu)(y, v)
    error = H - H[0]
    assert np.max(np.abs(error + c - c[0])) < 10 * h * h * np.max(np.abs(error))
    first, last = np.max(np.abs(error[:per_orbit])), np.max(np.abs(error[per_orbit:]))
    assert abs(last / first - 1) < 0.05


def _orbit_maxima(res, period, orbits, invariant, value0):
    """Largest |invariant - value0| in each of ``orbits`` (1-based) of a run
    sampled inside those orbits."""
    orbit = np.floor(res.t / period).astype(int) + 1
    error = np.abs(invariant(res.y, res.yp) - value0)
    return np.array([error[orbit == k].max() for k in orbits])


def _samples(orbits, period, step, per_orbit=64):
    """``per_orbit`` times inside each orbit, each a multiple of ``step``."""
    wanted = ((np.asarray(orbits)[:, None] - 1 + (np.arange(per_orbit) + 0.5) / per_orbit)
              * period).ravel()
    return step * np.round(wanted / step)


def test_rk4_energy_error_drifts_linearly_at_its_own_steps():
    """RK4 at the converged spline's work on the ellipse (step 0.01823): at its
    own steps the largest energy error in orbit k is a + c (k - 1), so that
    e_k - e_1 is proportional to k - 1 (log-log slope 1 from orbit 2 on, where
    a power law fitted to e_k itself gives less than 1 until c k >> a).
    Sampled at the spline's knots (multiples of 0.01) instead, RK4's values
    come from the cubic Hermite interpolant between its steps, whose own
    error is several times RK4's in the early orbits."""
    from splinestep.problems import kepler
    mu, h_rk4 = 0.6, 0.01823
    ellipse = problems.cannonball(mu)
    period = problems.orbit_elements(mu)["period"]
    orbits = np.array([1, 2, 4, 10, 30, 100, 300])
    energy = kepler.energy(mu)
    h0 = energy(ellipse.y0[:, None], ellipse.yp0[:, None])[0]
    own = splinestep.rk4(ellipse.fun, (0.0, 300 * period), ellipse.y0, ellipse.yp0, h_rk4,
                         args=ellipse.args, t_eval=_samples(orbits, period, h_rk4))
    e = _orbit_maxima(own, period, orbits, energy, h0)
    slope = np.polyfit(np.log(orbits[1:] - 1), np.log(e[1:] - e[0]), 1)[0]
    assert abs(slope - 1) < 0.05, slope
    drift, start = np.polyfit(orbits - 1, e, 1)
    assert abs(start / e[0] - 1) < 0.05 and abs(e[-1] / (start + 299 * drift) - 1) < 0.05
    between = splinestep.rk4(ellipse.fun, (0.0, 5 * period), ellipse.y0, ellipse.yp0, h_rk4,
                             args=ellipse.args, t_eval=_samples([4], period, 0.01))
    assert _orbit_maxima(between, period, [4], energy, h0)[0] > 2 * e[2]


def test_stability_limit_is_excluded_and_measured_below_it():
    """Stable for omega h < sqrt(12) only: the half trace of the step matrix,
    measured from one Newton-solved step of (y, h y') = (1, 0) and (0, 1),
    is above -1 just below sqrt(12) and below -1 just above it; at sqrt(12)
    itself the matrix is a Jordan block -I + N, N^2 = 0, and from (0, 1) the
    solution grows linearly, |y_n| = n/3 exactly (a growth that a threshold
    on |y| mistakes for stability)."""
    osc = problems.harmonic(omega=1.0)

    def run(x, y0, v0, steps):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # these steps are meant to be too large
            return splinestep.solve(osc.fun, (0.0, steps * x), np.asarray(y0, float),
                                    np.asarray(v0, float) / x, x, args=osc.args,
                                    jac=osc.jac, iteration="newton", tol=1e-15)

    def half_trace(x):
        res = run(x, [1.0, 0.0], [0.0, 1.0], 1)
        return 0.5 * (res.y[0, -1] + x * res.yp[1, -1])

    limit = np.sqrt(12.0)
    assert half_trace(limit * (1 - 1e-9)) > -1 > half_trace(limit * (1 + 1e-9))
    at_limit = run(limit, [0.0], [1.0], 1000)
    y = np.abs(at_limit.y[0, [10, 100, 1000]])
    assert np.allclose(y, np.array([10, 100, 1000]) / 3, rtol=1e-4)


def test_one_sweep_drifts_in_energy_and_shortens_the_period():
    """One fixed-point sweep per step keeps order 2 but is not symmetric: on
    the ellipse at h = 0.01 its energy error grows linearly (by about
    1.2e-7 per orbit against 6.4e-6 in the first), so that by orbit 1,000 it
    is 10 to 40 times the first orbit's, while the converged step's stays
    within 1 %.  Its energy drifts down, the orbit shrinks and the period
    shortens from orbit to orbit: the period fitted to the periapsis passages
    of the first 200 orbits is shorter, by more than 1e-4 of T, than that of
    the first 20 (measured: -8.7e-5 against +7.9e-5 of T), where the
    converged step's period error is the same in both windows to 2 %."""
    from splinestep.problems import kepler
    mu, h = 0.6, 0.01
    ellipse = problems.cannonball(mu)
    period = problems.orbit_elements(mu)["period"]
    energy = kepler.energy(mu)
    h0 = energy(ellipse.y0[:, None], ellipse.yp0[:, None])[0]
    orbits = np.array([1, 1000])
    ratios = {}
    for sweeps in (1, None):
        kwargs = dict(iterations=1) if sweeps else {}
        res = splinestep.solve(ellipse.fun, (0.0, 1000 * period), ellipse.y0, ellipse.yp0, h,
                               args=ellipse.args, t_eval=_samples(orbits, period, h), **kwargs)
        first, last = _orbit_maxima(res, period, orbits, energy, h0)
        ratios[sweeps] = last / first
        if sweeps:
            assert np.mean(energy(res.y, res.yp)[-64:]) < h0
    assert 10 < ratios[1] < 40 and abs(ratios[None] - 1) < 0.01
    t = h * np.arange(int(round(200 * period / h)) + 1)
    short = t <= 20 * period
    errors = {}
    for sweeps in (1, None):
        kwargs = dict(iterations=1) if sweeps else {}
        res = splinestep.solve(ellipse.fun, (0.0, t[-1]), ellipse.y0, ellipse.yp0, h,
                               args=ellipse.args, t_eval=t, **kwargs)
        errors[sweeps] = [diagnostics.phase_drift_from_passages(t[w], res.y[:, w], period)[1]
                          for w in (short, slice(None))]
    assert errors[1][1] < errors[1][0] - 1e-4
    assert abs(errors[None][1] / errors[None][0] - 1) < 0.02
