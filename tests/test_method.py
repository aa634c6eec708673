"""The stepper's defining properties, each against an independent formula."""

import warnings

import numpy as np
import pytest
from scipy.optimize import fsolve

import splinestep
from splinestep import problems


def newmark(fun, args, t0, y0, yp0, h, n, beta, gamma):
    """Newmark's method, written independently: solve each step's implicit
    equation for the new acceleration with scipy's fsolve."""
    rhs = fun
    fun = lambda *a: np.asarray(rhs(*a))
    y, yp = np.array(y0, float), np.array(yp0, float)
    a = fun(t0, y, yp, *args)
    ys = [y]
    for i in range(n):
        t1 = t0 + (i + 1) * h

        def new_state(a1):
            y1 = y + h * yp + h * h * ((0.5 - beta) * a + beta * a1)
            yp1 = yp + h * ((1 - gamma) * a + gamma * a1)
            return y1, yp1

        a1 = fsolve(lambda a1: a1 - fun(t1, *new_state(a1), *args), a, xtol=1e-15)
        y, yp = new_state(a1)
        a = a1
        ys.append(y)
    return np.array(ys).T


def test_spline_step_is_newmark_linear_acceleration():
    problem = problems.cannonball(0.6)
    n, h = 300, 0.01
    res = splinestep.solve(problem.fun.py_func, (0, n * h), problem.y0, problem.yp0, h,
                           args=problem.args, tol=1e-15, max_iter=100)
    ref = newmark(problem.fun.py_func, problem.args, 0.0, problem.y0, problem.yp0, h, n,
                  beta=1 / 6, gamma=0.5)
    assert np.max(np.abs(res.y - ref)) < 1e-12


def test_fixed_point_and_newton_agree_to_tolerance():
    problem = problems.cannonball(0.6)
    fixed = problem.solve("spline", iteration="fixed-point", tol=1e-13)
    newton = problem.solve("spline", iteration="newton", tol=1e-13)
    newton_fd = problem.solve("spline", iteration="newton", tol=1e-13, jac=None)
    scale = np.max(np.abs(fixed.y))
    assert np.max(np.abs(fixed.y - newton.y)) < 1e-9 * scale
    assert np.max(np.abs(newton_fd.y - newton.y)) < 1e-9 * scale
    assert newton.njev > 0 and newton_fd.njev == 0


@pytest.mark.parametrize("k", [1, 2, 5])
def test_fixed_number_of_sweeps(k):
    problem = problems.cannonball(0.5)
    res = problem.solve("spline", iterations=k)
    assert res.nstep == 5000
    assert res.nfev == 1 + k * res.nstep + 3 * (2 * 2 + 1)  # the start, the steps, the check
    assert res.niter == k * res.nstep


def test_newton_exact_in_one_iteration_on_linear_problem():
    """One Newton update solves a linear step equation exactly (with the
    exact Jacobian; finite differences leave a relative error near 1e-8)."""
    p = lambda t: 0.3 + np.sin(t)
    fun = splinestep.linear(p, 4.0, np.cos)
    jac = lambda t, y, yp: (-4.0 * np.eye(1), -p(t) * np.eye(1))
    converged = splinestep.solve(fun, (0, 10), 1.0, 0.0, 0.05, tol=1e-15, max_iter=200)
    one = splinestep.solve(fun, (0, 10), 1.0, 0.0, 0.05, iteration="newton",
                           iterations=1, jac=jac, reuse_jacobian=False)
    assert np.max(np.abs(one.y - converged.y)) < 1e-13
    # Every call counted: fun at t0, once per step; jac at t0 (the argument
    # check), once per step, and at the three states of the step-size check.
    assert one.nfev == 1 + one.nstep and one.njev == 1 + one.nstep + 3
    one_fd = splinestep.solve(fun, (0, 10), 1.0, 0.0, 0.05, iteration="newton", iterations=1,
                              reuse_jacobian=False)
    assert np.max(np.abs(one_fd.y - converged.y)) < 1e-8
    # residual + one difference column per step, 3 (2m + 1) for the check
    assert one_fd.nfev == 1 + 2 * one_fd.nstep + 3 * 3


def test_one_sweep_is_already_second_order():
    """The report's 'a few times' is not needed for the order: one sweep
    (a predictor-corrector) keeps order 2."""
    problem = problems.cannonball(0.6)
    t_eval = np.linspace(0, 50, 126)
    x, _ = problem.reference(t_eval)
    hs = np.array([0.02, 0.01, 0.005])
    errors = [np.max(np.abs(problem.solve(h=h, iterations=1, t_eval=t_eval).y - x)) for h in hs]
    order = np.polyfit(np.log(hs), np.log(errors), 1)[0]
    assert 1.9 <= order <= 2.1


