"""All knots at once: the spline step's relations solved together by
Newton's method with a sparse LU (the report's Sec. 5, "the coefficients at
all points in a single sweep ... through the use of Newton's method and
LU-decomposition").

The unknowns are y, y' and y'' at every knot t_0..t_n (3m(n + 1) numbers,
stored knot after knot).  The equations are the step relations of each
interval (:func:`splinestep.step.relations`, 2m each), the collocation
z_i = F(t_i, y_i, y'_i) at each knot (m each) and 2m boundary conditions:
y and y' at t_0 for an initial value problem (``solve(..., iteration="global")``), y at
both ends for a boundary value problem (:func:`solve_bvp`).  Ordered knot
by knot, the Jacobian is block-bidiagonal with bandwidth below 6m; it is
factorised by SuperLU (``scipy.sparse.linalg.splu``) in its natural column
order, which keeps the band.

For an initial value problem the solution is the one the stepper computes
one knot at a time (the same equations).  Solving them together costs more
on one processor (each Newton iteration touches every knot); it is the
structure that parallel-in-time methods distribute over processors.

References
----------
.. [1] U. M. Ascher, R. M. M. Mattheij, R. D. Russell, "Numerical Solution
   of Boundary Value Problems for Ordinary Differential Equations", SIAM
   (1995), Ch. 5 (collocation) and Ch. 7 (banded linear algebra).
.. [2] M. J. Gander, "50 years of time parallel time integration", in
   "Multiple Shooting and Time Domain Decomposition Methods", Springer (2015).
"""

import numpy as np

from . import _base, _compile
from ._base import FD_STEP
from .result import SplineSolution, new_result
from .step import EPS, ROUNDING_MULTIPLE, YP_START, YP_WEIGHT, Y_START, Y_WEIGHT, relations


class BadValue(ValueError):
    """A value of ``fun`` or ``jac`` that no Newton iteration can use; its
    text is the reason, as a run's message says it."""


def _value(fun, t, y, yp, args, m):
    """``fun(t, y, yp, *args)`` as m floats, or :class:`BadValue`."""
    value = fun(t, y, yp, *args)
    reason = _compile.fun_value_reason(value, t, m)
    if reason is not None:
        raise BadValue(reason)
    return np.asarray(value, dtype=float).reshape(m)


def _jacobian(jac, t, y, yp, args, m):
    """``jac(t, y, yp, *args)`` as two (m, m) float arrays, or
    :class:`BadValue` (also when jac raises: the message names jac)."""
    try:
        value = jac(t, y, yp, *args)
    except Exception as error:
        raise BadValue(f"jac raised {type(error).__name__} at t = {t:.10g}: {error}") from error
    if isinstance(value, (tuple, list)) and len(value) == 2:   # scipy.sparse: dense blocks
        value = [part.toarray() if _base.is_sparse(part) else part for part in value]
    reason = _compile.jac_value_reason(value, t, m)
    if reason is not None:
        raise BadValue(reason)
    return [np.asarray(part, dtype=float).reshape(m, m) for part in value]


def _evaluate(fun, jac, args, t, Y, YP, calls):
    """F, dF/dy and dF/dy' at every knot (arrays (n+1, m), (n+1, m, m) x 2);
    ``calls`` (a list [nfev, njev]) counts every call of fun and jac as it
    is made, also when a value no iteration can use raises
    :class:`BadValue`."""
    k, m = Y.shape
    F = np.empty((k, m))
    Fy = np.empty((k, m, m))
    Fyp = np.empty((k, m, m))
    for i in range(k):
        calls[0] += 1
        F[i] = _value(fun, t[i], Y[i], YP[i], args, m)
        if jac is not None:
            calls[1] += 1
            Fy[i], Fyp[i] = _jacobian(jac, t[i], Y[i], YP[i], args, m)
            continue
        for j in range(m):
            for target, part in ((Y, Fy), (YP, Fyp)):
                point = target[i].copy()
                step = FD_STEP * max(1.0, abs(point[j]))
                point[j] += step
                y_i, yp_i = (point, YP[i]) if target is Y else (Y[i], point)
                calls[0] += 1
                part[i, :, j] = (_value(fun, t[i], y_i, yp_i, args, m) - F[i]) / step
    return F, Fy, Fyp


