"""The one spline step, shared by every driver.

A step of size dt from the knot t, where the spline has value y, slope y'
and second derivative y'', to the knot t + dt extends the C2 cubic by one
interval and satisfies the ODE at the new knot.  With z = y''(t + dt) the
unknown (report eqs. 6-9),

    y_new  = y + dt y' + dt^2 (y''/3 + z/6),
    y'_new = y' + dt (y'' + z)/2,
    z      = F(t + dt, y_new, y'_new),

Newmark's method with beta = 1/6, gamma = 1/2.  Every member of Newmark's
family takes the same step with its own weights, read from the run's
:class:`splinestep.members.Scheme` (in :class:`Iteration`):

    y_new  = y + dt y' + dt^2 ((1/2 - beta) y'' + beta z),
    y'_new = y' + dt ((1 - gamma) y'' + gamma z),
    (1 - alpha_m) z + alpha_m y'' = F(t_new - alpha_f dt,
                                      (1 - alpha_f) y_new + alpha_f y, ...),

so that the steps solve z = G(z) = (F - alpha_m y'') / (1 - alpha_m) (F
itself for Newmark's members) at the state where F is evaluated.
:func:`sweep_step` solves the step equation by the report's fixed-point
sweep z <- G(z), :func:`newton_step` by
Newton's method; the settings travel as a :class:`Method` record, the
vectors as a :class:`State`, Newton's kept matrices as :class:`Kept`;
:func:`composed_step` chains it with the weights of a symmetric composition;
:func:`relations` is the step written as residuals, for the drivers that
solve all knots at once (:mod:`splinestep.bvp`).  The one driver
(:mod:`splinestep.driver`) calls these and nothing else of the method, as
it calls the baselines' steps (:mod:`splinestep._explicit`).

Newton's method is the simplified Newton of implicit Runge-Kutta codes
(Hairer and Wanner's RADAU5): the matrix I - dG/dz (I - dt^2/6 dF/dy - dt/2
dF/dy' for the spline) and
its LU factors are kept across iterations and steps, and rebuilt only when
the iteration contracts slowly (an update larger than :data:`SLOW_RATE`
times the one before), when it fails, or when the step changed by more than
:data:`STEP_CHANGE` since they were built.

References
----------
.. [1] E. Hairer, G. Wanner, "Solving Ordinary Differential Equations II",
   2nd ed., Springer (1996), Sec. IV.8 (simplified Newton iterations).
"""

import math
from collections import namedtuple

import numpy as np
from numba import njit
from numba.extending import register_jitable

from ._base import FD_STEP, evaluate, jacobian, wrong_length
from ._compile import external_matrix, external_solve
from .members import MEMBERS
from .status import BAD_SHAPE, DIVERGED, GREW, NON_FINITE, NOT_CONVERGED, OK, SINGULAR, TOO_SLOW

# The report's member, whose numbers the drivers that solve all knots at
# once (splinestep.bvp) and the analysis read: the coefficients of the
# unknown z in the step, as multiples of dt^2 and dt (beta, gamma), and
# those of y'' at the start (1/2 - beta, 1 - gamma).  Every step of the
# drivers reads its member's own (a splinestep.members.Scheme).
SPLINE = MEMBERS["spline"].scheme()
Y_WEIGHT, YP_WEIGHT, Y_START, YP_START = (SPLINE.beta, SPLINE.gamma, SPLINE.y_start,
                                          SPLINE.yp_start)

FIXED_POINT, NEWTON = 0, 1
# The rounding level of the step equation.  Below some tol the change of an
# iteration cannot get: F at a state known to rounding is itself known only
# to |dF/dy| eps |y| + |dF/dy'| eps |y'|, which on a stiff system (a chain of
# 10,000 masses at omega h = 1) is above tol = 1e-12 of the state.  An
# iteration whose residual z - F is within ROUNDING_MULTIPLE times that
# level has converged as far as double precision allows.  The sweep measures
# the level, when its change stops decreasing within ROUNDING_WINDOW of the
# state, by one evaluation of F at the state perturbed by eps of each
# component (signs from PROBE_SIGN), at most PROBES times a step; Newton
# bounds it from its matrix.
EPS = 2.220446049250313e-16
ROUNDING_MULTIPLE = 8.0
ROUNDING_WINDOW = 1.4901161193847656e-08
PROBES = 3
PROBE_SIGN = 2654435761
# Simplified Newton: rebuild the matrix when an iteration reduces the update
# by less than this factor, or when the step differs by more than this
# fraction from the one the matrix was built for.
SLOW_RATE = 0.5
STEP_CHANGE = 0.2
# The sweep's contraction theta is measured from changes above this
# multiple of the state (w_max |dz| > THETA_FLOOR |state|): below it the
# ratio of two changes is rounding's.
THETA_FLOOR = 1e3 * EPS


