"""Right-hand sides for linear equations f'' + p(t) f' + q(t) f = r(t)
(the report's eq. 4)."""

import numpy as np


def linear(p, q, r):
    """Build ``fun(t, y, yp)`` for f'' + p(t) f' + q(t) f = r(t).

    Parameters
    ----------
    p, q, r : callable or float
        Coefficients as functions of t (numbers are taken as constants).
        For a system, p(t) and q(t) may return (m, m) matrices and r(t) an
        (m,) vector; scalars act on every component.

    Returns
    -------
    callable
        ``fun(t, y, yp) = r(t) - p(t) yp - q(t) y`` for :func:`splinestep.solve`.
    """
    coeffs = [c if callable(c) else (lambda t, c=float(c): c) for c in (p, q, r)]
    p, q, r = coeffs

    def fun(t, y, yp):
        return np.asarray(r(t) - _apply(p(t), yp) - _apply(q(t), y), dtype=float)

    return fun


def _apply(coefficient, v):
    c = np.asarray(coefficient, dtype=float)
    return c @ v if c.ndim == 2 else c * v
