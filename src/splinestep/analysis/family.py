"""Newmark's family and its alpha extensions on the oscillator, derived by
sympy: the amplification matrix, the stability limit, the spectral radius at
infinite step, and the leading terms of the period error and of the
algorithmic damping, with their numeric counterparts.

A member (beta, gamma, alpha_m, alpha_f), in Chung and Hulbert's form [3]_,
steps y'' = F(t, y, y') from (y_n, y'_n, a_n) to t_{n+1} = t_n + h::

    y_{n+1}  = y_n + h y'_n + h^2 ((1/2 - beta) a_n + beta a_{n+1}),
    y'_{n+1} = y'_n + h ((1 - gamma) a_n + gamma a_{n+1}),
    (1 - alpha_m) a_{n+1} + alpha_m a_n
             = F(t_{n+1-alpha_f}, (1 - alpha_f) y_{n+1} + alpha_f y_n,
                 (1 - alpha_f) y'_{n+1} + alpha_f y'_n).

alpha_m = alpha_f = 0 is Newmark's method [1]_ (the report's spline step is
its linear-acceleration member, beta = 1/6, gamma = 1/2); alpha_m = 0 is
Hilber, Hughes and Taylor's [2]_.  On y'' = -omega^2 y - 2 xi omega y' the
step is linear in the scaled state X = (y, h y', h^2 a): X_{n+1} = A(Omega)
X_n with Omega = omega h (:func:`amplification_matrix`).  Period error and
algorithmic damping are read from the principal pair of A's eigenvalues,
lambda = exp(-xi_h theta +- i theta) in Hughes' notation [4]_ (Sec. 9.3):
T_h / T = Omega / arg(lambda) and xi_h = -ln|lambda| / arg(lambda).

The derivations take the coefficients as numbers: sympy Rationals, ints or
floats (a float is read as the fraction its printed digits give, sympy's
``nsimplify(..., rational=True)``: 0.1 as 1/10).  :func:`coefficients`
reads a member's from its record in :mod:`splinestep.members`;
:data:`MEMBERS`, :func:`hht_parameters` and
:func:`generalized_alpha_parameters` give the
coefficients of the named members.  The module uses nothing of the solver
but the members' records;
``tests/test_family_analysis.py`` checks each derived constant against the
numeric functions and the matrix against steps taken with the formulas above.

References
----------
.. [1] N. M. Newmark, "A method of computation for structural dynamics",
   J. Eng. Mech. Div. ASCE 85 (1959) 67-94.
.. [2] H. M. Hilber, T. J. R. Hughes, R. L. Taylor, "Improved numerical
   dissipation for time integration algorithms in structural dynamics",
   Earthquake Eng. Struct. Dyn. 5 (1977) 283-292.
.. [3] J. Chung, G. M. Hulbert, "A time integration algorithm for structural
   dynamics with improved numerical dissipation: the generalized-alpha
   method", J. Appl. Mech. 60 (1993) 371-375.
.. [4] T. J. R. Hughes, "The Finite Element Method", Prentice-Hall (1987);
   Dover (2000), Ch. 9.
"""

import functools
from fractions import Fraction

import numpy as np
from . import require

sp = require("sympy", __name__)

from .. import members as _members

Omega = sp.Symbol("Omega", positive=True)      # omega h
lam = sp.Symbol("lambda")                      # an eigenvalue of A
HALF = sp.Rational(1, 2)

def coefficients(member):
    """(beta, gamma, alpha_m, alpha_f) of a member of Newmark's family as
    sympy Rationals, read from its one record
    (:func:`splinestep.members.member`: a record, a name of
    :data:`splinestep.members.MEMBERS` or a pair (beta, gamma))."""
    record = _members.member(member)
    return tuple(sp.Rational(c.numerator, c.denominator)
                 for c in (record.beta, record.gamma, record.alpha_m, record.alpha_f))


def _fraction(value):
    """A sympy number or a Python one as a Fraction (exact for Rationals)."""
    value = sp.nsimplify(value, rational=True) if not isinstance(value, sp.Rational) else value
    return Fraction(int(value.p), int(value.q))


