"""splinestep: cubic-spline time stepping for second-order ODEs.

The public API:

- :func:`solve` -- the cubic-spline stepper for y'' = F(t, y, y') (uniform,
  given or adaptive knots; orders 2, 4, 6; stepwise or global Newton-LU);
- :func:`solve_bvp` -- the same spline for a boundary value problem;
- :func:`solve_reversible` -- time-reversible variable steps;
- :func:`rk4` -- the report's baseline, classical Runge-Kutta;
- :func:`verlet` -- Stormer-Verlet (velocity form), the second-order baseline;
- :func:`linear` -- builds F for f'' + p f' + q f = r;
- :mod:`splinestep.problems` -- the report's test problems with exact solutions;
- :class:`OdeResult`, :class:`SplineSolution`, :class:`HermiteSolution` -- what
  the solvers return.
"""

from . import _compile  # noqa: F401  (first: it sets how numba caches the package)
from .linear import linear
from .result import HermiteSolution, OdeResult, SplineSolution
from .rk4 import rk4
from .bvp import solve_bvp
from .reversible import solve_reversible
from .spline import solve
from .verlet import verlet

__all__ = ["solve", "solve_bvp", "solve_reversible", "rk4", "verlet", "linear", "problems",
           "OdeResult", "SplineSolution", "HermiteSolution"]
__version__ = "0.1.0"


def __getattr__(name):
    """``splinestep.problems`` imported when first used, not with the
    package: its compiled right-hand sides cost about 0.9 s to load, which
    a user of :func:`solve` alone need not pay."""
    if name == "problems":
        import importlib
        module = importlib.import_module(".problems", __name__)
        globals()["problems"] = module
        return module
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
