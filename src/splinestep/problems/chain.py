"""A chain of m equal masses joined by equal springs, both ends fixed: the
structural-dynamics model problem, with an exact modal solution at any m.

The masses sit at x_i = i / (m + 1) of a unit string; their displacements
y_i obey

    y'' = K y,   K = (m + 1)^2 tridiag(1, -2, 1)   (m x m),

the second-difference matrix of the wave equation y_tt = y_xx with y = 0
at x = 0 and x = 1.  K is diagonalised by the discrete sine transform:
its eigenvectors are phi_j(i) = sin(i j pi / (m + 1)), j = 1..m, with
eigenvalues -omega_j^2,

    omega_j = 2 (m + 1) sin(j pi / (2 (m + 1))),

so each mode oscillates on its own and the solution at any t is the
transform of a_j cos(omega_j t) + b_j / omega_j sin(omega_j t), with (a_j,
b_j) the modal coordinates of (y0, y'0).  The exact solution costs
O(m log m) per time (``scipy.fft.dst``, type I, orthonormal, its own
inverse).  The slowest mode has omega_1 ~ pi, the fastest omega_m ~ 2 (m +
1): a stiff problem whose stiffness grows like m, with a smooth solution.

References
----------
.. [1] G. Strang, "Computational Science and Engineering",
   Wellesley-Cambridge (2007), Sec. 1.5 (eigenvalues and eigenvectors of the
   second-difference matrix) and Sec. 2.2 (oscillation by Newton's law).
.. [2] K.-J. Bathe, "Finite Element Procedures", Prentice Hall (1996),
   Ch. 9 (direct integration and mode superposition).
"""

import numpy as np
from numba import njit

from ._problem import Problem


@njit(cache=True)
def chain_rhs(t, y, yp, scale):
    """K y with K = ``scale`` tridiag(1, -2, 1), fixed ends; O(m)."""
    m = y.shape[0]
    out = np.empty(m)
    for i in range(m):
        left = y[i - 1] if i > 0 else 0.0
        right = y[i + 1] if i < m - 1 else 0.0
        out[i] = scale * ((left - 2.0 * y[i]) + right)
    return out


def chain_matrix(m):
    """K = (m + 1)^2 tridiag(1, -2, 1) as a scipy.sparse CSR matrix."""
    from scipy import sparse
    scale = float(m + 1) ** 2
    return sparse.diags([scale * np.ones(m - 1), -2.0 * scale * np.ones(m),
                         scale * np.ones(m - 1)], [-1, 0, 1], format="csr")


def chain_frequencies(m):
    """omega_j = 2 (m + 1) sin(j pi / (2 (m + 1))), j = 1..m, ascending."""
    j = np.arange(1, m + 1)
    return 2.0 * (m + 1) * np.sin(j * np.pi / (2.0 * (m + 1)))


def chain(m, y0=None, yp0=None, periods=3.0, omega_h=1.0):
    """The chain of m masses y'' = K y, K = (m + 1)^2 tridiag(1, -2, 1).

    Parameters
    ----------
    m : int
        Number of masses (>= 1).
    y0 : array_like of shape (m,), optional
        Initial displacements.  By default the string's two slowest shapes,
        y0_i = sin(pi x_i) + 0.5 sin(2 pi x_i) with x_i = i / (m + 1): a
        smooth solution, whose error at a fixed step is that of its slow
        modes, so that each method shows its order.
    yp0 : array_like of shape (m,), optional
        Initial velocities; by default zero (from rest).
    periods : float
        The span: this many periods 2 pi / omega_1 of the slowest mode.
    omega_h : float
        The problem's step h is ``omega_h`` / omega_m, omega_m the fastest
        frequency (1: the step a structural code takes for the whole
        spectrum; the explicit methods and the fixed-point sweep need
        omega_m h below 2 to 2.8).

    Returns
    -------
    Problem
        ``fun`` compiled (O(m) per evaluation), ``args`` ((m + 1)^2,), ``jac``
        the constant pair (K, 0) of scipy.sparse matrices (accepted by
        :func:`splinestep.solve` as a constant Jacobian), ``exact`` the modal
        solution (O(m log m) per time).

    References
    ----------
    .. [1] G. Strang, "Computational Science and Engineering",
       Wellesley-Cambridge (2007), Sec. 1.5.
    """
    from scipy import sparse
    if not (isinstance(m, (int, np.integer)) and not isinstance(m, bool) and m >= 1):
        raise ValueError(f"m must be an integer >= 1, got {m!r}")
    m = int(m)
    x = np.arange(1, m + 1) / (m + 1.0)
    y0 = (np.sin(np.pi * x) + 0.5 * np.sin(2.0 * np.pi * x) if y0 is None
          else np.array(y0, dtype=float).reshape(m))
    yp0 = np.zeros(m) if yp0 is None else np.array(yp0, dtype=float).reshape(m)
    omega = chain_frequencies(m)
    a, b = _dst(y0), _dst(yp0) / omega
    T = 2.0 * np.pi / omega[0]

    def exact(t):
        t = np.atleast_1d(np.asarray(t, dtype=float))
        y, yp = np.empty((m, t.size)), np.empty((m, t.size))
        for k, tk in enumerate(t):
            c, s = np.cos(omega * tk), np.sin(omega * tk)
            y[:, k] = _dst(a * c + b * s)
            yp[:, k] = _dst(omega * (b * c - a * s))
        return y, yp

    return Problem(
        name=f"chain of {m} masses", fun=chain_rhs, args=(float(m + 1) ** 2,), y0=y0, yp0=yp0,
        t_span=(0.0, periods * T), h=omega_h / omega[-1],
        jac=(chain_matrix(m), sparse.csr_matrix((m, m))), exact=exact,
        invariants={"energy": lambda y, yp: 0.5 * np.sum(yp ** 2, axis=0)
                    - 0.5 * np.sum(y * (chain_matrix(m) @ y), axis=0)},
        notes="Exact: modal superposition by the discrete sine transform.")


def _dst(v):
    """The orthonormal discrete sine transform of type I (its own inverse)."""
    from scipy.fft import dst
    return dst(v, type=1, norm="ortho")
