"""The spline stepper is Stormer-Verlet seen through a change of variables.

For y'' = f(t, y) (no y' in the force) the spline step maps (y_n, y'_n) to
(y_{n+1}, y'_{n+1}).  With

    chi(y, y') = (Y, P) = (y - h^2 f(t, y) / 6, y'),

the images (Y_n, P_n) = chi(y_n, y'_n) are exactly the velocity-Verlet steps
for the modified force

    f~(t, Y) = f(t, y)   where   y - h^2 f(t, y) / 6 = Y,

so every property of Verlet on f~ (symmetric, symplectic for a conservative
f, a modified energy conserved without drift, Verlet's angular momentum)
holds for the spline stepper in the variables (Y, P).  ``notebooks/05_theory``
derives it and checks it over many orbits; this module supplies the map and
the modified force so that the check runs the package's own Verlet.

References
----------
.. [1] C. Kane, J. E. Marsden, M. Ortiz, M. West, "Variational integrators
   and the Newmark algorithm for conservative and dissipative mechanical
   systems", Int. J. Numer. Methods Eng. 49 (2000) 1295-1325.
"""

import numpy as np
from numba import njit

from .. import _adapters, _base
from ..step import Y_WEIGHT, solve_linear

# Newton's method for y from Y: stop when the correction is below this
# times max(1, |y|), or after NEWTON_ITERATIONS (quadratic convergence from
# the start y = Y, which is O(h^2) off, needs two or three).
NEWTON_TOL = 1e-15
NEWTON_ITERATIONS = 8


def to_verlet(t, y, yp, fun, h, args=()):
    """chi: the spline's states (y, y') at times t (shapes (m, k), (k,)) in
    Verlet's variables (Y, P) = (y - h^2 f(t, y) / 6, y')."""
    y = np.asarray(y, dtype=float)
    force = np.stack([_base.as_vector(fun(ti, y[:, i], yp[:, i], *args))
                      for i, ti in enumerate(np.atleast_1d(t))], axis=1)
    return y - Y_WEIGHT * h * h * force, np.asarray(yp, dtype=float).copy()


def modified_force(fun, jac, h, args=()):
    """The force f~(t, Y, P) of the Verlet problem conjugate to the spline
    stepper at step ``h``: f(t, y) at the y with y - h^2 f(t, y) / 6 = Y,
    found by Newton's method with ``jac`` (``args`` are bound into it).

    ``fun(t, y, yp, *args)`` and ``jac(t, y, yp, *args) -> (df/dy, df/dyp)``
    must be ``numba.njit`` functions whose force does not depend on y' (the
    conjugacy needs y'' = f(t, y)); the result is compiled too.
    """
    if not (_base.is_compiled(fun) and _base.is_compiled(jac)):
        raise ValueError("fun and jac must be numba.njit functions")
    h = float(h)
    if not (np.isfinite(h) and h > 0):
        raise ValueError(f"h must be positive and finite, got {h!r}")
    weight = Y_WEIGHT * h * h
    args = _adapters.passable(_base.check_args(args))

    @njit
    def force(t, Y, P):
        m = Y.shape[0]
        y = Y.copy()
        for _ in range(NEWTON_ITERATIONS):
            g = _base.as_vector(fun(t, y, P, *args))
            fy, _ = jac(t, y, P, *args)
            a = np.eye(m) - weight * fy
            r = np.empty(m)
            size = 1.0
            for k in range(m):
                r[k] = Y[k] - y[k] + weight * g[k]
                size = max(size, abs(y[k]))
            dy = solve_linear(a, r)
            change = 0.0
            for k in range(m):
                y[k] += dy[k]
                change = max(change, abs(dy[k]))
            if change <= NEWTON_TOL * size:
                break
        g = _base.as_vector(fun(t, y, P, *args))
        out = np.empty(m)
        for k in range(m):
            out[k] = g[k]
        return out

    return force


def compare(problem, steps, every=1):
    """The spline's run of ``problem`` over ``steps`` steps of its own h,
    mapped to Verlet's variables, against velocity Verlet on the modified
    force started from the mapped initial state, and against plain Verlet
    on f; sampled every ``every`` steps.

    Returns
    -------
    dict
        ``spline``: the spline's result (at the sampled knots);
        ``conjugate_gap``: the largest |Verlet on f~ - chi(spline)| over
        positions and velocities; ``plain_gap``: the largest
        |Verlet on f - spline| over positions.
    """
    from .. import solve, verlet
    h, span = problem.h, (0.0, steps * problem.h)   # a whole number of steps: chi uses h
    t = h * np.arange(0, steps + 1, every)
    spline = solve(problem.fun, span, problem.y0, problem.yp0, h, args=problem.args, t_eval=t)
    Q, P = to_verlet(t, spline.y, spline.yp, problem.fun, h, problem.args)
    Q0, P0 = to_verlet(t[:1], problem.y0[:, None], problem.yp0[:, None], problem.fun, h,
                       problem.args)
    force = modified_force(problem.fun, problem.jac, h, problem.args)
    on_modified = verlet(force, span, Q0[:, 0], P0[:, 0], h, t_eval=t)
    plain = verlet(problem.fun, span, problem.y0, problem.yp0, h, args=problem.args, t_eval=t)
    return dict(spline=spline,
                conjugate_gap=float(np.max(np.abs(np.vstack([Q - on_modified.y,
                                                             P - on_modified.yp])))),
                plain_gap=float(np.max(np.abs(plain.y - spline.y))))
