"""Step-size controllers: which knot comes next, and whether to keep a step.

The driver (:mod:`splinestep.driver`) asks its controller for the next
knot before each step and, for error control, whether to accept the step
just taken.  Three controllers, selected by :attr:`Control.kind`:

- :data:`CONSTANT`: the knots are given, as a uniform step h (the last step
  shortened to end at tf) or as an array; every step is accepted.
- :data:`ERROR`: the knots follow the spline's own error estimate (below),
  with rejected steps retried smaller.
- :data:`REVERSIBLE`: the steps are eps / rho, with rho following Hairer and
  Soderlind's symmetric recursion (:mod:`splinestep.reversible`), so that a
  run backwards retraces its knots.

A new controller is a new ``kind`` here (its settings in :class:`Control`,
its proposal in :func:`propose`) and one branch of the driver's acceptance;
the loop, the events, the output and the checks stay as they are.

The spline's own error estimate.  The third derivative of the cubic is
constant on each interval, j_i = (y''_{i+1} - y''_i) / h_i, and its jump
at a knot estimates the fourth derivative,

    y'''' ~ (j_i - j_{i-1}) / ((h_i + h_{i-1}) / 2),

with an error O(h) (the two interval means of y''' sit (h_i + h_{i-1})/2
apart).  A step from exact values misses, to leading order, h^4 y''''/24 in y and
h^3 y''''/12 in y' (:mod:`splinestep.analysis.theory`), so

    est_y = h^4 |y''''| / 24,   est_y' = |h|^3 |y''''| / 12.

The estimate of Newmark codes (Zienkiewicz and Xie, 1991) is proportional
to beta - 1/6 and vanishes for this method; the jump above does not.  The
other members of Newmark's family add their leading terms c3y |h|^3 |y'''|
and c2yp h^2 |y'''| (y''' from (a_{n+1} - a_n)/h), with the constants of
their records (:mod:`splinestep.members`); the alpha members estimate y
alone (their estimate of y' is 0, reported as NaN).  At
the first step there is no earlier interval: its role is taken by y''' at
t0, from one finite difference of F along the Taylor line.

What rtol and atol bound.  Each step's local error is controlled per unit
step (error per unit step: Shampine [4]_; Hairer, Norsett and Wanner [2]_,
Sec. II.4): both estimates are multiplied by |tf - t0| / |h|, so that in
a run whose every step passes, the local errors sum to at most the
tolerance (in the RMS norm below: one component may take up to sqrt(2m)
times its share).  The global error of a problem that does not amplify
errors is that sum to leading order, so it follows the tolerance in
proportion; bounding each step's error instead, as scipy's codes do,
gives a step of order rtol^(1/3) and a global error of order rtol^(2/3)
times the span.  The norm is scipy's: the root mean square over
the 2m components of both scaled estimates divided by atol + rtol
max(|old|, |new|), with rtol and atol per component.  A step is accepted
when the norm is at most 1; the next step is the current one times
SAFETY norm^(-1/order) (the member's order: the estimates per unit step
are O(h^2) for the second-order members), within
[MIN_FACTOR, MAX_FACTOR], and not larger right after a rejection.  Every
step is also kept below the contraction its equation allows (the sweep's
convergence, a conditionally stable member's stability limit), from the
largest contraction per h^2 the run's steps have shown (:func:`judge`,
:func:`contraction_target`).  A step whose equation could not be solved
(the sweep diverged, Newton failed) is rejected and retried at that bound,
within [MIN_FACTOR / 2, FAILED_FACTOR] of its size (FAILED_FACTOR times
smaller when no contraction was measured).  The estimates read y'' at the
knots through differences, so the sweep of a stiff equation goes on until
y'' is known well enough for them (:func:`noise_weights`).  Measured on
five problems over rtol = 1e-3 ... 1e-8 (:mod:`splinestep.analysis.tolerance`,
notebook 07), the final error of y stays below rtol times the solution's
scale and that of y' within 10 times (the largest error over a run up to
2.6 times, on the pendulum at rtol 1e-3), and the error falls with rtol at
slopes 0.90 to 1.28.  Where a problem amplifies errors, no control of
local errors bounds the global error: on Pleiades, whose close encounters
amplify them, the final error is about 40 times rtol (8 times rtol times
the largest |y|), still in proportion to it.

References
----------
.. [1] O. C. Zienkiewicz, Y. M. Xie, "A simple error estimator and adaptive
   time stepping procedure for dynamic analysis", Earthquake Eng. Struct.
   Dyn. 20 (1991) 871-887.
.. [2] E. Hairer, S. P. Norsett, G. Wanner, "Solving Ordinary Differential
   Equations I", 2nd ed., Springer (1993), Sec. II.4.
.. [3] E. Hairer, G. Soderlind, "Explicit, time reversible, adaptive step
   size control", SIAM J. Sci. Comput. 26 (2005) 1838-1851.
.. [4] L. F. Shampine, "Tolerance proportionality in ODE codes", in
   Numerical Methods for Ordinary Differential Equations, Lecture Notes in
   Math. 1386, Springer (1989) 118-136.
"""