# The members of the module docstring as (beta, gamma, alpha_m, alpha_f),
# from splinestep.members.
MEMBERS = {label: coefficients(name) for label, name in (
    ("linear acceleration", "spline"), ("average acceleration", "average-acceleration"),
    ("Fox-Goodwin", "fox-goodwin"), ("central difference", "central-difference"))}


def hht_parameters(a):
    """(beta, gamma, alpha_m, alpha_f) of the HHT-alpha method with
    dissipation ``a`` in [0, 1/3] (Hilber, Hughes and Taylor's alpha is
    -a): ((1 + a)^2 / 4, 1/2 + a, 0, a), exact, from
    :func:`splinestep.members.hht`.

    References
    ----------
    .. [1] H. M. Hilber, T. J. R. Hughes, R. L. Taylor, Earthquake Eng.
       Struct. Dyn. 5 (1977) 283-292.
    """
    return coefficients(_members.hht(_fraction(a)))


def generalized_alpha_parameters(rho_inf):
    """(beta, gamma, alpha_m, alpha_f) of the generalized-alpha method with
    spectral radius ``rho_inf`` in [0, 1] at infinite step: alpha_m = (2
    rho - 1) / (rho + 1), alpha_f = rho / (rho + 1), gamma = 1/2 - alpha_m +
    alpha_f, beta = (1 - alpha_m + alpha_f)^2 / 4, exact, from
    :func:`splinestep.members.generalized_alpha`.

    References
    ----------
    .. [1] J. Chung, G. M. Hulbert, J. Appl. Mech. 60 (1993) 371-375,
       Eqs. (25) and (26).
    """
    return coefficients(_members.generalized_alpha(_fraction(rho_inf)))


def _exact(value):
    """A coefficient as sympy reads it, a float as a fraction."""
    if isinstance(value, float):
        return sp.nsimplify(value, rational=True)
    return sp.sympify(value)


@functools.lru_cache(maxsize=256)
def _pencil(beta, gamma, alpha_m, alpha_f, xi):
    """(M1, M0) with M1 X_{n+1} = M0 X_n, X = (y, h y', h^2 a), from the
    step equations on y'' = -omega^2 y - 2 xi omega y' (times h^2)."""
    y0, v0, w0, y1, v1, w1 = sp.symbols("y0 v0 w0 y1 v1 w1")
    equations = [
        y1 - (y0 + v0 + (HALF - beta) * w0 + beta * w1),
        v1 - (v0 + (1 - gamma) * w0 + gamma * w1),
        (1 - alpha_m) * w1 + alpha_m * w0
        + Omega ** 2 * ((1 - alpha_f) * y1 + alpha_f * y0)
        + 2 * xi * Omega * ((1 - alpha_f) * v1 + alpha_f * v0)]
    M1 = sp.Matrix([[sp.diff(e, s) for s in (y1, v1, w1)] for e in equations])
    M0 = -sp.Matrix([[sp.diff(e, s) for s in (y0, v0, w0)] for e in equations])
    return sp.ImmutableMatrix(M1), sp.ImmutableMatrix(M0)


def step_matrices(beta, gamma, alpha_m=0, alpha_f=0, xi=0):
    """The step as a linear system on the scaled state.

    Parameters
    ----------
    beta, gamma, alpha_m, alpha_f : number
        The member.
    xi : number, optional
        The problem's damping ratio (y'' = -omega^2 y - 2 xi omega y').

    Returns
    -------
    (M1, M0) : sympy matrices
        M1 X_{n+1} = M0 X_n for X = (y, h y', h^2 a), entries polynomials in
        :data:`Omega`.

    References
    ----------
    .. [1] J. Chung, G. M. Hulbert, J. Appl. Mech. 60 (1993) 371-375,
       Eqs. (2)-(4).
    """
    return _pencil(*(_exact(c) for c in (beta, gamma, alpha_m, alpha_f, xi)))


