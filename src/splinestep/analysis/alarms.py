"""How well the step-too-large check (:mod:`splinestep.check`) tells
inaccurate fixed-step runs from accurate ones.

:func:`runs` solves a set of problems at several uniform steps, forwards
and backwards, and records for each run its error against an exact
solution (or a Radau solve at rtol = atol = 1e-12), relative to the
solution's largest |y|, and whether the run warned that its step is too
large.  :func:`tally` counts the false alarms (a warning on a run whose
error is below ``silent`` of the scale) and the misses (no warning on a run
whose error is above ``loud``); runs in between may go either way.
"""

import warnings

import numpy as np
from numba import njit

from .. import problems as _problems
from .. import solve
from ..problems._problem import first_order
from ..problems.nonlinear import duffing, pendulum, rational


@njit(cache=True)
def van_der_pol(t, y, yp, mu):
    return (mu * (1.0 - y[0] ** 2) * yp[0] - y[0],)


@njit(cache=True)
def damped_oscillator(t, y, yp, c):
    return (-y[0] - c * yp[0],)


def _radau(fun, args, t_span, y0, yp0):
    """A dense Radau solution (rtol = atol = 1e-12) of the first-order form."""
    from scipy.integrate import solve_ivp
    m = y0.size
    sol = solve_ivp(first_order(fun, args, m), t_span, np.r_[y0, yp0], method="Radau",
                    rtol=1e-12, atol=1e-12, dense_output=True)
    return lambda t: sol.sol(t)[:m]


def cases():
    """(name, fun, args, t_span, y0, yp0, steps, exact or None, options) of
    the study: the harmonic oscillator and a damped one (c = 0.1), forwards
    and backwards; Van der Pol at mu = 1 and 10 (Newton); the Kepler orbit
    e = 0.9 over one period; the pendulum from 3 rad; scipy's rational
    problem both ways; the forced Duffing oscillator."""
    one = np.ones(1)
    ecc, pen, duf = _problems.eccentric(0.9), pendulum(), duffing()
    period = ecc.t_span[1]
    out = []
    for span in ((0.0, 20.0), (20.0, 0.0)):
        out.append(("oscillator", _problems.harmonic().fun, (1.0,), span, one, 0 * one,
                    (0.05, 0.1, 0.3, 1.0), lambda t, s=span: np.cos(t - s[0])[None], {}))
        out.append(("damped oscillator", damped_oscillator, (0.1,), span, one, 0 * one,
                    (0.01, 0.1, 0.5, 1.0), None, {}))
    for mu, steps in ((1.0, (0.005, 0.02, 0.05, 0.1, 0.2)),
                      (10.0, (0.001, 0.005, 0.01, 0.02, 0.05))):
        out.append((f"Van der Pol mu = {mu:g}", van_der_pol, (mu,), (0.0, 30.0), 2 * one,
                    0 * one, steps, None, dict(iteration="newton")))
    out.append(("Kepler e = 0.9", ecc.fun, ecc.args, ecc.t_span, ecc.y0, ecc.yp0,
                tuple(period / n for n in (1000, 4000, 16000, 64000)),
                lambda t: ecc.exact(t)[0], {}))
    out.append(("pendulum, 3 rad", pen.fun, pen.args, pen.t_span, pen.y0, pen.yp0,
                (0.01, 0.05, 0.1, 0.3, 0.6), lambda t: pen.exact(t)[0], {}))
    for span in ((5.0, 1.0), (5.0, 9.0)):
        rat = rational(span)
        out.append(("rational", rat.fun, (), span, rat.y0, rat.yp0, (0.01, 0.1, 0.5, 1.0),
                    lambda t: (t / (t + 10.0))[None], {}))
    out.append(("forced Duffing", duf.fun, duf.args, duf.t_span, duf.y0, duf.yp0,
                (0.01, 0.1, 0.3, 0.6), None, {}))
    ball, body = _problems.cannonball(0.6), _problems.rigid_body()
    out.append(("cannonball mu = 0.6", ball.fun, ball.args, ball.t_span, ball.y0, ball.yp0,
                tuple(ball.h * k for k in (1, 8, 32, 128)), lambda t: ball.exact(t)[0], {}))
    out.append(("rigid body", body.fun, body.args, body.t_span, body.y0, body.yp0,
                tuple(body.h * k for k in (1, 8, 32)), lambda t: body.exact(t)[0], {}))
    fun, args, y0, yp0 = ground_motion_chain()
    out.append(("chain under a ground-motion record", fun, args, (0.0, 10.0), y0, yp0,
                (0.005, 0.01, 0.02, 0.04, 0.08), None, {}))
    return out


