"""What a run of the spline stepper can tell about its own accuracy.

A fixed step cannot promise accuracy, but the spline knows when the step is
far past what the solution supports, in two ways:

1. The local error estimate.  y''' is constant on each interval of the
   spline, so its jump at a knot, divided by the mean of the two steps,
   estimates y''''; one step from exact values misses h^4 y''''/24 in y and
   h^3 y''''/12 in y' to leading order (the constants of the member's
   record, :mod:`splinestep.members`, whose other members add their h^3
   y''' terms; the alpha members estimate y alone).  Every run
   reports the largest of these estimates and where.  When it exceeds
   :data:`LOCAL_FRACTION` of the largest |y| (or |y'|) of the run, the
   step cannot resolve the solution.  When the estimates summed over the
   run exceed :data:`ACCUMULATED_FRACTION` of it, the steps' errors add up
   to a solution about as far off, unless the equation damps them (for a
   problem that neither damps nor amplifies errors the sum of the y'
   estimates tracks the global error, at about 1.3 times it on the
   oscillator; the y estimates, O(h^4) each, sum to less).  The sum grows
   with the length of a run, so a long accurate run of a damped problem,
   whose errors decay, can warn falsely (a forced oscillator with damping
   0.1 over (0, 2000) at an error of 1e-3 of its size does); and an orbit
   whose drift amplifies its errors can be far off before the sum says so.

2. The linearised step.  Freezing the Jacobians A = dF/dy and B = dF/dy'
   at a state gives the linear equation y'' = A y + B y'; one step of the
   method multiplies (y, y') by an amplification matrix M, and the exact
   flow by exp(h L) with L = [[0, I], [A, B]].  When the spectral radius of M
   exceeds both 1 and that of exp(h L) by more than :data:`GROWTH_MARGIN`
   (and, where the equation grows, its growth rate log rho by more than
   :data:`RATE_MARGIN`, which a step of ordinary accuracy on a growing mode
   does not), the step amplifies what the equation does not: on y'' = -omega^2 y the
   method is stable for omega h < sqrt(12) only, and the test fires above
   omega h = 3.4641029, where rho = 1 + GROWTH_MARGIN.  At omega h =
   sqrt(12) itself M is a Jordan block with rho = 1 and the solution grows
   linearly, which a spectral radius cannot see; the local-error test above
   fires long before a step is that large.  Checked at the initial
   state, the state where the estimated local error is largest and the
   final state.

What the second test costs.  Up to :data:`DENSE_UP_TO` components it is
exact: A and B as dense matrices (from ``jac``, or 2m + 1 evaluations of F
by forward differences) and the eigenvalues of the 2m x 2m matrices M and
L, O(m^3) time and O(m^2) memory at each state.  Above, it looks at the
modes that decide stability, those of the largest eigenvalues: a few
Arnoldi steps (:data:`KRYLOV_STEPS`) on A and on B, each step one product
with the matrix (from ``jac``, dense or scipy.sparse) or one evaluation of
F (a forward-difference Jacobian-vector product), give Ritz pairs; the
:data:`RITZ` of largest modulus of each are judged as the scalar equation
y'' = a y + b y' they span (a, b their Rayleigh quotients of A and B: two
more products each for the other matrix), by the 2 x 2 amplification
matrix and the exact flow of that equation.  That is exact where A and B
share their eigenvectors (B = 0, B = c I, Rayleigh damping), and costs
O(KRYLOV_STEPS^2 m) arithmetic, without jac KRYLOV_STEPS + 2 evaluations of F
when F does not depend on y' and up to 2 KRYLOV_STEPS + 8 RITZ + 1 when it
does (the products with B too; 32 and 77 at the defaults), and
O(KRYLOV_STEPS m) memory per state.  On the chain of masses (a spectrum
dense near its top) 30 Arnoldi steps find the fastest frequency 3e-4 to
7e-4 low at m = 100 to 10,000, so the test fires from omega h = 3.4651 to
3.4665 instead of 3.4641.  The check can be switched off (``check=False``).

Either finding is a ``UserWarning`` and a sentence in the result's
``message``; the run keeps its status, since the numbers are what the
method computed.  Except where they are not a solution at all: when the
linearised step amplifies an equation that does not grow and the run's
largest |y| exceeds :data:`BLOWN_UP` times its start's size (not zero),
and a few more steps from the final state grow it as the linearised step
does, the run failed (status -1), and its message names the time, the
step, the estimated omega h (the undamped oscillation on which one step
grows as much) and the member's stability limit.  A run of order 4 or 6,
whose composed step the check does not retake, keeps the warning
(``y_max`` bounds any run).

References
----------
.. [1] Y. Saad, "Numerical Methods for Large Eigenvalue Problems", 2nd ed.,
   SIAM (2011), Ch. 6 (Arnoldi's method, Ritz values).
.. [2] D. A. Knoll, D. E. Keyes, "Jacobian-free Newton-Krylov methods: a
   survey of approaches and applications", J. Comput. Phys. 193 (2004)
   357-397 (Jacobian-vector products by differences of F).
"""