@njit(cache=True, error_model="numpy")
def lu_factor(a, piv):
    """LU factorisation with partial pivoting of ``a`` in place (Doolittle:
    unit lower triangle below the diagonal), row swaps in ``piv``.  Written
    out because numba's LAPACK binding multiplies the compile time of the
    step loops by four.  A zero pivot leaves a zero on the diagonal, which
    makes :func:`lu_solve` return non-finite values."""
    m = a.shape[0]
    for col in range(m):
        p = col
        for row in range(col + 1, m):
            if abs(a[row, col]) > abs(a[p, col]):
                p = row
        piv[col] = p
        if p != col:
            for k in range(m):
                a[col, k], a[p, k] = a[p, k], a[col, k]
        for row in range(col + 1, m):
            a[row, col] = a[row, col] / a[col, col]
            factor = a[row, col]
            for k in range(col + 1, m):
                a[row, k] -= factor * a[col, k]


@njit(cache=True, error_model="numpy")
def lu_solve(lu, piv, b):
    """Solve with the factors of :func:`lu_factor`, in place: ``b`` becomes
    the solution (and is returned)."""
    m = b.shape[0]
    x = b
    for col in range(m):
        p = piv[col]
        if p != col:
            x[col], x[p] = x[p], x[col]
    for row in range(m):
        for k in range(row):
            x[row] -= lu[row, k] * x[k]
    for row in range(m - 1, -1, -1):
        for k in range(row + 1, m):
            x[row] -= lu[row, k] * x[k]
        x[row] = x[row] / lu[row, row]
    return x


@njit(cache=True, error_model="numpy")
def solve_linear(a, b):
    """Solve a x = b (``a`` is overwritten, ``b`` is not)."""
    piv = np.empty(b.shape[0], dtype=np.int64)
    lu_factor(a, piv)
    return lu_solve(a, piv, b.copy())


# Rows of the work array a step uses (allocated once per run, not per step).
# _NOISE: the weights by which the sweep judges z for the error estimate
# (splinestep.controllers.noise_weights; its first entry negative: none).
_BASE_Y, _BASE_YP, _G, _RESIDUAL, _OWN_Y, _OWN_YP, _NOISE = range(7)

State = namedtuple("State", "y yp ypp y_new yp_new z")
State.__doc__ = """The vectors a step reads and writes: (y, y', y'') at the
start, and y, y' and z = y'' at the end (all of shape (m,))."""

Kept = namedtuple("Kept", "work lu piv info")
Kept.__doc__ = """What a driver allocates once for its steps
(:func:`step_state`): a work array (7, m) and the kept Newton matrices, one
per distinct sub-step of a composition: LU factors (slots, m, m), pivots
(slots, m) and, per slot, [built?, the step it was built for, the sweep's
contraction bound h^2/6 |dF/dy| + h/2 |dF/dy'| (max norm) read from it].  The LU
factors are (slots, 0, 0) where no dense matrix is factorised (the sweep,
the baselines), so that those paths need O(m) memory."""

Iteration = namedtuple("Iteration", "mode n_iter until_converged tol reuse matrices sparse "
                                   "scheme")
Iteration.__doc__ = """The step equation and how it is solved: ``scheme``
the member of Newmark's family whose equation it is (a
:class:`splinestep.members.Scheme`, numbers only); ``mode`` FIXED_POINT
or NEWTON; ``n_iter`` iterations at most, exactly when not
``until_converged``; converged when the change of the increments dt^2/6
|dz| and dt/2 |dz| is at most ``tol`` times the size of the state (max
norm), or the residual is at the rounding level (:data:`ROUNDING_MULTIPLE`);
``reuse`` of Newton's matrix.  ``matrices``: negative when the loop builds
Newton's matrix itself (from a compiled or plain ``jac``, or by finite
differences), else the key of the :class:`splinestep._linalg.Matrices`
that builds it in Python (a constant or sparse Jacobian), which also
factorises and solves with it when ``sparse``.  Numbers only: a record
holding arrays costs reference counting wherever it is passed in the hot
loop."""

Method = namedtuple("Method", "kind iteration weights slots inside inside_slots")
Method.__doc__ = """The step: the method ``kind`` (see :mod:`splinestep.driver`),
its :class:`Iteration`, a composition's sub-step ``weights`` with the
``slots`` of their kept Newton matrices, and the weights (and slots) of a
composition of the same order whose sub-steps stay between the step's ends
(``inside``), taken where a sub-step of ``weights`` would leave the span."""


