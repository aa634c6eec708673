"""Newton's matrices built outside the compiled loop, for a Jacobian given
as constant matrices or returned as scipy.sparse matrices.

The compiled loop builds Newton's matrix I - beta h^2 dF/dy - gamma h dF/dy'
(h^2/6 and h/2 for the spline; M - ... with a mass matrix, :class:`Mass`) itself
when ``jac`` is a function returning dense arrays (or by finite
differences), and factorises it by its own dense LU: O(m^3) per
factorisation, O(m^2) per solve and m^2 numbers of memory.  A
:class:`Matrices` builds it in Python instead, called from the loop as
plain Python (:func:`splinestep._compile.external_matrix`) when the matrix
is needed (at the first step, after a change of step, when the iteration
slows down: the loop keeps it as it keeps its own):

- sparse (``sparse``): the matrix is factorised by SuperLU
  (``scipy.sparse.linalg.splu``) and kept per slot; each Newton iteration
  solves with it through one more call into Python
  (:func:`splinestep._compile.external_solve`).  For the banded matrices of
  structural models (a chain of masses: tridiagonal) a factorisation and a
  solve cost O(m).
- dense: the matrix is written into the loop's dense buffer, which the
  loop factorises and solves with as it does its own (a constant dense
  Jacobian, or a sparse one of few components, where the dense compiled
  solve is faster than a call into Python: see :data:`SPARSE_FROM`).

References
----------
.. [1] X. S. Li, J. W. Demmel, J. R. Gilbert et al., "SuperLU Users'
   Guide", LBNL-44289 (1999), and scipy.sparse.linalg.splu.
.. [2] E. Hairer, G. Wanner, "Solving Ordinary Differential Equations II",
   2nd ed., Springer (1996), Sec. IV.8 (simplified Newton iterations).
"""

import numpy as np

from . import _base
from .status import OK, SINGULAR

# The number of components from which a sparse Jacobian is factorised by
# SuperLU in Python rather than densified into the compiled dense LU: the
# crossover measured on the chain of masses (benchmarks/scaling.py, Newton
# with the matrix kept, one solve a step): per step 7.7 us dense against
# 8.6 us SuperLU at m = 100, 12 us against 9.7 us at m = 150 (and 0.68 ms
# against 39 us at m = 1,000).  Below it the dense compiled solve, O(m^2)
# with no call into Python, is faster.
SPARSE_FROM = 120


class Matrices:
    """Newton's matrices of a run whose ``jac`` is the pair of constant
    matrices (dF/dy, dF/dy') or a function returning scipy.sparse matrices
    (``jac(t, y, yp, *args)``), or any ``jac`` of a run with a mass matrix
    (``mass``, a :class:`Mass`), for m components; ``sparse``: factorised
    by SuperLU here (else written into the loop's dense buffer)."""

    def __init__(self, jac, args, m, sparse, mass=None):
        self.args, self.m, self.sparse, self.mass = args, m, bool(sparse), mass
        self.constant = not callable(jac)
        self.jac = jac
        self.factors = {}
        self.reason = None
        if self.constant:
            self.parts = tuple(self._convert(part) for part in jac)

    def _convert(self, part):
        """A part of the Jacobian as CSC (sparse) or a dense float array."""
        if self.sparse:
            from scipy import sparse
            return sparse.csc_matrix(part, dtype=float)
        return part.toarray() if _base.is_sparse(part) else np.asarray(part, dtype=float)

    def _parts(self, t, y, yp):
        """(dF/dy, dF/dy', calls of jac) at (t, y, yp)."""
        if self.constant:
            return self.parts[0], self.parts[1], 0
        value = self.jac(t, y.copy(), yp.copy(), *self.args)
        reason = _base.jac_parts_reason(value, self.m, t)
        if reason is not None:
            raise ValueError(reason)
        return self._convert(value[0]), self._convert(value[1]), 1

    def build(self, slot, t, y, yp, wy, wyp, lu):
        """Build slot ``slot``'s matrix I - wy dF/dy - wyp dF/dy' at (t, y,
        yp) (with a mass matrix, M - wy dF/dy - wyp dF/dy'): factorised here
        (sparse: returns its contraction bound, the max-norm of wy dF/dy +
        wyp dF/dy', divided by M's smallest diagonal: an estimate of the
        bound of M^-1 (...), exact for a diagonal M, too small for a
        consistent one, which only makes the loop's test of an iterate at
        the rounding level stricter), or -(wy dF/dy + wyp
        dF/dy') (times M^-1) written into ``lu`` for the loop to finish.
        Returns (status, njev, bound); a jac that fails or a singular matrix
        is SINGULAR, its reason kept for the run's message."""
        njev = 0
        try:
            fy, fyp, njev = self._parts(t, y, yp)
            part = wy * fy + wyp * fyp
            if not self.sparse:
                if self.mass is not None:
                    part = self.mass.solve(part.toarray() if _base.is_sparse(part) else part)
                lu[:, :] = -part
                return OK, njev, 0.0
            from scipy import sparse
            from scipy.sparse.linalg import splu
            part = sparse.csc_matrix(part)
            bound = float(np.max(abs(part).sum(axis=1))) if part.nnz else 0.0
            if self.mass is None:
                left = sparse.identity(self.m, format="csc")
            else:
                left = sparse.csc_matrix(self.mass.matrix)
                bound /= float(np.min(np.abs(left.diagonal())))
            self.factors[slot] = splu((left - part).tocsc())
            return OK, njev, bound
        except Exception as error:   # jac raised, returned a bad value, or SuperLU failed
            self.reason = (f"Newton's matrix could not be built at t = {t:.10g}: "
                           f"{type(error).__name__}: {error}")
            self.factors.pop(slot, None)
            return SINGULAR, njev, 0.0

    def solve(self, slot, b):
        """Solve with slot ``slot``'s factors, ``b`` overwritten: the loop's
        residual b of z - M^-1 F becomes the update (M - ...)^-1 M b."""
        if self.mass is not None:
            b[:] = self.factors[slot].solve(self.mass.times(b))
        else:
            b[:] = self.factors[slot].solve(b)


