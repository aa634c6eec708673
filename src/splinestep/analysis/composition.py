"""Measurements of the symmetric compositions of order 4 and 6 (notebook
10): their fitted orders on problems with exact solutions, and the work
each route to higher order spends for a given error.
"""

import numpy as np
from . import require

pd = require("pandas", __name__)

from .extrapolation import richardson


def orders(cases, steps, samples=137):
    """The order of each composition on each problem, measured two ways.

    Parameters
    ----------
    cases : dict
        {name: problem} (:mod:`splinestep.problems`, with ``reference``).
    steps : dict
        {order: steps h, halving}.
    samples : int
        The error is the largest over this many evenly spaced times of the
        problem's span (times between the knots: the interpolant's error
        counts).

    Returns
    -------
    pandas.DataFrame
        One row per problem and order: ``slope``, the slope of log error
        against log h fitted against the exact solution; ``successive_slope``,
        log2 of the ratio of the last two successive differences of the runs
        (no exact solution used); ``largest_error`` and ``smallest_error``.
    """
    rows = []
    for name, problem in cases.items():
        t_check = np.linspace(problem.t_span[0], problem.t_span[1], samples)
        exact, _ = problem.reference(t_check)
        for order, hs in steps.items():
            runs = [problem.solve(h=h, order=order, t_eval=t_check).y for h in hs]
            errors = [np.max(np.abs(y - exact)) for y in runs]
            differences = [np.max(np.abs(a - b)) for a, b in zip(runs[:-1], runs[1:])]
            rows.append(dict(problem=name, order=order,
                             slope=np.polyfit(np.log(hs), np.log(errors), 1)[0],
                             successive_slope=np.log2(differences[-2] / differences[-1]),
                             largest_error=errors[0], smallest_error=errors[-1]))
    return pd.DataFrame(rows)


def work_precision(problem, t_eval, exact, steps, tolerances):
    """Evaluations of F against the largest position error at ``t_eval``
    (``exact``: the exact positions there) for the spline of orders 2, 4
    and 6, Richardson extrapolation of order 2 (:func:`richardson`) and RK4
    at each of ``steps``, and scipy's DOP853 at each of ``tolerances``
    (rtol; atol = rtol / 100).

    Returns
    -------
    pandas.DataFrame
        One row per run: ``method``, ``setting`` (h or rtol), ``nfev``,
        ``max_error``.
    """
    from scipy.integrate import solve_ivp
    from ..problems import first_order
    rows = []

    def row(method, setting, nfev, y):
        rows.append(dict(method=method, setting=setting, nfev=nfev,
                         max_error=np.max(np.abs(y - exact))))

    for h in steps:
        for order in (2, 4, 6):
            res = problem.solve(h=h, order=order, t_eval=t_eval)
            row(f"spline, order {order}", h, res.nfev, res.y)
        res = richardson(problem.fun, problem.t_span, problem.y0, problem.yp0, h,
                         t_eval=t_eval, args=problem.args)
        row("Richardson (order 2 at h, h/2)", h, res.nfev, res.y)
        res = problem.solve("rk4", h=h, t_eval=t_eval)
        row("RK4", h, res.nfev, res.y)
    m = problem.y0.size
    for tol in tolerances:
        sol = solve_ivp(first_order(problem.fun, problem.args, m), problem.t_span,
                        np.r_[problem.y0, problem.yp0], method="DOP853", rtol=tol,
                        atol=tol * 1e-2, t_eval=t_eval)
        row("scipy DOP853", tol, sol.nfev, sol.y[:m])
    return pd.DataFrame(rows)