@njit(cache=True)
def step_state(m, slots, dense):
    """The :class:`Kept` buffers of a run of m components; the (m, m) LU
    factors only when ``dense`` (Newton with a dense matrix)."""
    n = m if dense else 0
    work = np.empty((7, m))
    work[_NOISE, :1] = -1.0   # no weights: the sweep converges on the state alone
    return Kept(work, np.zeros((slots, n, n)), np.zeros((slots, m), dtype=np.int64),
                np.zeros((slots, 3)))


@njit(cache=True, error_model="numpy")
def _build_matrix(fun, args, jac, at, s, work, lu, piv, info, it, slot):
    """I - dG/dz at the current z, factorised into ``lu`` (one slot's), where
    G(z) = (F - alpha_m y'') / (1 - alpha_m) is the member's update of z (F
    itself for Newmark's members) and its value at z is in ``work``'s row
    _G.  ``at`` is (the time where F is evaluated, dt, the weights of z in
    the state where F is evaluated, alpha_m): :func:`_at`.  Returns (nfev,
    njev, status) spent (finite differences: m evaluations).  With
    ``it.matrices`` the Python :class:`splinestep._linalg.Matrices` builds
    it: factorised there (``it.sparse``) or written into ``lu`` and
    factorised here."""
    m = s.z.shape[0]
    t_ev, dt, wy_e, wyp_e, am = at
    scale = 1.0 - am
    wy = wy_e / scale
    wyp = wyp_e / scale
    z, y_new, yp_new, ypp = s.z, s.y_new, s.yp_new, s.ypp
    nfev = 0
    njev = 0
    finite_differences = True
    if it.matrices >= 0.0:
        code, njev, bound = external_matrix(it.matrices, slot, t_ev, y_new, yp_new, wy, wyp,
                                            lu)
        info[0], info[1], info[2] = 1.0, dt, bound
        if code != OK or it.sparse:
            return 0, njev, code
        finite_differences = False
    elif jac is not None:
        for j in range(m):
            y_new[j] = work[_BASE_Y, j] + wy_e * z[j]
            yp_new[j] = work[_BASE_YP, j] + wyp_e * z[j]
        fy, fyp = jacobian(jac, args, t_ev, y_new, yp_new)
        fy = np.asarray(fy)
        fyp = np.asarray(fyp)
        # two empty matrices: the stand-in for a missing jac (_compile.no_jacobian)
        finite_differences = fy.shape[0] == 0
        if not finite_differences:
            njev += 1
            for j in range(m):
                for k in range(m):
                    lu[j, k] = -(wy * fy[j, k] + wyp * fyp[j, k])
    if finite_differences:
        for k in range(m):
            step = FD_STEP * max(1.0, abs(z[k]))
            saved = z[k]
            z[k] = saved + step
            for j in range(m):
                y_new[j] = work[_BASE_Y, j] + wy_e * z[j]
                yp_new[j] = work[_BASE_YP, j] + wyp_e * z[j]
            gk = evaluate(fun, args, t_ev, y_new, yp_new)
            z[k] = saved
            if wrong_length(gk, m):   # nothing to read past its end
                return nfev + k + 1, njev, BAD_SHAPE
            for j in range(m):
                lu[j, k] = -((gk[j] - am * ypp[j]) / scale - work[_G, j]) / step
        nfev += m
    bound = 0.0
    for j in range(m):
        row = 0.0
        for k in range(m):
            row += abs(lu[j, k])
        bound = max(bound, row)
    for k in range(m):
        lu[k, k] += 1.0
    lu_factor(lu, piv)
    info[0] = 1.0
    info[1] = dt
    info[2] = bound
    return nfev, njev, OK


@njit(cache=True, error_model="numpy", inline="always")
def _at(sc, t_new, dt):
    """(the time where F is evaluated, dt, the weights of z in the state
    where F is evaluated, alpha_m) of the member ``sc``'s step to t_new:
    t_new - alpha_f dt, and (1 - alpha_f) beta dt^2, (1 - alpha_f) gamma dt
    (for Newmark's members t_new, beta dt^2 and gamma dt exactly)."""
    ef = 1.0 - sc.alpha_f
    return t_new - sc.alpha_f * dt, dt, ef * (sc.beta * dt * dt), ef * (sc.gamma * dt), sc.alpha_m


