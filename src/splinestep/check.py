"""What a run of the spline stepper can tell about its own accuracy.

A fixed step cannot promise accuracy, but the spline knows when the step is
far past what the solution supports, in two ways:

1. The local error estimate.  y''' is constant on each interval of the
   spline, so its jump at a knot, divided by the mean of the two steps,
   estimates y''''; one step from exact values misses h^4 y''''/24 in y and
   h^3 y''''/12 in y' to leading order (``step.ERR_Y``, ``step.ERR_YP``).  Every run
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

Either finding is a ``UserWarning`` and a sentence in the result's
``message``; the run keeps its status, since the numbers are what the
method computed.
"""

import warnings

import numpy as np

from . import _base
from ._base import FD_STEP

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


def amplification(fy, fyp, h, y_weight, yp_weight):
    """The matrix M with (y, y')_{n+1} = M (y, y')_n for one step of size h
    on y'' = fy y + fyp y' (the method's eqs. 6-9 with y'' = F at every
    knot)."""
    m = fy.shape[0]
    eye, zero = np.eye(m), np.zeros((m, m))
    p = np.hstack([fy, fyp])                               # y''_n = p (y, y')_n
    base_y = np.hstack([eye, h * eye]) + (h * h / 3.0) * p
    base_yp = np.hstack([zero, eye]) + (h / 2.0) * p
    k = eye - y_weight * h * h * fy - yp_weight * h * fyp
    z = np.linalg.solve(k, fy @ base_y + fyp @ base_yp)     # y''_{n+1}
    return np.vstack([base_y + y_weight * h * h * z, base_yp + yp_weight * h * z])


def growth(fy, fyp, h, y_weight, yp_weight):
    """(rho of the step's amplification matrix, rho of the exact flow over
    h): the largest |exp(h lambda)| over the eigenvalues lambda of the
    linearised flow, so that a backward step (h < 0) is compared with the
    backward flow."""
    m = fy.shape[0]
    flow = np.block([[np.zeros((m, m)), np.eye(m)], [fy, fyp]])
    exact = float(np.exp(np.max((h * np.linalg.eigvals(flow)).real)))
    try:
        step = float(np.max(np.abs(np.linalg.eigvals(
            amplification(fy, fyp, h, y_weight, yp_weight)))))
    except np.linalg.LinAlgError:
        step = np.inf
    return step, exact


def report(result, run, fun, jac, args, t0, y0, yp0, y_weight, yp_weight):
    """Attach the run's error estimate (``run``: the driver's
    :class:`splinestep.driver.Run`) to ``result``, warn (in a
    ``UserWarning`` and in ``result.message``) when the step is far too
    large for the solution, and count the evaluations the check makes in
    ``result.nfev`` and ``result.njev``.  The linearised step is taken at
    the step the run took there: the first, the one where the estimate is
    largest, the last."""
    (err_y, t_err, err_yp, y_scale, yp_scale, dt_err, dt_first, dt_last, sum_y,
     sum_yp) = (float(v) for v in run.estimate)
    estimated = result.nstep >= 2
    result.local_error = err_y if estimated else np.nan
    result.local_error_yp = err_yp if estimated else np.nan
    result.t_local_error = t_err if estimated else np.nan
    if result.nstep == 0:
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
            fy, fyp, nfev, njev = jacobians(fun, jac, args, t, y, yp)
        except Exception:  # a fun or jac that fails here: the check has nothing to say
            continue
        result.nfev += nfev
        result.njev += njev
        if not (np.all(np.isfinite(fy)) and np.all(np.isfinite(fyp))):
            continue
        rho, rho_exact = growth(fy, fyp, h, y_weight, yp_weight)
        if rho > max(1.0, rho_exact) ** (1.0 + RATE_MARGIN) * (1.0 + GROWTH_MARGIN):
            findings.append(
                f"at the {where} state (t = {_base.short(t)}) one step of the linearised "
                f"equation grows by {rho:.3g} where the equation grows by {rho_exact:.3g} "
                "(the step is past the method's stability limit, omega h = sqrt(12) "
                "for an oscillation)")
            break
    if findings:
        text = ("The step is too large for this solution: " + "; ".join(findings)
                + ". Try a smaller h.")
        result.message = f"{result.message} {text}"
        warnings.warn(text, UserWarning, stacklevel=4)
