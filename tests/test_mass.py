"""A constant mass matrix: M y'' = F(t, y, y') with ``mass=``.

References: the same run written by hand as y'' = M^-1 F with a dense
inverse (an independent formula: equal to rounding), and the exact modal
solution of M y'' + K y = 0 from the generalized eigenproblem K v = w^2 M v
(scipy.linalg.eigh), against which the order is fitted.  The OpenSees
comparison runs through ``mass=`` too (tests/test_opensees.py).
"""

import numpy as np
import pytest
import scipy.linalg
import scipy.sparse as sp

import splinestep
from splinestep._linalg import SPARSE_FROM
from splinestep.members import MEMBERS


def structure(m):
    """A fixed-fixed chain with a consistent mass matrix (linear elements)
    and Rayleigh damping: M, C, K as CSC matrices."""
    n = m + 1
    K = sp.diags([np.full(m - 1, -1.0), np.full(m, 2.0), np.full(m - 1, -1.0)], [-1, 0, 1],
                 format="csc") * n
    M = sp.diags([np.full(m - 1, 1.0), np.full(m, 4.0), np.full(m - 1, 1.0)], [-1, 0, 1],
                 format="csc") / (6.0 * n)
    return M, 0.05 * M + 1e-3 * K, K


def start(m):
    x = np.arange(1, m + 1) / (m + 1.0)
    return np.sin(np.pi * x) + 0.3 * np.sin(3 * np.pi * x), np.zeros(m)


@pytest.mark.parametrize("m", [6, SPARSE_FROM + 30])
@pytest.mark.parametrize("name", sorted(MEMBERS))
def test_mass_equals_the_inverse_written_by_hand(name, m):
    """Every member, on the sweep (if it converges there), finite-difference
    Newton and Newton with the constant matrices (SuperLU from SPARSE_FROM
    components): mass=M equals y'' = M^-1 F with a dense inverse to 1e-12
    of the solution (100 steps of rounding, each below 1e-14)."""
    M, C, K = structure(m)
    inverse = np.linalg.inv(M.toarray())
    y0, yp0 = start(m)
    h = 0.2 / m

    def fun(t, y, yp):
        return -(K @ y) - C @ yp

    def by_hand(t, y, yp):
        return inverse @ fun(t, y, yp)
    ways = [dict(iteration="newton"), dict(iteration="newton", jac=(-K, -C))]
    if MEMBERS[name].stability_limit > 3.0:
        ways.append(dict())
    for way in ways:
        res = splinestep.solve(fun, (0.0, 100 * h), y0, yp0, h, method=name, mass=M,
                               check=False, **way)
        hand_way = dict(way)
        if "jac" in way:
            hand_way["jac"] = (-(inverse @ K.toarray()), -(inverse @ C.toarray()))
        ref = splinestep.solve(by_hand, (0.0, 100 * h), y0, yp0, h, method=name, check=False,
                               **hand_way)
        assert res.status == 0 and ref.status == 0, res.message
        assert np.max(np.abs(res.y - ref.y)) < 1e-12 * np.max(np.abs(ref.y)), way


def test_mass_keeps_the_order_against_the_modal_solution():
    """M y'' + K y = 0 with a consistent M: the exact solution from K v =
    w^2 M v; the error at h and h/2 falls at order 2 (within 0.1) for the
    spline and for average acceleration."""
    m = 8
    M, _, K = structure(m)
    w2, V = scipy.linalg.eigh(K.toarray(), M.toarray())
    y0, yp0 = start(m)
    a = V.T @ (M @ y0)                      # modal coordinates (V is M-orthonormal)

    def exact(t):
        return V @ (a * np.cos(np.sqrt(w2) * t))
    for name in ("spline", "average-acceleration"):
        errors = []
        for h in (0.02, 0.01):
            res = splinestep.solve(lambda t, y, yp: -(K @ y), (0.0, 2.0), y0, yp0, h,
                                   method=name, mass=M, iteration="newton",
                                   jac=(-K, sp.csc_matrix((m, m))), check=False)
            errors.append(np.max(np.abs(res.y[:, -1] - exact(2.0))))
        assert abs(np.log2(errors[0] / errors[1]) - 2) < 0.1, (name, errors)


def test_newton_with_the_mass_solves_a_linear_step_at_once():
    """With M in Newton's matrix a linear step costs one iteration and a
    confirming one (2 per step), where M^-1 approximated by the lumped
    diagonal, as a user without ``mass=`` might, costs more."""
    m = SPARSE_FROM + 30
    M, C, K = structure(m)
    y0, yp0 = start(m)
    fun = lambda t, y, yp: -(K @ y) - C @ yp   # noqa: E731
    res = splinestep.solve(fun, (0.0, 0.05), y0, yp0, 0.001, method="average-acceleration",
                           mass=M, iteration="newton", jac=(-K, -C), check=False)
    assert res.status == 0 and res.niter == 2 * res.nstep
    lumped = 1.0 / np.asarray(M.sum(axis=1)).ravel()
    inverse = np.linalg.inv(M.toarray())
    approximate = splinestep.solve(lambda t, y, yp: inverse @ fun(t, y, yp), (0.0, 0.05), y0,
                                   yp0, 0.001, method="average-acceleration",
                                   iteration="newton",
                                   jac=(-sp.diags(lumped) @ K, -sp.diags(lumped) @ C),
                                   check=False)
    assert approximate.niter > 2.5 * approximate.nstep


def test_a_vector_is_a_diagonal_mass():
    m = 5
    M, C, K = structure(m)
    d = np.linspace(1.0, 2.0, m)
    y0, yp0 = start(m)
    fun = lambda t, y, yp: -(K @ y) - C @ yp   # noqa: E731
    res = splinestep.solve(fun, (0.0, 0.1), y0, yp0, 0.01, mass=d)
    ref = splinestep.solve(lambda t, y, yp: fun(t, y, yp) / d, (0.0, 0.1), y0, yp0, 0.01)
    np.testing.assert_array_equal(res.y, ref.y)


def test_bad_mass_is_a_value_error_naming_it():
    fun = lambda t, y, yp: -y   # noqa: E731
    for bad, words in ((np.eye(3), "shape"), (np.zeros((2, 2)), "singular"),
                       (np.array([[1.0, np.nan], [0.0, 1.0]]), "finite"),
                       ([1.0, 0.0], "singular"), ("heavy", "mass")):
        with pytest.raises(ValueError, match=words):
            splinestep.solve(fun, (0, 1), [1.0, 0.0], [0.0, 0.0], 0.1, mass=bad)
    with pytest.raises(ValueError, match="mass"):
        splinestep.solve(fun, (0, 1), [1.0, 0.0], [0.0, 0.0], 0.1, mass=np.eye(2),
                         iteration="global")
