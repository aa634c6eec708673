"""Cubic-spline time stepping for y'' = F(t, y, y').

On each interval [t_i, t_{i+1}] (h = t_{i+1} - t_i) the solution is the cubic

    s_i(t) = a_i + b_i (t - t_i) + c_i (t - t_i)^2 + d_i (t - t_i)^3,

continuous with its first two derivatives at the knots and satisfying the
ODE at every knot.  With z = y''(t_{i+1}) = 2 c_{i+1} the unknown of the step,

    d_i     = (z - y''_i) / (6 h)                        (report eq. 8)
    a_{i+1} = y_i + h y'_i + h^2 (y''_i / 3 + z / 6)      (eq. 6)
    b_{i+1} = y'_i + h (y''_i + z) / 2                     (eq. 7)
    z       = F(t_{i+1}, a_{i+1}, b_{i+1})                 (eq. 9, with c = y''/2)

which is Newmark's method with beta = 1/6, gamma = 1/2 (the "linear
acceleration" method).  The step equation is solved by the report's
fixed-point iteration (start from d_i = 0, i.e. z = y''_i) or by Newton's
method.
"""

import numpy as np
from numba import njit

from . import _base
from ._base import (BAD_SHAPE, NON_FINITE, NOT_CONVERGED, OK, SINGULAR, as_vector,
                    wrong_length)
from .result import SplineSolution

# The two coefficients of the unknown z in eqs. 6-7, as multiples of h^2 and h.
Y_WEIGHT = 1.0 / 6.0   # d a_{i+1} / d z = h^2 / 6
YP_WEIGHT = 0.5        # d b_{i+1} / d z = h / 2
# Relative step of the finite-difference Jacobian: sqrt(machine epsilon).
FD_STEP = 1.4901161193847656e-08

ITERATIONS = ("fixed-point", "newton")
# Loop modes: the iteration, and whether it runs a fixed number of times.
FIXED_POINT, NEWTON = 0, 1


@njit(cache=True, error_model="numpy")
def _lu_solve(a, b):
    """Solve a x = b by LU factorisation with partial pivoting (Gaussian
    elimination, overwriting a and b).  Written out because numba's LAPACK
    binding (np.linalg.solve) multiplies the compile time of the step loop
    by four; a singular matrix gives a non-finite x."""
    m = b.shape[0]
    for col in range(m):
        piv = col
        for row in range(col + 1, m):
            if abs(a[row, col]) > abs(a[piv, col]):
                piv = row
        if piv != col:
            for k in range(m):
                a[col, k], a[piv, k] = a[piv, k], a[col, k]
            b[col], b[piv] = b[piv], b[col]
        for row in range(col + 1, m):
            factor = a[row, col] / a[col, col]
            for k in range(col, m):
                a[row, k] -= factor * a[col, k]
            b[row] -= factor * b[col]
    x = np.empty(m)
    for row in range(m - 1, -1, -1):
        acc = b[row]
        for k in range(row + 1, m):
            acc -= a[row, k] * x[k]
        x[row] = acc / a[row, row]
    return x