import warnings

import numpy as np
from numba import njit

from . import _base
from ._base import FD_STEP
from .members import amplification
from .step import SPLINE

# The estimated local error, as a fraction of the run's largest |y| (or
# |y'|), above which the step does not resolve the solution.  Accurate runs
# sit many decades below it (tests/test_check.py measures the notebooks' runs).
LOCAL_FRACTION = 0.1
# The estimated local errors summed over the run, as a fraction of the
# run's largest |y| (or |y'|), above which the solution is off by as much.
ACCUMULATED_FRACTION = 0.3
# Relative growth per step of the linearised step beyond the equation's own.
GROWTH_MARGIN = 1e-3
# Where the equation grows (rho of exp(h L) > 1), the relative excess of the
# step's growth rate log rho over the equation's that is not mere accuracy.
RATE_MARGIN = 0.01
# Up to this many components the linearised step's eigenvalues are computed
# densely; above, estimated by Arnoldi steps on the Jacobians (module
# docstring).
DENSE_UP_TO = 64
KRYLOV_STEPS = 30
RITZ = 4
# A run whose largest |y| exceeds this many times its start's size (max
# |y0|, and max |y'0| times the span) while the linearised step amplifies
# an equation that does not grow has blown up: a failure (status -1), not
# a warning (a run that failed already, at ``y_max`` for one, keeps its
# own message).  A run from the zero state (y0 = 0 and y'0 = 0: size 0) is
# not judged so: how large its solution should be is not known (a mode
# that the step amplifies but that is not excited stays at 0), and it
# keeps the warning.
BLOWN_UP = 1e3
# The steps retaken from the final state to see whether it grows as the
# linearised step does (_grows_as_the_step), as many as can be taken; a
# state beyond OVERFLOWING (Euclidean norm of y) from which not one more
# step can be taken has grown to overflow.
RETAKEN = 4
OVERFLOWING = 1e150


def _jac_parts(jac, args, t, y, yp):
    """(dF/dy, dF/dy', calls of jac) from ``jac``, a function or the
    constant pair, dense or scipy.sparse as given."""
    if callable(jac):
        fy, fyp = jac(t, y.copy(), yp.copy(), *args)
        return fy, fyp, 1
    return jac[0], jac[1], 0


def _dense(part):
    return part.toarray() if _base.is_sparse(part) else np.asarray(part, dtype=float)