from collections import namedtuple

import numpy as np
from numba import njit

from .status import OK, RHO_NOT_POSITIVE, STEP_TOO_SMALL, TOO_MANY_STEPS
from .members import member
from .step import _NOISE, local_errors

CONSTANT, ERROR, REVERSIBLE = 0, 1, 2

SAFETY = 0.9
MIN_FACTOR = 0.2
MAX_FACTOR = 5.0
FAILED_FACTOR = 0.25
# The contraction a step of the error controller aims below: the sweep's
# theta (its change's factor per sweep, which grows like h^2 on an
# oscillation), and, for a conditionally stable member, STABLE_SAFETY of
# its stability limit in the same measure ((1 - alpha_f) beta/(1 - alpha_m)
# (omega h)^2, from Newton's matrix).  THETA_TARGET is the least cost of
# those measured on the chain of masses at m = 3,000, and within 7 % of it
# at m = 1,000 (the speed page's span, rtol 1e-3, atol 1e-8, measured with
# a STIFFNESS_MEMORY of 0.999): evaluations at m = 1,000 and 3,000 of
# 35,056 and 78,831 at a target of 0.135, 31,203 and 70,432 at 0.25,
# 29,277 and 101,033 at 0.5, 49,454 and 141,546 at 0.7 (at 0.25 with the
# memory of 0.99 below, 30,992 and 67,895).  At m = 10,000 it is not the
# least: 444,247 evaluations, where 0.5 with a memory of 0.999 took
# 317,955.  The best target depends on m, which a run does not know.  On an
# oscillation theta =
# beta (omega h)^2 and the sweeps per step grow like 1/|log theta|, so the
# sweeps per unit time like 1/(sqrt(theta) |log theta|), least at theta =
# e^-2; but the measured theta under-reads the fastest mode (the steps
# overshoot the target), and the sweeps that make y'' accurate enough for
# the error estimate (:func:`noise_weights`) cost more as theta grows.  A
# failed step's next size is h sqrt(target / theta), within
# [MIN_FACTOR / 2, FAILED_FACTOR] of h.
THETA_TARGET = 0.25
STABLE_SAFETY = 0.9
# The driver remembers the largest contraction per h^2 its steps showed
# (the sweep's measured theta sees only the modes its change holds, so the
# fastest shows itself when a sweep fails there), fading by this factor per
# step attempt so that a stiffness the equation loses stops bounding the
# steps (a half-life of about 70 attempts: on the chain of masses 0.99 and 0.999
# cost the same, 30,992 and 31,203 evaluations at m = 1,000; on the Kepler
# orbit e = 0.9, 0.999 held the steps near apoapsis to the stiffness of the
# inner orbit).
STIFFNESS_MEMORY = 0.99
# The share of the error norm the sweep's unfinished convergence may take
# (:func:`noise_weights`).
NOISE_SHARE = 0.1

Control = namedtuple("Control", "kind tf h n span first_step max_step max_steps eps rho0 "
                                "theta_max y_max")
Control.__doc__ = """The controller's settings, one record (of numbers only)
for every kind; its arrays (the given knots, atol, rtol) travel beside it as
:class:`Vectors`.

kind : CONSTANT, ERROR or REVERSIBLE.
tf : the end of the span.
h, n : CONSTANT: the uniform step (signed) and the number of steps.
span, first_step, max_step : ERROR: |tf - t0|, by which the local errors
    per unit step are multiplied; the first step (0: chosen from y0, yp0)
    and the largest.
max_steps : the most step attempts (every kind).
eps, rho0 : REVERSIBLE: the step at rho = 1 and rho at the start.
theta_max : ERROR: the contraction the steps aim below
    (:func:`contraction_target`; inf: none).
y_max : CONSTANT and ERROR (REVERSIBLE: inf): a run whose |y| exceeds it at a knot stops there,
    failed (inf: no bound; ``solve(..., y_max=...)``).
"""

