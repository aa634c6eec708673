"""Every member of Newmark's family on every path, from the registry.

The tests take their members from :data:`splinestep.members.MEMBERS`: a
member added there is run on the sweep and on Newton's method (finite
differences, a dense ``jac``, constant matrices, SuperLU on a sparse
system), under constant and error-controlled steps, with ``t_eval``, dense
output and events, without editing a test.  The reference is exact: a
damped oscillator y'' = -omega^2 y - c y' (and m uncoupled copies of it
with their own omega) has a closed-form solution, against which each run's
order is fitted from steps h and h/2; a member whose coefficients are off
(``test_a_broken_member_fails_the_order_test``) misses the order its
record states.
"""

from fractions import Fraction

import numpy as np
import pytest
import scipy.sparse as sp

import splinestep
from splinestep import members
from splinestep._linalg import SPARSE_FROM
from splinestep.members import MEMBERS

NAMES = sorted(MEMBERS)
C = 0.3                      # damping of the oscillators
T_END = 6.0


def omegas(m):
    return np.linspace(1.0, 2.0, m)


def exact(t, m=1):
    """y and y' of y'' = -omega^2 y - C y', y(0) = 1, y'(0) = 0, per omega."""
    w = omegas(m)[:, None] if m > 1 else np.array([[1.0]])
    r = C / 2
    wd = np.sqrt(w * w - r * r)
    t = np.asarray(t, dtype=float)[None, :]
    decay = np.exp(-r * t)
    return (decay * (np.cos(wd * t) + r / wd * np.sin(wd * t)),
            -decay * (w * w / wd) * np.sin(wd * t))


def oscillator(m):
    w2 = omegas(m) ** 2 if m > 1 else np.array([1.0])

    def fun(t, y, yp):
        return -w2 * y - C * yp
    fy, fyp = np.diag(-w2), -C * np.eye(m)
    return fun, fy, fyp


def run(member, path, h, **extra):
    """A run of ``member`` on ``path`` at step h over (0, T_END)."""
    m = SPARSE_FROM + 10 if path == "sparse" else 1
    fun, fy, fyp = oscillator(m)
    options = dict(method=member, check=False)
    if path != "sweep":
        options["iteration"] = "newton"
    if path == "jac":
        options["jac"] = lambda t, y, yp: (fy, fyp)
    elif path == "constant":
        options["jac"] = (fy, fyp)
    elif path == "sparse":
        options["jac"] = (sp.csc_matrix(fy), sp.csc_matrix(fyp))
    options.update(extra)
    return splinestep.solve(fun, (0.0, T_END), np.ones(m), np.zeros(m), h, **options)


def error(res):
    y, yp = exact(res.t, res.y.shape[0])
    return max(np.max(np.abs(res.y - y)), np.max(np.abs(res.yp - yp)))


def observed_order(member, path, h=0.05):
    coarse, fine = run(member, path, h), run(member, path, h / 2)
    assert coarse.status == 0 and fine.status == 0, (coarse.message, fine.message)
    return np.log2(error(coarse) / error(fine)), coarse


@pytest.mark.parametrize("path", ["sweep", "fd", "jac", "constant", "sparse"])
@pytest.mark.parametrize("name", NAMES)
def test_every_member_has_its_order_on_every_path(name, path):
    """The error at h and h/2 halves as the record's order says (within
    0.1: the next term is O(h) smaller at h = 0.05), and every path solves
    the same step equations: their runs agree with the sweep's to 1e-9 of
    the solution (the iterations' tolerance is 1e-12)."""
    member = MEMBERS[name]
    order, coarse = observed_order(name, path)
    assert abs(order - member.order) < 0.1, order
    assert coarse.method == name and coarse.order == member.order
    if path != "sparse":
        np.testing.assert_allclose(coarse.y, run(name, "sweep", 0.05).y, rtol=0, atol=1e-9)


def test_a_broken_member_fails_the_order_test(monkeypatch):
    """gamma 1/2 -> 0.52 (a second-order member turned first order) and
    beta off by 1 %: the first misses order 2, the second the spline's
    error (its runs move by more than the tolerance of the test above)."""
    off = members.newmark(Fraction(1, 6), Fraction(52, 100))
    order, _ = observed_order(off, "sweep")
    assert abs(order - 2) > 0.5 and off.order == 1
    spline = run("spline", "sweep", 0.05)
    broken = run(MEMBERS["spline"]._replace(beta=Fraction(101, 600)), "sweep", 0.05)
    assert np.max(np.abs(broken.y - spline.y)) > 1e3 * 1e-9