def amplification_matrix(beta, gamma, alpha_m=0, alpha_f=0, xi=0):
    """The amplification matrix A(Omega) of a member.

    Parameters
    ----------
    beta, gamma, alpha_m, alpha_f : number
        The member.
    xi : number, optional
        The problem's damping ratio.

    Returns
    -------
    sympy.Matrix
        The 3 x 3 matrix with (y, h y', h^2 a)_{n+1} = A (y, h y', h^2 a)_n
        on y'' = -omega^2 y - 2 xi omega y', entries rational in
        :data:`Omega` = omega h.  For alpha_m = alpha_f = 0 its third row is
        -Omega^2 times its first minus 2 xi Omega times its second, so that
        0 is an eigenvalue and the other two are those of the 2 x 2 map of
        (y, h y') (``theory.amplification`` for xi = 0, gamma = 1/2).

    References
    ----------
    .. [1] N. M. Newmark, J. Eng. Mech. Div. ASCE 85 (1959) 67-94.
    .. [2] T. J. R. Hughes, "The Finite Element Method", Sec. 9.3.
    """
    M1, M0 = step_matrices(beta, gamma, alpha_m, alpha_f, xi)
    return M1.LUsolve(M0).applyfunc(sp.cancel)


def characteristic_polynomial(beta, gamma, alpha_m=0, alpha_f=0, xi=0):
    """det(lambda M1 - M0): A's characteristic polynomial times det(M1).

    Parameters
    ----------
    beta, gamma, alpha_m, alpha_f, xi : number
        The member and the problem's damping ratio.

    Returns
    -------
    sympy expression
        A polynomial in :data:`lam` and :data:`Omega`, of degree 3 in
        lambda; for each Omega its roots are A's eigenvalues.

    References
    ----------
    .. [1] T. J. R. Hughes, "The Finite Element Method", Sec. 9.3
       (the stability polynomial of a one-step method).
    """
    M1, M0 = step_matrices(beta, gamma, alpha_m, alpha_f, xi)
    return sp.expand((lam * M1 - M0).det())


@functools.lru_cache(maxsize=256)
def _numeric_pencil(beta, gamma, alpha_m, alpha_f, xi):
    """A numpy function of Omega returning the 18 entries of M1 and M0."""
    M1, M0 = _pencil(beta, gamma, alpha_m, alpha_f, xi)
    return sp.lambdify(Omega, list(M1) + list(M0), "numpy")


def amplification_matrices(Omega, beta, gamma, alpha_m=0, alpha_f=0, xi=0):
    """A(Omega) evaluated in floating point, for many Omega at once.

    Parameters
    ----------
    Omega : array_like
        omega h, any shape.
    beta, gamma, alpha_m, alpha_f, xi : number
        The member and the problem's damping ratio.

    Returns
    -------
    ndarray, shape Omega.shape + (3, 3)
        The matrices of :func:`amplification_matrix`, solved from the step's
        linear system in floating point.

    References
    ----------
    .. [1] J. Chung, G. M. Hulbert, J. Appl. Mech. 60 (1993) 371-375.
    """
    x = np.asarray(Omega, float)
    entries = _numeric_pencil(*(_exact(c) for c in (beta, gamma, alpha_m, alpha_f, xi)))(x)
    stack = np.stack([np.broadcast_to(np.asarray(e, float), x.shape) for e in entries], -1)
    stack = stack.reshape(x.shape + (2, 3, 3))
    return np.linalg.solve(stack[..., 0, :, :], stack[..., 1, :, :])


def spectral_radius(Omega, beta, gamma, alpha_m=0, alpha_f=0, xi=0):
    """The spectral radius of A(Omega), in floating point.

    Parameters
    ----------
    Omega : array_like
        omega h, any shape.
    beta, gamma, alpha_m, alpha_f, xi : number
        The member and the problem's damping ratio.

    Returns
    -------
    ndarray
        max |lambda| over A's three eigenvalues, of the shape of Omega.

    References
    ----------
    .. [1] T. J. R. Hughes, "The Finite Element Method", Sec. 9.1.
    """
    A = amplification_matrices(Omega, beta, gamma, alpha_m, alpha_f, xi)
    return np.max(np.abs(np.linalg.eigvals(A)), axis=-1)


