"""The C loop's arithmetic (spline_step.c: the spline step with a fixed
number of fixed-point sweeps, nothing else) written in numba, to split the
compiled path's time per evaluation into its parts: what numba makes of the
bare arithmetic with the right-hand side inlined, what calling the
right-hand side through a function pointer adds (splinestep's loops do, so
that they compile once per machine), and what splinestep's loop adds to
that (the convergence test, the error estimate, output at t_eval)."""

import numpy as np
from numba import njit, types

from splinestep import _compile


def bare_loop(fun, args, t0, tf, n, sweeps, y, yp):
    """spline_step.c's DEFINE_LOOP; returns the number of evaluations."""
    m = y.shape[0]
    ypp = np.empty(m)
    base_y = np.empty(m)
    base_yp = np.empty(m)
    z = np.empty(m)
    y_new = np.empty(m)
    yp_new = np.empty(m)
    h = (tf - t0) / n
    t = t0
    g = fun(t0, y, yp, *args)
    nfev = 1
    for k in range(m):
        ypp[k] = g[k]
    for i in range(n):
        t_new = t0 + (i + 1) * h if i + 1 < n else tf
        dt = t_new - t
        wy = dt * dt / 6.0
        wyp = 0.5 * dt
        for k in range(m):
            base_y[k] = y[k] + dt * yp[k] + (dt * dt / 3.0) * ypp[k]
            base_yp[k] = yp[k] + wyp * ypp[k]
            z[k] = ypp[k]
        for _ in range(sweeps):
            for k in range(m):
                y_new[k] = base_y[k] + wy * z[k]
                yp_new[k] = base_yp[k] + wyp * z[k]
            g = fun(t_new, y_new, yp_new, *args)
            nfev += 1
            for k in range(m):
                if not abs(g[k]) < np.inf:
                    return -1
                z[k] = g[k]
        for k in range(m):
            y[k] = base_y[k] + wy * z[k]
            yp[k] = base_yp[k] + wyp * z[k]
            ypp[k] = z[k]
        t = t_new
    return nfev


INLINED = njit(bare_loop)  # specialised on fun itself: LLVM inlines it


def through_pointer(fun, args):
    """``bare_loop`` taking ``fun`` as splinestep's loops do."""
    fun_type, args_type, _ = _compile.loop_types(fun, None, args)
    return njit((fun_type, args_type, types.float64, types.float64, types.int64, types.int64,
                 _compile.VECTOR, _compile.VECTOR))(bare_loop)