# Not cache=True: numba's on-disk cache cannot key a loop on the function it
# is given (it recompiles every run) and pickles that function's type into its
# index, which breaks later processes.  The loop compiles once per process.
@njit
def _spline_loop(fun, args, jac, t0, h, n, knots, tf, y0, yp0, t_eval,
                 store_knots, mode, n_iter, until_converged, tol):
    """Step from t0 to tf.  Written once for both paths: compiled by numba
    when ``fun`` is compiled, run as plain Python (``py_func``) otherwise.
    Component loops over preallocated buffers keep the step free of
    temporary arrays.

    Returns (status, fail_step, t_last, t_fail, nfev, njev, niter, nstep,
    n_knots, n_eval, T, Y, YP, YPP, YE, YPE, YPPE); see ``_base.build_result``.
    """
    m = y0.shape[0]
    n_out = n + 1 if store_knots else 1
    T = np.empty(n_out)
    Y = np.empty((n_out, m))
    YP = np.empty((n_out, m))
    YPP = np.empty((n_out, m))
    ne = t_eval.shape[0]
    YE = np.empty((ne, m))
    YPE = np.empty((ne, m))
    YPPE = np.empty((ne, m))
    y = y0.copy()            # a_i
    yp = yp0.copy()          # b_i
    base_y = np.empty(m)     # a_{i+1} without the unknown's term
    base_yp = np.empty(m)    # b_{i+1} without the unknown's term
    z = np.empty(m)          # the unknown y''_{i+1} = 2 c_{i+1}
    y_new = np.empty(m)
    yp_new = np.empty(m)
    nfev = 0
    njev = 0
    niter = 0
    n_eval = 0

    g = as_vector(fun(t0, y, yp, *args))
    nfev += 1
    if wrong_length(g, m):
        return (BAD_SHAPE, 0, t0, t0, nfev, njev, niter, 0, 0, 0,
                T, Y, YP, YPP, YE, YPE, YPPE)
    ypp = np.empty(m)        # 2 c_i
    for k in range(m):
        ypp[k] = g[k]
        if not abs(g[k]) < np.inf:
            return (NON_FINITE, 0, t0, t0, nfev, njev, niter, 0, 0, 0,
                    T, Y, YP, YPP, YE, YPE, YPPE)
    T[0] = t0
    for k in range(m):
        Y[0, k] = y[k]
        YP[0, k] = yp[k]
        YPP[0, k] = ypp[k]
    n_knots = 1
    while n_eval < ne and t_eval[n_eval] <= t0:
        for k in range(m):
            YE[n_eval, k] = y[k]
            YPE[n_eval, k] = yp[k]
            YPPE[n_eval, k] = ypp[k]
        n_eval += 1

    t = t0
    for i in range(n):
        if knots.shape[0] > 0:
            t_new = knots[i + 1]
        elif i + 1 < n:
            t_new = t0 + (i + 1) * h
        else:
            t_new = tf
        dt = t_new - t
        wy = Y_WEIGHT * dt * dt
        wyp = YP_WEIGHT * dt
        w_max = max(wy, wyp)
        for k in range(m):
            base_y[k] = y[k] + dt * yp[k] + (dt * dt / 3.0) * ypp[k]
            base_yp[k] = yp[k] + wyp * ypp[k]
            z[k] = ypp[k]  # the report's initial guess d_i = 0
        status = NOT_CONVERGED if until_converged else OK
        for _ in range(n_iter):
            size = 0.0
            for k in range(m):
                y_new[k] = base_y[k] + wy * z[k]
                yp_new[k] = base_yp[k] + wyp * z[k]
                size = max(size, abs(y_new[k]), abs(yp_new[k]))
            g = as_vector(fun(t_new, y_new, yp_new, *args))
            nfev += 1
            if wrong_length(g, m):
                status = BAD_SHAPE
                break
            if mode == FIXED_POINT:
                # Sweep: eq. 9 gives the new c_{i+1} = z / 2 (eq. 8 then d_i).
                change = 0.0
                for k in range(m):
                    if not abs(g[k]) < np.inf:
                        status = NON_FINITE
                    change = max(change, abs(g[k] - z[k]))
                    z[k] = g[k]
                if status == NON_FINITE:
                    break
            else:
                # Newton on R(z) = z - F(t, a(z), b(z)) = 0 with J = I - dF/dz.
                for k in range(m):
                    if not abs(g[k]) < np.inf:
                        status = NON_FINITE
                if status == NON_FINITE:
                    break
                if jac is None:
                    dgdz = np.empty((m, m))
                    for k in range(m):
                        step = FD_STEP * max(1.0, abs(z[k]))
                        saved = z[k]
                        z[k] = saved + step
                        for j in range(m):
                            y_new[j] = base_y[j] + wy * z[j]
                            yp_new[j] = base_yp[j] + wyp * z[j]
                        gk = as_vector(fun(t_new, y_new, yp_new, *args))
                        z[k] = saved
                        for j in range(m):
                            dgdz[j, k] = (gk[j] - g[j]) / step
                    nfev += m
                else:
                    fy, fyp = jac(t_new, y_new, yp_new, *args)
                    njev += 1
                    dgdz = wy * np.asarray(fy) + wyp * np.asarray(fyp)
                residual = np.empty(m)
                for k in range(m):
                    residual[k] = g[k] - z[k]
                dz = _lu_solve(np.eye(m) - dgdz, residual)
                change = 0.0
                for k in range(m):
                    if not abs(dz[k]) < np.inf:
                        status = SINGULAR
                    change = max(change, abs(dz[k]))
                    z[k] += dz[k]
                if status == SINGULAR:
                    break
            niter += 1
            if until_converged and w_max * change <= tol * size:
                status = OK
                break
        if status != OK:
            return (status, i + 1, t, t_new, nfev, njev, niter, i, n_knots, n_eval,
                    T, Y, YP, YPP, YE, YPE, YPPE)

        # Report at the requested times inside (t, t_new] from the cubic itself.
        while n_eval < ne and t_eval[n_eval] <= t_new:
            s = t_eval[n_eval] - t
            for k in range(m):
                d = (z[k] - ypp[k]) / (6.0 * dt)
                YE[n_eval, k] = y[k] + s * (yp[k] + s * (0.5 * ypp[k] + s * d))
                YPE[n_eval, k] = yp[k] + s * (ypp[k] + 3.0 * s * d)
                YPPE[n_eval, k] = ypp[k] + 6.0 * s * d
            n_eval += 1
        for k in range(m):
            y[k] = base_y[k] + wy * z[k]
            yp[k] = base_yp[k] + wyp * z[k]
            ypp[k] = z[k]
        t = t_new
        if store_knots:
            T[n_knots] = t
            for k in range(m):
                Y[n_knots, k] = y[k]
                YP[n_knots, k] = yp[k]
                YPP[n_knots, k] = ypp[k]
            n_knots += 1
    return (OK, -1, t, t, nfev, njev, niter, n, n_knots, n_eval,
            T, Y, YP, YPP, YE, YPE, YPPE)


