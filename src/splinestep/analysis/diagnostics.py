"""Measurements of a computed solution that the notebooks report: the
amplitude factor and rotation of a step on the oscillator, and whether an
error stays bounded or grows along a run.

Each metric can say both things: the amplitude factor is below 1 for a
damped method and above 1 for an unstable one; the growth ratio is near 1
for a bounded error and near the number of windows for one that grows
linearly (tests/test_diagnostics.py shows both sides).
"""

import numpy as np


def recurrence_fit(y):
    """Amplitude factor and rotation per step of a sampled oscillation.

    A linear one-step method applied to y'' = -omega^2 y maps (y_n, y'_n)
    by a fixed 2x2 matrix with eigenvalues rho exp(+-i theta), so its
    samples satisfy y_{n+1} = 2 rho cos(theta) y_n - rho^2 y_{n-1}.  The two
    coefficients are fitted by least squares over the whole sequence.

    Parameters
    ----------
    y : array_like, shape (n,)
        Samples y_0, ..., y_{n-1} at the steps (n >= 4).

    Returns
    -------
    rho : float
        Amplitude factor per step, the larger modulus of the two roots of
        z^2 - 2 rho cos(theta) z + rho^2 (1: undamped, < 1: damped, > 1:
        growing; beyond a stability limit the roots are real and rho is the
        larger).
    theta : float
        Rotation per step, in [0, pi] (0 or pi when the roots are real); the
        numerical period is 2 pi h / theta.
    """
    y = np.asarray(y, dtype=float)
    if y.ndim != 1 or y.size < 4:
        raise ValueError("y must be a 1-D array of at least 4 samples")
    basis = np.stack([y[1:-1], -y[:-2]], axis=1)
    (two_c, product), *_ = np.linalg.lstsq(basis, y[2:], rcond=None)
    roots = np.roots([1.0, -two_c, product])
    largest = roots[np.argmax(np.abs(roots))]
    return float(np.abs(largest)), float(abs(np.angle(largest)))


def window_maxima(t, error, windows=8):
    """Largest ``error`` in each of ``windows`` equal parts of the run."""
    t = np.asarray(t, dtype=float)
    error = np.abs(np.asarray(error, dtype=float))
    edges = np.linspace(t[0], t[-1], windows + 1)
    index = np.clip(np.searchsorted(edges, t, side="right") - 1, 0, windows - 1)
    return np.array([error[index == k].max() for k in range(windows)])


def growth_ratio(t, error, windows=8):
    """Largest error in the last of ``windows`` equal parts of the run over
    the largest in the first: about 1 for an error that stays bounded once
    it has reached its level, about ``windows`` for one that grows linearly
    from zero."""
    maxima = window_maxima(t, error, windows)
    return float(maxima[-1] / maxima[0])


def loglog_interp(x, y, x_new):
    """Interpolate the curve (x, y) linearly in log x and log y at
    ``x_new``: nan outside the range of ``x`` (no extrapolation).  ``x``
    need not be sorted; the points are sorted by x first."""
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    order = np.argsort(x)
    log_new = np.log(np.asarray(x_new, dtype=float))
    out = np.exp(np.interp(log_new, np.log(x[order]), np.log(y[order])))
    return np.where((log_new < np.log(x.min())) | (log_new > np.log(x.max())), np.nan, out)


def work_to_reach(nfev, error, target):
    """Evaluations needed for ``error`` = ``target`` on a work-precision
    curve, interpolated log-log between the two measured points that
    bracket it; nan when no two points bracket the target."""
    nfev = np.asarray(nfev, dtype=float)
    error = np.asarray(error, dtype=float)
    order = np.argsort(nfev)
    nfev, error = nfev[order], error[order]
    for k in range(nfev.size - 1):
        (e0, e1), (n0, n1) = error[k:k + 2], nfev[k:k + 2]
        if min(e0, e1) <= target <= max(e0, e1) and e0 != e1:
            w = np.log(target / e0) / np.log(e1 / e0)
            return float(np.exp(np.log(n0) + w * np.log(n1 / n0)))
    return float("nan")