def jacobians(fun, jac, args, t, y, yp):
    """(dF/dy, dF/dy', evaluations of fun, evaluations of jac) at (t, y,
    y'), dense: from ``jac``, or by forward differences (2m + 1
    evaluations)."""
    if jac is not None:
        fy, fyp, calls = _jac_parts(jac, args, t, y, yp)
        return _dense(fy), _dense(fyp), 0, calls
    m = y.size
    g = np.atleast_1d(np.asarray(fun(t, y.copy(), yp.copy(), *args), dtype=float))
    fy, fyp = np.empty((m, m)), np.empty((m, m))
    for k in range(m):
        for x, d in ((y, fy), (yp, fyp)):
            step = FD_STEP * max(1.0, abs(x[k]))
            shifted = x.copy()
            shifted[k] += step
            args_k = (shifted, yp) if x is y else (y, shifted)
            value = fun(t, args_k[0].copy(), args_k[1].copy(), *args)
            d[:, k] = (np.atleast_1d(np.asarray(value, dtype=float)) - g) / step
    return fy, fyp, 2 * m + 1, 0


def growth(fy, fyp, h, sc=SPLINE):
    """(rho of the member ``sc``'s amplification matrix, rho of the exact
    flow over h): the largest |exp(h lambda)| over the eigenvalues lambda
    of the linearised flow, so that a backward step (h < 0) is compared
    with the backward flow."""
    m = fy.shape[0]
    flow = np.block([[np.zeros((m, m)), np.eye(m)], [fy, fyp]])
    exact = float(np.exp(np.max((h * np.linalg.eigvals(flow)).real)))
    try:
        step = float(np.max(np.abs(np.linalg.eigvals(amplification(fy, fyp, h, sc)))))
    except np.linalg.LinAlgError:
        step = np.inf
    return step, exact


def _products(fun, jac, args, t, y, yp, counts):
    """(A u, B v) as functions of a real vector at (t, y, y'): products
    with the matrices of ``jac``, or forward differences of F along u (one
    evaluation each, after one at the state); ``counts`` ([nfev, njev])
    counts the calls as they are made."""
    if jac is not None:
        fy, fyp, calls = _jac_parts(jac, args, t, y, yp)
        counts[1] += calls
        return (lambda u: np.asarray(fy @ u, dtype=float).reshape(-1),
                lambda v: np.asarray(fyp @ v, dtype=float).reshape(-1))
    counts[0] += 1
    g = np.atleast_1d(np.asarray(fun(t, y.copy(), yp.copy(), *args), dtype=float))

    def along(u, which):
        size = np.max(np.abs(u))
        if size == 0.0:
            return np.zeros_like(u)
        x = (y, yp)[which]
        delta = FD_STEP * max(1.0, float(np.max(np.abs(x)))) / size
        moved = [y.copy(), yp.copy()]
        moved[which] = x + delta * u
        counts[0] += 1
        value = np.atleast_1d(np.asarray(fun(t, *moved, *args), dtype=float))
        return (value - g) / delta
    return (lambda u: along(u, 0)), (lambda v: along(v, 1))


@njit(cache=True)
def _orthogonalise(V, j, w, column):
    """``w`` made orthogonal to the rows V[0..j] by modified Gram-Schmidt,
    twice (orthogonal to rounding), the coefficients added to ``column``;
    returns |w|.  Compiled, with no BLAS call: a threaded BLAS on a shared
    machine spends milliseconds a call on vectors of 10^5 numbers."""
    m = w.shape[0]
    for _ in range(2):
        for i in range(j + 1):
            c = 0.0
            for k in range(m):
                c += V[i, k] * w[k]
            for k in range(m):
                w[k] -= c * V[i, k]
            column[i] += c
    total = 0.0
    for k in range(m):
        total += w[k] * w[k]
    return np.sqrt(total)


def arnoldi(apply, m, steps, count=RITZ):
    """The Ritz values (k,) of the linear map ``apply`` from ``steps``
    Arnoldi steps with reorthogonalisation, from a fixed pseudo-random start
    (the check is reproducible), and the vectors (``count``, m) of the
    ``count`` largest in modulus; fewer steps when an invariant subspace is
    found (k = 1 and the value 0 for a zero map)."""
    V = np.empty((steps + 1, m))
    H = np.zeros((steps + 1, steps))
    start = np.random.default_rng(20240601).standard_normal(m)
    V[0] = start / np.sqrt(np.sum(start * start))
    k = steps
    for j in range(steps):
        w = np.array(apply(V[j]), dtype=float)
        H[j + 1, j] = _orthogonalise(V, j, w, H[:, j])
        if not H[j + 1, j] > 1e-12 * np.max(np.abs(H[:j + 2, :j + 1])):
            k = j + 1
            break
        V[j + 1] = w / H[j + 1, j]
    theta, S = np.linalg.eig(H[:k, :k])
    order = np.argsort(-np.abs(theta))[:count]
    return theta[order], np.einsum("ji,jk->ik", S[:, order], V[:k])