@njit(cache=True, error_model="numpy", inline="always")
def _start(dt, y, yp, ypp, z, work, sc):
    """The parts of y_new and y'_new that do not depend on z, into ``work``
    (for a member with alpha_f > 0 those of the state where F is evaluated,
    (1 - alpha_f) y_new + alpha_f y, with y_new's own in rows _OWN_Y and
    _OWN_YP), and the report's initial guess z = y'' (its d_i = 0)."""
    cy = sc.y_start * dt * dt
    cyp = sc.yp_start * dt
    for k in range(y.shape[0]):
        work[_BASE_Y, k] = y[k] + dt * yp[k] + cy * ypp[k]
        work[_BASE_YP, k] = yp[k] + cyp * ypp[k]
        z[k] = ypp[k]
    af = sc.alpha_f
    if af != 0.0:
        for k in range(y.shape[0]):
            work[_OWN_Y, k] = work[_BASE_Y, k]
            work[_OWN_YP, k] = work[_BASE_YP, k]
            work[_BASE_Y, k] = (1.0 - af) * work[_OWN_Y, k] + af * y[k]
            work[_BASE_YP, k] = (1.0 - af) * work[_OWN_YP, k] + af * yp[k]


@njit(cache=True, error_model="numpy", inline="always")
def _trial(wy, wyp, z, y_new, yp_new, work):
    """y_new and y'_new for the iterate z (for a member with alpha_f > 0,
    the state where F is evaluated); returns the size of the state (max
    norm), infinite when an iterate overflowed."""
    size = 0.0
    for k in range(z.shape[0]):
        y_new[k] = work[_BASE_Y, k] + wy * z[k]
        yp_new[k] = work[_BASE_YP, k] + wyp * z[k]
        size = max(size, abs(y_new[k]), abs(yp_new[k]))
    return size


@njit(cache=True, error_model="numpy", inline="always")
def _value_status(g, m):
    """OK, or BAD_SHAPE / NON_FINITE for a value g of F."""
    if wrong_length(g, m):
        return BAD_SHAPE
    bad = False
    for k in range(m):
        if not abs(g[k]) < np.inf:
            bad = True
    return NON_FINITE if bad else OK


@njit(cache=True, error_model="numpy", inline="always")
def _finish(dt, z, y_new, yp_new, work, sc):
    """y_new and y'_new from the final z; OK, or NON_FINITE if either
    overflowed."""
    wy = sc.beta * dt * dt
    wyp = sc.gamma * dt
    row_y, row_yp = (_OWN_Y, _OWN_YP) if sc.alpha_f != 0.0 else (_BASE_Y, _BASE_YP)
    status = OK
    for k in range(z.shape[0]):
        y_new[k] = work[row_y, k] + wy * z[k]
        yp_new[k] = work[row_yp, k] + wyp * z[k]
        if not (abs(y_new[k]) < np.inf and abs(yp_new[k]) < np.inf):
            status = NON_FINITE
    return status


@njit(cache=True, error_model="numpy")
def rounding_level(fun, args, t_ev, z, y_new, yp_new, ypp, am):
    """The rounding level of the update G = (F - am y'') / (1 - am) at
    (t_ev, y_new, y'_new), where G = z: the largest change of G when each
    component of the state moves by eps of itself (signs alternating
    pseudo-randomly, as rounding errors do), and not below eps |z|.  One
    evaluation; y_new and y'_new are left perturbed (the iteration
    recomputes them from z).  0 when F's value there is not usable (no
    iterate is then accepted at the rounding level)."""
    m = z.shape[0]
    scale = 0.0
    for k in range(m):
        sign = 1.0 if ((k * PROBE_SIGN) >> 13) & 1 else -1.0
        y_new[k] += sign * EPS * abs(y_new[k])
        yp_new[k] += sign * EPS * abs(yp_new[k])
        scale = max(scale, abs(z[k]))
    g = evaluate(fun, args, t_ev, y_new, yp_new)
    if _value_status(g, m) != OK:
        return 0.0
    level = EPS * scale
    for k in range(m):
        level = max(level, abs((g[k] - am * ypp[k]) / (1.0 - am) - z[k]))
    return level


@register_jitable
def contraction_rate(first, last, n):
    """The change's mean factor per iteration from ``first`` (after the
    first iteration) to ``last`` (after the n-th): an estimate of the
    iteration's contraction (NaN before two iterations)."""
    if n < 2 or not first > 0.0:
        return np.nan
    return (last / first) ** (1.0 / (n - 1))


