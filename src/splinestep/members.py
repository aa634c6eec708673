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
- :attr:`Member.stability_limit`: the largest omega h for which the step
  does not grow on y'' = -omega^2 y (infinite for the unconditionally stable
  members; 1/sqrt(gamma/2 - beta) for Newmark's with gamma >= 1/2 [4]_);
- :meth:`Member.error_constants`: the leading local errors of one step,
  the constants of the error estimate of the controllers, the driver's
  estimate and the step-size check (below);
- :attr:`Member.interpolant`: what ``t_eval``, the events and ``sol`` read
  between knots: the spline's own C2 cubic for the report's member, whose
  knots it joins; for every other member the quintic Hermite through both
  knots' (y, y', a) (C2; exact for a quintic, so between knots as accurate
  as the knots it joins, which are O(h^2));
- :meth:`Member.scheme`: the numbers the compiled steps read, a
  :class:`Scheme`.

The local error.  For a member whose accelerations are those of the exact
solution at a time shifted by delta h, a_n = y''(t_n + delta h) with delta
= alpha_m - alpha_f (what the last equation gives to leading order), a
step from exact y_n, y'_n misses

    err_y  = c3y h^3 y''' + c4y h^4 y'''',   err_y' = c2yp h^2 y''' + c3yp h^3 y'''',

with c3y = 1/6 - beta - delta/2, c2yp = 1/2 - gamma - delta (zero for the
second-order members), c4y = 1/24 - (1/2 - beta) delta^2/2 - beta (1 +
delta)^2/2 and c3yp = 1/6 - (1 - gamma) delta^2/2 - gamma (1 + delta)^2/2
(Taylor expansion; ``tests/test_members.py`` checks each against one step
from exact values).  Where delta is not 0 (the alpha members) the
estimate keeps c3y |h|^3 |y'''| alone: a_n's shift changes with the step,
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
    def explicit(self):
        """beta = 0 and alpha_f = 0: y_{n+1} does not depend on a_{n+1}, so
        that for an F free of y' one evaluation solves the step."""
        return self.beta == 0 and self.alpha_f == 0

    @property
    def stability_limit(self):
        """The largest omega h at which the step does not grow on y'' =
        -omega^2 y: infinite where beta >= gamma/2 >= 1/4 (with the alpha
        members' own conditions, alpha_m <= alpha_f <= 1/2 [3]_), else
        1/sqrt(gamma/2 - beta) (gamma >= 1/2; Hughes [4]_, Sec. 9.1)."""
        if self.alpha_m != 0 or self.alpha_f != 0:
            stable = (self.alpha_m <= self.alpha_f <= Fraction(1, 2)
                      and self.beta >= Fraction(1, 4) + (self.alpha_f - self.alpha_m) / 2)
            return math.inf if stable else math.nan
        gap = self.gamma / 2 - self.beta
        return math.inf if gap <= 0 else 1.0 / math.sqrt(gap)

    def error_constants(self):
        """(c3y, c4y, c2yp, c3yp) of the module docstring, as Fractions."""
        b, g, d = self.beta, self.gamma, self.delta
        return (Fraction(1, 6) - b - d / 2,
                Fraction(1, 24) - (Fraction(1, 2) - b) * d * d / 2 - b * (1 + d) ** 2 / 2,
                Fraction(1, 2) - g - d,
                Fraction(1, 6) - (1 - g) * d * d / 2 - g * (1 + d) ** 2 / 2)

    @property
    def interpolant(self):
        """The driver's code of the step's interpolant (module docstring)."""
        return CUBIC if self.is_spline else QUINTIC

    def scheme(self):
        """The :class:`Scheme` the compiled steps read, each number the
        double nearest the exact one."""
        c3y, c4y, c2yp, c3yp = (abs(c) for c in self.error_constants())
        if self.delta != 0:
            # a_n approximates y'' at t_n + delta h, a shift that changes
            # with h: where the step changes, the jump of the third
            # derivative measures the change of step, not the fourth.  The
            # estimate keeps its leading term in h^3 y''' alone.
            c4y, c3yp = Fraction(0), Fraction(0)
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