def _rayleigh(apply, x):
    """x^H M x / x^H x for the real map M = ``apply`` and a complex x (two
    products)."""
    mx = apply(x.real.copy()) + 1j * apply(x.imag.copy())
    return complex(np.sum(np.conj(x) * mx) / np.sum(np.abs(x) ** 2))


def _modes(apply_a, apply_b, m):
    """Pairs (a, b) of the modes of largest eigenvalues: the :data:`RITZ`
    Ritz values of largest modulus of A, each with the Rayleigh quotient of
    B on its vector, and those of B with A's (a matrix whose first product
    is zero, as B is when F does not depend on y', counts as zero)."""
    ritz = [arnoldi(apply, m, min(KRYLOV_STEPS, m)) for apply in (apply_a, apply_b)]
    zero = [theta.size == 1 and theta[0] == 0.0 for theta, _ in ritz]
    pairs = []
    for own, (theta, X) in enumerate(ritz):
        if zero[own]:
            continue
        other = (apply_b, apply_a)[own]
        for i in range(theta.size):
            value = 0.0 if zero[1 - own] else _rayleigh(other, X[i])
            pairs.append((complex(theta[i]), value) if own == 0 else (value, complex(theta[i])))
    return pairs or [(0.0, 0.0)]


def krylov_growth(fun, jac, args, t, y, yp, h, sc):
    """(rho of the step, rho of the flow, nfev, njev) over the modes of
    :func:`_modes` at (t, y, y'): :func:`growth` of each mode's scalar
    equation y'' = a y + b y' (rho NaN when fun or jac failed, or gave
    values that are not finite: the check has nothing to say there)."""
    counts = [0, 0]
    rho, rho_exact = 0.0, 0.0
    try:
        modes = _modes(*_products(fun, jac, args, t, y, yp, counts), y.size)
    except Exception:
        modes = []
    for a, b in modes:
        step, exact = growth(np.array([[a]]), np.array([[b]]), h, sc)
        rho, rho_exact = max(rho, step), max(rho_exact, exact)
    if not modes:
        rho = np.nan
    return rho, rho_exact, counts[0], counts[1]


def _linearised(fun, jac, args, t, y, yp, h, sc):
    """(rho of the step, rho of the flow, nfev, njev) at (t, y, y'): dense
    up to :data:`DENSE_UP_TO` components, by Arnoldi steps above."""
    if y.size > DENSE_UP_TO:
        return krylov_growth(fun, jac, args, t, y, yp, h, sc)
    fy, fyp, nfev, njev = jacobians(fun, jac, args, t, y, yp)
    if not (np.all(np.isfinite(fy)) and np.all(np.isfinite(fyp))):
        return np.nan, np.nan, nfev, njev
    return (*growth(fy, fyp, h, sc), nfev, njev)