Vectors = namedtuple("Vectors", "knots atol rtol")
Vectors.__doc__ = """The controller's arrays: the given knots (CONSTANT;
empty for a uniform grid), atol and rtol (ERROR; one per component)."""

_EMPTY = np.empty(0)


def constant(tf, h, n, knots, max_steps, y_max=np.inf):
    """The settings of the constant controller."""
    return (Control(CONSTANT, float(tf), float(h), int(n), 0.0, 0.0, 0.0, int(max_steps), 0.0,
                    0.0, np.inf, float(y_max)),
            Vectors(np.asarray(knots, dtype=float), _EMPTY, _EMPTY))


def error_control(t0, tf, rtol, atol, first_step, max_step, max_steps, theta_max=np.inf,
                  y_max=np.inf):
    """The settings of the error controller (rtol and atol of shape (m,);
    ``theta_max`` from :func:`contraction_target`)."""
    return (Control(ERROR, float(tf), 0.0, 0, abs(float(tf) - float(t0)), float(first_step),
                    float(max_step), int(max_steps), 0.0, 0.0, float(theta_max), float(y_max)),
            Vectors(_EMPTY, atol, rtol))


def contraction_target(member, sweep):
    """The contraction theta the error controller keeps the steps of
    ``member`` (a :class:`splinestep.members.Member`) below: for the sweep
    (``sweep``) THETA_TARGET; for a conditionally stable member with beta >
    0, at most (1 - alpha_f) beta / (1 - alpha_m) (STABLE_SAFETY
    omega_lim)^2, the measure of Newton's matrix at STABLE_SAFETY of its stability limit
    omega_lim (:attr:`splinestep.members.Member.stability_limit`; an
    oscillation's omega h).  inf: no bound (central difference, whose
    matrix holds no dF/dy, and the unconditionally stable members under
    Newton)."""
    target = THETA_TARGET if sweep else np.inf
    limit = member.stability_limit
    weight = float((1 - member.alpha_f) * member.beta / (1 - member.alpha_m))
    if weight > 0.0 and np.isfinite(limit):
        target = min(target, weight * (STABLE_SAFETY * float(limit)) ** 2)
    return target


def reversible(tf, eps, rho0, max_steps):
    """The settings of the time-reversible controller."""
    return (Control(REVERSIBLE, float(tf), 0.0, 0, 0.0, 0.0, 0.0, int(max_steps), float(eps),
                    float(rho0), np.inf, np.inf), Vectors(_EMPTY, _EMPTY, _EMPTY))


@njit(cache=True, inline="always")
def rounding_floor(t, t0, tf):
    """The smallest step the error controller takes at ``t`` on the span
    (t0, tf): 16 machine epsilons times the larger of |t| and the span
    (16 to 32 of its ulps; a step below it does not change t reliably).
    It bounds ``max_step`` too: a smaller one is refused by the front door."""
    return 16.0 * np.finfo(np.float64).eps * max(abs(t), abs(tf - t0))


@njit(cache=True)
def first_size(ctrl, atol, rtol, t0, y, yp):
    """The size (positive) of the first step: for ERROR, ``first_step`` or
    scipy's rule of thumb, 1 % of |y| / |y'| in the scaled norm, raised to
    the rounding floor (:func:`rounding_floor`) as scipy raises its steps
    to its minimum (a run started at a located event, where y is zero to
    rounding, would otherwise propose a step below the floor and stop at
    once); for the others, unused (0)."""
    if ctrl.kind != ERROR:
        return 0.0
    span = abs(ctrl.tf - t0)
    if ctrl.first_step > 0.0:
        dt = ctrl.first_step
    else:
        m = y.shape[0]
        d0 = 0.0
        d1 = 0.0
        for k in range(m):
            scale = atol[k] + rtol[k] * abs(y[k])
            d0 += (y[k] / scale) ** 2
            d1 += (yp[k] / scale) ** 2
        d0 = np.sqrt(d0 / m)
        d1 = np.sqrt(d1 / m)
        dt = 1e-6 if (d0 < 1e-5 or d1 < 1e-5) else 0.01 * d0 / d1
    return max(min(dt, ctrl.max_step, span), rounding_floor(t0, t0, ctrl.tf))