def ground_motion_chain(m=10, interval=0.01, seed=7):
    """(fun, args, y0, yp0) of a shear building of m storeys (storey
    stiffness 400, unit masses, Rayleigh damping 0.05 M + 0.002 K) shaken
    from rest by a ground acceleration given as a record at ``interval``
    (white noise, standard deviation 3, linear between its samples): a
    forcing with a kink at every sample, as a measured accelerogram has."""
    stiffness = (2 * np.eye(m) - np.eye(m, k=1) - np.eye(m, k=-1)) * 400.0
    stiffness[-1, -1] = 400.0
    damping = 0.05 * np.eye(m) + 0.002 * stiffness
    t_record = np.arange(0.0, 10.0 + interval / 2, interval)
    record = 3.0 * np.random.default_rng(seed).normal(size=t_record.size)
    return (_shaken, (stiffness, damping, t_record, record), np.zeros(m), np.zeros(m))


def _shaken(t, y, yp, stiffness, damping, t_record, record):
    return -stiffness @ y - damping @ yp - np.interp(t, t_record, record)


def runs():
    """One row per run of :func:`cases`: name, t_span, h, status, the
    largest error over the knots relative to the largest |y| of the
    reference, and whether the run warned that its step is too large."""
    rows = []
    for name, fun, args, span, y0, yp0, steps, exact, options in cases():
        reference = exact or _radau(fun, args, span, y0, yp0)
        for h in steps:
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                res = solve(fun, span, y0, yp0, h, args=args, **options)
            warned = any("too large" in str(w.message) for w in caught)
            error = np.nan
            if res.status == 0:
                ref = reference(res.t)
                error = float(np.max(np.abs(res.y - ref)) / np.max(np.abs(ref)))
            rows.append(dict(problem=name, t0=span[0], tf=span[1], h=h, status=res.status,
                             relative_error=error, warned=warned))
    return rows


def verdicts(rows, silent=0.01, loud=0.1):
    """The check's verdict on each run, in order: "run failed" (status not
    0); among the runs that reached the end, accurate below ``silent`` of
    the scale and inaccurate above ``loud``, "false alarm" (accurate and
    warned), "miss" (inaccurate and silent), "right" (otherwise: warned when
    inaccurate, silent when accurate) or "between" (neither accurate nor
    inaccurate, where either answer is fair)."""
    out = []
    for r in rows:
        if r["status"] != 0:
            out.append("run failed")
        elif r["relative_error"] < silent:
            out.append("false alarm" if r["warned"] else "right")
        elif r["relative_error"] > loud:
            out.append("right" if r["warned"] else "miss")
        else:
            out.append("between")
    return out


def tally(rows, silent=0.01, loud=0.1):
    """(false alarms, accurate runs, misses, inaccurate runs) among the runs
    that reached the end: accurate below ``silent`` of the scale,
    inaccurate above ``loud`` (the counts of :func:`verdicts`)."""
    done = [r for r in rows if r["status"] == 0]
    accurate = sum(r["relative_error"] < silent for r in done)
    inaccurate = sum(r["relative_error"] > loud for r in done)
    found = verdicts(rows, silent, loud)
    return found.count("false alarm"), accurate, found.count("miss"), inaccurate
