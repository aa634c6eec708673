"""Newmark's family: every member defined once, as a record.

A member of the family steps y'' = F(t, y, y') from the knot t_n, where it
holds y_n, y'_n and an acceleration a_n, to t_{n+1} = t_n + h:

    y_{n+1}  = y_n + h y'_n + h^2 ((1/2 - beta) a_n + beta a_{n+1}),
    y'_{n+1} = y'_n + h ((1 - gamma) a_n + gamma a_{n+1}),
    (1 - alpha_m) a_{n+1} + alpha_m a_n
             = F(t_{n+1} - alpha_f h, (1 - alpha_f) y_{n+1} + alpha_f y_n,
                 (1 - alpha_f) y'_{n+1} + alpha_f y'_n),

Chung and Hulbert's generalized-alpha form [3]_ (alpha_m = alpha_f = 0:
Newmark's method [1]_; alpha_m = 0: Hilber, Hughes and Taylor's [2]_).
The report's spline step is the member beta = 1/6, gamma = 1/2, alpha_m =
alpha_f = 0, Newmark's linear-acceleration method, whose knots are those of
a C2 cubic spline.

Each :class:`Member` holds its four coefficients (exact fractions where they
are rational) and derives from them everything the solver reads:

- :attr:`Member.order`: 2 when gamma = 1/2 - alpha_m + alpha_f, else 1;
- :attr:`Member.stability_limit`: the supremum of the omega h below which
  the step does not grow on y'' = -omega^2 y (infinite for the
  unconditionally stable members; 1/sqrt(gamma/2 - beta) for Newmark's
  with gamma >= 1/2 [4]_; at the limit itself a member with gamma = 1/2
  has a double eigenvalue -1 and grows linearly);
- :meth:`Member.error_constants`: the leading local errors of one step,
  the constants of the error estimate of the controllers, the driver's
  estimate and the step-size check (below);
- :attr:`Member.interpolant`: what ``t_eval``, the events and ``sol`` read
  between knots: the spline's own C2 cubic for the report's member, whose
  knots it joins; for every other member the quintic Hermite through both
  knots' (y, y', a) (C2; exact for a quintic: between knots its error is
  that of the knots' y, y' and a it joins, so a member whose y' is less
  accurate than its y, as Fox-Goodwin's on an oscillation, is less
  accurate between knots than at them);
- :meth:`Member.scheme`: the numbers the compiled steps read, a
  :class:`Scheme`.

The local error.  For a member whose accelerations are those of the exact
solution at a time shifted by delta h, a_n = y''(t_n + delta h) with delta
= alpha_m - alpha_f (what the last equation gives to leading order), a
step from exact y_n, y'_n misses

    err_y  = c3y h^3 y''' + ...,   err_y' = c2yp h^2 y''' + ...,

with c3y = 1/6 - beta - delta/2 and c2yp = 1/2 - gamma - delta (zero for
the second-order members).  For Newmark's members (delta = 0) the next
terms are c4y h^4 y'''' and c3yp h^3 y'''' with c4y = 1/24 - beta/2 and
c3yp = 1/6 - gamma/2 (Taylor expansion; ``tests/test_members.py`` checks
all four against one step from exact values).  For the alpha members the
next terms are not those of the shifted Taylor series (a_{n+1} itself
misses h^2 y'''' terms that depend on the member), and the estimate keeps
c3y |h|^3 |y'''| alone, for a second reason too: a_n's shift changes with
the step,
and where the step changes the jump of the third derivative measures that
change rather than y'''' (an error controller reading it rejected half of
its 109,480 steps on y'' = -4 y over (0, 5) at rtol = 1e-6).  For Newmark's members c3y = 1/6 - beta is the constant
of Zienkiewicz and Xie's estimate [5]_; for the spline it vanishes and the
next term, h^4 y''''/24 in y and h^3 y''''/12 in y', remains, estimated
from the jump of the spline's third derivative (:mod:`splinestep.controllers`).

Adding a member.  A new entry of :data:`MEMBERS` (or a record from
:func:`newmark`, :func:`hht` or :func:`generalized_alpha` passed as
``solve(..., method=...)``) is all it takes: the steps, the controllers,
the step-size check and the tests read the record, and
``tests/test_members.py`` runs every entry of :data:`MEMBERS` on every path.

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
.. [5] O. C. Zienkiewicz, Y. M. Xie, "A simple error estimator and adaptive
   time stepping procedure for dynamic analysis", Earthquake Eng. Struct.
   Dyn. 20 (1991) 871-887.
"""