def principal_root(Omega, beta, gamma, alpha_m=0, alpha_f=0, xi=0):
    """The principal eigenvalue of A(Omega): the one of the complex pair
    with positive imaginary part.

    Parameters
    ----------
    Omega : array_like
        omega h, any shape.
    beta, gamma, alpha_m, alpha_f, xi : number
        The member and the problem's damping ratio.

    Returns
    -------
    ndarray, complex
        lambda with arg(lambda) in (0, pi); NaN where the three eigenvalues
        are real (beyond the oscillatory range; a real 3 x 3 matrix has at
        most one complex pair, and at small Omega it is the principal one,
        near exp(+-i Omega)).

    References
    ----------
    .. [1] T. J. R. Hughes, "The Finite Element Method", Sec. 9.3.
    """
    A = amplification_matrices(Omega, beta, gamma, alpha_m, alpha_f, xi)
    roots = np.linalg.eigvals(A)
    index = np.argmax(roots.imag, axis=-1)[..., None]
    root = np.take_along_axis(roots, index, axis=-1)[..., 0]
    return np.where(root.imag > 0, root, np.nan + 0j)


def period_error(Omega, beta, gamma, alpha_m=0, alpha_f=0, xi=0):
    """The relative period error T_h / T - 1, in floating point.

    Parameters
    ----------
    Omega : array_like
        omega h (> 0), any shape.
    beta, gamma, alpha_m, alpha_f, xi : number
        The member and the problem's damping ratio.

    Returns
    -------
    ndarray
        Omega / arg(lambda) - 1 for the principal root lambda
        (:func:`principal_root`); NaN where the roots are real.

    References
    ----------
    .. [1] T. J. R. Hughes, "The Finite Element Method", Sec. 9.3
       (relative period error).
    """
    root = principal_root(Omega, beta, gamma, alpha_m, alpha_f, xi)
    return np.asarray(Omega, float) / np.angle(root) - 1


def damping_ratio(Omega, beta, gamma, alpha_m=0, alpha_f=0, xi=0):
    """The algorithmic damping ratio xi_h, in floating point.

    Parameters
    ----------
    Omega : array_like
        omega h (> 0), any shape.
    beta, gamma, alpha_m, alpha_f, xi : number
        The member and the problem's damping ratio.

    Returns
    -------
    ndarray
        -ln|lambda| / arg(lambda) for the principal root lambda
        (:func:`principal_root`); NaN where the roots are real.

    References
    ----------
    .. [1] T. J. R. Hughes, "The Finite Element Method", Sec. 9.3
       (algorithmic damping ratio).
    .. [2] H. M. Hilber, T. J. R. Hughes, R. L. Taylor, Earthquake Eng.
       Struct. Dyn. 5 (1977) 283-292.
    """
    root = principal_root(Omega, beta, gamma, alpha_m, alpha_f, xi)
    return -np.log(np.abs(root)) / np.angle(root)


def _positive_roots(expr):
    """The positive real roots in Omega of a polynomial (exact)."""
    poly = sp.Poly(expr, Omega)
    return [sp.radsimp(r) for r in poly.real_roots() if r.is_positive]


def stability_limit(beta, gamma, alpha_m=0, alpha_f=0):
    """Omega_crit: the end of the range 0 < Omega <= Omega_crit in which A's
    spectral radius is at most 1 on y'' = -omega^2 y.

    An eigenvalue can cross the unit circle only where one of the
    Routh-Hurwitz quantities of Q(s) = (1 - s)^3 P((1 + s) / (1 - s)) (P of
    :func:`characteristic_polynomial`; |lambda| < 1 is Re s < 0) vanishes:
    its coefficients a_0 .. a_3 (a_0 for lambda = 1, a_3 for lambda = -1)
    and a_1 a_2 - a_0 a_3 (a pair on the circle), or det(M1) (the step
    undefined).  Their positive roots, exact, cut the Omega axis into
    intervals on which stability does not change; the spectral radius at one
    point inside each (floating point, to 1e-9) says which are stable.

    Parameters
    ----------
    beta, gamma, alpha_m, alpha_f : number
        The member.

    Returns
    -------
    sympy number
        The first root past which the step is unstable (exact; 0 if it is
        unstable from the start, sympy ``oo`` if it is stable for every
        Omega).  For Newmark's members with gamma >= 1/2 and beta < gamma/2
        it is 1/sqrt(gamma/2 - beta): sqrt(12) for linear acceleration,
        sqrt(6) for Fox-Goodwin, 2 for central difference.

    References
    ----------
    .. [1] T. J. R. Hughes, "The Finite Element Method", Sec. 9.1
       (Omega_crit of Newmark's method).
    .. [2] J. Chung, G. M. Hulbert, J. Appl. Mech. 60 (1993) 371-375.
    """
    s = sp.Symbol("s")
    P = characteristic_polynomial(beta, gamma, alpha_m, alpha_f)
    Q = sp.expand(sp.cancel((1 - s) ** 3 * P.subs(lam, (1 + s) / (1 - s))))
    a = [Q.coeff(s, k) for k in range(4)]
    quantities = a + [a[1] * a[2] - a[0] * a[3], P.coeff(lam, 3)]
    cuts = set()
    for q in quantities:
        if sp.expand(q) != 0:
            cuts.update(_positive_roots(q))
    bounds = [sp.Integer(0)] + sorted(cuts, key=float)
    probes = [float(lo + hi) / 2 for lo, hi in zip(bounds, bounds[1:])] + [float(bounds[-1]) + 1]
    radius = spectral_radius(np.array(probes), beta, gamma, alpha_m, alpha_f)
    for bound, r in zip(bounds, radius):
        if r > 1 + 1e-9:
            return bound
    return sp.oo


