"""The Pleiades problem: seven stars in the plane (Hairer, Norsett and
Wanner's test problem PLEI).

Star i (i = 1..7) has mass m_i = i and moves under the others' gravity,

    q_i'' = sum_{j != i} m_j (q_j - q_i) / |q_j - q_i|^3,

from the initial values below, over t in [0, 3].  Several close encounters
make the step equation of an implicit method hard: near one, h^2/6 dF/dy has
an eigenvalue near 1.  No exact solution: the reference is a DOP853 solve
at rtol 1e-13, atol 1e-14 (:meth:`Problem.reference`).

References
----------
.. [1] E. Hairer, S. P. Norsett, G. Wanner, "Solving Ordinary Differential
   Equations I", 2nd ed., Springer (1993), Sec. II.10, problem PLEI.
.. [2] F. Mazzia, C. Magherini, "Test Set for Initial Value Problem
   Solvers", release 2.4, University of Bari (2008), problem "Pleiades".
"""

import numpy as np
from numba import njit

from ._problem import Problem

MASSES = np.arange(1.0, 8.0)
X0 = np.array([3.0, 3.0, -1.0, -3.0, 2.0, -2.0, 2.0])
Y0 = np.array([3.0, -3.0, 2.0, 0.0, 0.0, -4.0, 4.0])
XP0 = np.array([0.0, 0.0, 0.0, 0.0, 0.0, 1.75, -1.5])
YP0 = np.array([0.0, 0.0, 0.0, -1.25, 1.0, 0.0, 0.0])
T_SPAN = (0.0, 3.0)


@njit(cache=True)
def pleiades_rhs(t, q, qp, masses):
    """Accelerations of the seven stars; q = (x_1..x_7, y_1..y_7)."""
    n = masses.shape[0]
    out = np.zeros(2 * n)
    for i in range(n):
        for j in range(i + 1, n):
            dx = q[j] - q[i]
            dy = q[n + j] - q[n + i]
            r2 = dx * dx + dy * dy
            w = 1.0 / (r2 * np.sqrt(r2))
            out[i] += masses[j] * w * dx
            out[n + i] += masses[j] * w * dy
            out[j] -= masses[i] * w * dx
            out[n + j] -= masses[i] * w * dy
    return out


def pleiades():
    """The Pleiades problem, 14 components, t in [0, 3].

    The default step h = 1e-3 reaches t = 3 but is too large: the error
    there is 0.38 and the run warns so.  Uniform steps of 1e-4 (error
    3.6e-3) or adaptive knots (rtol = atol = 1e-4: 4.3e-3; 1e-6: 4.0e-5) give
    usable solutions."""
    return Problem(
        name="Pleiades (7 bodies)", fun=pleiades_rhs, args=(MASSES.copy(),),
        y0=np.concatenate([X0, Y0]), yp0=np.concatenate([XP0, YP0]), t_span=T_SPAN, h=1e-3,
        notes="Hairer, Norsett and Wanner's PLEI; reference: DOP853 at rtol 1e-13.")