def _system(t, U, F, Fy, Fyp, boundary):
    """Residual and sparse Jacobian of the whole trajectory.

    ``U`` is (n+1, 3, m): y, y', y'' per knot.  ``boundary`` is a list of
    (knot, component 0 for y or 1 for y', target values), m rows each;
    those at knot 0 come before its equations, the others after the last
    interval's (so the matrix stays banded); or a callable
    ``bc(y_a, yp_a, y_b, yp_b) -> (2m,)``, whose rows come last (they couple
    the two ends; SuperLU fills them in) and whose Jacobian is taken by
    finite differences."""
    k, _, m = U.shape
    n = k - 1
    dt = np.diff(t)
    Y, YP, Z = U[:, 0], U[:, 1], U[:, 2]
    r_y, r_yp = relations(dt[:, None], Y[:-1], YP[:-1], Z[:-1], Y[1:], YP[1:], Z[1:])
    r_z = Z - F
    general = boundary if callable(boundary) else None
    boundary = [] if general else boundary
    first = [b for b in boundary if b[0] == 0]
    rest = [b for b in boundary if b[0] != 0]
    start = m * len(first)          # rows of the boundary conditions at knot 0
    r, c = np.indices((m, m)).reshape(2, -1)
    eye = np.broadcast_to(np.eye(m), (n, m, m))
    rows, cols, vals = [], [], []

    def put(row0, knot, part, blocks):
        """Blocks (count, m, m) at rows row0 + ..., columns of (knot, part)."""
        row0 = np.atleast_1d(row0)
        col0 = 3 * m * np.atleast_1d(knot) + part * m
        rows.append((row0[:, None] + r[None]).ravel())
        cols.append((col0[:, None] + c[None]).ravel())
        vals.append(np.asarray(blocks).reshape(-1, m * m).ravel())

    for j, (knot, part, _) in enumerate(first):
        put(j * m, knot, part, np.eye(m)[None])
    # Collocation at every knot: z_i - F_i.
    z_rows = np.r_[start, start + m + 3 * m * np.arange(n) + 2 * m]
    knots = np.arange(k)
    put(z_rows, knots, 2, np.broadcast_to(np.eye(m), (k, m, m)))
    put(z_rows, knots, 0, -Fy)
    put(z_rows, knots, 1, -Fyp)
    # The step relations of each interval (splinestep.step.relations).
    i = np.arange(n)
    h = dt[:, None, None]
    y_rows = start + m + 3 * m * i
    put(y_rows, i + 1, 0, eye)
    put(y_rows, i, 0, -eye)
    put(y_rows, i, 1, -h * eye)
    put(y_rows, i, 2, -h * h * Y_START * eye)
    put(y_rows, i + 1, 2, -h * h * Y_WEIGHT * eye)
    put(y_rows + m, i + 1, 1, eye)
    put(y_rows + m, i, 1, -eye)
    put(y_rows + m, i, 2, -h * YP_START * eye)
    put(y_rows + m, i + 1, 2, -h * YP_WEIGHT * eye)
    end = start + m + 3 * m * n
    for j, (knot, part, _) in enumerate(rest):
        put(end + j * m, knot, part, np.eye(m)[None])
    size = 3 * m * k
    residual = np.empty(size)
    if general is not None:
        ends = [U[0, 0], U[0, 1], U[-1, 0], U[-1, 1]]
        value = np.asarray(general(*ends), dtype=float).reshape(2 * m)
        residual[end:] = value
        for slot, (knot, part) in enumerate(((0, 0), (0, 1), (n, 0), (n, 1))):
            block = np.empty((2 * m, m))
            for j in range(m):
                moved = [e.copy() for e in ends]
                step = FD_STEP * max(1.0, abs(moved[slot][j]))
                moved[slot][j] += step
                block[:, j] = (np.asarray(general(*moved), dtype=float).reshape(2 * m)
                               - value) / step
            rr, cc = np.indices((2 * m, m)).reshape(2, -1)
            rows.append(end + rr)
            cols.append(3 * m * knot + part * m + cc)
            vals.append(block[rr, cc])
    for j, (knot, part, target) in enumerate(first):
        residual[j * m:(j + 1) * m] = U[knot, part] - target
    residual[(z_rows[:, None] + np.arange(m)).ravel()] = r_z.ravel()
    residual[(y_rows[:, None] + np.arange(m)).ravel()] = r_y.ravel()
    residual[(y_rows[:, None] + m + np.arange(m)).ravel()] = r_yp.ravel()
    for j, (knot, part, target) in enumerate(rest):
        residual[end + j * m:end + (j + 1) * m] = U[knot, part] - target
    from scipy import sparse   # here: scipy takes 0.3 s to import
    matrix = sparse.csc_matrix((np.concatenate(vals), (np.concatenate(rows),
                                                       np.concatenate(cols))),
                               shape=(size, size))
    return residual, matrix


