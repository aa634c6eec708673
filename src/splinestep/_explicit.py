"""The explicit baselines' steps: classical RK4 (:func:`rk4_step`) and
velocity Verlet (:func:`verlet_step`), in the protocol of the spline step
(:mod:`splinestep.step`): each advances (y, y', y'') from t to t_new into
``y_new``, ``yp_new`` and ``z`` (y'' at t_new) and returns (status, nfev,
njev, niter, rate), rate NaN (no iteration).  The one driver (:mod:`splinestep.driver`) takes them as it
takes the spline step; both are inlined there (numba ``inline="always"``):
as calls, they cost each method 1.3 to 1.5 times the time per evaluation
(``make bench``)."""

import numpy as np
from numba import njit

from ._base import evaluate
from .status import BAD_SHAPE, OK
from .step import _value_status

# Butcher tableau of the classical method: stage j (j = 2, 3, 4) is taken
# at t + NODES[j-2] h from the state advanced by the previous stage; the
# stages are combined with weights FIRST_WEIGHT, then STAGE_WEIGHTS.
NODES = (0.5, 0.5, 1.0)
FIRST_WEIGHT = 1.0 / 6.0
STAGE_WEIGHTS = (1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0)


@njit(cache=True, inline="always")
def _checked(g, a, m):
    """Copy the value ``g`` of fun into ``a``; the status it implies
    (:func:`splinestep.step._value_status`)."""
    status = _value_status(g, m)
    if status != BAD_SHAPE:
        for k in range(m):
            a[k] = g[k]
    return status


@njit(cache=True, inline="always")
def rk4_step(fun, args, t, t_new, dt, y, yp, ypp, y_new, yp_new, a, stage):
    """One RK4 step on u = (y, y'), u' = (y', F) from (y, y', y''):
    y_new, yp_new, and y'' at t_new in ``a``; ``stage`` (4, m) holds the
    stage state, velocity and the two weighted sums.  Returns (status, nfev,
    njev, niter, rate): 4 evaluations of F unless one failed, no Jacobian, no
    iteration (rate NaN)."""
    y_stage, v, sum_v, sum_a = stage[0], stage[1], stage[2], stage[3]
    m = y.shape[0]
    # Stage 1 is (y', y'') at t; stage j+1 advances by NODES[j] dt with stage j.
    for k in range(m):
        v[k] = yp[k]
        a[k] = ypp[k]
        sum_v[k] = FIRST_WEIGHT * v[k]
        sum_a[k] = FIRST_WEIGHT * a[k]
    for j in range(4):
        if j < 3:
            c = NODES[j] * dt
            for k in range(m):
                y_stage[k] = y[k] + c * v[k]
                v[k] = yp[k] + c * a[k]
            g = evaluate(fun, args, t + c, y_stage, v)
        else:
            # y'' at the new knot: the first stage of the next step.
            for k in range(m):
                y_new[k] = y[k] + dt * sum_v[k]
                yp_new[k] = yp[k] + dt * sum_a[k]
            g = evaluate(fun, args, t_new, y_new, yp_new)
        status = _checked(g, a, m)
        if status != OK:
            return status, j + 1, 0, 0, np.nan
        if j < 3:
            for k in range(m):
                sum_v[k] += STAGE_WEIGHTS[j] * v[k]
                sum_a[k] += STAGE_WEIGHTS[j] * a[k]
    return OK, 4, 0, 0, np.nan


@njit(cache=True, inline="always")
def verlet_step(fun, args, t_new, dt, y, yp, ypp, y_new, yp_new, a, v):
    """One velocity-Verlet step from (y, y', y''): y_new, yp_new, and y'' at
    t_new in ``a``; one evaluation of F.  F's y' argument is the predictor
    y' + dt y'' (O(dt^2) off, so the step keeps order 2 when F depends on
    y'), kept in ``v``.  Returns (status, 1, 0, 0, NaN)."""
    m = y.shape[0]
    for k in range(m):
        y_new[k] = y[k] + dt * yp[k] + (0.5 * dt * dt) * ypp[k]
        v[k] = yp[k] + dt * ypp[k]
    status = _checked(evaluate(fun, args, t_new, y_new, v), a, m)
    for k in range(m):
        yp_new[k] = yp[k] + (0.5 * dt) * (ypp[k] + a[k])
    return status, 1, 0, 0, np.nan
