"""Problems of the tolerance study (:mod:`splinestep.analysis.tolerance`),
beyond the report's: a large-amplitude pendulum (exact, Jacobi elliptic
functions), a forced Duffing oscillator (reference: a tight DOP853 solve)
and scipy's rational test problem in second-order form (exact)."""

import math

import numpy as np
from numba import njit

from ._problem import Problem


@njit(cache=True)
def pendulum_rhs(t, y, yp):
    return (-math.sin(y[0]),)


@njit(cache=True)
def pendulum_jac(t, y, yp):
    return np.array([[-math.cos(y[0])]]), np.zeros((1, 1))


def pendulum(theta0=3.0, t_span=(0.0, 50.0)):
    """y'' = -sin y from rest at y(0) = ``theta0`` (radians, below pi).
    Exact solution: with k = sin(theta0 / 2), m = k^2 and K = K(m),
    y = 2 arcsin(k sn(K - t | m)) and y' = -2 k cn(K - t | m) (the
    pendulum's closed form; e.g. Lawden, "Elliptic Functions and
    Applications", Sec. 5.2)."""
    from scipy.special import ellipj, ellipk
    theta0 = float(theta0)
    if not 0.0 < theta0 < math.pi:
        raise ValueError(f"theta0 must lie in (0, pi), got {theta0!r}")
    k = math.sin(theta0 / 2.0)
    quarter = float(ellipk(k * k))

    def exact(t):
        t = np.atleast_1d(np.asarray(t, dtype=float))
        sn, cn, _, _ = ellipj(quarter - t, k * k)
        return (2.0 * np.arcsin(k * sn))[None], (-2.0 * k * cn)[None]

    return Problem(
        name=f"pendulum theta0={theta0:g}", fun=pendulum_rhs, args=(), jac=pendulum_jac,
        y0=np.array([theta0]), yp0=np.array([0.0]), t_span=tuple(t_span), h=0.01,
        exact=exact, notes=f"period {4 * quarter:.6g}")


@njit(cache=True)
def duffing_rhs(t, y, yp, delta, alpha, beta, gamma, omega):
    return (gamma * math.cos(omega * t) - delta * yp[0] - alpha * y[0] - beta * y[0] ** 3,)


@njit(cache=True)
def duffing_jac(t, y, yp, delta, alpha, beta, gamma, omega):
    return (np.array([[-alpha - 3.0 * beta * y[0] ** 2]]), np.array([[-delta]]))


def duffing(t_span=(0.0, 30.0), delta=0.1, alpha=1.0, beta=1.0, gamma=0.5, omega=1.2):
    """The forced Duffing oscillator y'' = gamma cos(omega t) - delta y' -
    alpha y - beta y^3 from y = 1, y' = 0 (a hardening spring, off
    resonance: not chaotic).  Reference: DOP853 at rtol 1e-13."""
    return Problem(
        name="forced Duffing oscillator", fun=duffing_rhs,
        args=tuple(float(v) for v in (delta, alpha, beta, gamma, omega)), jac=duffing_jac,
        y0=np.array([1.0]), yp0=np.array([0.0]), t_span=tuple(t_span), h=0.01)


@njit(cache=True)
def rational_rhs(t, y, yp):
    return (-yp[0] * (1.0 - y[0]) / 5.0,)


def rational(t_span=(5.0, 1.0)):
    """scipy's rational test problem (scipy/integrate/_ivp/tests/test_ivp.py,
    fun_rational) as one second-order equation: its solution u = t / (t + 10)
    with y_1 = t u' solves y'' = -y' (1 - y) / 5 from y(5) = 1/3,
    y'(5) = 2/45.  Exact solution: y = t / (t + 10), y' = 10 / (t + 10)^2."""
    def exact(t):
        t = np.atleast_1d(np.asarray(t, dtype=float))
        return (t / (t + 10.0))[None], (10.0 / (t + 10.0) ** 2)[None]

    return Problem(
        name="scipy's rational problem", fun=rational_rhs, args=(), jac=None,
        y0=np.array([1.0 / 3.0]), yp0=np.array([2.0 / 45.0]), t_span=tuple(t_span), h=0.01,
        exact=exact)
