"""The rule of tests/reproduction.py is strict where it matters and
lenient where it must be: rounding-level changes (what another CPU does)
pass; a 1 % change of one coefficient of the scheme, or a 1 % change of the
step, fails.  Checked on the spline rows of data/cannonball-max-errors.csv,
recomputed here; the perturbed scheme runs its step loop as plain Python
(a compiled loop keeps the constants it was compiled with)."""

from fractions import Fraction
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import reproduction
import splinestep
from splinestep import members, problems

ROOT = Path(__file__).resolve().parents[1]
COLUMNS = ["mu", "method", "energy_error", "momentum_error", "position_error"]


def spline_max_errors(h=None, launch_ulps=0):
    rows = []
    for mu in problems.CANNONBALL_MU:
        problem = problems.cannonball(mu)
        y0 = problem.y0 * (1 + launch_ulps * np.finfo(float).eps)
        yp0 = problem.yp0 * (1 + launch_ulps * np.finfo(float).eps)
        res = splinestep.solve(problem.fun.py_func, problem.t_span, y0, yp0,
                               problem.h if h is None else h, args=problem.args)
        assert res.success, res.message
        exact, _ = problem.exact(res.t)
        energy = problem.invariants["energy"](res.y, res.yp)
        momentum = problem.invariants["angular momentum"](res.y, res.yp)
        rows.append(dict(mu=mu, method="spline",
                         energy_error=np.max(np.abs(energy - energy[0])),
                         momentum_error=np.max(np.abs(momentum - momentum[0])),
                         position_error=np.max(np.hypot(*(res.y - exact)))))
    return pd.DataFrame(rows)


@pytest.fixture(scope="module")
def committed():
    frame = pd.read_csv(ROOT / "data" / "cannonball-max-errors.csv")
    return frame[frame.method == "spline"][COLUMNS].reset_index(drop=True)


def compare(committed, new):
    return reproduction.compare_frames("cannonball-max-errors", committed, new[COLUMNS])


def test_recomputation_reproduces(committed):
    assert compare(committed, spline_max_errors()) == []


@pytest.mark.parametrize("ulps", [2, 8])
def test_rounding_level_change_passes(committed, ulps):
    """A launch perturbed by a few units in the last place moves every
    number the way another CPU's rounding does; the rule accepts it."""
    new = spline_max_errors(launch_ulps=ulps)
    assert not np.allclose(new.position_error, committed.position_error, rtol=0, atol=0)
    assert compare(committed, new) == []


def test_one_percent_change_of_a_coefficient_fails(committed, monkeypatch):
    """beta = 1/6 -> 1.01/6 (the h^2 weight of the new acceleration in eq. 6),
    in the record of the member every run of the spline reads."""
    spline = members.MEMBERS["spline"]
    changed = spline._replace(beta=spline.beta * Fraction(101, 100))
    monkeypatch.setitem(members.MEMBERS, "spline", changed)
    problems_found = compare(committed, spline_max_errors())
    assert any("position_error" in p for p in problems_found), problems_found


def test_one_percent_change_of_the_step_fails(committed):
    problems_found = compare(committed, spline_max_errors(h=0.0101))
    assert any("position_error" in p for p in problems_found), problems_found


def test_figure_rule_survives_rounding_and_fails_when_a_curve_moves(tmp_path):
    """The same plot from data changed at the rounding level matches; the
    same plot with one curve moved by 1 % of its values does not."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    t = np.linspace(0, 50, 2001)
    curves = [1e-6 * (1 + t) * (1.5 + np.sin(t)), 1e-9 * (1 + t)]

    def draw(name, scale_second=1.0, noise=0.0):
        fig, ax = plt.subplots(figsize=(7, 4), dpi=100)
        for k, c in enumerate(curves):
            ax.semilogy(t, c * (1 + noise * np.sin(7 * t)) * (scale_second if k else 1.0))
        fig.savefig(tmp_path / name, dpi=150, metadata={"Software": None})
        plt.close(fig)
        return tmp_path / name

    base = draw("base.png")
    assert reproduction.figures_match(base, draw("rounded.png", noise=1e-9))
    assert not reproduction.figures_match(base, draw("moved.png", scale_second=1.01))
    assert not reproduction.figures_match(base, draw("moved-more.png", scale_second=1.1))