def rho_infinity(beta, gamma, alpha_m=0, alpha_f=0):
    """The spectral radius of A(Omega) as Omega -> infinity.

    A's characteristic polynomial (monic) has coefficients rational in
    Omega; if one grows without bound, so does an eigenvalue (they are
    symmetric functions of the eigenvalues), else the eigenvalues tend to
    the roots of the limiting polynomial.

    Parameters
    ----------
    beta, gamma, alpha_m, alpha_f : number
        The member.

    Returns
    -------
    sympy number
        The largest |root| of the limiting polynomial (exact), or ``oo``.

    References
    ----------
    .. [1] J. Chung, G. M. Hulbert, J. Appl. Mech. 60 (1993) 371-375
       (rho_infinity).
    .. [2] H. M. Hilber, T. J. R. Hughes, R. L. Taylor, Earthquake Eng.
       Struct. Dyn. 5 (1977) 283-292.
    """
    P = characteristic_polynomial(beta, gamma, alpha_m, alpha_f)
    coefficients = [sp.Poly(P.coeff(lam, j), Omega) for j in range(4)]
    top = coefficients[3].degree()
    if any(c.degree() > top for c in coefficients):
        return sp.oo
    limit = sp.Poly([c.coeff_monomial(Omega ** top) for c in coefficients[::-1]], lam)
    roots = limit.all_roots()
    largest = max(roots, key=lambda r: abs(complex(r.evalf())))
    return sp.simplify(sp.Abs(largest))


def _times(a, b, n):
    """The product of two power series (coefficient lists), n terms."""
    out = [sp.Integer(0)] * n
    for i, ai in enumerate(a[:n]):
        if ai != 0:
            for j, bj in enumerate(b[:n - i]):
                out[i + j] += ai * bj
    return [sp.expand(c) for c in out]


def _compose(outer, inner, n):
    """sum_j outer[j] inner^j (inner without constant term), n terms."""
    out, power = [sp.Integer(0)] * n, [sp.Integer(1)] + [sp.Integer(0)] * (n - 1)
    for c in outer[:n]:
        out = [o + c * p for o, p in zip(out, power)]
        power = _times(power, inner, n)
    return out


@functools.lru_cache(maxsize=256)
def _log_root(params, terms):
    """ln(lambda) of the principal root lambda(Omega) = 1 + i Omega + ...
    of P, as ``terms`` coefficients of Omega^k, by undetermined
    coefficients: the Omega^(k+1) term of P(lambda) fixes that of Omega^k."""
    P = characteristic_polynomial(*params)
    p = [sp.Poly(P.coeff(lam, j), Omega).all_coeffs()[::-1] for j in range(4)]

    def residual(root, n):                       # P(root(Omega)), n terms
        total, power = [sp.Integer(0)] * n, [sp.Integer(1)] + [sp.Integer(0)] * (n - 1)
        for pj in p:
            total = [t + c for t, c in zip(total, _times(pj, power, n))]
            power = _times(power, root, n)
        return total

    root = [sp.Integer(1), sp.I]
    for k in range(2, terms):
        r0 = residual(root + [0], k + 2)
        if any(sp.simplify(c) != 0 for c in r0[:k + 1]):
            raise ValueError(f"no root 1 + i Omega + ...: P's Omega^k terms {r0[:k + 1]}")
        r1 = residual(root + [1], k + 2)[k + 1]
        root.append(sp.simplify(-r0[k + 1] / (r1 - r0[k + 1])))
    log = [sp.Integer(0)] + [sp.Integer(-1) ** (j + 1) / j for j in range(1, terms)]
    return tuple(sp.simplify(c) for c in _compose(log, [0] + root[1:], terms))


