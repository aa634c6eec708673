"""Measurements of the symmetric compositions of order 4 and 6 (notebook
10): their fitted orders on problems with exact solutions, measured against
the exact solution and from successive differences of the runs.  Their work
against precision is :func:`splinestep.analysis.diagnostics.work_precision`.
"""

import numpy as np
from . import require

pd = require("pandas", __name__)



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