def report(result, run, fun, jac, args, start, member, enabled=True, retake=None):
    """Attach the run's error estimate (``run``: the driver's
    :class:`splinestep.driver.Run`) to ``result``, warn (in a
    ``UserWarning`` and in ``result.message``) when the step is far too
    large for the solution, and count the evaluations the check makes in
    ``result.nfev`` and ``result.njev``.  ``start`` is (t0, y0, y'0),
    ``member`` the run's :class:`splinestep.members.Member`; ``enabled`` False
    attaches the estimate only (no finding, no evaluation).  The linearised
    step is taken at the step the run took there: the first, the one where
    the estimate is largest, the last."""
    t0, y0, yp0 = start
    (err_y, t_err, err_yp, y_scale, yp_scale, dt_err, dt_first, dt_last, sum_y,
     sum_yp) = (float(v) for v in run.estimate)
    estimated = result.nstep >= 2
    result.local_error = err_y if estimated else np.nan
    sc = member.scheme()
    has_yp = sc.c2yp != 0.0 or sc.c3yp != 0.0   # the alpha members estimate y alone
    result.local_error_yp = err_yp if estimated and has_yp else np.nan
    result.t_local_error = t_err if estimated else np.nan
    if result.nstep == 0 or not enabled:
        return
    findings = []
    if estimated and (err_y > LOCAL_FRACTION * y_scale or err_yp > LOCAL_FRACTION * yp_scale):
        findings.append(
            f"the estimated local error ({err_y:.2g} in y, {err_yp:.2g} in y', largest at "
            f"t = {_base.short(t_err)}) exceeds {LOCAL_FRACTION:g} of the solution's size "
            f"(max |y| = {y_scale:.3g}, max |y'| = {yp_scale:.3g})")
    elif estimated and (sum_y > ACCUMULATED_FRACTION * y_scale
                        or sum_yp > ACCUMULATED_FRACTION * yp_scale):
        findings.append(
            f"the estimated local errors sum to {sum_y:.2g} in y and {sum_yp:.2g} in y' over "
            f"the run, more than {ACCUMULATED_FRACTION:g} of the solution's size (max |y| = "
            f"{y_scale:.3g}, max |y'| = {yp_scale:.3g}): unless the equation damps them, the "
            "solution is off by as much")
    states = (("initial", t0, y0, yp0, dt_first),
              ("largest-error", t_err, run.y_at_err, run.yp_at_err, dt_err if estimated
               else dt_first),
              ("final", run.t_last, run.y_end, run.yp_end, dt_last))
    for where, t, y, yp, h in states:
        if not (np.all(np.isfinite(y)) and np.all(np.isfinite(yp))) or h == 0.0:
            continue
        try:
            rho, rho_exact, nfev, njev = _linearised(fun, jac, args, t, y, yp, h,
                                                     member.scheme())
        except Exception:  # a fun or jac that fails here: the check has nothing to say
            continue
        result.nfev += nfev
        result.njev += njev
        if rho > max(1.0, rho_exact) ** (1.0 + RATE_MARGIN) * (1.0 + GROWTH_MARGIN):
            findings.append(
                f"at the {where} state (t = {_base.short(t)}) one step of the linearised "
                f"equation grows by {rho:.3g} where the equation grows by {rho_exact:.3g} "
                + _limit(member))
            start_size = max(np.max(np.abs(y0)), np.max(np.abs(yp0)) * abs(run.t_last - t0))
            if (result.status == 0 and rho_exact <= 1.0 + GROWTH_MARGIN and start_size > 0.0
                    and y_scale > BLOWN_UP * start_size and _grows_as_the_step(run, retake, rho)):
                _blown_up(result, member, t, h, rho, y_scale, start_size)
                return
            break
    if findings:
        text = ("The step is too large for this solution: " + "; ".join(findings)
                + ". Try a smaller h.")
        result.message = f"{result.message} {text}"
        warnings.warn(text, UserWarning, stacklevel=4)


