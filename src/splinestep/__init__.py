"""splinestep: cubic-spline time stepping for second-order ODEs.

The public API:

- :func:`solve` -- the cubic-spline stepper for y'' = F(t, y, y');
- :func:`rk4` -- the report's baseline, classical Runge-Kutta;
- :func:`verlet` -- Stormer-Verlet (velocity form), the second-order baseline;
- :func:`linear` -- builds F for f'' + p f' + q f = r;
- :mod:`splinestep.problems` -- the report's test problems with exact solutions;
- :class:`OdeResult`, :class:`SplineSolution` -- what the solvers return.
"""

from . import _compile  # noqa: F401  (first: it sets how numba caches the package)
from . import problems
from .linear import linear
from .result import OdeResult, SplineSolution
from .rk4 import rk4
from .spline import solve
from .verlet import verlet

__all__ = ["solve", "rk4", "verlet", "linear", "problems", "OdeResult", "SplineSolution"]
__version__ = "0.1.0"