def _rounding(F, Fy, Fyp, U):
    """The rounding level of the collocation z = F at the iterate ``U``:
    the largest eps (|dF/dy| |y| + |dF/dy'| |y'| + |F|) over the knots
    (F is known no better at a state known to rounding), the level below
    which an update of z cannot be relied on to fall."""
    level = (np.einsum("kij,kj->ki", np.abs(Fy), np.abs(U[:, 0]))
             + np.einsum("kij,kj->ki", np.abs(Fyp), np.abs(U[:, 1])) + np.abs(F))
    return EPS * float(np.max(level))


def newton(fun, jac, args, t, U, boundary, tol, max_iter,
           hint="try a better y_guess or a finer mesh"):
    """Newton's method on the whole trajectory from the guess ``U``
    ((n+1, 3, m), overwritten).  Converged when the largest update is at
    most ``tol`` times max(1, the largest |value|), or within
    ROUNDING_MULTIPLE times the rounding level of F (:func:`_rounding`; on
    the chain of m masses that level, about 4 (m + 1)^2 eps |y|, passes
    tol = 1e-12 of the largest value from about m = 150 on), a floor like
    the step's (:func:`splinestep.step.newton_step`); ``hint`` ends the
    message of a run that does not converge.

    Returns (status, message, niter, nfev, njev): status 0 converged, -1
    not (the message says why)."""
    calls = [0, 0]
    for it in range(1, max_iter + 1):
        try:
            F, Fy, Fyp = _evaluate(fun, jac, args, t, U[:, 0], U[:, 1], calls)
        except BadValue as error:
            return -1, f"Newton iteration {it}: {error}", it - 1, *calls
        except (ArithmeticError, ValueError) as error:
            return -1, (f"Newton iteration {it}: fun raised {type(error).__name__} at the "
                        f"current iterate: {error}"), it - 1, *calls
        bad_f = ~np.all(np.isfinite(F), axis=1)
        bad_j = ~(np.all(np.isfinite(Fy), axis=(1, 2)) & np.all(np.isfinite(Fyp), axis=(1, 2)))
        if bad_f.any() or bad_j.any():
            where = np.flatnonzero(bad_f | bad_j)[0]
            what = ("fun" if bad_f[where] else "jac" if jac is not None
                    else "the finite-difference Jacobian")
            return -1, (f"Newton iteration {it}: {what} is not finite at t = {t[where]:.10g} "
                        f"(the first such knot); {hint}."), it - 1, *calls
        residual, matrix = _system(t, U, F, Fy, Fyp, boundary)
        try:
            from scipy.sparse.linalg import splu
            delta = splu(matrix, permc_spec="NATURAL").solve(-residual)
        except RuntimeError as error:  # SuperLU: "Factor is exactly singular"
            return -1, f"Newton iteration {it}: the Jacobian is singular ({error})", it, \
                *calls
        if not np.all(np.isfinite(delta)):
            return -1, f"Newton iteration {it}: the update is not finite", it, *calls
        U += delta.reshape(U.shape)
        if np.max(np.abs(delta)) <= max(tol * max(1.0, np.max(np.abs(U))),
                                        ROUNDING_MULTIPLE * _rounding(F, Fy, Fyp, U)):
            return 0, "Newton's method converged on the whole trajectory.", it, *calls
    return -1, (f"Newton's method on the whole trajectory did not converge in {max_iter} "
                f"iterations; {hint}."), max_iter, *calls


