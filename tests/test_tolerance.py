"""rtol as a tolerance on the global error (splinestep.controllers: error
per unit step): the final error of an adaptive run stays below rtol times
the solution's scale and follows rtol proportionally, against exact
solutions."""

import numpy as np
import pandas as pd
import pytest

import splinestep
from splinestep.analysis import tolerance

RTOLS = 10.0 ** -np.arange(3, 9)


@pytest.mark.parametrize("name", ["harmonic oscillator", "pendulum, 3 rad", "Kepler e = 0.9",
                                  "rational, backwards"])
def test_the_final_error_follows_rtol(name):
    """Over rtol = 1e-3 ... 1e-8 (atol = 1e-3 rtol) the final error of y is
    below rtol times the largest |y| of the exact solution, that of y'
    within 10 times rtol times the largest |y'|, and log(error) against
    log(rtol) has a slope within 0.2 or 0.3 of 1 (a per-step bound gives
    about 2/3).  The problems' exact solutions: cos t, the pendulum's
    Jacobi elliptic closed form, Kepler's equation, t / (t + 10)."""
    rows = tolerance.runs(tolerance.problems()[name], RTOLS, methods=("spline",))
    assert all(row["status"] == 0 for row in rows)
    assert max(row["error_ratio"] for row in rows) < 1.0
    assert max(row["error_ratio_yp"] for row in rows) < 10.0
    slope = tolerance.slope(RTOLS, [row["error"] for row in rows])
    assert 0.8 < slope < 1.3


def test_a_hundred_times_smaller_rtol_gives_a_hundred_times_smaller_error():
    """On the oscillator the final error at rtol 1e-4 over that at 1e-6 is
    near 100; a bound on each step's error (error ~ rtol^(2/3)) would give
    100^(2/3) = 21.5."""
    problem = tolerance.problems()["harmonic oscillator"]
    errors = [row["error"] for row in tolerance.runs(problem, [1e-4, 1e-6], methods=("spline",))]
    assert 50 < errors[0] / errors[1] < 200


def test_the_tolerance_is_spread_over_the_span():
    """The same problem over twice the span takes about twice the steps per
    unit time at the same rtol (h ~ (rtol / span)^(1/2)): the local errors
    of the longer run sum over twice as many steps."""
    def oscillator(t, y, yp):
        return -y
    short = splinestep.solve(oscillator, (0.0, 10.0), 1.0, 0.0, rtol=1e-5, atol=1e-8)
    long = splinestep.solve(oscillator, (0.0, 20.0), 1.0, 0.0, rtol=1e-5, atol=1e-8)
    per_time = (long.nstep / 20.0) / (short.nstep / 10.0)
    assert 1.2 < per_time < 1.7          # sqrt(2) = 1.41


def test_a_late_start_takes_its_first_step():
    """The first step's finite difference of F is sqrt(eps) times the
    smaller of |t0| and the span: a run of y'' = -y from y' = 0 at t0 = 1e8
    over a span of 10 goes as one from t0 = 0 (relative to |t0| alone it
    could not take its first step)."""
    def oscillator(t, y, yp):
        return -y
    runs = [splinestep.solve(oscillator, (t0, t0 + 10.0), 1.0, 0.0, rtol=1e-6, atol=1e-9)
            for t0 in (0.0, 1e8)]
    assert all(r.status == 0 for r in runs)
    assert runs[1].nstep == runs[0].nstep
    assert abs(runs[1].y[0, -1] - np.cos(10.0)) < 1e-6


def test_uniform_steps_are_log_spaced_eight_per_decade():
    """The oscillator's uniform runs: 2000 to 1.6 million steps, 2.9 decades,
    so 25 counts at a ratio of 800^(1/24) = 1.32 from one to the next."""
    steps = tolerance.uniform_steps("harmonic oscillator")
    assert steps[0] == 2000 and steps[-1] == 1_600_000 and steps.size == 25
    assert np.allclose(steps[1:] / steps[:-1], 800 ** (1 / 24), rtol=2e-3)


def test_converging_part_leaves_out_a_coarse_error_through_zero():
    """A coarse run whose error passes near zero by chance (n = 300 below)
    is not part of the curve: it stops at the first coarser step whose
    error does not grow."""
    curve = pd.DataFrame(dict(n=[100, 200, 300, 400, 800, 1600],
                              error=[0.2, 0.05, 1e-5, 4e-3, 1e-3, 2.5e-4]))
    assert list(tolerance.converging_part(curve).n) == [400, 800, 1600]
    assert list(tolerance.converging_part(curve.iloc[3:]).n) == [400, 800, 1600]


def test_the_oscillators_verdict_depends_on_the_uniform_runs_sweeps():
    """On y'' = -y over (0, 50) at rtol 1e-4 and 1e-5, against uniform runs
    matched to the adaptive run's error: iterated on both sides the knots
    cost 0.7 to 1.1 times the uniform evaluations (0.75 and 1.06 measured),
    against a uniform run with one sweep per step about twice (2.16 and
    2.11), since a fine iterated step takes 2 sweeps where 1 reaches the
    same error."""
    name = "harmonic oscillator"
    study = {name: tolerance.problems()[name]}
    adaptive = pd.DataFrame(tolerance.runs(study[name], [1e-4, 1e-5], methods=("spline",)))
    uniform = pd.DataFrame(tolerance.uniform_runs(study[name], [8000, 16000, 32000, 64000],
                                                  sweeps=("iterated", "1 sweep")))
    cost = tolerance.cost_ratios(study, adaptive.assign(problem=name),
                                 uniform.assign(problem=name),
                                 pairs=(("spline", "uniform, iterated"),
                                        ("spline", "uniform, 1 sweep")))
    assert np.all(np.abs(cost.uniform_error / cost.adaptive_error - 1) < 0.02)   # matched
    iterated = cost[cost.uniform == "uniform, iterated"].ratio
    one_sweep = cost[cost.uniform == "uniform, 1 sweep"].ratio
    assert np.all((0.7 < iterated) & (iterated < 1.1))
    assert np.all((1.9 < one_sweep) & (one_sweep < 2.3))


def test_ratio_ranges_as_the_notebook_prints_them():
    ratios = pd.DataFrame(dict(problem=["p"] * 3 + ["q"] * 3, adaptive="spline",
                               uniform="uniform, iterated",
                               ratio=[0.566, 1.0615, 0.9, 0.0269, 0.0362, np.nan]))
    table = tolerance.ratio_ranges(ratios)
    assert table.loc["p", "spline / uniform, iterated"] == "0.57 to 1.06"
    assert table.loc["q", "spline / uniform, iterated"] == "0.027 to 0.036 (2 of 3)"
    assert tolerance.ratio_text(0.0201) == "0.020"