def _angle_and_decay(beta, gamma, alpha_m, alpha_f, order):
    """theta / Omega and -ln|lambda| / Omega of the principal root on the
    undamped problem, as coefficients of Omega^0 .. Omega^order."""
    params = tuple(_exact(c) for c in (beta, gamma, alpha_m, alpha_f))
    mu = _log_root(params, order + 2)[1:]
    return ([sp.simplify(sp.im(c)) for c in mu], [sp.simplify(-sp.re(c)) for c in mu])


def period_error_series(beta, gamma, alpha_m=0, alpha_f=0, order=6):
    """T_h / T - 1 as a series in Omega (undamped problem).

    Parameters
    ----------
    beta, gamma, alpha_m, alpha_f : number
        The member.
    order : int, optional
        The last power of Omega kept.

    Returns
    -------
    sympy expression
        The series Omega / arg(lambda) - 1 through Omega^order (a
        polynomial), lambda the principal root.  Newmark's members with
        gamma = 1/2 give (beta - 1/12) Omega^2 / 2 + ...

    References
    ----------
    .. [1] T. J. R. Hughes, "The Finite Element Method", Sec. 9.3.
    .. [2] N. M. Newmark, J. Eng. Mech. Div. ASCE 85 (1959) 67-94.
    """
    angle, _ = _angle_and_decay(beta, gamma, alpha_m, alpha_f, order)
    reciprocal = _compose([sp.Integer(-1) ** j for j in range(order + 1)],
                          [0] + angle[1:], order + 1)
    return sum(c * Omega ** k for k, c in enumerate(reciprocal) if k > 0)


def damping_series(beta, gamma, alpha_m=0, alpha_f=0, order=5):
    """The algorithmic damping ratio xi_h as a series in Omega (undamped
    problem).

    Parameters
    ----------
    beta, gamma, alpha_m, alpha_f : number
        The member.
    order : int, optional
        The last power of Omega kept.

    Returns
    -------
    sympy expression
        The series -ln|lambda| / arg(lambda) through Omega^order (a
        polynomial), lambda the principal root: 0 for Newmark's members
        with gamma = 1/2, (gamma - 1/2) Omega / 2 + ... for gamma != 1/2.

    References
    ----------
    .. [1] T. J. R. Hughes, "The Finite Element Method", Sec. 9.3.
    .. [2] H. M. Hilber, T. J. R. Hughes, R. L. Taylor, Earthquake Eng.
       Struct. Dyn. 5 (1977) 283-292.
    .. [3] J. Chung, G. M. Hulbert, J. Appl. Mech. 60 (1993) 371-375.
    """
    angle, decay = _angle_and_decay(beta, gamma, alpha_m, alpha_f, order)
    reciprocal = _compose([sp.Integer(-1) ** j for j in range(order + 1)],
                          [0] + angle[1:], order + 1)
    return sum(c * Omega ** k for k, c in enumerate(_times(decay, reciprocal, order + 1)))


def largest_step(member, omega_1, omega_m, periods=3.0, phase=1e-3, margin=0.02):
    """The step a structural analyst would take with ``member`` on a system
    whose slowest and fastest angular frequencies are ``omega_1`` and
    ``omega_m``: the largest h at which the slowest mode's phase error over
    ``periods`` of its periods, 2 pi periods |T_h/T - 1|, stays within
    ``phase``, or the member's stability limit at the fastest mode less
    ``margin`` (a fraction) if that is smaller.  The phase condition is read
    on a grid of 3,000 values of omega h from 1e-3 to 3."""
    b, g, am, af = coefficients(member)
    x = np.geomspace(1e-3, 3.0, 3000)
    drift = 2 * np.pi * periods * np.abs(period_error(x, b, g, am, af))
    accurate = x[drift <= phase].max() / omega_1
    return min(accurate, (1 - margin) * member.stability_limit / omega_m)