import math
from collections import namedtuple
from fractions import Fraction

# The interpolants of a step (the driver's codes; :mod:`splinestep.driver`).
CUBIC, QUINTIC, HERMITE = 0, 1, 2

Scheme = namedtuple("Scheme", "beta gamma alpha_m alpha_f y_start yp_start c3y c4y c2yp c3yp "
                              "exponent interpolant")
Scheme.__doc__ = """The numbers of a member that the compiled steps read
(numbers only: a record holding arrays costs reference counting in the hot
loop): the coefficients, the weights 1/2 - beta and 1 - gamma of a_n, the
absolute error constants (:meth:`Member.error_constants`), the error
controller's exponent 1/order and the interpolant's code."""


def amplification(fy, fyp, h, sc):
    """The matrix M of one step of size h of the member ``sc`` (a
    :class:`splinestep.members.Scheme`) on y'' = fy y + fyp y': (y,
    y')_{n+1} = M (y, y')_n for Newmark's members, whose y'' at a knot is F
    there (the spline's eqs. 6-9), and (y, y', a)_{n+1} = M (y, y', a)_n for
    the alpha members, whose acceleration a_n is a state of its own (the
    step-size check's linearised step, :mod:`splinestep.check`, and
    :attr:`Member.stability_limit` where no formula holds)."""
    import numpy as np
    m = fy.shape[0]
    eye, zero = np.eye(m), np.zeros((m, m))
    wy, wyp = sc.beta * h * h, sc.gamma * h
    if sc.alpha_m == 0.0 and sc.alpha_f == 0.0:
        p = np.hstack([fy, fyp])                               # y''_n = p (y, y')_n
        base_y = np.hstack([eye, h * eye]) + (sc.y_start * h * h) * p
        base_yp = np.hstack([zero, eye]) + (sc.yp_start * h) * p
        k = eye - wy * fy - wyp * fyp
        z = np.linalg.solve(k, fy @ base_y + fyp @ base_yp)     # y''_{n+1}
        return np.vstack([base_y + wy * z, base_yp + wyp * z])
    af, am = sc.alpha_f, sc.alpha_m
    base_y = np.hstack([eye, h * eye, (sc.y_start * h * h) * eye])
    base_yp = np.hstack([zero, eye, (sc.yp_start * h) * eye])
    own_y, own_yp, own_a = (np.hstack([eye, zero, zero]), np.hstack([zero, eye, zero]),
                            np.hstack([zero, zero, eye]))
    k = (1.0 - am) * eye - (1.0 - af) * (wy * fy + wyp * fyp)
    rhs = (-am * own_a + fy @ ((1.0 - af) * base_y + af * own_y)
           + fyp @ ((1.0 - af) * base_yp + af * own_yp))
    a = np.linalg.solve(k, rhs)                                  # a_{n+1}
    return np.vstack([base_y + wy * a, base_yp + wyp * a, a])



def _first_growth(member, margin=1e-9):
    """The first omega h at which ``member``'s amplification matrix on y''
    = -omega^2 y (:func:`amplification`) has a spectral radius above 1 +
    ``margin`` (a grid of 2,000 points to 1e6, then bisection), inf if none
    there."""
    import numpy as np
    sc, zero = member.scheme(), np.zeros((1, 1))

    def radius(x):
        return np.max(np.abs(np.linalg.eigvals(amplification(np.array([[-x * x]]), zero, 1.0,
                                                             sc))))
    grid = np.concatenate([[0.0], np.geomspace(1e-6, 1e6, 2000)])
    above = [x for x in grid if radius(x) > 1.0 + margin]
    if not above:
        return math.inf
    high = above[0]
    if high == 0.0:
        return 0.0
    low = grid[int(np.searchsorted(grid, high)) - 1]
    for _ in range(60):
        mid = 0.5 * (low + high)
        low, high = (mid, high) if radius(mid) <= 1.0 + margin else (low, mid)
    return float(high)


def _exact(value, name):
    """``value`` as a Fraction (a float exactly as it is), or a ValueError
    naming ``name``."""
    if isinstance(value, bool) or not isinstance(value, (int, float, Fraction)):
        try:
            value = float(value)
        except (TypeError, ValueError):
            raise ValueError(f"{name} must be a real number, got {value!r}") from None
    if isinstance(value, float) and not math.isfinite(value):
        raise ValueError(f"{name} must be finite, got {value!r}")
    return Fraction(value)


