"""Newmark's family against OpenSees, an independent code, step by step.

``scripts/opensees_reference.py`` (``make opensees-reference``) ran
OpenSees's Newmark, HHT and HHTGeneralized integrators on three problems (a
forced damped oscillator, a Rayleigh-damped chain driven by a ground
acceleration record, a piecewise-linear hardening spring) and wrote every
step to ``tests/data/opensees/``.  Each member of the package runs the same
problem from the same start (a_0 = F at t_0, as OpenSees is given with
``setNodeAccel``) and must agree at every knot, in y, y' and y'', to
rounding: relative to the largest |y|, |y'|, |y''| of the run, within
:data:`AGREEMENT`.  That bound is not a fit to this machine's digits: the
script's own numpy step agrees with OpenSees to 1.4e-15 ... 2.1e-13
(its ``agreement_*`` fields), the largest where OpenSees's accumulated
clock drifts from t_0 + n h by 4e-14 on a load of period 0.7; 200 steps of
rounding at eps = 2.2e-16, each amplified by a condition below 10, stay
below 1e-12.
"""

import json
import pathlib
from fractions import Fraction

import numpy as np
import pytest

import splinestep
from splinestep.members import MEMBERS

DATA = pathlib.Path(__file__).resolve().parent / "data" / "opensees"
CASES = ("sdof", "damped-chain", "hardening-spring")
AGREEMENT = 1e-11


def load(case):
    return json.loads((DATA / f"{case}.json").read_text())


def named(record):
    """The package's member with the record's four coefficients."""
    key = tuple(Fraction(record[k]).limit_denominator(1000)
                for k in ("beta", "gamma", "alpha_m", "alpha_f"))
    for member in MEMBERS.values():
        if (member.beta, member.gamma, member.alpha_m, member.alpha_f) == key:
            return member
    raise LookupError(f"no member has {key}")


def force(problem):
    """f(t) of the record's load, written from its stated formula."""
    load_ = problem["load"]
    m = problem["n_dof"]
    if load_["kind"] == "sine":
        def f(t):
            out = np.zeros(m)
            out[load_["dof"]] = load_["amplitude"] * np.sin(2 * np.pi * t / load_["period"])
            return out
        return f
    values, dt = np.array(load_["values"]), load_["dt"]
    mass_ones = np.array(problem["mass"]) @ np.ones(m)

    def f(t):
        k = min(int(np.floor(t / dt)), values.size - 1)
        ag = values[-1] if k + 1 >= values.size else (
            values[k] + (values[k + 1] - values[k]) * (t / dt - k))
        return -mass_ones * ag
    return f


def restoring(problem):
    """R(y) = K y plus the nonlinear spring's force, if any."""
    K = np.array(problem["stiffness"])
    spring = problem["nonlinear_spring"]
    if spring is None:
        return lambda y: K @ y
    strain, force_ = np.array(spring["strain"]), np.array(spring["force"])

    def r(y):
        i = int(np.clip(np.searchsorted(strain, y[0]) - 1, 0, strain.size - 2))
        slope = (force_[i + 1] - force_[i]) / (strain[i + 1] - strain[i])
        out = K @ y
        out[0] += force_[i] + slope * (y[0] - strain[i])
        return out
    return r


def package_run(problem, member, mass=False):
    """The package's run of the record's problem with ``member``: y'' =
    M^-1 (f - C y' - R(y)) written out (M is lumped), or with ``mass`` M
    y'' = f - C y' - R(y) with ``mass=M``."""
    M, C = np.array(problem["mass"]), np.array(problem["damping"])
    minv = 1.0 / np.diag(M)
    assert np.array_equal(M, np.diag(np.diag(M)))   # lumped: F = M^-1 (...)
    f, r = force(problem), restoring(problem)

    def fun(t, y, yp):
        return (1.0 if mass else minv) * (f(t) - C @ yp - r(y))
    t0, h, n = problem["t0"], problem["h"], problem["n_steps"]
    return splinestep.solve(fun, (t0, t0 + n * h), np.array(problem["y0"]),
                            np.array(problem["yp0"]), h, method=member, iteration="newton",
                            tol=1e-15, check=False, mass=M if mass else None)


@pytest.mark.parametrize("mass", [False, True])
@pytest.mark.parametrize("case", CASES)
def test_every_member_equals_opensees_step_by_step(case, mass):
    data = load(case)
    problem = data["problem"]
    assert len(data["members"]) == 6
    for record in data["members"].values():
        member = named(record)
        res = package_run(problem, member, mass)
        assert res.status == 0 and res.t.size == problem["n_steps"] + 1, res.message
        for ours, key in ((res.y, "y"), (res.yp, "yp"), (res.ypp, "ypp")):
            theirs = np.array(record[key]).T
            gap = np.max(np.abs(ours - theirs)) / np.max(np.abs(theirs))
            assert gap < AGREEMENT, (case, member.name, key, gap)


def test_the_comparison_sees_a_wrong_member():
    """The bound is tight enough to tell neighbours apart: average
    acceleration's run is far from OpenSees's linear-acceleration one."""
    problem = load("sdof")["problem"]
    record = load("sdof")["members"]["linear acceleration"]
    res = package_run(problem, "average-acceleration")
    gap = np.max(np.abs(res.y - np.array(record["y"]).T)) / np.max(np.abs(res.y))
    assert gap > 1e3 * AGREEMENT
