"""Long runs on the Kepler problem: invariant errors sampled orbit by orbit,
the spline stepper's modified invariants, and the growth fitted to them
(notebooks 08 and 10).

A long run is sampled over whole orbits at a few orbit numbers (spaced
logarithmically), at every one of the method's steps in them
(``orbit_steps``); in each sampled orbit the largest error of each
invariant is kept.  ``fitted_growth`` then tells a
bounded error (exponent 0) from a drift (exponent 1), ``crossing`` finds
the orbit where a sampled error passes a level.  ``fixed_step_runs`` makes
the long fixed-step runs side by side, ``matching_tolerance`` picks
DOP853's tolerance, ``drift_summary`` and ``reproducible_round`` print
what reproduces on another CPU, and ``accumulated_estimate`` reads the
step-size check's verdict on a long run.
"""

import re
from concurrent.futures import ThreadPoolExecutor

import numpy as np
from . import require

pd = require("pandas", __name__)

from ..problems import kepler
from ..problems import first_order

# How far an evaluation count of scipy's adaptive DOP853 may move from one
# CPU to another: an accept/reject decision flips with the rounding of its
# error estimate, and the step sequence changes from there on.  Measured on
# the 1,000-orbit run of notebook 08: 194.99 evaluations per orbit on an AMD
# EPYC, 195.61 on an Intel Xeon, and 195.55 there with atol 1e-6 written
# instead of 1e-4 * 1e-2, one rounding unit away; the data checks allow 5 %
# (tests/reproduction.py, kind "adaptive").
ADAPTIVE_SPREAD = 0.05


def orbit_steps(orbits, step, period):
    """Every step of a fixed-step run that falls in the sampled orbits.

    Parameters
    ----------
    orbits : array_like of int
        Zero-based numbers of the sampled orbits (orbit k covers
        [k T, (k + 1) T)).
    step : float
        The run's step h.
    period : float
        The orbit's period T.

    Returns
    -------
    ndarray
        The increasing multiples n h with floor(n h / T) in ``orbits``:
        the run's output times, so that the largest error in a sampled
        orbit is taken over all of its steps, not over a few samples that
        may miss the periapsis.
    """
    orbits = np.asarray(orbits, dtype=np.int64)
    counts = [np.arange(np.floor(k * period / step), np.ceil((k + 1) * period / step) + 1)
              for k in orbits]
    t = step * np.concatenate(counts)
    return np.unique(t[np.isin(np.floor(t / period).astype(np.int64), orbits)])


def modified_energy(y, yp, mu, h):
    """The spline stepper's modified energy H~ on the Kepler problem, in its
    own variables (notebook 05, section 4):

        H~ = H + h^2 (|grad V|^2 / 24 + V_qq(v, v) / 12),

    with |grad V|^2 = mu^2 / r^4 and V_qq(v, v) = mu (|v|^2 / r^3 -
    3 (q.v)^2 / r^5).  ``y`` and ``yp`` have shape (2, n)."""
    y, yp = np.asarray(y, dtype=float), np.asarray(yp, dtype=float)
    r = np.hypot(*y)
    vqq = mu * (np.sum(yp * yp, axis=0) / r ** 3 - 3 * np.sum(y * yp, axis=0) ** 2 / r ** 5)
    return kepler.energy(mu)(y, yp) + h * h * (mu ** 2 / r ** 4 / 24 + vqq / 12)


def modified_momentum(y, yp, mu, h):
    """The spline stepper's conserved angular momentum on the Kepler
    problem, (1 + h^2 mu / (6 r^3)) q x v (Verlet's q x v in the spline's
    variables)."""
    r = np.hypot(*np.asarray(y, dtype=float))
    return (1 + h * h * mu / (6 * r ** 3)) * kepler.angular_momentum(y, yp)


