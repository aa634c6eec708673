"""Long runs on the Kepler problem: invariant errors sampled orbit by orbit,
the spline stepper's modified invariants, and the growth fitted to them
(notebook 08).

A long run is sampled over whole orbits at a few orbit numbers (spaced
logarithmically), at the method's own steps; in each sampled orbit the
largest error of each invariant is kept.  ``fitted_growth`` then tells a
bounded error (exponent 0) from a drift (exponent 1).
"""

import numpy as np
import pandas as pd

from ..problems import kepler
from ..problems import first_order


def orbit_sample_times(orbits, samples, period):
    """Times spread over the sampled orbits, half a sample from each end.

    Parameters
    ----------
    orbits : array_like of int
        Zero-based numbers of the sampled orbits (orbit k covers
        [k T, (k + 1) T)).
    samples : int
        Samples per orbit.
    period : float
        The orbit's period T.

    Returns
    -------
    ndarray, shape (len(orbits) * samples,)
        Increasing times; move them to a method's steps with ``at_steps``.
    """
    orbits = np.asarray(orbits)
    return ((orbits[:, None] + (np.arange(samples)[None, :] + 0.5) / samples)
            * period).ravel()


def at_steps(t, step):
    """Each time moved to the nearest multiple of ``step`` (a step of the
    method measured), so that the method is measured where it computed."""
    return step * np.round(np.asarray(t) / step)


def modified_energy(y, yp, mu, h):
    """The spline stepper's modified energy H~ on the Kepler problem, in its
    own variables (notebook 06, section 4):

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