@njit(cache=True, error_model="numpy", inline="always")
def sweep_step(fun, args, t_new, dt, y, yp, ypp, z, y_new, yp_new, it, work):
    """One step from (y, y', y'') to t_new = t + dt by the report's
    fixed-point sweep z <- F(t_new, y_new(z), y'_new(z)) (eq. 9),
    ``it.n_iter`` sweeps at most (exactly, when not ``it.until_converged``;
    ``it`` is an :class:`Iteration`).  On return ``z`` holds y'' at t_new and
    ``y_new``, ``yp_new`` the value and slope there (consistent with z).
    Returns (status, nfev, njev, niter, theta); no Jacobian is evaluated
    (njev = 0).  ``theta`` is the sweep's contraction, watched as Hairer and
    Wanner's RADAU5 watches Newton's [1]_: the largest ratio of successive
    changes above rounding (:data:`THETA_FLOOR`), NaN when fewer than two
    were measured (a failed step then reports :func:`contraction_rate`).
    The error controller bounds the next step by it
    (:func:`splinestep.controllers.judge`), the run's message reports it.
    The sweep gives up at once, not after ``it.n_iter`` sweeps, when two
    ratios in a row are 1 or more, or when the latest ratio predicts more
    sweeps than are left to bring the change even within ROUNDING_WINDOW
    of the state.

    Converged when the change of the increments is at most tol times the
    state, or, once the change stops decreasing within ROUNDING_WINDOW of
    the state, when the change is within ROUNDING_MULTIPLE times the
    rounding level of F there (:func:`rounding_level`).  Under error
    control ``work``'s row _NOISE holds weights w_k^2, and a sweep
    that passes the test on the state goes on until its last change e of z
    also satisfies sqrt(mean_k w_k^2 e_k^2) <= 1, so that the error estimate,
    which reads z through differences, reads the solution and not the
    sweep's unfinished convergence
    (:func:`splinestep.controllers.noise_weights`), or until the change
    stops falling or the sweeps run out (then converged on the state).

    Inlined into the driver: this is its hot path, which ``make bench``
    holds against a C loop, so it takes its vectors one by one (a record
    of arrays costs reference counting at every step).  The change of z is
    computed only when it is tested."""
    m = y.shape[0]
    sc = it.scheme
    t_ev, _, wy_e, wyp_e, am = _at(sc, t_new, dt)
    w_max = max(sc.beta * dt * dt, abs(sc.gamma * dt))
    until_converged = it.until_converged
    _start(dt, y, yp, ypp, z, work, sc)
    status = NOT_CONVERGED if until_converged else OK
    nfev = 0
    niter = 0
    first, last, probes, theta, ratio = 0.0, np.inf, 0, np.nan, np.nan
    targeted, settled = m > 0 and work[_NOISE, 0] >= 0.0 and until_converged, False
    for _ in range(it.n_iter):
        size = _trial(wy_e, wyp_e, z, y_new, yp_new, work)
        if not size < np.inf:
            # A diverging sweep overflows; an infinite size would pass the
            # relative convergence test below.
            status = DIVERGED
            break
        g = evaluate(fun, args, t_ev, y_new, yp_new)
        nfev += 1
        status = _value_status(g, m)
        if status != OK:
            break
        status = NOT_CONVERGED if until_converged else OK
        niter += 1
        change, spread = 0.0, 0.0
        if am != 0.0:   # (1 - alpha_m) z + alpha_m y'' = F
            for k in range(m):
                gk = (g[k] - am * ypp[k]) / (1.0 - am)
                change = max(change, abs(gk - z[k]))
                if targeted:
                    spread += work[_NOISE, k] * (gk - z[k]) ** 2
                z[k] = gk
        elif targeted:
            for k in range(m):
                d = g[k] - z[k]
                change = max(change, abs(d))
                spread += work[_NOISE, k] * d * d
                z[k] = g[k]
        elif until_converged:
            for k in range(m):
                change = max(change, abs(g[k] - z[k]))
                z[k] = g[k]
        else:
            for k in range(m):
                z[k] = g[k]
        if until_converged:
            if w_max * change <= it.tol * size:
                # Converged on the state; under error control on z too, or
                # once the change stops falling (rounding).
                settled = True
                if not targeted or spread <= m or change >= last:
                    status = OK
                    break
            if (change >= last and probes < PROBES
                    and w_max * change <= ROUNDING_WINDOW * size):
                probes += 1
                nfev += 1
                if change <= ROUNDING_MULTIPLE * rounding_level(fun, args, t_ev, z, y_new,
                                                                yp_new, ypp, am):
                    status = OK
                    break
            if niter >= 2 and w_max * change > THETA_FLOOR * size:
                # The contraction, watched: the largest ratio of successive
                # changes above rounding (Hairer and Wanner's theta).
                previous, ratio = ratio, change / last
                theta = ratio if not theta >= ratio else theta
                # Diverging, or too slow to reach even the rounding window
                # in the iterations left: given up now, not after max_iter.
                if w_max * change > ROUNDING_WINDOW * size:
                    if ratio >= 1.0 and previous >= 1.0:
                        status = GREW
                        break
                    if ratio < 1.0 and math.log(ROUNDING_WINDOW * size / (w_max * change)) \
                            < (it.n_iter - niter) * math.log(ratio):
                        status = TOO_SLOW
                        break
            if niter == 1:
                first = change
            last = change
    if settled and status == NOT_CONVERGED:
        status = OK
    if status == OK:
        status = _finish(dt, z, y_new, yp_new, work, sc)
    elif until_converged and not theta >= 0.0:
        theta = contraction_rate(first, last, niter)
    return status, nfev, 0, niter, theta