class Member(namedtuple("Member", "name beta gamma alpha_m alpha_f")):
    """One member of Newmark's family (module docstring): its ``name`` and
    its coefficients as Fractions.  Build one with :func:`newmark`,
    :func:`hht` or :func:`generalized_alpha`, or take one from
    :data:`MEMBERS`."""

    __slots__ = ()

    @property
    def delta(self):
        """alpha_m - alpha_f: a_n approximates y'' at t_n + delta h."""
        return self.alpha_m - self.alpha_f

    @property
    def order(self):
        """2 when gamma = 1/2 - alpha_m + alpha_f, else 1."""
        return 2 if self.gamma == Fraction(1, 2) - self.delta else 1

    @property
    def is_spline(self):
        """Whether the knots are a C2 cubic spline's: the report's member."""
        return (self.beta, self.gamma, self.alpha_m, self.alpha_f) == (
            Fraction(1, 6), Fraction(1, 2), 0, 0)

    @property
    def symmetric(self):
        """Whether the step is time-symmetric (Newmark's with gamma = 1/2):
        the compositions of order 4 and 6 raise the order of such a step
        only."""
        return self.gamma == Fraction(1, 2) and self.alpha_m == 0 and self.alpha_f == 0

    @property
    def stability_limit(self):
        """The supremum of the omega h at which the step does not grow on
        y'' = -omega^2 y (module docstring).  Newmark's members (gamma >=
        1/2): infinite where beta >= gamma/2, else 1/sqrt(gamma/2 - beta)
        (Hughes [4]_, Sec. 9.1).  The alpha members: infinite under Chung
        and Hulbert's conditions [3]_ (gamma = 1/2 - alpha_m + alpha_f,
        alpha_m <= alpha_f <= 1/2, beta >= 1/4 + (alpha_f - alpha_m)/2);
        for any other record, the first omega h where the spectral radius
        of the step's amplification matrix exceeds 1 (by 1e-9), found on a
        grid to 1e6 and refined by bisection (0 when it grows at once)."""
        am, af = self.alpha_m, self.alpha_f
        if am == 0 and af == 0 and self.gamma >= Fraction(1, 2):
            gap = self.gamma / 2 - self.beta
            return math.inf if gap <= 0 else 1.0 / math.sqrt(gap)
        if (self.gamma == Fraction(1, 2) - am + af and am <= af <= Fraction(1, 2)
                and self.beta >= Fraction(1, 4) + (af - am) / 2):
            return math.inf
        return _first_growth(self)

    def error_constants(self):
        """(c3y, c4y, c2yp, c3yp) of the module docstring, as Fractions;
        c4y and c3yp are None for the alpha members (not derived: module
        docstring)."""
        b, g, d = self.beta, self.gamma, self.delta
        if d != 0 or self.alpha_f != 0:
            return Fraction(1, 6) - b - d / 2, None, Fraction(1, 2) - g - d, None
        return (Fraction(1, 6) - b, Fraction(1, 24) - b / 2, Fraction(1, 2) - g,
                Fraction(1, 6) - g / 2)

    @property
    def interpolant(self):
        """The driver's code of the step's interpolant (module docstring)."""
        return CUBIC if self.is_spline else QUINTIC

    def scheme(self):
        """The :class:`Scheme` the compiled steps read, each number the
        double nearest the exact one."""
        # The alpha members' estimate keeps its leading term in h^3 y'''
        # alone (module docstring): no c4y, c3yp.
        c3y, c4y, c2yp, c3yp = (Fraction(0) if c is None else abs(c)
                                for c in self.error_constants())
        return Scheme(float(self.beta), float(self.gamma), float(self.alpha_m),
                      float(self.alpha_f), float(Fraction(1, 2) - self.beta),
                      float(1 - self.gamma), float(c3y), float(c4y), float(c2yp), float(c3yp),
                      1.0 / self.order, self.interpolant)

    def describe(self):
        """One line: the name and the coefficients."""
        coefficients = (f"beta = {float(self.beta):.6g}, gamma = {float(self.gamma):.6g}")
        if self.alpha_m or self.alpha_f:
            coefficients += (f", alpha_m = {float(self.alpha_m):.6g}, "
                             f"alpha_f = {float(self.alpha_f):.6g}")
        return f"{self.name} ({coefficients})"