# Newton's method on a mesh stops when its update is at most this times
# max(1, the largest |value|); the solution's error is judged by ``tol``.
NEWTON_TOL = 1e-10
# The estimate must fall at least this much when the mesh is halved (order 2:
# by 4) for the solution to be taken as converging with the mesh.
CONVERGING = 2.0
# A refined mesh aims at this fraction of the bound (:func:`refined`).
TARGET = 0.5
# The most parts an interval is split into at once: the fourth derivative is
# estimated on a mesh that may not resolve the solution yet.
MAX_SPLIT = 4


def solve_bvp(fun, x, ya=None, yb=None, *, bc=None, y_guess=None, tol=1e-6, max_nodes=1000,
              max_iter=50, jac=None, args=()):
    """Solve the boundary value problem y'' = F(x, y, y'), y(x[0]) = ya,
    y(x[-1]) = yb (or general conditions ``bc``), with the C2 cubic spline on
    a mesh that satisfies the equation at every mesh point, refined from
    ``x`` until the estimated error of y is within ``tol``.

    The error of the solution on a mesh is estimated by solving again on
    the mesh with every interval halved: the method is of order 2, so
    (y_h - y_{h/2}) 4/3 estimates the error of y_h (Richardson).  While the
    estimate exceeds ``tol`` max(1, max |y|), the mesh is refined where the
    spline's truncation error is large (:func:`refined`: intervals split
    into up to :data:`MAX_SPLIT` parts, those where the solution is smooth
    left as they are), up to ``max_nodes`` points (the mesh of the estimate
    may have up to twice as many).  On scipy's shock-layer test problem
    (eps = 1e-3) at tol = 1e-3, 1e-5, 1e-7 the meshes have 90, 715 and
    7,264 points, where halving the whole mesh needs 257, 4,097 and 32,769
    (``tests/test_bvp.py``).  A run that ends without meeting ``tol`` (at ``max_nodes``, or
    when Newton fails on a refined mesh) fails; when its last estimates did
    not fall at least twofold as the mesh was halved, the message adds that
    the solution does not converge with the mesh: the problem may have no
    solution, or no unique one, near the guess (its linearisation singular
    or nearly so, as y'' = -y on [0, pi] with y(0) = 0, y(pi) = 1), or the
    mesh is still too coarse to resolve it (y'' = -300^2 y on 641 points).
    A problem with many solutions, such as y'' = -y on [0, pi] with y(0) =
    y(pi) = 0, converges to the one near the guess without a word.

    Parameters
    ----------
    fun : callable
        ``fun(x, y, yp, *args) -> y''`` as for :func:`splinestep.solve`.
    x : array_like, shape (k,)
        The initial mesh, strictly increasing, k >= 3.
    ya, yb : float or array_like, shape (m,)
        The boundary values (None when ``bc`` is given).
    bc : callable, optional
        ``bc(y_a, yp_a, y_b, yp_b) -> residual`` of shape (2m,), zero when the
        conditions hold, as scipy's ``solve_bvp``'s ``bc`` for the
        first-order form; instead of ``ya`` and ``yb``, with ``y_guess``
        giving m.  Its Jacobian is taken by finite differences.
    y_guess : array_like, shape (m, k), optional
        Initial guess of y on the mesh (zero by default), as in
        ``scipy.integrate.solve_bvp``; a problem with several solutions
        (Bratu's) converges to the one near the guess.  y' and y'' start from
        its finite differences.
    tol : float
        The estimated error of y (largest over mesh points and components)
        must be at most ``tol`` times max(1, max |y|).  ``np.inf``: the
        solution on ``x`` as given, without an estimate (for a study on
        chosen meshes).  Newton's method on each mesh stops when its update
        is at most :data:`NEWTON_TOL` times max(1, the largest |value|).
    max_nodes : int
        The most mesh points the refinement may reach (scipy's
        ``max_nodes``); a mesh ``x`` of max_nodes points or more is not
        refined, only its error estimated.
    max_iter : int
        Newton iterations allowed on each mesh.
    jac : callable, optional
        ``jac(x, y, yp, *args) -> (dF/dy, dF/dyp)``; finite differences
        otherwise (2m evaluations per mesh point and iteration).
    args : tuple
        Extra arguments of ``fun`` and ``jac``.

    Returns
    -------
    OdeResult
        ``t`` (the final mesh), ``y``, ``yp``, ``ypp`` (m, k), ``sol`` (the
        spline), ``error_estimate`` (the estimated error of y on that
        mesh; NaN with ``tol = inf``, and when Newton failed on the mesh
        that would have estimated it: the message then quotes the
        estimates of the coarser meshes), ``niter`` (Newton iterations on the
        returned mesh), ``nfev`` and ``njev`` (every call, on every mesh
        solved), ``status`` (0: converged within ``tol``; -1: Newton failed,
        or the estimate exceeds ``tol`` at ``max_nodes``), ``message``,
        ``success``.  Order 2 in the mesh width.

    References
    ----------
    .. [1] U. M. Ascher, R. M. M. Mattheij, R. D. Russell, "Numerical Solution
       of Boundary Value Problems for Ordinary Differential Equations", SIAM
       (1995), Sec. 5.4 (spline collocation), Sec. 9.1 (mesh selection by
       equidistribution) and Sec. 9.3 (error estimates by mesh halving).
    """
    x = _base._real_array(x, "x")
    if x.ndim != 1 or x.size < 3 or not np.all(np.isfinite(x)) or not np.all(np.diff(x) > 0):
        raise ValueError("x must be a finite, strictly increasing 1-D array of at least "
                         "3 points")
    if bc is None:
        if ya is None or yb is None:
            raise ValueError("give ya and yb, or bc")
        ya, yb = _base.check_state(ya, yb)
        m = ya.size
    else:
        if ya is not None or yb is not None:
            raise ValueError("give ya and yb, or bc, not both")
        if not callable(bc):
            raise ValueError("bc must be callable")
        if y_guess is None:
            raise ValueError("bc needs y_guess (of shape (m, x.size)) to give m")
        m = np.atleast_2d(np.asarray(y_guess, dtype=float)).shape[0]
    args = _base.check_args(args)
    if not callable(fun):
        raise ValueError("fun must be callable")
    if jac is not None and not callable(jac):
        raise ValueError("jac must be callable or None")
    if not (_base.is_real(tol) and tol > 0):
        raise ValueError(f"tol must be positive (inf: no estimate), got {tol!r}")
    if not (_base.is_integer(max_nodes) and max_nodes >= 3):
        raise ValueError(f"max_nodes must be an integer >= 3, got {max_nodes!r}")
    if not (_base.is_integer(max_iter) and max_iter >= 1):
        raise ValueError(f"max_iter must be an integer >= 1, got {max_iter!r}")
    if y_guess is None:
        y_guess = np.zeros((m, x.size))
    y_guess = _base._real_array(y_guess, "y_guess")
    if y_guess.shape != (m, x.size) or not np.all(np.isfinite(y_guess)):
        raise ValueError(f"y_guess must be finite, of shape ({m}, {x.size}), "
                         f"got shape {y_guess.shape}")
    Y = y_guess.T.copy()
    _base.check_fun(fun, x[0], Y[0], np.zeros(m), args)
    if jac is not None:
        _base.check_jac(jac, x[0], Y[0], np.zeros(m), args)
    if bc is not None:
        try:
            value = np.asarray(bc(Y[0], np.zeros(m), Y[-1], np.zeros(m)), dtype=float)
        except Exception as error:
            raise ValueError(f"bc raised {type(error).__name__}: {error}") from error
        if value.shape != (2 * m,):
            raise ValueError(f"bc must return {2 * m} residuals (2m), got shape {value.shape}")
    YP = np.gradient(Y, x, axis=0)
    Z = np.gradient(YP, x, axis=0)
    U = np.stack([Y, YP, Z], axis=1)
    # The counts include the calls of fun and jac that checked them at x[0].
    counts = [1, int(jac is not None)]

    def on(mesh, U):
        """Newton on ``mesh`` from the guess ``U`` (overwritten): (status,
        message, niter), the calls counted."""
        conditions = bc if bc is not None else [(0, 0, ya), (mesh.size - 1, 0, yb)]
        with np.errstate(all="ignore"):
            status, message, niter, nfev, njev = newton(fun, jac, args, mesh, U, conditions,
                                                        NEWTON_TOL, max_iter)
        counts[0] += nfev
        counts[1] += njev
        return status, message, niter

    status, message, niter = on(x, U)
    if status != 0 or not np.isfinite(tol):
        return result(x, U, status, message, niter, *counts)
    history = []       # the estimates of the meshes solved so far

    def diverging():
        """The sentence for estimates that did not fall with the mesh, or ''."""
        if len(history) < 2 or history[-1] * CONVERGING <= history[-2]:
            return ""
        return (f" The solution does not converge as the mesh is refined (estimates "
                f"{history[-2]:.2g} -> {history[-1]:.2g}): the problem may have no solution, "
                "or no unique one, near the guess (its linearisation singular or nearly so), "
                "or the mesh is still too coarse to resolve it.")

    while True:
        fine, U_fine = _halved(x, U)
        fine_status, fine_message, fine_niter = on(fine, U_fine)
        if fine_status != 0:
            return result(x, U, -1, f"On the refined mesh of {fine.size} points: "
                          f"{fine_message}{diverging()}", niter, *counts)
        estimate = float(np.max(np.abs(U[:, 0] - U_fine[::2, 0]))) * 4.0 / 3.0
        history.append(estimate)
        bound = tol * max(1.0, float(np.max(np.abs(U[:, 0]))))
        if estimate <= bound:
            return result(x, U, 0, f"Converged: the estimated error of y, {estimate:.2g}, is "
                          f"within tol on {x.size} mesh points.", niter, *counts,
                          error_estimate=estimate)
        mesh = refined(x, fine, U_fine[:, 2], estimate, bound)
        if mesh.size > max_nodes:
            text = (f"The estimated error of y, {estimate:.2g}, exceeds tol "
                    f"({bound:.2g}) on {x.size} mesh points, and the mesh it needs "
                    f"({mesh.size} points) may not grow past max_nodes = {max_nodes}.")
            return result(x, U, -1, text + diverging(), niter, *counts,
                          error_estimate=estimate)
        if np.array_equal(mesh, fine):
            x, U, niter = fine, U_fine, fine_niter
            continue
        U = _on_mesh(fine, U_fine, mesh)
        status, message, niter = on(mesh, U)
        if status != 0:
            return result(mesh, U, -1, f"On the refined mesh of {mesh.size} points: "
                          f"{message}{diverging()}", niter, *counts)
        x = mesh