@njit(cache=True, error_model="numpy", inline="always")
def _rounding_bound(bound, wy, wyp, y_new, yp_new, scale, work):
    """eps (|dF/dy| |y| + |dF/dy'| |y'| + |F|) (max norms), with |dF/dy| and
    |dF/dy'| bounded by the contraction bound h^2/6 |dF/dy| + h/2 |dF/dy'|
    of Newton's matrix divided by h^2/6 and h/2; ``scale`` is |F|.  With
    ``work`` (the alpha members), |y| and |y'| are at least the parts of
    the state that do not depend on z: their sum cancels where the state
    is small beside its acceleration a_n (the spurious mode that the alpha
    members damp by rho_inf per step, at large omega h), and its rounding
    is theirs."""
    y_max, yp_max = 0.0, 0.0
    for k in range(y_new.shape[0]):
        y_max = max(y_max, abs(y_new[k]))
        yp_max = max(yp_max, abs(yp_new[k]))
    if work is not None:
        for k in range(y_new.shape[0]):
            y_max = max(y_max, abs(work[_BASE_Y, k]))
            yp_max = max(yp_max, abs(work[_BASE_YP, k]))
    # beta = 0: the matrix holds no dF/dy, and y_new no z
    return EPS * (bound * ((y_max / wy if wy > 0.0 else 0.0) + yp_max / abs(wyp)) + scale)


