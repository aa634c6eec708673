"""The Bratu problem y'' + lambda exp(y) = 0, y(0) = y(1) = 0.

For 0 < lambda < lambda_c = 3.5138... it has two solutions,

    y(x) = -2 ln( cosh((x - 1/2) theta / 2) / cosh(theta / 4) ),

one for each root theta of theta = sqrt(2 lambda) cosh(theta / 4): the
lower branch (small theta) and the upper one.

References
----------
.. [1] U. M. Ascher, R. M. M. Mattheij, R. D. Russell, "Numerical Solution
   of Boundary Value Problems for Ordinary Differential Equations", SIAM
   (1995), Example 1.6 (Bratu's problem).
"""

import numpy as np
from numba import njit


def _fold_u():
    """theta / 4 at the fold, where the two branches meet: the root of
    u tanh(u) = 1 (lambda is largest there), by Newton's method from 1.2."""
    u = 1.2
    for _ in range(20):
        step = (u * np.tanh(u) - 1.0) / (np.tanh(u) + u / np.cosh(u) ** 2)
        u -= step
        if abs(step) <= 1e-16 * u:
            break
    return u


_FOLD_U = _fold_u()
LAMBDA_CRITICAL = 8.0 * _FOLD_U ** 2 / np.cosh(_FOLD_U) ** 2


@njit(cache=True)
def bratu_rhs(x, y, yp, lam):
    return -lam * np.exp(y)


@njit(cache=True)
def bratu_jac(x, y, yp, lam):
    return -lam * np.exp(y[0]) * np.eye(1), np.zeros((1, 1))


def bratu_theta(lam, branch):
    """The root theta of theta = sqrt(2 lambda) cosh(theta/4) on ``branch``
    "lower" or "upper"."""
    from scipy.optimize import brentq   # here: scipy.optimize takes 0.3 s to import
    lam = float(lam)
    if not 0 < lam < LAMBDA_CRITICAL:
        raise ValueError(f"lam must lie in (0, {LAMBDA_CRITICAL:.6f}), got {lam}")
    fold = 4 * _FOLD_U
    g = lambda th: th - np.sqrt(2 * lam) * np.cosh(th / 4)   # noqa: E731
    if branch == "lower":
        return brentq(g, 0.0, fold, xtol=1e-15, rtol=1e-15)
    if branch == "upper":
        hi = 2 * fold
        while g(hi) > 0:
            hi *= 2
        return brentq(g, fold, hi, xtol=1e-15, rtol=1e-15)
    raise ValueError(f"branch must be 'lower' or 'upper', got {branch!r}")


def bratu(lam=1.0, branch="lower"):
    """(fun, jac, args, exact) of the Bratu problem on [0, 1] for ``lam``;
    ``exact(x)`` is the solution on ``branch``, shape (1, k)."""
    theta = bratu_theta(lam, branch)

    def exact(x):
        x = np.asarray(x, dtype=float)
        return (-2 * np.log(np.cosh((x - 0.5) * theta / 2) / np.cosh(theta / 4)))[None]
    return bratu_rhs, bratu_jac, (float(lam),), exact