@pytest.mark.parametrize("x", [0.5, 1.5, 2.5, 3.3])
def test_phase_error_matches_closed_form(x):
    """On y'' = -w^2 y the method rotates by Omega h per step with
    cos(Omega h) = 1 - x^2 / (2 + x^2/3), x = w h, and keeps the amplitude
    of the modified energy (no numerical damping)."""
    h = 0.1
    omega = x / h
    problem = problems.harmonic(omega, t_span=(0, 200 * h), h=h)
    with pytest.warns(UserWarning, match="The step is too large"):   # the phase drifts
        res = problem.solve("spline", iteration="newton")
    # The exact discrete solution: y_n = A cos(n Omega h) + B sin(n Omega h).
    theta = np.arccos(1 - x * x / (2 + x * x / 3))
    n = np.arange(res.t.size)
    basis = np.stack([np.cos(n * theta), np.sin(n * theta)], axis=1)
    coef, *_ = np.linalg.lstsq(basis, res.y[0], rcond=None)
    assert np.max(np.abs(basis @ coef - res.y[0])) < 1e-10


def test_unstable_beyond_sqrt12():
    """Past omega h = sqrt(12) the solution grows by orders of magnitude: a
    failure, whose message names omega h, estimated from the growth of one
    linearised step (the inverse of the amplification factor)."""
    x = np.sqrt(12) * 1.01
    problem = problems.harmonic(x / 0.1, t_span=(0, 20), h=0.1)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        res = problem.solve("spline", iteration="newton")
    assert np.max(np.abs(res.y)) > 1e3
    assert res.status == -1 and not res.success and "blew up" in res.message
    assert f"estimated omega h = {x:.3g}, past its stability limit omega h = 3.464" \
        in res.message


def test_fixed_point_diverges_beyond_sqrt6_where_newton_converges():
    """The sweep multiplies the error by -(w h)^2 / 6: it diverges for
    w h > sqrt(6) although the method itself is stable for w h < sqrt(12)."""
    x = 2.6
    problem = problems.harmonic(x / 0.1, t_span=(0, 5), h=0.1)
    fixed = problem.solve("spline", iteration="fixed-point")
    with pytest.warns(UserWarning, match="The step is too large"):   # phase, not stability
        newton = problem.solve("spline", iteration="newton")
    assert fixed.status == -1 and "diverged" in fixed.message and fixed.niter <= 4
    assert "Step 1 " in fixed.message
    assert newton.success and np.max(np.abs(newton.y)) < 2


def test_dense_output_is_c2_and_matches_knots_and_t_eval():
    problem = problems.cannonball(0.6)
    res = problem.solve(dense_output=True)
    sol = res.sol
    assert np.max(np.abs(sol(res.t) - res.y)) < 1e-13
    assert np.max(np.abs(sol(res.t, 1) - res.yp)) < 1e-13
    # y'' is continuous across interior knots: compare both one-sided limits.
    knots = res.t[1:-1]
    eps = 1e-9
    left, right = sol(knots - eps, 2), sol(knots + eps, 2)
    assert np.max(np.abs(left - right)) < 1e-6
    t_eval = np.linspace(0, 50, 777)
    sub = problem.solve(t_eval=t_eval)
    assert np.max(np.abs(sub.y - sol(t_eval))) < 1e-12
    assert np.max(np.abs(sub.yp - sol(t_eval, 1))) < 1e-12
    assert np.max(np.abs(sub.ypp - sol(t_eval, 2))) < 1e-10


def test_rk4_t_eval_interpolation_is_fourth_order_accurate():
    """Between steps, the Hermite interpolant is as accurate as the steps."""
    problem = problems.cannonball(0.6)
    knots = problem.solve("rk4")
    knot_error = np.max(np.abs(knots.y - problem.reference(knots.t)[0]))
    t_eval = np.linspace(0, 50, 777)  # mostly between knots
    x, v = problem.reference(t_eval)
    res = problem.solve("rk4", t_eval=t_eval)
    assert np.max(np.abs(res.y - x)) < 1.5 * knot_error
    assert np.max(np.abs(res.yp - v)) < 1e-6


def test_last_step_shortened_to_end_of_span():
    res = splinestep.solve(lambda t, y, yp: -y, (0, 1), 1.0, 0.0, 0.3)
    assert np.allclose(res.t, [0, 0.3, 0.6, 0.9, 1.0], rtol=0, atol=1e-15)
    assert res.t[-1] == 1.0
    assert res.y.shape == (1, 5)


def test_scalar_problem_and_shapes():
    res = splinestep.solve(lambda t, y, yp: -y, (0, np.pi), 1.0, 0.0, np.pi / 200)
    assert res.y.shape == res.yp.shape == res.ypp.shape == (1, 201)
    assert abs(res.y[0, -1] + 1) < 1e-4
    assert res.success and res.status == 0
