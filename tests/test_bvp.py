"""solve_bvp's mesh refinement, on scipy's shock-layer test problem
(scipy/integrate/tests/test_bvp.py: shock_fun, shock_sol), whose exact
solution y = cos(pi x) + erf(x / sqrt(2 eps)) / erf(1 / sqrt(2 eps)) has a
layer of width sqrt(eps) at x = 0."""

import numpy as np
import pytest
from scipy.special import erf

import splinestep as ss

EPS = 1e-3


def shock(x, y, yp):
    return -(x * yp + EPS * np.pi ** 2 * np.cos(np.pi * x) + np.pi * x * np.sin(np.pi * x)) / EPS


def exact(x):
    return np.cos(np.pi * x) + erf(x / np.sqrt(2 * EPS)) / erf(1 / np.sqrt(2 * EPS))


def error(res):
    x = np.linspace(-1.0, 1.0, 4001)
    return float(np.max(np.abs(np.atleast_2d(res.sol(x))[0] - exact(x))))


@pytest.mark.parametrize("tol", [1e-3, 1e-5])
def test_the_shock_layer_is_solved_within_tol(tol):
    """tol bounds the error of y against the exact solution (times
    max(1, max |y|) = 2), as scipy's test asks of its own solve_bvp (which
    bounds a residual) from the same five points."""
    res = ss.solve_bvp(shock, np.linspace(-1, 1, 5), -2.0, 0.0, tol=tol, max_nodes=100_000)
    assert res.status == 0, res.message
    assert error(res) <= tol * 2.0


def test_the_mesh_is_refined_where_the_layer_is():
    """The steps near the layer are at least 8 times smaller than away from
    it, and the mesh is less than a quarter of the uniform mesh of the same
    smallest step, which halving the whole mesh would have needed."""
    res = ss.solve_bvp(shock, np.linspace(-1, 1, 5), -2.0, 0.0, tol=1e-5, max_nodes=100_000)
    h = np.diff(res.t)
    middle = 0.5 * (res.t[1:] + res.t[:-1])
    assert np.max(h[np.abs(middle) > 0.5]) >= 8.0 * np.max(h[np.abs(middle) < 0.05])
    assert res.t.size < 0.25 * (2.0 / h.min() + 1)


def test_a_problem_solvable_within_max_nodes_is_solved():
    """At tol = 1e-5 the shock needs 4,097 points when the whole mesh is
    halved; refined where the layer is, it fits in max_nodes = 1000."""
    res = ss.solve_bvp(shock, np.linspace(-1, 1, 5), -2.0, 0.0, tol=1e-5, max_nodes=1000)
    assert res.status == 0, res.message
    assert res.t.size <= 1000
    assert error(res) <= 2e-5


def test_too_few_nodes_fails_with_the_mesh_it_needs():
    res = ss.solve_bvp(shock, np.linspace(-1, 1, 5), -2.0, 0.0, tol=1e-7, max_nodes=1000)
    assert res.status == -1
    assert "max_nodes = 1000" in res.message
    assert np.isfinite(res.error_estimate) and res.error_estimate > 2e-7