def solve(fun, t_span, y0, yp0, h=None, *, knots=None, t_eval=None, args=(),
          iteration="fixed-point", iterations=None, tol=1e-12, max_iter=50,
          jac=None, dense_output=False):
    """Solve y'' = F(t, y, y') by cubic-spline time stepping.

    Each step extends a C2 cubic spline by one knot and satisfies the ODE at
    the new knot; the implicit unknown (the third-derivative coefficient
    d_i, equivalently y'' at the new knot) is found by fixed-point
    iteration, as in the report, or by Newton's method.

    Parameters
    ----------
    fun : callable
        ``fun(t, y, yp, *args) -> y''``, with y, yp and the result arrays of
        shape (m,).  When ``fun`` is a ``numba.njit`` function, the whole
        stepping loop runs compiled; a compiled ``fun`` may also return a
        tuple of m floats, which spares an array allocation per evaluation
        (about half the cost of a small right-hand side).
    t_span : (float, float)
        Interval of integration (t0, tf), t0 < tf.
    y0, yp0 : float or array_like, shape (m,)
        Initial value and initial first derivative.
    h : float, optional
        Uniform step.  When tf - t0 is not a multiple of h, the last step is
        shortened to end exactly at tf.
    knots : array_like, optional
        Non-uniform knots t0 = knots[0] < ... < knots[-1] = tf (instead of h).
    t_eval : array_like, optional
        Sorted times in t_span at which to report the solution, evaluated
        from the spline; the knots are then not stored.
    args : tuple, optional
        Extra arguments passed to ``fun`` and ``jac``.
    iteration : {"fixed-point", "newton"}
        How the step equation is solved.  "fixed-point" is the report's
        scheme; it converges when h^2/6 |dF/dy| + h/2 |dF/dy'| < 1.
        "newton" uses Newton's method with an LU solve of
        I - h^2/6 dF/dy - h/2 dF/dy'; it is exact in one iteration on
        linear problems.
    iterations : int, optional
        Exactly this many iterations per step, with no convergence test
        (the report's "a few times").  By default iterate until converged.
    tol : float
        Convergence test: the change of the step's increments (of y and y'
        at the new knot) is at most ``tol`` times the size of the state
        (max norm).
    max_iter : int
        Iterations allowed per step before the run fails (when
        ``iterations`` is None).
    jac : callable, optional
        ``jac(t, y, yp, *args) -> (dF/dy, dF/dyp)``, two (m, m) arrays, used
        by Newton's method; finite differences otherwise.
    dense_output : bool
        Return the spline itself as ``sol``.

    Returns
    -------
    OdeResult
        ``t`` (k,), ``y``, ``yp``, ``ypp`` (m, k), ``sol``, ``nfev``,
        ``njev``, ``niter``, ``nstep``, ``status`` (0 reached the end, -1
        failed), ``message``, ``success``.  A failed run returns the steps
        completed before the failure and says in ``message`` which step
        failed and why.

    References
    ----------
    .. [1] N. M. Newmark, "A method of computation for structural dynamics",
       J. Eng. Mech. Div. ASCE 85 (1959) 67-94.
    .. [2] E. L. Wilson, I. Farhoomand, K. J. Bathe, "Nonlinear dynamic
       analysis of complex structures", Earthquake Eng. Struct. Dyn. 1 (1973)
       241-252 (the linear acceleration method).

    Examples
    --------
    >>> import numpy as np, splinestep
    >>> res = splinestep.solve(lambda t, y, yp: -y, (0, np.pi), 1.0, 0.0, h=np.pi / 100)
    >>> bool(abs(res.y[0, -1] + 1) < 1e-3)
    True
    """
    t0, tf = _base.check_span(t_span)
    y0, yp0 = _base.check_state(y0, yp0)
    h, n, knots = _base.check_grid(t0, tf, h, knots)
    t_eval = _base.check_t_eval(t_eval, t0, tf)
    args = _base.check_args(args)
    if iteration not in ITERATIONS:
        raise ValueError(f"iteration must be one of {ITERATIONS}, got {iteration!r}")
    if not (isinstance(tol, (int, float)) and np.isfinite(tol) and tol > 0):
        raise ValueError(f"tol must be positive and finite, got {tol!r}")
    if not (isinstance(max_iter, (int, np.integer)) and max_iter >= 1):
        raise ValueError(f"max_iter must be an integer >= 1, got {max_iter!r}")
    if iterations is not None and not (
            isinstance(iterations, (int, np.integer)) and iterations >= 1):
        raise ValueError(f"iterations must be None or an integer >= 1, got {iterations!r}")
    if not callable(fun):
        raise ValueError("fun must be callable")
    if jac is not None and not callable(jac):
        raise ValueError("jac must be callable or None")

    mode = FIXED_POINT if iteration == "fixed-point" else NEWTON
    until_converged = iterations is None
    n_iter = max_iter if until_converged else iterations
    store_knots = t_eval is None or dense_output
    loop = _base.select_loop(_spline_loop, fun, jac)
    out = loop(fun, args, jac, t0, h, n, knots, tf, y0, yp0,
               np.empty(0) if t_eval is None else t_eval,
               store_knots, mode, int(n_iter), until_converged, float(tol))
    result, knot_values = _base.build_result(out, t_eval, n_iter)
    if dense_output and knot_values[0].size >= 2:
        result.sol = SplineSolution(*knot_values)
    return result