@njit(cache=True, error_model="numpy", inline="always")
def newton_step(fun, args, jac, t_new, dt, s, it, kept, slot):
    """One step by simplified Newton on R(z) = z - F(t_new, y_new(z),
    y'_new(z)) = 0, on the vectors of the :class:`State` ``s``, with ``jac``
    (None: finite differences) and the :class:`Kept` buffers; returns as
    :func:`sweep_step`.

    The step keeps its Newton matrix in ``slot`` and rebuilds it at every
    iteration when not ``it.reuse``.  A step that fails with a kept
    matrix is tried again from the start with the matrix rebuilt at every
    iteration, so reusing it never loses a step that full Newton would solve.
    Converged when the update is at most tol times the state, or when the
    residual is within ROUNDING_MULTIPLE times the rounding level of F,
    eps (|dF/dy| |y| + |dF/dy'| |y'| + |F|), bounded from the matrix's
    contraction bound (its max-norm).  With matrices built in Python
    (``it.matrices``) the residual is tested before the solve, so that a
    step of a linear problem costs one solve, not two (a solve through
    SuperLU costs far more than one of the loop's).

    Inlined into :func:`composed_step` and :func:`newton_call`: its code
    inlined beside the sweep in the driver's own loop slows the sweep down
    by about a third (``make bench``)."""
    m = s.y.shape[0]
    y, yp, ypp, z, y_new, yp_new = s.y, s.yp, s.ypp, s.z, s.y_new, s.yp_new
    sc = it.scheme
    at = _at(sc, t_new, dt)
    t_ev, _, wy_e, wyp_e, am = at
    w_max = max(sc.beta * dt * dt, abs(sc.gamma * dt))
    wy, wyp = wy_e / (1.0 - am), wyp_e / (1.0 - am)   # Newton's matrix's weights
    until_converged = it.until_converged
    work, info = kept.work, kept.info
    # The alpha members' rounding level counts the terms that cancel
    # (_rounding_bound); alpha_m y'' enters G's scale.
    terms = work if (am != 0.0 or sc.alpha_f != 0.0) else None
    scale_a, nfev, njev, niter, status, reuse = 0.0, 0, 0, 0, OK, it.reuse
    # Views made once per step, not per iteration (each costs reference counting).
    dz, lu_slot, piv_slot = work[_RESIDUAL], kept.lu[slot], kept.piv[slot]
    first, rate, sparse = 0.0, np.nan, it.sparse
    for attempt in range(2):
        _start(dt, y, yp, ypp, z, work, sc)
        status = NOT_CONVERGED if until_converged else OK
        if info[slot, 0] != 0.0 and abs(dt - info[slot, 1]) > STEP_CHANGE * abs(info[slot, 1]):
            info[slot, 0] = 0.0
        # fresh: the matrix was built during this step
        fresh, last_change, n_attempt = False, np.inf, 0
        for _ in range(it.n_iter):
            size = _trial(wy_e, wyp_e, z, y_new, yp_new, work)
            if not size < np.inf:
                status = DIVERGED
                break
            g = evaluate(fun, args, t_ev, y_new, yp_new)
            nfev += 1
            status = _value_status(g, m)
            if status != OK:
                break
            status = NOT_CONVERGED if until_converged else OK
            # The update G = (F - alpha_m y'') / (1 - alpha_m) (F itself for
            # Newmark's members) kept in row _G: ``g`` may be the loop's one
            # buffer, which the finite differences of a new matrix overwrite.
            if am == 0.0:
                for k in range(m):
                    work[_G, k] = g[k]
            else:
                for k in range(m):
                    work[_G, k] = (g[k] - am * ypp[k]) / (1.0 - am)
                    scale_a = max(scale_a, abs(am * ypp[k]) / (1.0 - am))
            if info[slot, 0] == 0.0:
                fe, je, status = _build_matrix(fun, args, jac, at, s, work, lu_slot,
                                               piv_slot, info[slot], it, slot)
                nfev += fe
                njev += je
                fresh = True
                if status != OK:
                    break
                status = NOT_CONVERGED if until_converged else OK
            residual, scale = 0.0, scale_a
            for k in range(m):
                dz[k] = work[_G, k] - z[k]
                residual = max(residual, abs(dz[k]))
                scale = max(scale, abs(work[_G, k]))
            if (until_converged and it.matrices >= 0.0 and residual <= ROUNDING_MULTIPLE
                    * _rounding_bound(info[slot, 2], wy, wyp, y_new, yp_new, scale, terms)):
                # Matrices built in Python (a constant or sparse Jacobian): a
                # residual at the rounding level needs no further solve.
                niter += 1
                status = OK
                break
            if sparse:
                external_solve(it.matrices, slot, dz)
            else:
                lu_solve(lu_slot, piv_slot, dz)
            bad = False
            for k in range(m):
                if not abs(dz[k]) < np.inf:
                    bad = True
            if bad:
                if fresh:
                    status = SINGULAR
                    break
                info[slot, 0] = 0.0  # a kept matrix failed: rebuild it next iteration
                niter += 1
                continue
            change = 0.0
            for k in range(m):
                change = max(change, abs(dz[k]))
                z[k] += dz[k]
            converged = w_max * change <= it.tol * size
            rounded = (until_converged and not converged and residual <= ROUNDING_MULTIPLE
                       * _rounding_bound(info[slot, 2], wy, wyp, y_new, yp_new, scale, terms))
            if not reuse or (change > SLOW_RATE * last_change and not fresh and not rounded):
                info[slot, 0] = 0.0
            last_change = change
            niter += 1
            n_attempt += 1
            if n_attempt == 1:
                first = change
            if until_converged and (converged or rounded):
                status = OK
                break
        if status == OK:
            status = _finish(dt, z, y_new, yp_new, work, sc)
            # the matrix's contraction bound at this step's size (judge's theta)
            rate = info[slot, 2] * (dt / info[slot, 1]) ** 2 if info[slot, 1] != 0.0 else rate
        elif until_converged:
            rate = contraction_rate(first, last_change, n_attempt)
        if status != OK:
            info[slot, 0] = 0.0
        if status == OK or not reuse or fresh:
            break
        reuse = False   # the kept matrix failed this step: redo it with full Newton
    return status, nfev, njev, niter, rate


@njit(cache=True, error_model="numpy")
def newton_call(fun, args, jac, t_new, dt, s, it, kept, slot):
    """:func:`newton_step` as a call, not inlined: the driver's Newton
    steps, kept out of the code of its inlined sweep."""
    return newton_step(fun, args, jac, t_new, dt, s, it, kept, slot)


@njit(cache=True, error_model="numpy", inline="always")
def _copy_state(y, yp, ypp, sub):
    """(y, y', y'') into the three vectors of ``sub``."""
    sub_y, sub_yp, sub_ypp = sub.y, sub.yp, sub.ypp
    for k in range(y.shape[0]):
        sub_y[k] = y[k]
        sub_yp[k] = yp[k]
        sub_ypp[k] = ypp[k]


