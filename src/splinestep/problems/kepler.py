"""Newton's cannonball: the Kepler problem x'' = -mu x / |x|^3 (report eqs. 10-12).

The report does not print its initial values.  The launch x(0) = (1, 0),
x'(0) = (0, 1) gives, for its four gravity parameters, exactly the orbits it
names: the energy is 1/2 - mu, so mu = 0.4 is hyperbolic, 0.5 parabolic,
0.6 elliptic and 1 circular.  The energy is 1/2 |x'|^2 - mu / |x| (the
report's eq. 13 omits mu, which is right only for mu = 1).

The exact solution uses universal variables (one Kepler equation for all
three conic types): Bate, Mueller & White, "Fundamentals of
Astrodynamics", Dover (1971), Ch. 4; Curtis, "Orbital Mechanics for
Engineering Students", Sec. 3.7.
"""

import numpy as np
from numba import njit

from ._problem import Problem

CANNONBALL_MU = (0.4, 0.5, 0.6, 1.0)
ORBIT_TYPES = {0.4: "hyperbolic", 0.5: "parabolic", 0.6: "elliptic", 1.0: "circular"}
LAUNCH_POSITION = (1.0, 0.0)
LAUNCH_VELOCITY = (0.0, 1.0)
T_SPAN = (0.0, 50.0)
STEP = 0.01


@njit(cache=True)
def kepler_rhs(t, y, yp, mu):
    """x'' = -mu x / |x|^3 (eqs. 10-12: omega^2 = mu / r^3), as a tuple
    (no array allocated per evaluation)."""
    r2 = y[0] * y[0] + y[1] * y[1]
    w2 = mu / (r2 * np.sqrt(r2))
    return (-w2 * y[0], -w2 * y[1])


@njit(cache=True)
def step_size_control(t, y, yp, mu):
    """G = -(3/2) x.x' / |x|^2 = -d/dt ln s for the step-size function s = r^(3/2):
    the control of :func:`splinestep.solve_reversible` for Kepler orbits
    (steps ~ r^(3/2), Hairer and Soderlind 2005), compiled, so that the
    compiled loop calls it directly."""
    return -1.5 * (y[0] * yp[0] + y[1] * yp[1]) / (y[0] * y[0] + y[1] * y[1])


@njit(cache=True)
def kepler_jac(t, y, yp, mu):
    """dF/dx = -mu / r^3 (I - 3 x x^T / r^2); dF/dx' = 0."""
    r2 = y[0] * y[0] + y[1] * y[1]
    w2 = mu / (r2 * np.sqrt(r2))
    fy = np.empty((2, 2))
    for i in range(2):
        for j in range(2):
            fy[i, j] = w2 * (3.0 * y[i] * y[j] / r2 - (1.0 if i == j else 0.0))
    return fy, np.zeros((2, 2))


def energy(mu):
    """H = 1/2 |x'|^2 - mu / |x|, for y, yp of shape (2, k)."""
    return lambda y, yp: 0.5 * np.sum(yp * yp, axis=0) - mu / np.hypot(y[0], y[1])


def angular_momentum(y, yp):
    """M = x y' - y x' (eq. 14)."""
    return y[0] * yp[1] - y[1] * yp[0]


def energy_as_printed(y, yp):
    """The report's eq. 13 as printed, 1/2 |x'|^2 - 1/|x| (no mu)."""
    return energy(1.0)(y, yp)


@njit(cache=True)
def _stumpff(z):
    """Stumpff functions C(z) and S(z), with series near z = 0."""
    if abs(z) < 1.0:
        term_c = 0.5
        term_s = 1.0 / 6.0
        sum_c, sum_s = term_c, term_s
        for k in range(1, 12):  # C = sum (-z)^k/(2k+2)!, S = sum (-z)^k/(2k+3)!
            term_c = term_c * (-z) / ((2 * k + 1) * (2 * k + 2))
            term_s = term_s * (-z) / ((2 * k + 2) * (2 * k + 3))
            sum_c += term_c
            sum_s += term_s
        return sum_c, sum_s
    if z >= 1.0:
        sq = np.sqrt(z)
        return (1.0 - np.cos(sq)) / z, (sq - np.sin(sq)) / sq ** 3
    sq = np.sqrt(-z)
    return (np.cosh(sq) - 1.0) / (-z), (np.sinh(sq) - sq) / sq ** 3