@pytest.mark.parametrize("name", NAMES)
def test_every_member_under_error_control(name):
    """Adaptive steps: the run ends, and its error follows rtol: below 20
    rtol at the first (the alpha members control their estimate of y alone;
    measured 6 rtol), and smaller by at least the square root of the ratio
    of the tolerances at the second (the controller aims at proportionality):
    1e-6 and 1e-8 for the second-order members, 1e-3 and 1e-4 for a
    first-order one, whose steps grow like 1/rtol."""
    fun, _, _ = oscillator(1)
    errors = []
    rtols = (1e-6, 1e-8) if MEMBERS[name].order == 2 else (1e-3, 1e-4)
    for rtol in rtols:
        res = splinestep.solve(fun, (0.0, T_END), 1.0, 0.0, method=name, rtol=rtol, atol=1e-9,
                               check=False)
        assert res.status == 0, res.message
        errors.append(error(res))
    assert errors[0] < 20 * rtols[0], errors
    assert errors[1] < errors[0] / np.sqrt(rtols[0] / rtols[1]), errors


@pytest.mark.parametrize("name", NAMES)
def test_every_member_between_knots(name):
    """t_eval, ``sol`` and events read the member's interpolant: t_eval's
    values equal sol's to rounding, are as accurate as the knots (within 2
    times their largest error), and the first zero of y is located within
    that error divided by |y'| there."""
    h = 0.05
    t_eval = np.linspace(0.0, T_END, 97)

    def zero(t, y, yp):
        return y[0]
    knots = run(name, "sweep", h, dense_output=True, events=zero)
    at = run(name, "sweep", h, t_eval=t_eval)
    np.testing.assert_allclose(at.y, knots.sol(t_eval)[:1], rtol=0, atol=1e-13)
    assert error(at) <= 2 * error(knots)
    r, wd = C / 2, np.sqrt(1 - C * C / 4)
    t_zero = (np.arctan2(-1.0, r / wd) % np.pi) / wd      # cos + (r/wd) sin = 0
    slope = abs(exact([t_zero])[1][0, 0])
    assert abs(knots.t_events[0][0] - t_zero) < 2 * error(knots) / slope


@pytest.mark.parametrize("name", NAMES)
def test_the_compositions_take_the_symmetric_members_only(name):
    """order=4 raises a symmetric member's order to 4 (fitted, within 0.3);
    a member that is not symmetric is a ValueError naming it."""
    member = MEMBERS[name]
    fun, _, _ = oscillator(1)
    if not member.symmetric:
        with pytest.raises(ValueError, match="symmetric"):
            splinestep.solve(fun, (0.0, T_END), 1.0, 0.0, 0.1, method=name, order=4)
        return
    e = [error(splinestep.solve(fun, (0.0, T_END), 1.0, 0.0, h, method=name, order=4,
                                check=False)) for h in (0.1, 0.05)]
    assert abs(np.log2(e[0] / e[1]) - 4) < 0.3, e


@pytest.mark.parametrize("name", NAMES)
def test_every_member_at_its_stability_limit(name):
    """y'' = -y over 2,000 steps: bounded (within 10 times its start) at
    omega h = 0.98 times the record's limit (at 100 for the unconditionally
    stable), and growing past 1e3 or failing at 1.05 times it."""
    member = MEMBERS[name]
    limit = member.stability_limit
    stable_h = 100.0 if np.isinf(limit) else 0.98 * limit
    fun = lambda t, y, yp: -y   # noqa: E731
    res = splinestep.solve(fun, (0.0, 2000 * stable_h), 1.0, 0.0, stable_h, method=name,
                           iteration="newton", jac=(np.array([[-1.0]]), np.array([[0.0]])),
                           check=False)
    assert res.status == 0 and np.max(np.abs(res.y)) < 10, res.message
    if np.isfinite(limit):
        h = 1.05 * limit
        res = splinestep.solve(fun, (0.0, 2000 * h), 1.0, 0.0, h, method=name,
                               iteration="newton", jac=(np.array([[-1.0]]), np.array([[0.0]])),
                               check=False)
        assert res.status == -1 or np.max(np.abs(res.y)) > 1e3