def newmark(beta, gamma=Fraction(1, 2), name=None):
    """Newmark's member (beta, gamma): 0 <= beta <= 1/2 and 1/2 <= gamma
    <= 1 (below 1/2 the step amplifies every oscillation)."""
    beta, gamma = _exact(beta, "beta"), _exact(gamma, "gamma")
    if not 0 <= beta <= Fraction(1, 2):
        raise ValueError(f"beta must be in [0, 1/2], got {float(beta):g}")
    if not Fraction(1, 2) <= gamma <= 1:
        raise ValueError(f"gamma must be in [1/2, 1], got {float(gamma):g}")
    for known in _NEWMARK:
        if (known.beta, known.gamma) == (beta, gamma):
            return known if name is None else known._replace(name=name)
    return Member(name or f"newmark({float(beta):.6g}, {float(gamma):.6g})", beta, gamma,
                  Fraction(0), Fraction(0))


def hht(alpha):
    """Hilber, Hughes and Taylor's member [2]_: alpha_f = ``alpha`` in [0,
    1/3], alpha_m = 0, gamma = 1/2 + alpha, beta = (1 + alpha)^2/4
    (OpenSees's ``HHT`` takes 1 - alpha).  Second order, unconditionally
    stable, damping the high frequencies more as alpha grows."""
    a = _exact(alpha, "alpha")
    if not 0 <= a <= Fraction(1, 3):
        raise ValueError(f"alpha must be in [0, 1/3], got {float(a):g}")
    return Member(f"hht({float(a):.6g})", (1 + a) ** 2 / 4, Fraction(1, 2) + a, Fraction(0), a)


def generalized_alpha(rho_inf):
    """Chung and Hulbert's member [3]_ of spectral radius ``rho_inf`` in [0,
    1] at omega h -> infinity: alpha_m = (2 rho - 1)/(rho + 1), alpha_f =
    rho/(rho + 1), gamma = 1/2 - alpha_m + alpha_f, beta = (1 - alpha_m +
    alpha_f)^2/4.  Second order, unconditionally stable, with the least low
    frequency damping for its high frequency damping."""
    rho = _exact(rho_inf, "rho_inf")
    if not 0 <= rho <= 1:
        raise ValueError(f"rho_inf must be in [0, 1], got {float(rho):g}")
    am, af = (2 * rho - 1) / (rho + 1), rho / (rho + 1)
    return Member(f"generalized-alpha({float(rho):.6g})", (1 - am + af) ** 2 / 4,
                  Fraction(1, 2) - am + af, am, af)


_NEWMARK = (
    Member("spline", Fraction(1, 6), Fraction(1, 2), Fraction(0), Fraction(0)),
    Member("average-acceleration", Fraction(1, 4), Fraction(1, 2), Fraction(0), Fraction(0)),
    Member("fox-goodwin", Fraction(1, 12), Fraction(1, 2), Fraction(0), Fraction(0)),
    Member("central-difference", Fraction(0), Fraction(1, 2), Fraction(0), Fraction(0)),
)

#: The named members, by name: ``solve(..., method=name)``.  "spline" is the
#: report's method (Newmark's linear acceleration), the default.
MEMBERS = {member.name: member for member in _NEWMARK}
MEMBERS["hht"] = hht(Fraction(1, 10))._replace(name="hht")
MEMBERS["generalized-alpha"] = generalized_alpha(Fraction(4, 5))._replace(
    name="generalized-alpha")
#: Other names of the named members.
ALIASES = {"linear-acceleration": "spline", "trapezoidal": "average-acceleration"}


def member(method):
    """The :class:`Member` that ``method`` names: a name of :data:`MEMBERS`
    (or of :data:`ALIASES`), a pair (beta, gamma) of Newmark's, or a
    :class:`Member`; anything else is a ValueError naming ``method``."""
    if isinstance(method, Member):
        return method
    if isinstance(method, str):
        name = ALIASES.get(method, method)
        if name not in MEMBERS:
            raise ValueError(f"method must be one of {sorted(MEMBERS) + sorted(ALIASES)}, a "
                             f"pair (beta, gamma) or a member record, got {method!r}")
        return MEMBERS[name]
    if isinstance(method, tuple) and len(method) == 2:
        return newmark(*method)
    raise ValueError(f"method must be a member's name, a pair (beta, gamma) or a member "
                     f"record, got {method!r}")