def _grows_as_the_step(run, retake, rho):
    """Whether RETAKEN more steps of the run's step from its final state
    grow that state by at least half the linearised step's excess growth
    rho - 1 per step (by (1 + (rho - 1) / 2)^(k / 2) after k steps): the
    state is then the amplified mode's, not a solution that grew for its
    own reasons (a resonance) beside a mode the step would amplify but that
    is not excited.  The growth is read in the Euclidean norm of y, over
    several steps: the run's last step may be a shorter one, after which
    the state holds the decaying mode too, and a state made of many
    amplified modes of nearly the same growth (the top of a chain's
    spectrum) may shrink in its largest component at a step (on the chain
    of 100 masses at omega_m h = 4, one step after the run's shortened
    last one multiplies the norm by 0.84, two by 0.99, where the step grows
    by 1.81).  Judged by as many of those steps as can be taken; False when
    the step cannot be retaken (``retake`` None: a composition), or not
    once from a state below OVERFLOWING."""
    h = float(run.estimate[7])
    if retake is None or h == 0.0:
        return False
    t, y, yp, taken = run.t_last, run.y_end, run.yp_end, 0
    for _ in range(RETAKEN):
        try:
            after = retake(t, y, yp, h)
        except Exception:  # a fun that fails here: judged by the steps taken
            after = None
        if after is None or not np.all(np.isfinite(after[0])):
            break
        t, (y, yp), taken = t + h, after[:2], taken + 1
    size = _euclidean(run.y_end)
    if taken == 0:   # not even one more step: overflowing, or nothing to judge by
        return size > OVERFLOWING
    return bool(_euclidean(y) > (1.0 + (rho - 1.0) / 2) ** (taken / 2) * size)


def _euclidean(y):
    """The Euclidean norm of ``y``, scaled so that its squares do not
    overflow (np.linalg.norm of 1e200 is inf)."""
    scale = float(np.max(np.abs(y)))
    return scale * float(np.linalg.norm(y / scale)) if 0.0 < scale < np.inf else scale


def _blown_up(result, member, t, h, rho, y_scale, start_size):
    """Make ``result`` a failure: the solution grew by orders of magnitude
    (its largest |y|, ``y_scale``, beyond BLOWN_UP times ``start_size``)
    where the step ``h`` (at ``t``) amplifies by ``rho`` an equation that
    does not grow."""
    limit = member.stability_limit
    omega_h = omega_h_of_growth(rho, member.scheme(), limit)
    where = (f"estimated omega h = {omega_h:.3g}, past its stability limit omega h = "
             f"{limit:.4g}"
             if np.isfinite(omega_h) else _limit(member)[1:-1])
    result.status, result.success = -1, False
    result.message = (
        f"The solution blew up: its largest |y| is {y_scale:.3g}, {y_scale / start_size:.2g} "
        f"times its start's size, and at t = {_base.short(t)} a step h = {h:.3g} of "
        f"{member.describe()} multiplies the linearised equation's solution by {rho:.3g} "
        f"where the equation does not grow ({where}). Try a smaller h.")


def omega_h_of_growth(rho, sc, limit):
    """omega h of the undamped oscillation y'' = -omega^2 y on which one
    step of the member ``sc`` (a :class:`splinestep.members.Scheme`) grows
    by ``rho`` > 1, for a member stable up to ``limit`` (finite) and growing
    beyond it; NaN otherwise."""
    if not (np.isfinite(limit) and rho > 1.0):
        return np.nan

    def excess(omega_h):
        matrix = amplification(np.array([[-omega_h ** 2]]), np.zeros((1, 1)), 1.0, sc)
        return float(np.max(np.abs(np.linalg.eigvals(matrix)))) - rho

    low, high = float(limit), 2.0 * float(limit)
    while excess(high) < 0.0:
        low, high = high, 2.0 * high
        if high > 1e12:
            return np.nan
    for _ in range(100):
        middle = 0.5 * (low + high)
        low, high = (middle, high) if excess(middle) < 0.0 else (low, middle)
    return 0.5 * (low + high)


def _limit(member):
    """The clause of a finding that names the member's stability limit."""
    if member.is_spline:
        return ("(the step is past the method's stability limit, omega h = sqrt(12) "
                "for an oscillation)")
    limit = member.stability_limit
    where = (f"omega h = {limit:.4g} for an oscillation" if np.isfinite(limit) else
             "unconditionally stable on an oscillation: the equation's own growth or damping "
             "is what the step misjudges")
    return f"(the step is past the stability of {member.name}, {where})"
