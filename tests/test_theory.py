"""The derived constants of splinestep.theory against measurements made with
the package: local errors, period error, stability limit, the Verlet
conjugacy, the higher-degree splines, and Verlet's order."""

import numpy as np
import sympy as sp

import splinestep
from splinestep import conjugacy, diagnostics, problems, theory
from splinestep.higher_degree import solve_degree


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
