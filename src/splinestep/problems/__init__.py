"""The report's test problems, with exact reference solutions.

- :func:`cannonball` -- Newton's cannonball, the Kepler problem (report
  Sec. 3.1), for the gravity parameters :data:`CANNONBALL_MU`;
- :func:`rigid_body` -- Euler's torque-free rigid body in the report's
  second-order form (Sec. 3.2);
- :func:`harmonic` -- y'' = -omega^2 y, the model problem of the stability
  and phase-error theory;
- :func:`eccentric` -- a Kepler orbit of given eccentricity from periapsis;
- :func:`pleiades` -- seven stars with close encounters (PLEI);
- :func:`bratu` -- the Bratu boundary value problem and its two solutions;
- :func:`chain` -- a chain of m masses and springs, y'' = K y, the
  structural-dynamics model problem at any m (exact modal solution);
- :func:`first_order` -- any of them as the first-order system scipy's
  ``solve_ivp`` takes.
"""

from ._problem import Problem, first_order
from .kepler import (CANNONBALL_MU, ORBIT_TYPES, acceleration_derivatives, cannonball,
                     step_size_control, eccentric, kepler_exact, orbit_elements, path_curvature)
from .boundary import bratu
from .pleiades import pleiades
from .oscillator import harmonic
from .euler_top import euler_top_exact, rigid_body
from .chain import chain, chain_frequencies, chain_matrix

__all__ = ["Problem", "first_order", "cannonball", "CANNONBALL_MU", "ORBIT_TYPES", "kepler_exact",
           "orbit_elements", "acceleration_derivatives", "path_curvature", "step_size_control",
           "rigid_body", "euler_top_exact", "harmonic", "eccentric", "pleiades", "bratu",
           "chain", "chain_matrix", "chain_frequencies"]
