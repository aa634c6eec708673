"""Measurements of adaptive knots: the true local error of each step
(notebook 07) and, over long runs, the energy error orbit by orbit
(notebook 08).  Their cost against uniform steps is measured in
:mod:`splinestep.analysis.tolerance`.
"""

import numpy as np
from . import require

pd = require("pandas", __name__)

from .. import solve


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


def first_orbit_above(errors, level):
    """The first orbit (counted from 1) at which ``errors`` (one value per
    orbit) exceeds ``level`` (a number or one value per orbit), or 0 if it
    never does."""
    above = np.asarray(errors) > np.asarray(level)
    return int(np.argmax(above)) + 1 if above.any() else 0


def orbits_changing_sign(signed):
    """The runs of consecutive orbits in which ``signed`` (from
    ``energy_per_orbit``) takes both signs, as strings "first-last"."""
    both = np.flatnonzero((signed.max() > 0) & (signed.min() < 0)) + 1
    runs = np.split(both, np.flatnonzero(np.diff(both) > 1) + 1)
    return [f"{r[0]}-{r[-1]}" for r in runs if r.size]


def variable_step_runs(problem, orbits, period, rtol, atol, eps_values, step_size_control):
    """One Kepler problem over ``orbits`` orbits of length ``period``, run
    with error-controlled knots at ``rtol``, ``atol`` and with
    time-reversible steps (:func:`splinestep.solve_reversible`, the control
    ``step_size_control``) at each of ``eps_values``.

    Returns
    -------
    runs : dict
        {label: result}, labels "adaptive knots, rtol R" and "reversible
        steps, eps E".
    by_orbit : dict
        {label: :func:`energy_per_orbit` of the run}.
    table : pandas.DataFrame
        One row per run and orbit: method, orbit, energy_error (the largest
        |H - H0| at the run's own knots in that orbit), nfev_per_orbit.
    """
    from .. import solve_reversible
    energy = problem.invariants["energy"]
    e0 = energy(problem.y0[:, None], problem.yp0[:, None])[0]
    runs = {f"adaptive knots, rtol {rtol:g}": problem.solve(h="adaptive", rtol=rtol, atol=atol)}
    for eps in eps_values:
        runs[f"reversible steps, eps {eps:g}"] = solve_reversible(
            problem.fun, problem.t_span, problem.y0, problem.yp0, eps, step_size_control,
            args=problem.args)
    by_orbit = {label: energy_per_orbit(res, energy, e0, period, orbits)
                for label, res in runs.items()}
    table = pd.concat([pd.DataFrame(dict(
        method=label, orbit=np.arange(1, orbits + 1),
        energy_error=by_orbit[label].apply(lambda g: g.abs().max()).to_numpy(),
        nfev_per_orbit=res.nfev / orbits)) for label, res in runs.items()], ignore_index=True)
    return runs, by_orbit, table


def estimates_along(problem, run):
    """Each step of an adaptive ``run`` of ``problem`` but the first (the
    jump estimate needs the step before): its start t, size h, radius r
    (for a planar orbit), the controller's estimate of its local error
    (:func:`splinestep.controllers.jump_estimates`) and its true local
    error (:func:`true_local_errors`), as a DataFrame."""
    from ..controllers import jump_estimates
    estimate, _ = jump_estimates(run.t, run.ypp)
    steps = np.arange(1, run.t.size - 1)
    return pd.DataFrame(dict(t=run.t[steps], h=np.diff(run.t)[steps],
                             r=np.hypot(*run.y[:, steps]), estimated=estimate[steps - 1],
                             true=true_local_errors(problem, run.t[1:])))