def invariants_per_orbit(method, t, y, yp, y0, yp0, mu, period, orbits, h=None):
    """Largest invariant errors in each sampled orbit of a Kepler run.

    Parameters
    ----------
    method : str
        The name written in the table's ``method`` column.
    t, y, yp : ndarray
        The run at its output times: shapes (n,), (2, n), (2, n).
    y0, yp0 : array_like, shape (2,)
        The initial state, whose invariants are the reference.
    mu : float
        The gravitational parameter.
    period : float
        The orbit's period T.
    orbits : array_like of int
        Zero-based numbers of the orbits kept; samples in other orbits are
        dropped.
    h : float, optional
        The spline stepper's step: given, the errors of its modified energy
        and modified angular momentum are added.

    Returns
    -------
    DataFrame
        One row per sampled orbit: ``method``, ``orbit`` (one-based) and the
        largest ``energy_error`` and ``momentum_error`` in it (and
        ``modified_energy_error``, ``modified_momentum_error`` with ``h``).
    """
    y0, yp0 = np.asarray(y0, dtype=float)[:, None], np.asarray(yp0, dtype=float)[:, None]
    orbit = np.floor(t / period).astype(int)
    keep = np.isin(orbit, orbits)
    y, yp, orbit = y[:, keep], yp[:, keep], orbit[keep]
    energy = kepler.energy(mu)
    rows = dict(energy_error=np.abs(energy(y, yp) - energy(y0, yp0)[0]),
                momentum_error=np.abs(kepler.angular_momentum(y, yp)
                                      - kepler.angular_momentum(y0, yp0)[0]))
    if h is not None:
        rows["modified_energy_error"] = np.abs(modified_energy(y, yp, mu, h)
                                               - modified_energy(y0, yp0, mu, h)[0])
        rows["modified_momentum_error"] = np.abs(modified_momentum(y, yp, mu, h)
                                                 - modified_momentum(y0, yp0, mu, h)[0])
    out = pd.DataFrame(rows).groupby(orbit + 1).max()
    return out.rename_axis("orbit").reset_index().assign(method=method)[
        ["method", "orbit", *rows]]


def fitted_growth(orbit, error, from_orbit):
    """How an error grows with the orbit number.

    Parameters
    ----------
    orbit, error : array_like
        Sampled orbit numbers (one-based) and the error in each.
    from_orbit : int
        The power law is fitted to the orbits from this one on.

    Returns
    -------
    exponent : float
        b in error ~ orbit^b over orbits >= ``from_orbit`` (0: bounded,
        1: linear drift).  An error that starts at a and drifts by c per
        orbit has a local log-log slope c k / (a + c k), below 1 until c k
        dominates a: hence a fit that starts late.
    drift : float
        c of the line a + c (orbit - 1), fitted by least squares to every
        sampled orbit.
    start : float
        a of that line.
    """
    orbit, error = np.asarray(orbit, dtype=float), np.asarray(error, dtype=float)
    tail = orbit >= from_orbit
    exponent = np.polyfit(np.log(orbit[tail]), np.log(error[tail]), 1)[0]
    drift, start = np.polyfit(orbit - 1, error, 1)
    return exponent, drift, start


def drift_table(errors, evaluations_per_orbit, from_orbit, conserved=1e-9):
    """One row per method of ``invariants_per_orbit`` tables: the fitted
    growth of its energy and angular-momentum errors and their final values.

    An angular-momentum error that stays below ``conserved`` is conserved
    to rounding: its exponent and drift are NaN (no growth to fit).
    """
    rows = []
    for method, group in errors.groupby("method", sort=False):
        e_exp, e_rate, e_start = fitted_growth(group.orbit, group.energy_error, from_orbit)
        m_exp, m_rate, _ = fitted_growth(group.orbit, group.momentum_error, from_orbit)
        if group.momentum_error.max() < conserved:
            m_exp = m_rate = np.nan
        rows.append(dict(method=method, orbits=int(group.orbit.max()),
                         evaluations_per_orbit=evaluations_per_orbit[method],
                         energy_exponent=e_exp, energy_drift_per_orbit=e_rate,
                         energy_error_start=e_start,
                         final_energy_error=group.energy_error.iloc[-1],
                         momentum_exponent=m_exp, momentum_drift_per_orbit=m_rate,
                         final_momentum_error=group.momentum_error.iloc[-1]))
    return pd.DataFrame(rows)


