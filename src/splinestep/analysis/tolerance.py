"""What a tolerance buys: the global error of adaptive runs against rtol.

For each problem of :func:`problems` and each rtol, the final error of the
spline stepper's adaptive knots (``splinestep.solve(..., rtol=, atol=)``)
and of scipy's RK45 and DOP853 on the first-order form at the same rtol
and atol, divided by rtol times the solution's scale (the largest |y|, or
|y'|, of the exact or reference solution over the span), with the
evaluations each run took.  A ratio below 1 means the tolerance bounded
the global error; a ratio that stays level as rtol falls means the error
follows the tolerance proportionally.

What the adaptive knots cost: uniform runs of each problem at
:data:`STEPS_PER_DECADE` log-spaced step counts per decade
(:func:`uniform_steps`), each iterated to convergence, with two sweeps and
with one sweep per step (:data:`SWEEPS`), give dense work-precision curves;
:func:`cost_ratios` finds on them the step count whose error is that of
each adaptive run, runs it, and compares the evaluations of the two runs.
"""

import numpy as np
from . import require

pd = require("pandas", __name__)

from .. import problems as _problems
from .. import solve
from ..problems._problem import first_order
from ..problems.nonlinear import duffing, pendulum, rational

# atol as a fraction of rtol in the study (the solutions are of order 1).
ATOL_FRACTION = 1e-3
SCALE_SAMPLES = 2001

# The uniform runs: how each solves its step equation (solve's keywords).
# "iterated" is solve's default, sweeps until the change is below 1e-12.
SWEEPS = {"iterated": {}, "2 sweeps": dict(iterations=2), "1 sweep": dict(iterations=1)}
# Their step counts, log-spaced between these bounds, so that their final
# errors bracket those of the adaptive runs (iterated and one sweep) at
# rtol = 1e-3 ... 1e-8, except Kepler's at rtol 1e-7 and 1e-8, which would
# need about 7 and 23 million uniform steps.
UNIFORM_STEPS = {"harmonic oscillator": (2000, 1_600_000), "forced Duffing": (1500, 2_400_000),
                 "pendulum, 3 rad": (200, 1_200_000), "Kepler e = 0.9": (30_000, 3_000_000),
                 "rational, backwards": (3, 4000)}
STEPS_PER_DECADE = 8
# The comparisons of cost_ratios: (adaptive run, uniform run), as named in
# the method columns of runs() and uniform_runs().
PAIRS = (("spline", "uniform, iterated"), ("spline", "uniform, 2 sweeps"),
         ("spline", "uniform, 1 sweep"), ("spline, 1 sweep", "uniform, 1 sweep"))


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
    scale (``error_ratio``, ``error_ratio_yp``).  The methods: "spline"
    (adaptive knots, each step iterated to convergence), "spline, 1 sweep"
    (one sweep per step), and scipy's ``solve_ivp`` methods by name."""
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
            if method.startswith("spline"):
                sweeps = dict(iterations=1) if method == "spline, 1 sweep" else {}
                res = solve(problem.fun, problem.t_span, problem.y0, problem.yp0, rtol=rtol,
                            atol=atol, args=problem.args, **sweeps)
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


def uniform_steps(name, per_decade=STEPS_PER_DECADE):
    """The step counts of the uniform runs of problem ``name``: integers
    log-spaced between its :data:`UNIFORM_STEPS`, ``per_decade`` per
    factor of 10."""
    first, last = UNIFORM_STEPS[name]
    points = int(np.ceil(per_decade * np.log10(last / first))) + 1
    return np.unique(np.round(np.geomspace(first, last, points)).astype(int))


def _uniform(problem, n, sweeps):
    """(nfev, final error of y) of ``n`` uniform steps over the problem's
    span, the step equation solved as :data:`SWEEPS` [``sweeps``] says."""
    t0, tf = problem.t_span
    res = solve(problem.fun, problem.t_span, problem.y0, problem.yp0, abs(tf - t0) / n,
                t_eval=[tf], args=problem.args, **SWEEPS[sweeps])
    ref_y = problem.reference(np.array([tf]))[0][:, 0]
    return int(res.nfev), float(np.max(np.abs(res.y[:, -1] - ref_y)))