def work_precision(problem, t_eval, exact, steps, runs, tolerances=(), scipy_methods=()):
    """Evaluations of F against the largest position error at ``t_eval``
    (``exact``: the exact positions there), for each fixed-step run at each
    of ``steps`` and for scipy's adaptive codes at each of ``tolerances``.

    Parameters
    ----------
    problem : splinestep.problems.Problem
        Its ``fun``, ``args``, ``t_span``, ``y0`` and ``yp0`` set up scipy's
        first-order system.
    t_eval, exact : array_like
        The times compared and the exact positions there, shape (m, k).
    steps : sequence of float
    runs : dict
        {label: callable(h) returning an OdeResult with ``nfev`` and ``y``
        at ``t_eval``}, run in that order at each step.
    tolerances : sequence of float
        rtol of scipy's runs (atol = rtol / 100).
    scipy_methods : sequence of str
        ``solve_ivp`` methods, labelled "scipy NAME".

    Returns
    -------
    list of dict
        One per run, in that order (each step's runs, then each scipy
        method's tolerances): method, setting (h or rtol), nfev, max_error.
    """
    from scipy.integrate import solve_ivp
    from ..problems import first_order
    exact = np.asarray(exact)
    rows = []
    for h in steps:
        for label, run in runs.items():
            res = run(h)
            rows.append(dict(method=label, setting=h, nfev=res.nfev,
                             max_error=np.max(np.abs(res.y - exact))))
    m = problem.y0.size
    for method in scipy_methods:
        for tol in tolerances:
            sol = solve_ivp(first_order(problem.fun, problem.args, m), problem.t_span,
                            np.r_[problem.y0, problem.yp0], method=method, rtol=tol,
                            atol=tol * 1e-2, t_eval=t_eval)
            rows.append(dict(method=f"scipy {method}", setting=tol, nfev=sol.nfev,
                             max_error=np.max(np.abs(sol.y[:m] - exact))))
    return rows


def reach_table(curves, methods, targets):
    """For each method and target error, :func:`work_to_reach` on its
    curve, with the curve's fewest and most evaluations and the errors
    there (why a target is not read off: below the fewest's error already,
    or not reached by the most's).

    Parameters
    ----------
    curves : dict
        {method: (evaluations, errors)} of a work-precision comparison.
    methods, targets : sequence
        The rows, in order.

    Returns
    -------
    list of dict
        One per method and target: method, target, nfev_interpolated,
        fewest_tested, error_at_fewest, most_tested, error_at_most.
    """
    rows = []
    for method in methods:
        nfev, error = (np.asarray(v) for v in curves[method])
        for target in targets:
            rows.append(dict(method=method, target=target,
                             nfev_interpolated=work_to_reach(nfev, error, target),
                             fewest_tested=nfev.min(), error_at_fewest=error[np.argmin(nfev)],
                             most_tested=nfev.max(), error_at_most=error[np.argmax(nfev)]))
    return rows


def ratio_range(reference, other):
    """Smallest and largest ratio other_error / reference_error at equal
    work, over the evaluation counts both curves cover (interpolated
    log-log at 200 counts).  Each argument is a pair (nfev, error)."""
    lo = max(np.min(reference[0]), np.min(other[0]))
    hi = min(np.max(reference[0]), np.max(other[0]))
    if not lo < hi:
        return float("nan"), float("nan")
    grid = np.geomspace(lo, hi, 200)
    ratio = loglog_interp(*other, grid) / loglog_interp(*reference, grid)
    return float(np.nanmin(ratio)), float(np.nanmax(ratio))


def work_ratio_range(reference, other):
    """Smallest and largest ratio reference_nfev / other_nfev at equal
    error, over the errors both work-precision curves cover (interpolated
    log-log at 200 errors).  Each argument is a pair (nfev, error); a ratio
    above 1 means ``other`` needs fewer evaluations."""
    lo = max(np.min(reference[1]), np.min(other[1]))
    hi = min(np.max(reference[1]), np.max(other[1]))
    if not lo < hi:
        return float("nan"), float("nan")
    grid = np.geomspace(lo, hi, 200)
    ratio = (loglog_interp(reference[1], reference[0], grid)
             / loglog_interp(other[1], other[0], grid))
    return float(np.nanmin(ratio)), float(np.nanmax(ratio))


def _polar_angle(y):
    """Unwrapped polar angle of planar positions y (shape (2, n)), in time order."""
    return np.unwrap(np.arctan2(y[1], y[0]))


