"""The solver as a scipy user meets it: a run that the method itself can see
is wrong says so; both paths accept the same right-hand sides; every bad
input named in the docs is a ValueError naming the argument."""

import math
import re
import warnings

import numpy as np
import pytest
from numba import njit

import splinestep
from splinestep import check, problems


def van_der_pol(t, y, yp, mu):
    return mu * (1 - y**2) * yp - y


CHAIN = 20
STIFFNESS = 2 * np.eye(CHAIN) - np.eye(CHAIN, k=1) - np.eye(CHAIN, k=-1)
OMEGA_MAX = math.sqrt(np.linalg.eigvalsh(STIFFNESS).max())


def chain(t, y, yp):
    return -STIFFNESS @ y


def run_quietly(*args, **kwargs):
    """Run solve and return (result, the UserWarnings it gave)."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        res = splinestep.solve(*args, **kwargs)
    return res, [w for w in caught if issubclass(w.category, UserWarning)]


@pytest.mark.parametrize("case", ["van der pol mu=10, h=0.2", "mass chain omega h=3.6"])
def test_a_wrong_answer_is_flagged(case):
    if case.startswith("van"):
        res, caught = run_quietly(van_der_pol, (0, 60), 2.0, 0.0, 0.2, iteration="newton",
                                  args=(10.0,), reuse_jacobian=False)
        assert np.abs(res.y).max() > 100          # the true solution stays below 2.02
    else:
        res, caught = run_quietly(chain, (0, 100), np.sin(np.arange(CHAIN)), np.zeros(CHAIN),
                                  3.6 / OMEGA_MAX, iteration="newton")
        # grown by orders of magnitude past the stability limit: a failure
        assert res.status == -1 and "blew up" in res.message and not caught
        assert "estimated omega h = 3.6, past its stability limit" in res.message
        return
    assert res.status == 0 and len(caught) == 1
    assert "too large" in str(caught[0].message) and "too large" in res.message
    assert res.local_error > check.LOCAL_FRACTION * np.abs(res.y).max()


def test_stability_limit_is_where_the_linear_analysis_puts_it():
    """The linearised-step check fires on y'' = -omega^2 y past omega h =
    sqrt(12), above 3.4641029 (where the spectral radius reaches 1 +
    GROWTH_MARGIN, splinestep/check.py), and not at or below sqrt(12)."""
    for x, fires in ((3.45, False), (math.sqrt(12), False), (3.4641025, False),
                     (3.4641035, True), (3.48, True)):
        rho, exact = check.growth(np.array([[-1.0]]), np.array([[0.0]]), x)
        assert (rho > exact * (1 + check.GROWTH_MARGIN)) == fires
    # Against the closed form of the amplification factor: eigenvalues of
    # lambda^2 - 2 b lambda + 1 with b = 1 - x^2 / (2 (1 + x^2 / 6)).
    x = 3.6
    b = 1 - x * x / (2 * (1 + x * x / 6))
    rho, _ = check.growth(np.array([[-1.0]]), np.array([[0.0]]), x)
    assert rho == pytest.approx(abs(b) + math.sqrt(b * b - 1), rel=1e-12)


REPORT_RUNS = [(problems.cannonball(mu), method) for mu in problems.CANNONBALL_MU
               for method in ("fixed-point", "newton")] + \
              [(problems.rigid_body(case), "fixed-point") for case in ("printed", "consistent")]


@pytest.mark.parametrize("problem, iteration", REPORT_RUNS,
                         ids=[f"{p.name}-{it}" for p, it in REPORT_RUNS])
def test_accurate_runs_are_not_flagged(problem, iteration):
    res, caught = run_quietly(problem.fun, problem.t_span, problem.y0, problem.yp0,
                              problem.h, args=problem.args, iteration=iteration)
    assert res.success and not caught
    # The estimate is far from the threshold: at least 10^4 times below it.
    assert res.local_error < 1e-4 * check.LOCAL_FRACTION * np.abs(res.y).max()


def test_local_error_estimate_is_the_leading_term_on_a_known_solution():
    """On y = cos t the step's local error in y is h^4 y''''/24 = h^4 cos(t)/24:
    the estimate's largest value is h^4/24 times max |cos|, where it occurs."""
    h = 0.01
    res = splinestep.solve(lambda t, y, yp: -y, (0, 10), 1.0, 0.0, h)
    assert res.local_error == pytest.approx(h**4 / 24, rel=1e-3)
    assert res.local_error_yp == pytest.approx(h**3 / 12, rel=1e-3)
    assert abs(math.cos(res.t_local_error)) > 1 - 1e-3


@njit
def pendulum_scalar(t, y, yp):
    return -math.sin(y[0])


@njit
def pendulum_list(t, y, yp):
    return [-math.sin(y[0])]


@njit
def pendulum_tuple(t, y, yp):
    return (-math.sin(y[0]),)


@pytest.mark.parametrize("fun", [pendulum_scalar, pendulum_list, pendulum_tuple],
                         ids=["scalar", "list", "tuple"])
def test_both_paths_accept_the_same_returns(fun):
    compiled = splinestep.solve(fun, (0, 10), 1.0, 0.0, 0.01)
    plain = splinestep.solve(fun.py_func, (0, 10), 1.0, 0.0, 0.01)
    assert compiled.path == "compiled" and plain.path == "plain"
    reference = splinestep.solve(lambda t, y, yp: -np.sin(y), (0, 10), 1.0, 0.0, 0.01)
    for res in (compiled, plain):
        assert res.success
        assert np.max(np.abs(res.y - reference.y)) <= 1e-12


@pytest.mark.parametrize("returned, shown", [
    (None, "got None"), (np.zeros(3), r"got a ndarray of shape \(3,\)"),
    (np.zeros((2, 1)), r"got a ndarray of shape \(2, 1\)"), ("a", "got a str"),
    (1.0, r"got a float")])
def test_a_wrong_return_at_t0_is_a_value_error(returned, shown):
    with pytest.raises(ValueError, match=r"fun must return an array of shape \(2,\).*" + shown):
        splinestep.solve(lambda t, y, yp: returned, (0, 1), [1.0, 0.0], [0.0, 1.0], 0.1)


def test_complex_values_are_refused():
    with pytest.raises(ValueError, match="y0 must be real"):
        splinestep.solve(lambda t, y, yp: -y, (0, 1), [1 + 1j], [0.0], 0.1)
    with pytest.raises(ValueError, match="complex"):
        splinestep.solve(lambda t, y, yp: -y * 1j, (0, 1), 1.0, 0.0, 0.1)
    with pytest.raises(ValueError, match="args must be real"):
        splinestep.solve(lambda t, y, yp, c: -y, (0, 1), 1.0, 0.0, 0.1, args=(1j,))


@njit
def scaled(t, y, yp, k):
    return -k * y


def test_numeric_args_are_coerced_so_the_loop_compiles_once():
    from splinestep import _compile
    splinestep.solve(scaled, (0, 1), 1.0, 0.0, 0.1, args=(1.0,))
    before = len(_compile._LOOPS)
    for args in ((1,), (np.int64(2),), (True * 1.0,)):
        res = splinestep.solve(scaled, (0, 1), 1.0, 0.0, 0.1, args=args)
        assert res.path == "compiled" and res.success
    assert len(_compile._LOOPS) == before
    res = splinestep.solve(lambda t, y, yp, k: -k @ y, (0, 1), [1.0], [0.0], 0.01,
                           args=(np.array([[2]]),))
    assert res.y[0, -1] == pytest.approx(math.cos(math.sqrt(2)), abs=1e-4)


def test_args_a_compiled_loop_cannot_take_are_a_value_error():
    @njit
    def uses(t, y, yp, d):
        return -y
    with pytest.raises(ValueError, match=r"args\[0\] is a dict.*a compiled fun takes numbers"):
        splinestep.solve(uses, (0, 1), 1.0, 0.0, 0.1, args=({"k": 1.0},))
    # The same function as plain Python takes anything.
    assert splinestep.solve(uses.py_func, (0, 1), 1.0, 0.0, 0.1, args=({"k": 1.0},)).success


@pytest.mark.parametrize("jac, match", [
    (lambda t, y, yp: (np.zeros((1, 1)), np.zeros((1, 1))), "dF/dy has shape (1, 1)"),
    (lambda t, y, yp: (np.zeros(2), np.zeros((2, 2))), "dF/dy has shape (2,)"),
    (lambda t, y, yp: (np.zeros((2, 2)), np.zeros((3, 3))), "dF/dyp has shape (3, 3)"),
    (lambda t, y, yp: np.zeros((2, 2)), "got a ndarray of shape (2, 2)"),
    (lambda t, y, yp: (np.full((2, 2), np.nan), np.zeros((2, 2))), "of finite real numbers")])
def test_jac_is_checked_at_t0(jac, match):
    with pytest.raises(ValueError, match="jac must return .*" + re.escape(match)):
        splinestep.solve(lambda t, y, yp: -y, (0, 1), [1.0, 0.0], [0.0, 1.0], 0.1,
                         iteration="newton", jac=jac)


def test_jac_with_fixed_point_is_unused_with_a_warning():
    jac = lambda t, y, yp: (-np.eye(1), np.zeros((1, 1)))   # noqa: E731
    with pytest.warns(UserWarning, match="jac is not used by the fixed-point"):
        res = splinestep.solve(pendulum_tuple, (0, 1), 1.0, 0.0, 0.1, jac=jac)
    assert res.path == "compiled" and res.njev == 0


def test_compiled_fun_with_plain_jac_warns_and_says_which_path_ran():
    jac = lambda t, y, yp: (np.array([[-math.cos(y[0])]]), np.zeros((1, 1)))   # noqa: E731
    with pytest.warns(UserWarning, match="compile jac"):
        res = splinestep.solve(pendulum_tuple, (0, 1), 1.0, 0.0, 0.1, iteration="newton",
                               jac=jac)
    assert res.path == "plain" and res.njev > 0


def test_newton_on_a_linear_problem_takes_two_iterations_per_step():
    """The docstring's statement: the first iteration solves the step, the
    second confirms it.  Full Newton builds the matrix at each (m + 1
    evaluations with finite differences); the kept matrix of a linear,
    constant-coefficient problem at a uniform step is built once."""
    jac = lambda t, y, yp: (-STIFFNESS, np.zeros_like(STIFFNESS))   # noqa: E731
    args = (chain, (0, 1), np.sin(np.arange(CHAIN)), np.zeros(CHAIN), 0.1)
    # Beyond the steps' own: jac once at t0 and at the three states of the
    # step-size check, or fun 3 (2m + 1) times there.
    with_jac, check_fev = 1 + 3, 3 * (2 * CHAIN + 1)
    full = splinestep.solve(*args, iteration="newton", jac=jac, reuse_jacobian=False)
    assert full.niter == 2 * full.nstep and full.njev == 2 * full.nstep + with_jac
    fd = splinestep.solve(*args, iteration="newton", reuse_jacobian=False)
    assert fd.nfev == 1 + fd.niter * (CHAIN + 1) + check_fev
    res = splinestep.solve(*args, iteration="newton", jac=jac)
    assert res.niter == 2 * res.nstep and res.njev == 1 + with_jac
    assert np.max(np.abs(res.y - full.y)) < 1e-13
    kept = splinestep.solve(*args, iteration="newton")
    assert kept.nfev == 1 + kept.niter + CHAIN + check_fev
    one = splinestep.solve(chain, (0, 1), np.sin(np.arange(CHAIN)), np.zeros(CHAIN), 0.1,
                           iteration="newton", iterations=1, jac=jac)
    assert np.max(np.abs(one.y - res.y)) < 1e-13


def test_steps_and_spans_at_the_edges():
    # A step a hair larger than the span: one step over the span.
    res = splinestep.solve(lambda t, y, yp: -y, (0, 1), 1.0, 0.0, 1.0000001)
    assert res.nstep == 1 and res.t.tolist() == [0.0, 1.0]
    # A span a rounding-level hair longer than 10 steps: 10 steps, no sliver.
    res = splinestep.solve(lambda t, y, yp: -y, (0, 1 + 1e-12), 1.0, 0.0, 0.1)
    assert res.nstep == 10 and res.t[-1] == 1 + 1e-12
    assert np.min(np.diff(res.t)) > 0.09
    # A span that is not a multiple of h: the last step is shortened.
    res = splinestep.solve(lambda t, y, yp: -y, (0, 1.05), 1.0, 0.0, 0.1)
    assert res.nstep == 11 and np.diff(res.t)[-1] == pytest.approx(0.05)
    # 10^9 steps: more than max_steps (10^8 by default), refused before the run;
    # allowed by a larger max_steps, with a warning before the run (turned into
    # an error so that it does not start).
    with pytest.raises(ValueError, match="1e\\+09 steps, more than max_steps = 100000000"):
        splinestep.solve(lambda t, y, yp: -y, (0, 10), 1.0, 0.0, 1e-8)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(UserWarning, match="1e\\+09 steps"):
            splinestep.solve(lambda t, y, yp: -y, (0, 10), 1.0, 0.0, 1e-8, max_steps=10**10)


def test_messages_use_short_times():
    res = splinestep.solve(lambda t, y, yp: -900.0 * y, (0, 1), 1.0, 0.0, 0.1, max_iter=30)
    assert "t = 0.1)" in res.message and "0.10000000000000001" not in res.message


def test_the_readme_and_guide_examples_run():
    """The Python blocks of the README and of the user guide
    (website/guide.md), each file's run in order in one namespace."""
    from pathlib import Path
    root = Path(__file__).resolve().parents[1]
    namespaces = {}
    for name in ("README.md", "website/guide.md"):
        text = (root / name).read_text()
        blocks = re.findall(r"```python\n(.*?)```", text, flags=re.S)
        assert blocks, name
        namespace = namespaces[name] = {}
        for block in blocks:
            exec(compile(block, name, "exec"), namespace)  # noqa: S102
    assert namespaces["README.md"]["res"].success
    namespace = namespaces["website/guide.md"]
    assert float(namespace["np"].log2(namespace["errors"][0] / namespace["errors"][1])) \
        == pytest.approx(2.0, abs=0.05)
    assert namespace["stiff"].status == -1 and namespace["stiff"].nstep == 0
    bvp, exact = namespace["bvp"], namespace["exact"]
    # tol (1e-6) bounds the estimated error; the true error within ten times it
    assert bvp.status == 0 and np.max(np.abs(bvp.y[0] - exact(bvp.t))) < 1e-5
    res = namespace["res"]
    assert res.success and res.path == "compiled"
    # The building: mass= equals y'' = M^-1 (...) written out (M is diagonal)
    quake, building, M = namespace["quake"], namespace["building"], namespace["M"]
    masses = M.diagonal()
    by_hand = splinestep.solve(lambda t, y, yp: building(t, y, yp) / masses, (0.0, 10.0),
                               np.zeros(masses.size), np.zeros(masses.size),
                               h=namespace["dt_record"], method="average-acceleration")
    assert quake.status == 0 and quake.niter == 2 * quake.nstep
    assert np.max(np.abs(quake.y - by_hand.y)) < 1e-10 * np.max(np.abs(by_hand.y))
    g, height, speed = 9.81, 10.0, 5.0
    landing = (speed + math.sqrt(speed**2 + 2 * g * height)) / g
    ball = splinestep.solve(lambda t, y, yp: -g, (0, 10), height, speed, h=0.01,
                            events=namespace["ground"])
    assert ball.status == 1 and ball.t_events[0][0] == pytest.approx(landing, abs=1e-12)