def uniform_runs(problem, steps, sweeps=tuple(SWEEPS)):
    """One row per number of uniform steps n (h = span / n) and way of
    solving the step equation (``sweeps``, keys of :data:`SWEEPS`): method
    ("uniform, iterated", "uniform, 2 sweeps", "uniform, 1 sweep"), n, nfev
    and the final error of y, with the scale of y (:func:`scales`): the
    work a uniform run needs for a given error."""
    scale_y = scales(problem)[0]
    rows = []
    for label in sweeps:
        for n in steps:
            nfev, error = _uniform(problem, n, label)
            rows.append(dict(method=f"uniform, {label}", n=int(n), nfev=nfev, error=error,
                             scale_y=scale_y))
    return rows


def slope(rtols, errors):
    """The least-squares slope of log(error) against log(rtol): 1 when the
    error follows the tolerance proportionally."""
    return float(np.polyfit(np.log(rtols), np.log(errors), 1)[0])


def bounds(table, rtols):
    """What rtol bounds, per problem, from the rows of :func:`runs` in
    ``table`` (a DataFrame with a ``problem`` column) at the tolerances
    ``rtols``: the largest final error of y and of y' over rtol times the
    solution's scale for the spline iterated to convergence, the largest of
    y with one sweep per step, and the slope of the iterated error against
    rtol (:func:`slope`).

    Returns
    -------
    pandas.DataFrame
        Indexed by problem, in the order of ``table``.
    """
    def one(g):
        iterated, swept = g[g.method == "spline"], g[g.method == "spline, 1 sweep"]
        return pd.Series({"largest error / (rtol scale), y": iterated.error_ratio.max(),
                          "y'": iterated.error_ratio_yp.max(),
                          "y, one sweep per step": swept.error_ratio.max(),
                          "slope of error against rtol": slope(rtols, iterated.error)})
    return table.groupby("problem", sort=False).apply(one, include_groups=False)


def converging_part(curve):
    """The uniform runs of one work-precision curve (rows of
    :func:`uniform_runs`) over which the error falls as the step shrinks:
    from the finest step back to the first coarser step whose error is not
    larger.  Coarser steps are not yet in the asymptotic range: their
    errors can pass through zero by chance (the pendulum's with 2 sweeps
    at 293 steps), which would make a coarse run look as accurate as a fine
    one.  Returns the rows by increasing n."""
    curve = curve.sort_values("n", ascending=False)
    error = curve.error.to_numpy()
    rising = np.r_[True, error[1:] > error[:-1]]
    keep = np.argmin(rising) if not rising.all() else rising.size
    return curve.iloc[:keep].iloc[::-1]


def cost_ratios(study, adaptive, uniform, pairs=PAIRS):
    """What adaptive knots cost against uniform steps reaching the same
    final error.  For each adaptive run and each comparison of ``pairs``:
    the step count n at which the uniform runs' error equals the adaptive
    run's (interpolated linearly in log(n) and log(error) between the two
    runs of :func:`converging_part` that bracket it), a uniform run of n
    steps (the matched run), and the adaptive run's evaluations over the
    matched run's.  The evaluations read off the uniform curve at the same
    error (interpolated in log(nfev)) are kept beside them: an iterated run
    needs a number of sweeps per step that changes with the step, so its
    work curve has kinks between the tested steps that the matched run
    sees and the interpolation does not.

    Parameters
    ----------
    study : dict
        The problems by name (:func:`problems`).
    adaptive, uniform : DataFrame
        Rows of :func:`runs` and of :func:`uniform_runs`, with a
        ``problem`` column.
    pairs : sequence of (str, str)
        (adaptive method, uniform method) to compare.

    Returns
    -------
    DataFrame
        ``problem``, ``adaptive`` and ``uniform`` (the two methods),
        ``rtol``, ``adaptive_nfev``, ``adaptive_error``, the matched run's
        ``n``, ``uniform_nfev`` and ``uniform_error``, ``interpolated_nfev``
        (all nan where the uniform runs do not bracket the adaptive run's
        error), and ``ratio`` = adaptive_nfev / uniform_nfev (above 1: the
        uniform step is cheaper).
    """
    from .diagnostics import loglog_interp
    rows = []
    for name in adaptive.problem.unique():
        for adaptive_method, uniform_method in pairs:
            runs_ = adaptive[(adaptive.problem == name) & (adaptive.method == adaptive_method)]
            curve = converging_part(uniform[(uniform.problem == name)
                                            & (uniform.method == uniform_method)])
            steps = loglog_interp(curve.error, curve.n, runs_.error)
            interpolated = loglog_interp(curve.error, curve.nfev, runs_.error)
            for run, n, nfev in zip(runs_.itertuples(), steps, interpolated):
                row = dict(problem=name, adaptive=adaptive_method, uniform=uniform_method,
                           rtol=run.rtol, adaptive_nfev=run.nfev, adaptive_error=run.error,
                           n=np.nan, uniform_nfev=np.nan, uniform_error=np.nan,
                           interpolated_nfev=nfev)
                if np.isfinite(n):
                    row["n"] = int(round(n))
                    row["uniform_nfev"], row["uniform_error"] = _uniform(
                        study[name], row["n"], uniform_method.split(", ")[1])
                rows.append(row)
    ratios = pd.DataFrame(rows)
    ratios["ratio"] = ratios.adaptive_nfev / ratios.uniform_nfev
    return ratios