def phase_drift_from_angle(t, y, y_exact, period):
    """Phase drift per orbit from the unwrapped polar-angle error.

    The angle error ``theta(t) - theta_exact(t)`` is unwrapped along the
    samples (which must be dense enough that neither angle turns by more
    than pi between two of them), averaged over each whole orbit of the
    exact solution, and fitted linearly against the orbit number.

    Parameters
    ----------
    t : array_like, shape (n,)
        Sample times, increasing, from 0.
    y, y_exact : array_like, shape (2, n)
        Computed and exact planar positions at ``t``.
    period : float
        The exact orbit's period.

    Returns
    -------
    float
        The fitted drift of the polar angle per orbit, in radians (negative:
        the computed body lags).
    """
    t = np.asarray(t, dtype=float)
    error = _polar_angle(np.asarray(y)) - _polar_angle(np.asarray(y_exact))
    orbit = np.floor(t / period).astype(int)
    whole = orbit < np.floor(t[-1] / period)
    if np.unique(orbit[whole]).size < 2:
        raise ValueError("t must span at least two whole orbits")
    means = np.bincount(orbit[whole], error[whole]) / np.bincount(orbit[whole])
    return np.polyfit(np.arange(means.size) + 0.5, means, 1)[0]


def periapsis_passages(t, y):
    """Times and polar angles of the computed orbit's periapsis passages.

    Each local minimum of the distance ``r`` among the samples is refined by
    the parabola through it and its two neighbours (uniform samples), and
    the polar angle is interpolated to the refined time.

    Parameters
    ----------
    t : array_like, shape (n,)
        Uniformly spaced sample times.
    y : array_like, shape (2, n)
        Planar positions at ``t``.

    Returns
    -------
    times, angles : ndarray
        The refined passage times and the unwrapped polar angles there.
    """
    t = np.asarray(t, dtype=float)
    y = np.asarray(y, dtype=float)
    r = np.hypot(y[0], y[1])
    i = np.flatnonzero((r[1:-1] < r[:-2]) & (r[1:-1] <= r[2:])) + 1
    shift = 0.5 * (r[i - 1] - r[i + 1]) / (r[i - 1] - 2 * r[i] + r[i + 1])
    theta = _polar_angle(y)
    dt = t[1] - t[0]
    return t[i] + shift * dt, theta[i] + shift * 0.5 * (theta[i + 1] - theta[i - 1])


def phase_drift_from_passages(t, y, period):
    """Phase drift per orbit from the periapsis passages alone (no reference
    solution): the computed anomalistic period ``T_h`` (the slope of the
    passage times against their count) and the precession of the periapsis
    per orbit (the slope of its angle less 2 pi per orbit) give the drift
    of the polar angle per orbit, ``2 pi (T/T_h - 1) + precession``.

    Returns
    -------
    drift : float
        Radians per orbit (negative: the computed body lags).
    period_error : float
        ``T_h/T - 1``.
    precession : float
        Turn of the periapsis per orbit, radians.
    """
    times, angles = periapsis_passages(t, y)
    if times.size < 3:
        raise ValueError("t must contain at least three periapsis passages")
    count = np.arange(times.size)
    computed_period = np.polyfit(count, times, 1)[0]
    precession = np.polyfit(count, angles - 2 * np.pi * count, 1)[0]
    return (2 * np.pi * (period / computed_period - 1) + precession,
            computed_period / period - 1, precession)


def phase_drifts(t, y, y_exact, period):
    """The phase drift per orbit of a computed Kepler orbit measured both
    ways: ``drift_from_angle`` (``phase_drift_from_angle``, against the
    exact solution) and ``drift_from_passages`` with its two parts,
    ``period_error`` and ``precession_per_orbit``
    (``phase_drift_from_passages``, from the computed orbit alone)."""
    by_passages, period_error, precession = phase_drift_from_passages(t, y, period)
    return dict(drift_from_angle=phase_drift_from_angle(t, y, y_exact, period),
                drift_from_passages=by_passages, period_error=period_error,
                precession_per_orbit=precession)


def extrema(values):
    """Indices of the interior local maxima and minima of a sampled curve
    (where its slope changes sign)."""
    slope = np.sign(np.diff(values))
    return np.flatnonzero(slope[1:] * slope[:-1] < 0) + 1