@pytest.mark.parametrize("name", [n for n in NAMES if MEMBERS[n].alpha_f == 0])
def test_the_error_constants_equal_one_step_from_exact_values(name):
    """For y = t^4/24 (y''' = t, y'''' = 1) one step of Newmark's member
    from exact values at t = 1 misses c3y h^3 + c4y h^4 in y and c2yp h^2 +
    c3yp h^3 in y' exactly (higher derivatives vanish): to rounding."""
    member = MEMBERS[name]
    c3y, c4y, c2yp, c3yp = (float(c) for c in member.error_constants())
    h = 0.1
    res = splinestep.solve(lambda t, y, yp: t * t / 2, (1.0, 1.0 + h), 1 / 24, 1 / 6, h,
                           method=name, check=False)
    t = 1.0 + h
    assert t ** 4 / 24 - res.y[0, -1] == pytest.approx(c3y * h ** 3 + c4y * h ** 4, abs=1e-15)
    assert t ** 3 / 6 - res.yp[0, -1] == pytest.approx(c2yp * h ** 2 + c3yp * h ** 3, abs=1e-15)


def test_method_names_and_refusals():
    assert splinestep.solve(lambda t, y, yp: -y, (0, 1), 1.0, 0.0, 0.1,
                            method=(0.25, 0.5)).method == "average-acceleration"
    assert members.member("linear-acceleration") is MEMBERS["spline"]
    for bad, word in (("newmark", "method"), ((0.7, 0.5), "beta"), ((0.25, 0.4), "gamma"),
                      (3, "method")):
        with pytest.raises(ValueError, match=word):
            splinestep.solve(lambda t, y, yp: -y, (0, 1), 1.0, 0.0, 0.1, method=bad)
    with pytest.raises(ValueError, match="rho_inf"):
        members.generalized_alpha(1.5)
    with pytest.raises(ValueError, match="alpha"):
        members.hht(0.5)
    with pytest.raises(ValueError, match="global"):
        splinestep.solve(lambda t, y, yp: -y, (0, 1), 1.0, 0.0, 0.1, method="hht",
                         iteration="global")


def test_the_stability_limit_of_any_record():
    """Records outside the formulas: the limit is where the amplification
    matrix's spectral radius first exceeds 1, found numerically: sqrt(10)
    for (beta, gamma, alpha_m, alpha_f) = (1/6, 1/2, 1/4, 1/5) (the
    derivation of splinestep.analysis.family), and at once (below 1e-3)
    for HHT's beta and alpha_f with gamma = 1/2, whose step grows at every
    omega h; a run past the first limit grows."""
    odd = members.Member("odd", Fraction(1, 6), Fraction(1, 2), Fraction(1, 4), Fraction(1, 5))
    assert odd.stability_limit == pytest.approx(np.sqrt(10), rel=1e-9)
    growing = members.Member("growing", Fraction(121, 400), Fraction(1, 2), Fraction(0),
                             Fraction(1, 10))
    assert growing.stability_limit < 1e-3
    for h, bounded in ((0.95 * np.sqrt(10), True), (1.05 * np.sqrt(10), False)):
        res = splinestep.solve(lambda t, y, yp: -y, (0.0, 2000 * h), 1.0, 0.0, h, method=odd,
                               iteration="newton", jac=(np.array([[-1.0]]), np.array([[0.0]])),
                               check=False)
        assert (res.status == 0 and np.max(np.abs(res.y)) < 10) == bounded


@pytest.mark.parametrize("name", NAMES)
def test_the_estimates_a_member_reports(name):
    """The alpha members estimate y alone: their local_error_yp is NaN, the
    others' a number; local_error is a number for all."""
    fun, _, _ = oscillator(1)
    res = splinestep.solve(fun, (0.0, T_END), 1.0, 0.0, 0.05, method=name)
    assert np.isfinite(res.local_error)
    alpha = MEMBERS[name].alpha_m != 0 or MEMBERS[name].alpha_f != 0
    assert np.isnan(res.local_error_yp) == alpha
