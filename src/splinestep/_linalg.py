"""Newton's matrices built outside the compiled loop, for a Jacobian given
as constant matrices or returned as scipy.sparse matrices.

The compiled loop builds Newton's matrix I - h^2/6 dF/dy - h/2 dF/dy' itself
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
    (``jac(t, y, yp, *args)``), for m components; ``sparse``: factorised
    by SuperLU here (else written into the loop's dense buffer)."""

    def __init__(self, jac, args, m, sparse):
        self.args, self.m, self.sparse = args, m, bool(sparse)
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
        yp): factorised here (sparse: returns its contraction bound, the
        max-norm of wy dF/dy + wyp dF/dy'), or -(wy dF/dy + wyp dF/dy')
        written into ``lu`` for the loop to finish.  Returns (status, njev,
        bound); a jac that fails or a singular matrix is SINGULAR, its
        reason kept for the run's message."""
        njev = 0
        try:
            fy, fyp, njev = self._parts(t, y, yp)
            if not self.sparse:
                lu[:, :] = -(wy * fy + wyp * fyp)
                return OK, njev, 0.0
            from scipy import sparse
            from scipy.sparse.linalg import splu
            part = (wy * fy + wyp * fyp).tocsc()
            bound = float(np.max(abs(part).sum(axis=1))) if part.nnz else 0.0
            self.factors[slot] = splu(sparse.identity(self.m, format="csc") - part)
            return OK, njev, bound
        except Exception as error:   # jac raised, returned a bad value, or SuperLU failed
            self.reason = (f"Newton's matrix could not be built at t = {t:.10g}: "
                           f"{type(error).__name__}: {error}")
            self.factors.pop(slot, None)
            return SINGULAR, njev, 0.0

    def solve(self, slot, b):
        """Solve with slot ``slot``'s factors, ``b`` overwritten."""
        b[:] = self.factors[slot].solve(b)
