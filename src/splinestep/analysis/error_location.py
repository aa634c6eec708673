"""Where along an orbit a run's error is made: notebook 02's measurement
of the report's Sec. 5 claim that the cannonball's error "corresponds with
the curvature".

:func:`along_the_orbit` compares, over the first orbit of a closed Kepler
orbit, the rate at which the energy error changes with three candidates
for "curvature": the path's curvature, the acceleration mu / r^2 (the
solution's second derivative) and |x''''|, which sets the method's local
error, each on the arc around periapsis (r < inner) against the arc around
apoapsis (r > outer).
"""

import numpy as np
from . import require

pd = require("pandas", __name__)

from .. import problems

# The quantities of :func:`along_the_orbit`'s table, with what each means.
QUANTITIES = {
    "time_share_r_lt_1_5": "share of the time at r < 1.5",
    "energy_variation_share_r_lt_1_5": "share of the energy error's variation at r < 1.5",
    "curvature_ratio_arcs": "path curvature, periapsis arc / apoapsis arc",
    "min_curvature": "smallest path curvature",
    "r_min_curvature": "r where the path curvature is smallest",
    "acceleration_ratio_apsides": "acceleration, periapsis / apoapsis",
    "acceleration_ratio_arcs": "acceleration, periapsis arc / apoapsis arc",
    "x4_ratio_arcs": "|x''''|, periapsis arc / apoapsis arc",
    "energy_rate_ratio_arcs": "energy-error rate, periapsis arc / apoapsis arc",
    "log_correlation_rate_curvature": "log-correlation: rate and path curvature",
    "log_correlation_rate_acceleration": "log-correlation: rate and acceleration",
    "log_correlation_rate_x4": "log-correlation: rate and |x''''|",
    "energy_error_apoapsis": "energy error at apoapsis",
    "energy_error_next_periapsis": "energy error at the next periapsis",
    "max_position_error": "largest position error",
    "t_max_position_error": "t of the largest position error",
    "r_max_position_error": "r of the largest position error",
}


def along_the_orbit(res, mu, inner=1.5, outer=4.5):
    """The error of the run ``res`` (a cannonball solution with knots
    ``res.t``, launched as :func:`splinestep.problems.cannonball`) along the
    closed orbit of ``mu``.

    Returns
    -------
    table : pandas.DataFrame
        Columns ``quantity`` (the keys of :data:`QUANTITIES`) and ``value``;
        ratios are largest values on the periapsis arc (r < ``inner``) over
        the apoapsis arc (r > ``outer``), over the first orbit; the shares
        are over the whole run.
    curves : dict
        The sampled curves the notebook plots: ``t``, ``r``, ``curvature``,
        ``acceleration`` (|x''|), ``x4`` (|x''''|) at the knots; ``middle``
        and ``rate`` (|change of the energy error| / step) on the steps;
        the masks ``one`` (knots of the first orbit) and ``first`` (steps of
        the first orbit); ``apoapsis_arc`` (the knots ending the steps of
        the first orbit's apoapsis arc, the denominators of the ratios).
    """
    problem = problems.cannonball(mu)
    elements = problems.orbit_elements(mu)
    period = elements["period"]
    t = res.t
    x_exact, v_exact = problem.exact(t)
    acceleration, _, fourth = problems.acceleration_derivatives(x_exact, v_exact, mu)
    curvature = problems.path_curvature(v_exact, acceleration)
    x2, x4, r = np.hypot(*acceleration), np.hypot(*fourth), np.hypot(*x_exact)
    energy_error = problem.invariants["energy"](res.y, res.yp) - elements["energy"]
    rate = np.abs(np.diff(energy_error)) / np.diff(t)   # per unit time, on each step
    middle = 0.5 * (t[1:] + t[:-1])
    first, one = middle < period, t <= period
    apoapsis = np.argmin(np.abs(t - period / 2))
    r_mid = 0.5 * (r[1:] + r[:-1])
    near = r_mid < inner
    x_err = np.hypot(*(res.y - x_exact))
    peak = np.argmax(x_err)
    peri_arc, apo_arc = first & (r_mid < inner), first & (r_mid > outer)

    def arc_ratio(values):
        values = values[1:] if values.size == r.size else values
        return values[peri_arc].max() / values[apo_arc].max()

    def log_corr(values):
        return np.corrcoef(np.log(values[1:][first]), np.log(rate[first]))[0, 1]

    change = np.abs(np.diff(energy_error))
    values = [near.mean(), change[near].sum() / change.sum(),
              arc_ratio(curvature), curvature[one].min(),
              r[np.argmin(np.where(one, curvature, np.inf))],
              x2[one].max() / x2[one].min(), arc_ratio(x2), arc_ratio(x4), arc_ratio(rate),
              log_corr(curvature), log_corr(x2), log_corr(x4), abs(energy_error[apoapsis]),
              abs(energy_error[np.argmin(np.abs(t - period))]),
              x_err[peak], t[peak], r[peak]]
    table = pd.DataFrame({"quantity": list(QUANTITIES), "value": values})
    curves = dict(t=t, r=r, curvature=curvature, acceleration=x2, x4=x4, middle=middle,
                  rate=rate, one=one, first=first, apoapsis_arc=np.r_[False, apo_arc])
    return table, curves