def matching_tolerance(problem, t_end, target, rtols, samples=401):
    """The rtol at which scipy's DOP853 (atol = rtol / 100) has, over
    [t0, t_end], the largest position error closest to ``target`` (on a log
    scale), for a run of DOP853 beside another method of that error.

    Returns
    -------
    rtol : float
        The chosen tolerance, one of ``rtols``.
    ratio : float
        DOP853's error over ``target`` at that tolerance.
    """
    from scipy.integrate import solve_ivp

    t = np.linspace(problem.t_span[0], t_end, samples)
    exact = problem.reference(t)[0]
    rhs = first_order(problem.fun, problem.args, problem.y0.size)
    ratios = []
    for rtol in rtols:
        sol = solve_ivp(rhs, (t[0], t[-1]), np.r_[problem.y0, problem.yp0], method="DOP853",
                        rtol=rtol, atol=rtol * 1e-2, t_eval=t)
        ratios.append(np.max(np.abs(sol.y[:problem.y0.size] - exact)) / target)
    best = int(np.argmin(np.abs(np.log(ratios))))
    return rtols[best], ratios[best]


def fixed_step_runs(problem, t_end, h, t_eval, threads=2):
    """The long fixed-step runs of notebook 08, side by side in threads.

    Parameters
    ----------
    problem : splinestep.problems.Problem
        The problem (its ``fun``, ``args``, ``y0``, ``yp0``; the run starts
        at t = 0).
    t_end : float
        The end of the runs.
    h : float
        The step of all three runs.
    t_eval : array_like
        The output times, multiples of ``h`` (see ``orbit_steps``).
    threads : int, optional
        Threads to run them in.  The compiled loops release the GIL, so the
        runs go side by side; each result is, bit for bit, that of the same
        run made alone.

    Returns
    -------
    dict
        ``"spline"`` (iterated to convergence), ``"spline, 1 sweep"`` (one
        fixed-point sweep per step) and ``"Verlet"``: the results of
        ``splinestep.solve`` and ``splinestep.verlet``.
    """
    from .. import solve, verlet

    runs = {"spline": (solve, {}), "spline, 1 sweep": (solve, dict(iterations=1)),
            "Verlet": (verlet, {})}
    with ThreadPoolExecutor(threads) as pool:
        jobs = {name: pool.submit(method, problem.fun, (0.0, t_end), problem.y0, problem.yp0,
                                  h, args=problem.args, t_eval=t_eval, **options)
                for name, (method, options) in runs.items()}
        return {name: job.result() for name, job in jobs.items()}


def reproducible_round(value, spread=0.0, digits=2):
    """``value`` to the digits that reproduce when it may move by a
    relative ``spread`` (on another CPU, say).

    Parameters
    ----------
    value : float
        A positive number.
    spread : float, optional
        How far, relative to ``value``, another computation of it may lie;
        0 for a number that reproduces to all its digits.
    digits : int, optional
        The most significant digits to keep.

    Returns
    -------
    float
        ``value`` rounded to the most significant digits, at most
        ``digits`` and at least one, at which every number within
        ``spread`` of it rounds alike.  DOP853's 194.99 evaluations per
        orbit, 195.61 on another CPU, are 190 and 200 at two digits; with
        ``spread = ADAPTIVE_SPREAD`` both are 200.  (Near a boundary of
        one digit, such as 150 at a 5 % spread, one digit is returned
        although it does not reproduce.)
    """
    def rounded(v, d):
        return float(f"{v:.{d - 1}e}")

    for d in range(digits, 1, -1):
        if rounded(value * (1 - spread), d) == rounded(value * (1 + spread), d):
            return rounded(value, d)
    return rounded(value, 1)


def _decade(value):
    """``value`` as its nearest power of ten, "~1e-02"."""
    return f"~{10.0 ** np.round(np.log10(value)):.0e}"


def _signed(value, decimals):
    """``value`` with a sign and ``decimals`` decimals, never "-0.00"."""
    text = f"{value:+.{decimals}f}"
    return text.replace("-", "+") if float(text) == 0 else text