@njit(cache=True, inline="always")
def _inside(t, dt, weights, span):
    """Whether every sub-step end t + (w_0 + ... + w_j) dt lies in span."""
    c = 0.0
    for j in range(weights.shape[0]):
        c += weights[j]
        if not span[0] <= t + c * dt <= span[1]:
            return False
    return True


@njit(cache=True, error_model="numpy")
def composed_step(fun, args, jac, t, t_new, s, method, kept, sub, span):
    """The step from t to t_new = t + dt as spline steps of sizes
    method.weights[j] dt in turn (weights summing to 1; a single weight 1
    is one spline step, the last sub-step ends at t_new exactly).  Where a
    sub-step of those weights would reach outside ``span`` = (lo, hi) (the
    first and last steps of a uniform grid, whose negative and overshooting
    sub-steps pass t0 and tf), the step takes ``method.inside`` instead, a
    composition of the same order whose sub-steps stay within [t, t_new],
    so that F is never evaluated outside the span.
    Sub-step j keeps its Newton matrix in slot ``method.slots[j]``; ``sub``
    is a :class:`State` whose start vectors hold each sub-step's start and
    whose end vectors are ``s``'s (the step's start is copied there too:
    choosing between arrays per sub-step costs reference counting).  Returns
    what :func:`sweep_step` returns, summed; on success ``s.y_new``,
    ``s.yp_new``, ``s.z`` hold the state at t + dt.

    The sub-steps' loop is written once per iteration mode: a loop whose
    body chooses between the two takes about 1.3 times as long per
    evaluation (``make bench``)."""
    weights, slots, it = method.weights, method.slots, method.iteration
    dt = t_new - t
    if not _inside(t, dt, weights, span):
        weights, slots = method.inside, method.inside_slots
    n_sub = weights.shape[0]
    nfev = 0
    njev = 0
    niter = 0
    rate = np.nan
    status = OK
    t_sub = t
    _copy_state(s.y, s.yp, s.ypp, sub)
    if it.mode == FIXED_POINT:
        for j in range(n_sub):
            t_next = t_new if j == n_sub - 1 else t_sub + weights[j] * dt
            if j > 0:
                _copy_state(s.y_new, s.yp_new, s.z, sub)
            status, fe, je, n_it, rate = sweep_step(fun, args, t_next, t_next - t_sub, sub.y,
                                                    sub.yp, sub.ypp, s.z, s.y_new, s.yp_new, it,
                                                    kept.work)
            nfev += fe
            niter += n_it
            if status != OK:
                break
            t_sub = t_next
    else:
        for j in range(n_sub):
            t_next = t_new if j == n_sub - 1 else t_sub + weights[j] * dt
            if j > 0:
                _copy_state(s.y_new, s.yp_new, s.z, sub)
            status, fe, je, n_it, rate = newton_step(fun, args, jac, t_next, t_next - t_sub,
                                                     sub, it, kept, slots[j])
            nfev += fe
            njev += je
            niter += n_it
            if status != OK:
                break
            t_sub = t_next
    return status, nfev, njev, niter, rate


@register_jitable
def local_errors(y3, jump, dt, dt_prev, sc):
    """The estimated local errors (of y, of y') of the member ``sc``'s
    step of size ``dt``, whose mean third derivative (a_{n+1} - a_n) / dt
    is ``y3`` in size, and whose third derivative differs by ``jump`` from
    that of the step before, of size ``dt_prev``: the jump estimates the
    fourth derivative, and the estimates are c3y |h|^3 |y'''| + c4y h^4
    |y''''| and c2yp h^2 |y'''| + c3yp |h|^3 |y''''| (the constants of
    :meth:`splinestep.members.Member.error_constants`; for the spline c3y
    = c2yp = 0, c4y = 1/24, c3yp = 1/12).  Numbers in compiled code,
    arrays (broadcast) in Python."""
    y4 = jump / abs(0.5 * (dt + dt_prev))
    h3 = abs(dt * dt * dt)
    return (sc.c4y * (dt * dt) * (dt * dt) * y4 + sc.c3y * h3 * y3,
            sc.c3yp * h3 * y4 + sc.c2yp * (dt * dt) * y3)


def relations(dt, y, yp, ypp, y1, yp1, z):
    """The step as residuals: zero when (y1, yp1, z) at t + dt is the spline
    step from (y, yp, ypp) at t (any broadcastable arrays; the collocation
    z = F(t + dt, y1, yp1) is the caller's)."""
    return (y1 - (y + dt * yp + dt * dt * (Y_START * ypp + Y_WEIGHT * z)),
            yp1 - (yp + dt * (YP_START * ypp + YP_WEIGHT * z)))
