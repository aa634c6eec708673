"""The harmonic oscillator y'' = -omega^2 y, the model problem of the
stability and phase-error analysis (exact solution cos, sin)."""

import numpy as np
from numba import njit

from ._problem import Problem


@njit(cache=True)
def harmonic_rhs(t, y, yp, omega2):
    return -omega2 * y


@njit(cache=True)
def harmonic_jac(t, y, yp, omega2):
    m = y.shape[0]
    return -omega2 * np.eye(m), np.zeros((m, m))


def harmonic(omega=1.0, t_span=(0.0, 10.0), h=0.1):
    """y'' = -omega^2 y, y(0) = 1, y'(0) = 0: y = cos(omega t)."""
    omega = float(omega)

    def exact(t):
        t = np.atleast_1d(np.asarray(t, dtype=float))
        return np.cos(omega * t)[None], (-omega * np.sin(omega * t))[None]

    return Problem(
        name=f"harmonic oscillator omega={omega:g}", fun=harmonic_rhs,
        args=(omega * omega,), jac=harmonic_jac, y0=np.array([1.0]),
        yp0=np.array([0.0]), t_span=tuple(t_span), h=h, exact=exact,
        invariants={"energy": lambda y, yp: 0.5 * (yp[0] ** 2 + omega ** 2 * y[0] ** 2)})