def candidates(location):
    """The three candidates for "curvature" beside the energy error's rate:
    for each, its largest value on the periapsis arc over its largest on
    the apoapsis arc, and the correlation of its logarithm with the
    logarithm of the rate (``location`` from :func:`along_the_orbit`)."""
    value = location.set_index("quantity").value
    names = {"curvature": "path curvature κ", "acceleration": "acceleration |x''| = μ/r²",
             "x4": "|x''''|, which sets the local error"}
    rows = {label: (value[f"{name}_ratio_arcs"], value[f"log_correlation_rate_{name}"])
            for name, label in names.items()}
    rows["energy-error rate"] = (value["energy_rate_ratio_arcs"], np.nan)
    return pd.DataFrame.from_dict(rows, orient="index", columns=[
        "periapsis arc / apoapsis arc", "log-correlation with the rate"])


def closed_form_ratios(mu, outer=4.5):
    """The acceleration ratios of :func:`along_the_orbit` in closed form,
    each with the relative tolerance the knots allow.

    The acceleration is mu / r^2, so the ratio between the apsides is
    ((1 + e) / (1 - e))^2, and between the arcs' largest values (at
    periapsis and at r = ``outer``) (outer / r_peri)^2.  For the cannonball
    at mu = 0.6, knots every 0.01 miss an apsis by at most
    |r''| 0.005^2 / 2 <= 5e-6 of r (|r''| <= 0.4), and pass r = 4.5 by at most
    |r'| 0.01 < 1.4e-3 (|r'| = 0.13 there): the ratios within 1e-4 and 1e-3.
    """
    elements = problems.orbit_elements(mu)
    e = elements["eccentricity"]
    r_peri = elements["a"] * (1 - e)
    return {"acceleration_ratio_apsides": (((1 + e) / (1 - e)) ** 2, 1e-4),
            "acceleration_ratio_arcs": ((outer / r_peri) ** 2, 1e-3)}


def error_histories(runs):
    """Energy, angular-momentum and position errors along cannonball runs,
    each against the exact flow.

    Parameters
    ----------
    runs : dict
        ``{mu: {method: result}}``.

    Returns
    -------
    DataFrame
        ``mu``, ``method``, ``t``, ``r`` and the absolute ``energy_error``,
        ``momentum_error`` and ``position_error`` at every output.
    """
    frames = []
    for mu, by_method in runs.items():
        problem = problems.cannonball(mu)
        for method, res in by_method.items():
            exact, _ = problem.exact(res.t)
            energy = problem.invariants["energy"](res.y, res.yp)
            momentum = problem.invariants["angular momentum"](res.y, res.yp)
            frames.append(pd.DataFrame({
                "mu": mu, "method": method, "t": res.t,
                "r": np.hypot(res.y[0], res.y[1]),
                "energy_error": np.abs(energy - energy[0]),
                "momentum_error": np.abs(momentum - momentum[0]),
                "position_error": np.hypot(*(res.y - exact))}))
    return pd.concat(frames, ignore_index=True)


def trajectories(runs, stride=10):
    """The cannonball runs' positions beside the exact ones, every
    ``stride``-th output (the data behind notebook 02's Figure 1a).

    Parameters
    ----------
    runs : dict
        ``{mu: {"spline": result, "rk4": result}}`` on the same outputs.

    Returns
    -------
    DataFrame
        ``mu``, ``t``, ``x_spline``, ``y_spline``, ``x_rk4``, ``y_rk4``,
        ``x_exact``, ``y_exact``.
    """
    frames = []
    for mu, by_method in runs.items():
        t = by_method["spline"].t
        exact, _ = problems.cannonball(mu).exact(t)
        columns = {"mu": mu, "t": t}
        for name, y in (("spline", by_method["spline"].y), ("rk4", by_method["rk4"].y),
                        ("exact", exact)):
            columns[f"x_{name}"], columns[f"y_{name}"] = y[0], y[1]
        frames.append(pd.DataFrame(columns).iloc[::stride])
    return pd.concat(frames)


def largest_separation(runs):
    """Per orbit, the largest distance between a run and the exact orbit,
    as a share of the orbit's larger extent in x or y (the width of its
    panel in Figure 1a)."""
    shares = {}
    for mu, by_method in runs.items():
        problem = problems.cannonball(mu)
        worst = 0.0
        for res in by_method.values():
            exact, _ = problem.exact(res.t)
            worst = max(worst, np.max(np.hypot(*(res.y - exact))))
        exact, _ = problem.exact(by_method["spline"].t)
        shares[mu] = worst / max(np.ptp(exact[0]), np.ptp(exact[1]))
    return shares
