"""Step-size controllers: which knot comes next after a spline step.

The spline's own error estimate.  The third derivative of the cubic is
constant on each interval, j_i = (y''_{i+1} - y''_i) / h_i, and its jump
at a knot estimates the fourth derivative,

    y'''' ~ (j_i - j_{i-1}) / ((h_i + h_{i-1}) / 2),

with an error O(h) (the two interval means of y''' sit (h_i + h_{i-1})/2
apart).  A step from exact values misses, to leading order, h^4 y''''/24 in y and
h^3 y''''/12 in y' (:mod:`splinestep.analysis.theory`), so

    est_y = h^4 |y''''| / 24,   est_y' = |h|^3 |y''''| / 12.

The estimate of Newmark codes (Zienkiewicz and Xie, 1991) is proportional
to beta - 1/6 and vanishes for this method; the jump above does not.  At
the first step there is no earlier interval: its role is taken by y''' at
t0, from one finite difference of F along the Taylor line.

The norm is scipy's: the root mean square over the 2m components of each
estimate divided by atol + rtol max(|old|, |new|).  A step is accepted when
the norm is at most 1; the next step is the current one times
SAFETY norm^(-1/3) (the estimate of y' is O(h^3)), within [MIN_FACTOR,
MAX_FACTOR], and not larger right after a rejection.  A step whose
equation could not be solved (the sweep diverged, Newton failed) is
rejected and retried FAILED_FACTOR times smaller.

References
----------
.. [1] O. C. Zienkiewicz, Y. M. Xie, "A simple error estimator and adaptive
   time stepping procedure for dynamic analysis", Earthquake Eng. Struct.
   Dyn. 20 (1991) 871-887.
.. [2] E. Hairer, S. P. Norsett, G. Wanner, "Solving Ordinary Differential
   Equations I", 2nd ed., Springer (1993), Sec. II.4.
"""

import numpy as np
from numba import njit

from .step import local_errors

SAFETY = 0.9
MIN_FACTOR = 0.2
MAX_FACTOR = 5.0
FAILED_FACTOR = 0.25
ERROR_EXPONENT = 1.0 / 3.0


@njit(cache=True)
def error_norm(dt, dt_prev, jerk_new, jerk_old, y, yp, y_new, yp_new, rtol, atol):
    """The scaled RMS norm of the estimated local errors of the step of
    size ``dt`` whose third derivative is ``jerk_new``, after the interval
    of size ``dt_prev`` with ``jerk_old`` (``dt_prev`` = 0 at the start,
    where ``jerk_old`` is y''' at the knot itself)."""
    m = y.shape[0]
    total = 0.0
    for k in range(m):
        est_y, est_yp = local_errors(jerk_new[k], jerk_old[k], dt, dt_prev)
        scale_y = atol[k] + rtol * max(abs(y[k]), abs(y_new[k]))
        scale_yp = atol[k] + rtol * max(abs(yp[k]), abs(yp_new[k]))
        total += (est_y / scale_y) ** 2 + (est_yp / scale_yp) ** 2
    return np.sqrt(total / (2 * m))


@njit(cache=True)
def step_factor(norm, after_reject):
    """The factor for the next step after a step whose error norm is
    ``norm``."""
    if norm == 0.0:
        factor = MAX_FACTOR
    else:
        factor = min(MAX_FACTOR, max(MIN_FACTOR, SAFETY * norm ** -ERROR_EXPONENT))
    if after_reject:
        factor = min(factor, 1.0)
    return factor


def jump_estimates(t, ypp):
    """The estimates est_y, est_y' (max over components) of every step of a
    run after the first, from its knots ``t`` (k,) and y'' there (m, k): the
    numbers the controller compares with the tolerance."""
    steps = np.diff(t)
    jerk = np.diff(ypp, axis=1) / steps
    est_y, est_yp = local_errors(jerk[:, 1:], jerk[:, :-1], steps[1:], steps[:-1])
    return np.max(est_y, axis=0), np.max(est_yp, axis=0)