@njit(cache=True, inline="always")
def propose(ctrl, knots, t0, t, attempts, accepted, size, rho):
    """The next knot after ``t`` (given ``knots``: the next of them).
    Returns (status, t_new, done): ``done``
    when the end is reached (no step to take), a status other than OK when
    the run must stop (max_steps, a step below rounding, rho not
    positive).  ``size`` is the error controller's next step size (positive),
    ``rho`` the reversible control variable; ``accepted`` counts the steps
    kept, ``attempts`` every step tried."""
    tf = ctrl.tf
    direction = 1.0 if tf > t0 else -1.0
    if ctrl.kind == CONSTANT:
        if accepted >= ctrl.n:
            return OK, t, True
        if knots.shape[0] > 0:
            return OK, knots[accepted + 1], False
        if accepted + 1 < ctrl.n:
            return OK, t0 + (accepted + 1) * ctrl.h, False
        return OK, tf, False
    if not direction * (tf - t) > 0.0:
        return OK, t, True
    if attempts >= ctrl.max_steps:
        return TOO_MANY_STEPS, t, False
    remaining = abs(tf - t)
    min_step = rounding_floor(t, t0, tf)
    if ctrl.kind == REVERSIBLE:
        if not 0.0 < rho < np.inf:
            return RHO_NOT_POSITIVE, t, False
        dt = ctrl.eps / rho
        # A remainder below the rounding floor joins this step, as on the
        # error controller (ten steps of 0.1 end at 1 - 1.1e-16).
        end = dt >= remaining or remaining - dt < min_step
        return OK, (tf if end else t + direction * dt), False
    if size < min_step:
        return STEP_TOO_SMALL, t, False
    if size >= remaining or remaining - size < min_step:
        return OK, tf, False
    return OK, t + direction * size, False


@njit(cache=True)
def error_norm(sc, dt, dt_prev, jerk_new, jerk_old, y, yp, y_new, yp_new, rtol, atol, span):
    """The scaled RMS norm of the estimated local errors per unit step,
    times ``span``, of the member ``sc``'s step of size ``dt`` whose third
    derivative is ``jerk_new``, after the interval of size ``dt_prev`` with
    ``jerk_old`` (``dt_prev`` = 0 at the start, where ``jerk_old`` is y'''
    at the knot itself)."""
    m = y_new.shape[0]
    total = 0.0
    per_unit = span / abs(dt)
    for k in range(m):
        est_y, est_yp = local_errors(abs(jerk_new[k]), abs(jerk_new[k] - jerk_old[k]), dt,
                                     dt_prev, sc)
        est_y *= per_unit
        est_yp *= per_unit
        scale_y = atol[k] + rtol[k] * max(abs(y[k]), abs(y_new[k]))
        scale_yp = atol[k] + rtol[k] * max(abs(yp[k]), abs(yp_new[k]))
        total += (est_y / scale_y) ** 2 + (est_yp / scale_yp) ** 2
    return np.sqrt(total / (2 * m))


@njit(cache=True)
def noise_weights(ctrl, vectors, sc, dt, y, yp, work, stiffness):
    """Into ``work``'s row _NOISE, under error control (else nothing): the
    weights w_k^2 by which the sweep of a step of size ``dt`` from (y, y')
    judges whether its unknown z = y'' at the step's end is known well
    enough for the error estimate (:func:`error_norm`) that reads it.

    The estimates read z through differences: errors up to e_k in z_k at
    the three knots of two steps of about equal size h enter the jump of
    y''' as up to 4 e_k / h and y''' as 2 e_k / h (after a step h_prev
    shorter than h, the jump's share is larger by about h / h_prev), so the
    estimates per unit step as span e_k (4 c3yp + 2 c2yp) (of y') and span
    |h| e_k (4 c4y + 2 c3y) (of y).  The error a sweep's last change c_k
    leaves is theta / (1 - theta) c_k for a contraction theta, here the
    run's remembered ``stiffness`` (:func:`judge`) times h^2, at most 1/2;
    the weights hold that factor, so that the sweep compares its last
    change with them: it iterates until sqrt(mean_k w_k^2 c_k^2) <= 1, the
    terms above within NOISE_SHARE of the tolerance (or until the change
    stops falling, at rounding).  Where no contraction was measured (the
    changes all below rounding: a mild equation), the weights are 0 and
    nothing is asked beyond the test on the state.

    Without them the sweep stops when its increments are within tol of
    the state, which leaves z an error of order |dF/dy| tol times the
    state's size (omega^2 tol on an oscillation of frequency omega), which
    the estimate reads as a fourth derivative.  On the chain of 10,000
    masses over the speed page's span (rtol 1e-3, atol 1e-8) the weights
    save 7 % of the evaluations (444,247 against 478,132) and 1 % of the
    steps; at m = 1,000 they change nothing."""
    if ctrl.kind != ERROR:
        return
    m = y.shape[0]
    theta = min(stiffness * dt * dt, 0.5)
    left = theta / (1.0 - theta)   # the error left per unit of the last change
    a_y = ctrl.span * abs(dt) * (4.0 * sc.c4y + 2.0 * sc.c3y) * left / NOISE_SHARE
    a_yp = ctrl.span * (4.0 * sc.c3yp + 2.0 * sc.c2yp) * left / NOISE_SHARE
    atol, rtol = vectors.atol, vectors.rtol
    for k in range(m):
        w_y = a_y / (atol[k] + rtol[k] * abs(y[k]))
        w_yp = a_yp / (atol[k] + rtol[k] * abs(yp[k]))
        work[_NOISE, k] = 0.5 * (w_y * w_y + w_yp * w_yp)