def _on_mesh(x, U, mesh):
    """y, y', y'' (stacked as U) of the spline through ``U`` on ``x``, at ``mesh``."""
    spline = SplineSolution(x, U[:, 0], U[:, 1], U[:, 2])
    return np.stack([spline(mesh, nu).T for nu in range(3)], axis=1)


def _halved(x, U):
    """``x`` with every interval halved, and the spline through U there."""
    fine = np.empty(2 * x.size - 1)
    fine[::2], fine[1::2] = x, 0.5 * (x[:-1] + x[1:])
    return fine, _on_mesh(x, U, fine)


def refined(x, fine, Z, estimate, bound):
    """The next mesh: each interval of ``x`` split into k_i equal parts.

    The spline's truncation error on an interval of width h_i is
    O(h_i^2 y''''), y'''' estimated by the jumps of the third derivative
    of the solution on ``fine`` (``x`` with every interval halved; ``Z`` is
    y'' there) at the interval's ends and middle: r_i = h_i^2 max |y''''|.
    The error of y is modelled as proportional to sum h_i r_i (the
    truncation error integrated against a bounded Green's function), so
    splitting interval i into k_i parts multiplies it by
    sum (h_i r_i / k_i^2) / sum h_i r_i.  The k_i = ceil(sqrt(r_i / r*))
    are those of the largest threshold r* whose predicted estimate is
    :data:`TARGET` times ``bound``: the intervals where the solution is
    smooth stay as they are (equidistribution: Ascher, Mattheij and
    Russell, Sec. 9.1)."""
    hf = np.diff(fine)
    jerk = np.diff(Z, axis=0) / hf[:, None]
    fourth = np.zeros(fine.size)
    fourth[1:-1] = np.max(np.abs(np.diff(jerk, axis=0)), axis=1) / (0.5 * (hf[1:] + hf[:-1]))
    fourth[0], fourth[-1] = fourth[1], fourth[-2]
    h = np.diff(x)
    r = h ** 2 * np.maximum(np.maximum(fourth[:-1:2], fourth[1::2]), fourth[2::2])
    weight = h * r
    if not (np.all(np.isfinite(weight)) and np.sum(weight) > 0.0):
        return fine
    wanted = TARGET * bound / estimate
    lo, hi = np.log(np.max(r)) + 2.0 * np.log(wanted), np.log(np.max(r))
    for _ in range(60):   # bisection on log r*: the predicted factor grows with r*
        mid = 0.5 * (lo + hi)
        k = np.minimum(np.ceil(np.sqrt(r / np.exp(mid))), MAX_SPLIT)
        if np.sum(weight / k ** 2) <= wanted * np.sum(weight):
            lo = mid
        else:
            hi = mid
    k = np.clip(np.ceil(np.sqrt(r / np.exp(lo))), 1, MAX_SPLIT).astype(int)
    mesh = np.concatenate([x[:1]] + [x[i] + h[i] * np.arange(1, k[i] + 1) / k[i]
                                      for i in range(h.size)])
    mesh[np.cumsum(k)] = x[1:]
    return mesh


def result(t, U, status, message, niter, nfev, njev, t_eval=None, dense_output=True,
           error_estimate=np.nan):
    """The :class:`OdeResult` of a whole-trajectory solve on the knots ``t``
    (the same keys as every solver's; no local error estimate); on one
    knot alone (a failed run), no dense output and no t_eval."""
    T, Y, YP, Z = t, U[:, 0], U[:, 1], U[:, 2]
    sol = SplineSolution(T, Y, YP, Z) if T.size > 1 else None
    if t_eval is not None:
        t_out, y, yp, ypp = t_eval, sol(t_eval), sol(t_eval, 1), sol(t_eval, 2)
    else:
        t_out, y, yp, ypp = T.copy(), Y.T.copy(), YP.T.copy(), Z.T.copy()
    return new_result(t=t_out, y=y, yp=yp, ypp=ypp, sol=sol if dense_output else None,
                      nfev=nfev, njev=njev, niter=niter, nstep=T.size - 1,
                      status=0 if status == 0 else -1, message=message,
                      error_estimate=error_estimate)