@njit(cache=True)
def _universal_anomaly(t, rn, sigma, alpha, sqmu, r_peri):
    """The universal anomaly chi at each time of ``t``: the root of the
    universal Kepler equation F(chi) = 0 by Newton's method kept inside a
    bracket (F is monotone in chi; a step that leaves the bracket bisects).
    Returns chi and the Stumpff functions C and S of alpha chi^2; chi is
    -1.0 where it did not converge in 200 iterations (the bracket makes that
    impossible)."""
    out = np.empty(t.shape[0])
    out_c = np.empty(t.shape[0])
    out_s = np.empty(t.shape[0])
    for i in range(t.shape[0]):
        lo = 0.0
        # Periapsis distance bounds r from below, so F(chi) >= r_p chi - sqrt(mu) t.
        hi = sqmu * t[i] / r_peri * (1.0 + 1e-9) + 1e-300
        chi = sqmu * t[i] / rn if alpha <= 0 else min(sqmu * t[i] * alpha, hi)
        chi = min(max(chi, lo), hi)
        out[i] = -1.0
        for _ in range(200):
            z = alpha * chi * chi
            c, s = _stumpff(z)
            f = sigma * chi * chi * c + (1.0 - alpha * rn) * chi ** 3 * s + rn * chi - sqmu * t[i]
            r = chi * chi * c + sigma * chi * (1.0 - z * s) + rn * (1.0 - z * c)
            if f < 0:
                lo = chi
            if f > 0:
                hi = chi
            new = chi - f / r
            if new <= lo or new >= hi:
                new = 0.5 * (lo + hi)
            done = abs(new - chi) <= 4e-16 * max(abs(chi), 1.0)
            chi = new
            if done:
                out[i] = chi
                break
        out_c[i], out_s[i] = _stumpff(alpha * chi * chi)
    return out, out_c, out_s


def kepler_exact(t, mu, r0=LAUNCH_POSITION, v0=LAUNCH_VELOCITY):
    """Exact position and velocity of the Kepler orbit at times t >= 0.

    Solves the universal Kepler equation for the universal anomaly chi by a
    bracketed Newton iteration (the equation is monotone in chi), compiled,
    one time at a time, and applies the Lagrange f and g coefficients.
    Valid for elliptic, parabolic and hyperbolic orbits; accurate to about
    1e-13 relative over the report's span.

    Returns
    -------
    x, v : ndarray, shape (2, k)
        At the k = t.size times of ``t``, flattened.
    """
    t = np.atleast_1d(np.asarray(t, dtype=float)).ravel()
    if np.any(t < 0):
        raise ValueError("t must be non-negative")
    r0 = np.asarray(r0, dtype=float)
    v0 = np.asarray(v0, dtype=float)
    rn = np.hypot(*r0)
    sqmu = np.sqrt(mu)
    sigma = r0 @ v0 / sqmu
    alpha = 2.0 / rn - v0 @ v0 / mu
    h = r0[0] * v0[1] - r0[1] * v0[0]
    ecc = np.hypot(*((v0 @ v0 - mu / rn) * r0 - (r0 @ v0) * v0)) / mu
    r_peri = h * h / mu / (1.0 + ecc)
    chi, c, s = _universal_anomaly(t, rn, sigma, alpha, sqmu, r_peri)
    if np.any(chi < 0):  # pragma: no cover - the bracket guarantees convergence
        raise RuntimeError("universal Kepler equation did not converge")
    z = alpha * chi * chi
    r = chi * chi * c + sigma * chi * (1.0 - z * s) + rn * (1.0 - z * c)
    f = 1.0 - chi * chi / rn * c
    g = t - chi ** 3 * s / sqmu
    fdot = sqmu / (r * rn) * chi * (z * s - 1.0)
    gdot = 1.0 - chi * chi / r * c
    x = np.outer(r0, f) + np.outer(v0, g)
    v = np.outer(r0, fdot) + np.outer(v0, gdot)
    return x, v


def cannonball(mu):
    """Newton's cannonball (report Sec. 3.1) for gravity parameter ``mu``.

    Launch x(0) = (1, 0), x'(0) = (0, 1) (not printed in the report; it is
    the launch that gives its four orbit types), t in [0, 50], h = 0.01.
    Invariants: the energy 1/2 |x'|^2 - mu/|x| and the angular momentum
    x y' - y x'.
    """
    mu = float(mu)
    if not (np.isfinite(mu) and mu > 0):
        raise ValueError(f"mu must be positive and finite, got {mu}")
    kind = ORBIT_TYPES.get(mu, "elliptic" if mu > 0.5 else "hyperbolic")
    return Problem(
        name=f"cannonball mu={mu:g} ({kind})",
        fun=kepler_rhs, args=(mu,), jac=kepler_jac,
        y0=np.array(LAUNCH_POSITION), yp0=np.array(LAUNCH_VELOCITY),
        t_span=T_SPAN, h=STEP,
        exact=lambda t: kepler_exact(t, mu),
        invariants={"energy": energy(mu), "angular momentum": angular_momentum},
        notes=("Launch x(0) = (1, 0), x'(0) = (0, 1) (not printed in the report); "
               "energy 1/2|v|^2 - mu/r = 1/2 - mu."),
    )


