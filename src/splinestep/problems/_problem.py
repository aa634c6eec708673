"""The test-problem record shared by the report's problems."""

from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from ..members import MEMBERS
from ..rk4 import rk4
from ..spline import solve
from ..verlet import verlet

# Tolerances of the scipy solve used where no exact solution exists.
REFERENCE_RTOL = 1e-13
REFERENCE_ATOL = 1e-14


def first_order(fun, args, m):
    """y'' = fun(t, y, y', *args) with m components as the first-order
    system u' = (y', fun) of u = (y, y'), for scipy's ``solve_ivp`` (a
    compiled ``fun`` is called through its plain Python source)."""
    f = getattr(fun, "py_func", fun)

    def system(t, u):
        return np.concatenate([u[m:], np.atleast_1d(f(t, u[:m], u[m:], *args))])
    return system


@dataclass(frozen=True)
class Problem:
    """A second-order initial value problem y'' = fun(t, y, y', *args).

    Attributes
    ----------
    name : str
    fun : callable
        ``numba.njit`` right-hand side ``fun(t, y, yp, *args)``, returning
        y'' as a tuple of floats or an array; its plain Python source is
        ``fun.py_func``.
    args : tuple
        Parameters passed to ``fun`` and ``jac``.
    y0, yp0 : ndarray, shape (m,)
    t_span : (float, float)
    h : float
        The step the report uses.
    jac : callable, pair of matrices, or None
        ``jac(t, y, yp, *args) -> (dF/dy, dF/dyp)``, or the constant pair
        (dense or scipy.sparse), as :func:`splinestep.solve` takes it.
    exact : callable or None
        ``exact(t) -> (y, yp)``, each of shape (m, k), the exact solution.
    invariants : dict of str to callable
        ``invariant(y, yp) -> array``, quantities the exact flow conserves
        (y and yp of shape (m, k)).
    notes : str
        Where the values come from and what the report leaves unsaid.
    """

    name: str
    fun: Callable
    args: tuple
    y0: np.ndarray
    yp0: np.ndarray
    t_span: tuple
    h: float
    jac: Callable = None
    exact: Callable = None
    invariants: dict = field(default_factory=dict)
    notes: str = ""

    def solve(self, method="spline", h=None, **kwargs):
        """Integrate with ``method`` "spline" (:func:`splinestep.solve`),
        another member of Newmark's family (a name of
        :data:`splinestep.members.MEMBERS`, on :func:`splinestep.solve`),
        "rk4" (:func:`splinestep.rk4`) or "verlet" (:func:`splinestep.verlet`)
        at step ``h`` (default: the report's step; "adaptive": the spline
        stepper's adaptive knots, with ``rtol`` and ``atol``); further
        keywords go to the solver."""
        solvers = {"spline": solve, "rk4": rk4, "verlet": verlet}
        if isinstance(method, str) and method in MEMBERS and method not in solvers:
            # another member of Newmark's family (splinestep.members)
            kwargs["method"], method = method, "spline"
        if method not in solvers:
            raise ValueError(f"method must be one of {tuple(solvers)} or a member of "
                             f"{sorted(MEMBERS)}, got {method!r}")
        if isinstance(h, str) and (h != "adaptive" or method != "spline"):
            raise ValueError(f'h must be a number, None or "adaptive" (spline only), got {h!r}')
        if (method == "spline" and kwargs.get("iteration") in ("newton", "global")
                and "jac" not in kwargs):
            kwargs["jac"] = self.jac
        step = None if isinstance(h, str) else self.h if h is None else h
        return solvers[method](self.fun, self.t_span, self.y0, self.yp0, step,
                               args=self.args, **kwargs)

    @property
    def reference_kind(self):
        """How :meth:`reference` is computed."""
        if self.exact is not None:
            return "exact"
        return (f"scipy solve_ivp DOP853, rtol={REFERENCE_RTOL:g}, "
                f"atol={REFERENCE_ATOL:g}")

    def reference(self, t):
        """Reference solution (y, yp) at times t, each of shape (m, k):
        the exact solution when there is one, otherwise a DOP853 solve at
        rtol = 1e-13, atol = 1e-14 of the first-order form."""
        t = np.atleast_1d(np.asarray(t, dtype=float))
        if self.exact is not None:
            return self.exact(t)
        m = self.y0.size
        from scipy.integrate import solve_ivp   # here: scipy takes 0.3 s to import
        sol = solve_ivp(first_order(self.fun, self.args, m), (self.t_span[0], t[-1]),
                        np.concatenate([self.y0, self.yp0]), method="DOP853",
                        t_eval=t, rtol=REFERENCE_RTOL, atol=REFERENCE_ATOL)
        if not sol.success:
            raise RuntimeError(f"reference solve failed: {sol.message}")
        return sol.y[:m], sol.y[m:]