@njit(cache=True)
def step_factor(norm, after_reject, exponent):
    """The factor for the next step after a step whose error norm is
    ``norm``, for an estimate per unit step of order 1/``exponent``."""
    if norm == 0.0:
        factor = MAX_FACTOR
    else:
        factor = min(MAX_FACTOR, max(MIN_FACTOR, SAFETY * norm ** -exponent))
    if after_reject:
        factor = min(factor, 1.0)
    return factor


@njit(cache=True)
def judge(ctrl, vectors, sc, outcome, dt, dt_prev, jerks, y, yp, y_new, yp_new, memory):
    """The error controller's verdict on the member ``sc``'s step of size
    ``dt`` (signed): (accept, next size, memory).  ``outcome`` is the
    step's (status, contraction theta): the sweep's measured theta, the
    bound of Newton's matrix, NaN when unknown.  ``jerks`` holds the step's
    third derivative and that of the step before; ``memory`` what the
    controller keeps between steps, (the largest theta per h^2 seen, fading
    by STIFFNESS_MEMORY per step attempt; whether the last step was rejected),
    (0, False) at the start.

    A step whose equation failed is retried at h sqrt(theta_max / theta)
    (:func:`contraction_target`), within [MIN_FACTOR / 2, FAILED_FACTOR] of
    h, or FAILED_FACTOR times smaller when theta is unknown; one whose error
    norm exceeds 1 is retried smaller; an accepted one sets the next size
    from the norm, within ``max_step``.  Every next size is at most
    sqrt(theta_max / stiffness), the remembered stiffness's (but a failed
    step's retry is at least MIN_FACTOR / 2 of it): theta grows
    like h^2 on an oscillation, so the steps stay where the sweep converges
    and the member is stable instead of cycling between growth and failure
    there."""
    status, rate = outcome
    stiffness, after_reject = memory
    stiffness *= STIFFNESS_MEMORY
    if rate > 0.0:
        stiffness = max(stiffness, rate / (dt * dt))
    bound = np.inf
    if stiffness > 0.0 and ctrl.theta_max < np.inf:
        bound = np.sqrt(ctrl.theta_max / stiffness)
    if status != OK:
        if bound < np.inf:
            return (False, min(max(bound, 0.5 * MIN_FACTOR * abs(dt)), FAILED_FACTOR * abs(dt)),
                    (stiffness, True))
        return False, abs(dt) * FAILED_FACTOR, (stiffness, True)
    norm = error_norm(sc, dt, dt_prev, jerks[0], jerks[1], y, yp, y_new, yp_new, vectors.rtol,
                      vectors.atol, ctrl.span)
    factor = step_factor(norm, after_reject, sc.exponent)
    if not norm <= 1.0:
        return False, min(abs(dt) * min(factor, 1.0), bound), (stiffness, True)
    return True, min(abs(dt) * factor, ctrl.max_step, bound), (stiffness, False)


def jump_estimates(t, ypp, method="spline"):
    """The estimates est_y, est_y' (max over components) of every step of a
    run of the member ``method`` (:func:`splinestep.members.member`) after
    the first, from its knots ``t`` (k,) and y'' there (m, k): the numbers
    the controller compares with the tolerance."""
    steps = np.diff(t)
    jerk = np.diff(ypp, axis=1) / steps
    est_y, est_yp = local_errors(np.abs(jerk[:, 1:]), np.abs(jerk[:, 1:] - jerk[:, :-1]),
                                 steps[1:], steps[:-1], member(method).scheme())
    return np.max(est_y, axis=0), np.max(est_yp, axis=0)
