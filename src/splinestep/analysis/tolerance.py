"""What a tolerance buys: the global error of adaptive runs against rtol.

For each problem of :func:`problems` and each rtol, the final error of the
spline stepper's adaptive knots (``splinestep.solve(..., rtol=, atol=)``)
and of scipy's RK45 and DOP853 on the first-order form at the same rtol
and atol, divided by rtol times the solution's scale (the largest |y|, or
|y'|, of the exact or reference solution over the span), with the
evaluations each run took.  A ratio below 1 means the tolerance bounded
the global error; a ratio that stays level as rtol falls means the error
follows the tolerance proportionally.
"""

import numpy as np
import pandas as pd

from .. import problems as _problems
from .. import solve
from ..problems._problem import first_order
from ..problems.nonlinear import duffing, pendulum, rational

# atol as a fraction of rtol in the study (the solutions are of order 1).
ATOL_FRACTION = 1e-3
SCALE_SAMPLES = 2001


def problems():
    """The five problems of the study, by name: the harmonic oscillator over
    (0, 50), a forced Duffing oscillator over (0, 30), a pendulum from 3 rad
    over (0, 50), the Kepler orbit e = 0.9 over one period (198.7) and
    scipy's rational problem backwards over (5, 1)."""
    return {"harmonic oscillator": _problems.harmonic(1.0, (0.0, 50.0)),
            "forced Duffing": duffing(),
            "pendulum, 3 rad": pendulum(),
            "Kepler e = 0.9": _problems.eccentric(0.9),
            "rational, backwards": rational()}


def scales(problem):
    """(largest |y|, largest |y'|) of the problem's reference solution over
    its span, on SCALE_SAMPLES equally spaced times."""
    y, yp = problem.reference(np.linspace(*problem.t_span, SCALE_SAMPLES))
    return float(np.max(np.abs(y))), float(np.max(np.abs(yp)))


def runs(problem, rtols, methods=("spline", "RK45", "DOP853")):
    """One row per method and rtol: method, rtol, nfev, status, the final
    errors of y and y' (largest over components), the scale of y
    (:func:`scales`), and the errors divided by rtol times the solution's
    scale (``error_ratio``, ``error_ratio_yp``)."""
    from scipy.integrate import solve_ivp
    t0, tf = problem.t_span
    m = problem.y0.size
    system = first_order(problem.fun, problem.args, m)
    ref_y, ref_yp = (r[:, 0] for r in problem.reference(np.array([tf])))
    scale_y, scale_yp = scales(problem)
    rows = []
    for rtol in rtols:
        atol = ATOL_FRACTION * rtol
        for method in methods:
            if method == "spline":
                res = solve(problem.fun, problem.t_span, problem.y0, problem.yp0, rtol=rtol,
                            atol=atol, args=problem.args)
                y, yp, nfev, status = res.y[:, -1], res.yp[:, -1], res.nfev, res.status
            else:
                sol = solve_ivp(system, problem.t_span, np.r_[problem.y0, problem.yp0],
                                method=method, rtol=rtol, atol=atol)
                y, yp, nfev, status = sol.y[:m, -1], sol.y[m:, -1], sol.nfev, sol.status
            error = float(np.max(np.abs(y - ref_y)))
            error_yp = float(np.max(np.abs(yp - ref_yp)))
            rows.append(dict(method=method, rtol=rtol, nfev=int(nfev), status=int(status),
                             error=error, error_yp=error_yp, scale_y=scale_y,
                             error_ratio=error / (rtol * scale_y),
                             error_ratio_yp=error_yp / (rtol * scale_yp)))
    return rows


def uniform_runs(problem, steps):
    """One row per number of uniform steps n (h = span / n): n, nfev and
    the final error of y, with the scale of y (:func:`scales`): the work a
    uniform run needs for a given error."""
    t0, tf = problem.t_span
    ref_y = problem.reference(np.array([tf]))[0][:, 0]
    scale_y = scales(problem)[0]
    rows = []
    for n in steps:
        res = solve(problem.fun, problem.t_span, problem.y0, problem.yp0, abs(tf - t0) / n,
                    args=problem.args)
        rows.append(dict(method="spline, uniform", n=int(n), nfev=int(res.nfev),
                         error=float(np.max(np.abs(res.y[:, -1] - ref_y))), scale_y=scale_y))
    return rows


def slope(rtols, errors):
    """The least-squares slope of log(error) against log(rtol): 1 when the
    error follows the tolerance proportionally."""
    return float(np.polyfit(np.log(rtols), np.log(errors), 1)[0])


def adaptive_over_uniform(adaptive, uniform):
    """What adaptive knots cost against a uniform step reaching the same
    final error: the least and the largest ratio of their evaluations over
    the errors both work-precision curves cover, per problem.

    Parameters
    ----------
    adaptive, uniform : DataFrame
        Rows of ``runs`` (the spline's) and of ``uniform_runs``, with a
        ``problem`` column.

    Returns
    -------
    DataFrame
        Indexed by problem; ``least`` and ``most`` (above 1: the uniform
        step is cheaper).
    """
    from .diagnostics import work_ratio_range

    def curve(frame):
        frame = frame.sort_values("nfev")
        return frame.nfev.to_numpy(), frame.error.to_numpy()

    rows = {name: work_ratio_range(curve(group), curve(uniform[uniform.problem == name]))
            for name, group in adaptive.groupby("problem", sort=False)}
    return pd.DataFrame.from_dict(rows, orient="index", columns=["least", "most"])