def orbit_elements(mu, r0=LAUNCH_POSITION, v0=LAUNCH_VELOCITY):
    """Energy, eccentricity and (for an ellipse) semi-major axis and period
    of the Kepler orbit launched from ``r0`` with velocity ``v0``.

    Returns
    -------
    dict with keys ``energy`` (1/2 |v|^2 - mu/r), ``eccentricity``, ``a``
    (semi-major axis, inf for a parabola, negative for a hyperbola) and
    ``period`` (2 pi sqrt(a^3 / mu), or nan when the orbit is not closed).
    """
    r0 = np.asarray(r0, dtype=float)
    v0 = np.asarray(v0, dtype=float)
    rn = np.hypot(*r0)
    energy_ = 0.5 * (v0 @ v0) - mu / rn
    ecc = np.hypot(*((v0 @ v0 - mu / rn) * r0 - (r0 @ v0) * v0)) / mu
    a = -mu / (2.0 * energy_) if energy_ != 0 else np.inf
    period = 2.0 * np.pi * np.sqrt(a ** 3 / mu) if energy_ < 0 else np.nan
    return dict(energy=float(energy_), eccentricity=float(ecc), a=float(a), period=float(period))


def acceleration_derivatives(x, v, mu):
    """The acceleration a = x'' = -mu x / r^3 and its first two time
    derivatives along a Kepler orbit, in closed form from the state.

    With r' = x.v / r and r'' = (|v|^2 + x.a - r'^2) / r:

        a'  = -mu (v / r^3 - 3 x r' / r^4)
        a'' = -mu (a / r^3 - 6 v r' / r^4 - 3 x r'' / r^4 + 12 x r'^2 / r^5)

    a'' is x'''', which sets the local error h^4 x''''/24 of the spline step.

    Parameters
    ----------
    x, v : ndarray, shape (2, k)

    Returns
    -------
    a, a1, a2 : ndarray, shape (2, k)
    """
    x = np.asarray(x, dtype=float)
    v = np.asarray(v, dtype=float)
    r = np.hypot(x[0], x[1])
    a = -mu * x / r ** 3
    rdot = np.sum(x * v, axis=0) / r
    rddot = (np.sum(v * v, axis=0) + np.sum(x * a, axis=0) - rdot ** 2) / r
    a1 = -mu * (v / r ** 3 - 3.0 * x * rdot / r ** 4)
    a2 = -mu * (a / r ** 3 - 6.0 * v * rdot / r ** 4 - 3.0 * x * rddot / r ** 4
                + 12.0 * x * rdot ** 2 / r ** 5)
    return a, a1, a2


def path_curvature(v, a):
    """Curvature |v x a| / |v|^3 of a plane path with velocity v and
    acceleration a, each of shape (2, k)."""
    return np.abs(v[0] * a[1] - v[1] * a[0]) / np.hypot(v[0], v[1]) ** 3


def eccentric(e=0.9, orbits=1):
    """A Kepler orbit of eccentricity ``e`` (0 <= e < 1) with mu = 1,
    launched at periapsis r = 1 with speed sqrt(1 + e), over ``orbits``
    periods T = 2 pi / (1 - e)^(3/2).  The speed at periapsis is
    (1 + e) / (1 - e) times that at apoapsis (angular momentum), so a uniform step spends
    most of its work where the orbit is slow.  ``h`` is T / 10,000.
    Exact solution: :func:`kepler_exact`."""
    e = float(e)
    if not (np.isfinite(e) and 0 <= e < 1):
        raise ValueError(f"e must lie in [0, 1), got {e}")
    if not (isinstance(orbits, (int, np.integer)) and orbits >= 1):
        raise ValueError(f"orbits must be an integer >= 1, got {orbits!r}")
    period = 2 * np.pi / (1 - e) ** 1.5
    r0, v0 = (1.0, 0.0), (0.0, float(np.sqrt(1 + e)))
    return Problem(
        name=f"Kepler orbit e={e:g}", fun=kepler_rhs, args=(1.0,), jac=kepler_jac,
        y0=np.array(r0), yp0=np.array(v0), t_span=(0.0, orbits * period),
        h=period / 10_000, exact=lambda t: kepler_exact(t, 1.0, r0, v0),
        invariants={"energy": energy(1.0), "angular momentum": angular_momentum},
        notes=f"mu = 1, periapsis r = 1, period {period:.6g}.")