def ratio_text(value):
    """A cost ratio as the notebook prints it: two decimals from 0.1 up
    (0.57, 5.06), two significant digits below (0.027, 0.020)."""
    return f"{value:.2f}" if value >= 0.1 else f"{value:#.2g}"


def ratio_ranges(ratios):
    """The least and the largest ratio of :func:`cost_ratios` per problem
    (rows) and comparison (columns, "adaptive / uniform"), as text "a to b"
    (:func:`ratio_text`), with the number of adaptive runs matched, "(4 of
    6)", where the uniform runs do not reach every adaptive run's error."""
    def text(group):
        found = group.ratio.dropna()
        note = f" ({len(found)} of {len(group)})" if len(found) < len(group) else ""
        return f"{ratio_text(found.min())} to {ratio_text(found.max())}{note}"
    table = ratios.groupby(["problem", "adaptive", "uniform"], sort=False).apply(
        text, include_groups=False).rename("range").reset_index()
    table["comparison"] = table.adaptive + " / " + table.uniform
    return table.pivot(index="problem", columns="comparison", values="range").reindex(
        index=ratios.problem.unique(), columns=table.comparison.unique()).rename_axis(
        index=None, columns=None)


# The graded knots of :func:`graded_runs`: the reference is sampled at this
# many times, y'''' taken by two central differences of F along it.
GRADING_SAMPLES = 100_001


def graded_knots(problem, exponent, n):
    """``n`` steps over the problem's span whose local density is
    proportional to |y''''|^exponent along the reference solution (the
    largest over components; exponent 0: uniform).  A local error of y'
    of h^3 |y''''| / 12 per step makes 1/3 the exponent that minimises
    the sum of the local errors for a given n (equidistribution), and 1/2
    the grading of knots whose every step's error per unit step is the
    same (:mod:`splinestep.controllers`)."""
    t = np.linspace(*problem.t_span, GRADING_SAMPLES)
    y, yp = problem.reference(t)
    ypp = np.array([problem.fun(tk, y[:, k], yp[:, k], *problem.args)
                    for k, tk in enumerate(t)]).reshape(t.size, -1).T
    fourth = np.max(np.abs(np.gradient(np.gradient(ypp, t, axis=1), t, axis=1)), axis=0)
    density = (fourth + np.finfo(float).tiny) ** exponent
    cumulative = np.concatenate([[0.0], np.cumsum(0.5 * (density[1:] + density[:-1])
                                                  * np.diff(t))])
    knots = np.interp(np.linspace(0.0, cumulative[-1], n + 1), cumulative, t)
    knots[0], knots[-1] = problem.t_span
    return knots


def graded_runs(problem, exponents, counts):
    """One row per exponent of :func:`graded_knots` and number of steps n:
    exponent, n, nfev and the final error of y (each step iterated to
    convergence), and that error over the uniform run's (exponent 0) of
    the same n: below 1, knots graded by the local error beat uniform
    ones at equal work."""
    t0, tf = problem.t_span
    ref_y = problem.reference(np.array([tf]))[0][:, 0]
    rows = []
    for exponent in exponents:
        for n in counts:
            knots = graded_knots(problem, exponent, n) if exponent else None
            res = solve(problem.fun, problem.t_span, problem.y0, problem.yp0,
                        None if exponent else abs(tf - t0) / n, knots=knots, t_eval=[tf],
                        args=problem.args)
            rows.append(dict(exponent=exponent, n=int(n), nfev=int(res.nfev),
                             error=float(np.max(np.abs(res.y[:, -1] - ref_y)))))
    table = pd.DataFrame(rows)
    uniform = table[table.exponent == 0].set_index("n").error
    table["error_over_uniform"] = table.error / table.n.map(uniform)
    return table