class Mass:
    """A constant mass matrix M of M y'' = F(t, y, y'), factorised once.

    ``mass`` is an (m, m) array or scipy.sparse matrix, or a vector of m
    numbers (a diagonal, lumped M).  The step equation of a run with a mass
    matrix is the member's with F replaced by M^-1 F (:meth:`apply`, one
    solve with the kept factors per evaluation: what the fixed-point sweep
    needs), and Newton's matrix is M - wy dF/dy - wyp dF/dy' (built by
    :class:`Matrices`, sparse when M or the Jacobian is), whose solve
    replaces a solve with I - wy M^-1 dF/dy - wyp M^-1 dF/dy', a matrix
    that is dense even where M and the Jacobian are sparse.  Factorised by
    SuperLU when M is sparse with :data:`SPARSE_FROM` components or more,
    by a dense LU otherwise, by division when it is a vector.  A ValueError
    names ``mass`` when it is not square of size m, not finite, or
    singular."""

    def __init__(self, mass, m):
        from scipy import sparse
        self.m = m
        self.diagonal = None
        if _base.is_sparse(mass):
            matrix = sparse.csc_matrix(mass, dtype=float)
            values = matrix.data
        else:
            matrix = np.asarray(mass)
            if not (np.issubdtype(matrix.dtype, np.number) and matrix.ndim in (1, 2)):
                raise ValueError("mass must be an (m, m) array, a scipy.sparse matrix or a "
                                 f"vector of m numbers, got {type(mass).__name__}")
            matrix = matrix.astype(float)
            values = matrix
        shape = matrix.shape
        if shape not in ((m,), (m, m)):
            raise ValueError(f"mass must have shape ({m}, {m}) or ({m},) for m = {m} "
                             f"components, got {shape}")
        if not np.all(np.isfinite(values)):
            raise ValueError("mass has values that are not finite")
        self.sparse = _base.is_sparse(mass) and m >= SPARSE_FROM
        if matrix.ndim == 1:
            if np.any(matrix == 0.0):
                raise ValueError("mass is singular: a zero on its diagonal")
            self.diagonal, self.matrix = matrix, sparse.diags(matrix, format="csc")
            return
        self.matrix = matrix if self.sparse else (
            matrix.toarray() if _base.is_sparse(matrix) else matrix)
        self.factors = self._factor()

    def _factor(self):
        """The kept factors of M; a ValueError naming ``mass`` if singular."""
        import warnings
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            try:
                if self.sparse:
                    from scipy.sparse.linalg import splu
                    return splu(self.matrix)
                from scipy.linalg import lu_factor
                factors = lu_factor(self.matrix, check_finite=False)
            except (RuntimeError, Warning, ValueError) as error:
                raise ValueError(f"mass is singular ({error})") from None
        if not np.all(np.abs(np.diag(factors[0])) > 0.0):
            raise ValueError("mass is singular: a zero pivot in its LU factors")
        return factors

    def solve(self, b):
        """M^-1 b (b of shape (m,) or (m, k)); a new array."""
        if self.diagonal is not None:
            return b / (self.diagonal if b.ndim == 1 else self.diagonal[:, None])
        if self.sparse:
            return self.factors.solve(np.asarray(b, dtype=float))
        from scipy.linalg import lu_solve
        return lu_solve(self.factors, b, check_finite=False)

    def times(self, b):
        """M b."""
        return self.matrix @ b

    def apply(self, fun):
        """F as the loop sees it: ``fun``'s value times M^-1, a plain
        function of the same arguments (a value of the wrong length is
        passed on, so that the loop reports it)."""
        def with_mass(t, y, yp, *args):
            value = np.atleast_1d(np.asarray(fun(t, y, yp, *args), dtype=float))
            return self.solve(value) if value.shape == (self.m,) else value
        return with_mass
