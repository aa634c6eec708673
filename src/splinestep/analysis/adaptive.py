"""Measurements of adaptive knots (notebook 09): the true local error of
each step, work against precision beside uniform steps, uniform runs
matched to adaptive ones, and the energy error orbit by orbit.
"""

import numpy as np
import pandas as pd

from .. import solve
from .diagnostics import loglog_interp


def true_local_errors(problem, knots, tol=1e-15):
    """The error of each step between consecutive ``knots`` when started
    from the problem's reference solution: the local error that an error
    estimate should predict.

    Returns
    -------
    ndarray, shape (len(knots) - 1,)
        Largest component of |y_step - y_reference| at the end of each step.
    """
    knots = np.asarray(knots, dtype=float)
    errors = np.empty(knots.size - 1)
    for i in range(knots.size - 1):
        y, yp = problem.reference(knots[i:i + 2])
        one = solve(problem.fun, (knots[i], knots[i + 1]), y[:, 0], yp[:, 0],
                    knots=knots[i:i + 2], args=problem.args, tol=tol)
        errors[i] = np.max(np.abs(one.y[:, -1] - y[:, 1]))
    return errors


def final_error(res, exact_end):
    """Largest component of the run's error at its last output."""
    return np.max(np.abs(res.y[:, -1] - exact_end))


def work_precision(problem, t_end, steps, rtols, atol_share=1e-3):
    """Uniform and adaptive runs over [t0, t_end], each with one sweep per
    step and iterated to convergence.

    Parameters
    ----------
    problem : splinestep.problems.Problem
    t_end : float
        The end of the runs; the error is measured there.
    steps : array_like of int
        Numbers of uniform steps.
    rtols : array_like of float
        Tolerances of the adaptive runs, with atol = ``atol_share`` * rtol.

    Returns
    -------
    DataFrame
        ``method`` ("uniform, 1 sweep", "uniform, iterated", "adaptive, 1
        sweep", "adaptive, iterated"), ``setting`` (the step or the rtol),
        ``nfev`` and ``final_error``.
    """
    exact_end = problem.reference(np.array([t_end]))[0][:, 0]
    sweeps = (("1 sweep", dict(iterations=1)), ("iterated", {}))
    rows = []
    for n in steps:
        for label, kwargs in sweeps:
            res = problem.solve(h=t_end / n, **kwargs)
            rows.append(dict(method=f"uniform, {label}", setting=t_end / n, nfev=res.nfev,
                             final_error=final_error(res, exact_end)))
    for rtol in rtols:
        for label, kwargs in sweeps:
            res = problem.solve(h="adaptive", rtol=rtol, atol=rtol * atol_share, **kwargs)
            rows.append(dict(method=f"adaptive, {label}", setting=rtol, nfev=res.nfev,
                             final_error=final_error(res, exact_end)))
    return pd.DataFrame(rows)


def matched_uniform_runs(problem, t_end, work):
    """For each adaptive run of ``work`` (from ``work_precision``) whose
    error the uniform runs cover, a uniform run whose step is the nearest
    tested one scaled by order 2 to the adaptive run's error.

    Returns
    -------
    DataFrame
        ``sweeps``, ``rtol``, the two runs' ``*_nfev`` and ``*_error``,
        ``interpolated`` (the uniform evaluations at the adaptive run's
        error read off the uniform curve, over the adaptive run's) and
        ``direct`` (the matched uniform run's evaluations over the adaptive
        run's).
    """
    exact_end = problem.reference(np.array([t_end]))[0][:, 0]
    rows = []
    for sweeps, kwargs in (("1 sweep", dict(iterations=1)), ("iterated", {})):
        uniform = work[work.method == f"uniform, {sweeps}"]
        for row in work[work.method == f"adaptive, {sweeps}"].itertuples():
            if not uniform.final_error.min() < row.final_error < uniform.final_error.max():
                continue
            near = uniform.iloc[np.argmin(np.abs(np.log(uniform.final_error / row.final_error)))]
            n = int(round(t_end / near.setting * np.sqrt(near.final_error / row.final_error)))
            res = problem.solve(h=t_end / n, **kwargs)
            rows.append(dict(
                sweeps=sweeps, rtol=row.setting, adaptive_nfev=row.nfev,
                adaptive_error=row.final_error, uniform_nfev=res.nfev,
                uniform_error=final_error(res, exact_end),
                interpolated=loglog_interp(uniform.final_error, uniform.nfev,
                                           [row.final_error])[0] / row.nfev))
    matched = pd.DataFrame(rows)
    matched["direct"] = matched.uniform_nfev / matched.adaptive_nfev
    return matched


def energy_per_orbit(res, energy, e0, period, orbits):
    """The signed energy error H - H0 of a run at its own knots, grouped by
    orbit (1 to ``orbits``; knots past the last orbit's end go to it).

    Returns
    -------
    pandas.core.groupby.SeriesGroupBy
        ``.apply(lambda g: g.abs().max())`` gives the largest error per
        orbit; ``.max()`` and ``.min()`` its extremes.
    """
    orbit = np.minimum(np.floor(res.t / period).astype(int), orbits - 1) + 1
    return pd.Series(energy(res.y, res.yp) - e0).groupby(orbit)


def orbits_changing_sign(signed):
    """The runs of consecutive orbits in which ``signed`` (from
    ``energy_per_orbit``) takes both signs, as strings "first-last"."""
    both = np.flatnonzero((signed.max() > 0) & (signed.min() < 0)) + 1
    runs = np.split(both, np.flatnonzero(np.diff(both) > 1) + 1)
    return [f"{r[0]}-{r[-1]}" for r in runs if r.size]