def drift_summary(drift, rough="DOP853"):
    """The table of ``drift_table`` to the digits that reproduce.

    Parameters
    ----------
    drift : DataFrame
        A table of ``drift_table``.
    rough : str, optional
        Methods whose name starts with it are adaptive runs (scipy's
        DOP853), whose step sequence, and with it the size of their errors,
        changes from one CPU to another by up to a few tens of per cent
        over 1,000 orbits (tests/reproduction.py, kind "adaptive-long"):
        their exponents are given to one decimal and their errors as the
        nearest power of ten.  Other rows: exponents to two decimals,
        energy errors to two digits, momentum errors to one.

    Returns
    -------
    DataFrame of str
        Indexed by method: the orbits run, the fitted growth exponent b of
        the energy error (error ~ orbit^b), its final value, and the same
        for the angular momentum ("conserved" where ``drift_table`` found
        it conserved to rounding).
    """
    rows = {}
    for row in drift.itertuples():
        is_rough = row.method.startswith(rough)
        exponent = (lambda v: _signed(v, 1 if is_rough else 2))
        error = (lambda v, d: _decade(v) if is_rough else f"{v:.{d - 1}e}")
        rows[row.method] = {
            "orbits": f"{row.orbits:,}",
            "energy error ~ orbit^b: b": exponent(row.energy_exponent),
            "final energy error": error(row.final_energy_error, 2),
            "angular momentum: b": (exponent(row.momentum_exponent)
                                    if np.isfinite(row.momentum_exponent) else "conserved"),
            "final momentum error": error(row.final_momentum_error, 1)}
    return pd.DataFrame.from_dict(rows, orient="index").rename_axis("method")


def crossing(orbit, error, level):
    """The orbit where a sampled error first exceeds ``level``.

    Parameters
    ----------
    orbit, error : array_like
        Sampled orbit numbers, increasing, and the error in each.
    level : float
        The level.

    Returns
    -------
    float
        The orbit where the error, interpolated linearly in log orbit and
        log error between the last sample at or below ``level`` and the
        first above it, reaches ``level``: the first sampled orbit if the
        error is above from the start, NaN if it never is.  Exact for an
        error that grows as a power of the orbit between the two samples;
        otherwise known to within their spacing only.
    """
    orbit, error = np.asarray(orbit, dtype=float), np.asarray(error, dtype=float)
    above = np.flatnonzero(error > level)
    if above.size == 0:
        return np.nan
    k = above[0]
    if k == 0:
        return orbit[0]
    slope = np.log(level / error[k - 1]) / np.log(error[k] / error[k - 1])
    return float(np.exp(np.log(orbit[k - 1]) + slope * np.log(orbit[k] / orbit[k - 1])))


_SUM = re.compile(r"local errors sum to (\S+) in y and (\S+) in y' over the run, more than "
                  r"(\S+) of the solution's size \(max \|y\| = (\S+), max \|y'\| = ([^)]+)\)")


def accumulated_estimate(result):
    """The step-size check's summed local-error estimates, when they flag
    the run (``splinestep.check``, the second finding).

    Parameters
    ----------
    result : splinestep result
        A fixed-step run of the spline stepper.

    Returns
    -------
    dict or None
        ``sum_y``, ``sum_yp`` (the estimates summed over the run),
        ``fraction`` (the check's threshold, 0.3 of the solution's size),
        ``y_scale``, ``yp_scale`` (the run's largest |y| and |y'|), as the
        run's ``message`` states them (two or three significant digits);
        None if the check did not flag the sum.  For a composed step
        (``order`` 4 or 6) the estimates are those of one cubic step of
        the composed step's size, from the jumps of the mean third
        derivative at its knots: the local errors of the report's method,
        not of the composition.
    """
    match = _SUM.search(result.message)
    if match is None:
        return None
    names = ("sum_y", "sum_yp", "fraction", "y_scale", "yp_scale")
    return dict(zip(names, (float(v) for v in match.groups())))
