"""The compiled and the plain-Python loop are one source: same numbers,
same counters, same failures."""

import subprocess
import sys

import numpy as np
import pytest
from numba import njit

import splinestep
from splinestep import _compile, problems


def assert_same(a, b):
    assert a.status == b.status and a.message == b.message
    assert (a.nfev, a.njev, a.niter, a.nstep) == (b.nfev, b.njev, b.niter, b.nstep)
    np.testing.assert_array_equal(a.t, b.t)
    for key in ("y", "yp", "ypp"):
        scale = max(np.max(np.abs(a[key])), 1.0)
        assert np.max(np.abs(a[key] - b[key]), initial=0.0) <= 1e-12 * scale


CASES = [
    (problems.cannonball(0.6), dict()),
    (problems.cannonball(0.4), dict(iteration="newton")),
    (problems.cannonball(0.4), dict(iteration="newton", jac=None)),
    (problems.cannonball(1.0), dict(iterations=2, t_eval=np.linspace(0, 50, 333))),
    (problems.rigid_body("printed"), dict()),
    # A failure part way: fixed-point sweeps diverge at w h = 3 > sqrt(6).
    (problems.harmonic(30.0, t_span=(0, 1), h=0.1), dict(max_iter=20)),
]


@pytest.mark.parametrize("problem, kwargs", CASES)
def test_spline_compiled_equals_plain(problem, kwargs):
    if kwargs.get("iteration") == "newton":
        kwargs = {"jac": problem.jac, **kwargs}
    else:
        kwargs = {"jac": None, **kwargs}
    t_span = (problem.t_span[0], min(problem.t_span[1], 10.0))
    if "t_eval" in kwargs:
        t_span = problem.t_span
    compiled = splinestep.solve(problem.fun, t_span, problem.y0, problem.yp0, problem.h,
                                args=problem.args, **kwargs)
    jac = kwargs.pop("jac")
    plain = splinestep.solve(problem.fun.py_func, t_span, problem.y0, problem.yp0,
                             problem.h, args=problem.args,
                             jac=None if jac is None else jac.py_func, **kwargs)
    assert_same(compiled, plain)


def test_harmonic_case_fails_in_both_paths():
    problem, kwargs = CASES[-1]
    res = problem.solve(**kwargs)
    assert res.status == -1 and "diverged" in res.message


@pytest.mark.parametrize("problem", [problems.cannonball(0.5), problems.rigid_body()])
def test_rk4_compiled_equals_plain(problem):
    t_eval = np.linspace(0, 10, 77)
    compiled = splinestep.rk4(problem.fun, (0, 10), problem.y0, problem.yp0, problem.h,
                              args=problem.args, t_eval=t_eval)
    plain = splinestep.rk4(problem.fun.py_func, (0, 10), problem.y0, problem.yp0,
                           problem.h, args=problem.args, t_eval=t_eval)
    assert_same(compiled, plain)


MEMORY_SCRIPT = """
import resource, numpy as np
from splinestep import _compile, problems
p = problems.cannonball(0.6)
p.solve(h=0.01, t_eval=np.linspace(0, 1, 10))          # compile first
before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
res = p.solve(h=50 / 5_000_000, t_eval=np.linspace(0, 50, 1000), iterations=1)
after = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
assert res.success and res.nstep == 5_000_000 and res.y.shape == (2, 1000)
print((after - before) / 1024)
"""


def test_memory_does_not_grow_with_steps_when_t_eval_is_given():
    """5,000,000 steps reported at 1,000 times: the peak resident memory
    grows by less than 100 MB (storing every knot would take 320 MB)."""
    out = subprocess.run([sys.executable, "-c", MEMORY_SCRIPT], capture_output=True,
                         text=True, check=True)
    growth_mb = float(out.stdout.strip().splitlines()[-1])
    assert growth_mb < 100


@njit
def oscillator_tuple(t, y, yp):
    return (-y[0] - 0.1 * yp[0],)


@njit
def oscillator_array(t, y, yp):
    return -y - 0.1 * yp


@njit
def two_components(t, y, yp):
    return (1.0, 2.0)


@pytest.mark.parametrize("solver", [splinestep.solve, splinestep.rk4])
def test_tuple_and_array_right_hand_sides_agree(solver):
    as_tuple = solver(oscillator_tuple, (0, 10), 1.0, 0.0, 0.01)
    as_array = solver(oscillator_array, (0, 10), 1.0, 0.0, 0.01)
    plain = solver(oscillator_tuple.py_func, (0, 10), 1.0, 0.0, 0.01)
    assert_same(as_tuple, as_array)
    assert_same(as_tuple, plain)


@pytest.mark.parametrize("solver", [splinestep.solve, splinestep.rk4])
@pytest.mark.parametrize("fun", [two_components, two_components.py_func],
                         ids=["compiled", "python"])
def test_tuple_of_wrong_length_is_a_value_error(solver, fun):
    with pytest.raises(ValueError, match=r"fun must return an array of shape \(1,\).*"
                                         r"tuple of shape \(2,\)"):
        solver(fun, (0, 1), 1.0, 0.0, 0.1)


def test_loops_release_the_gil_and_threads_reproduce_sequential_runs():
    """Two solves in two threads (one with a compiled fun, whose loop runs
    without the GIL, one with a plain-Python fun, whose calls take the GIL
    back) give bit for bit what the same solves give one after the other."""
    from concurrent.futures import ThreadPoolExecutor


    problem = problems.cannonball(0.6)
    plain_fun = problem.fun.py_func

    def runs():
        return (lambda: splinestep.solve(problem.fun, (0.0, 30.0), problem.y0, problem.yp0,
                                         0.01, args=problem.args),
                lambda: splinestep.verlet(problem.fun, (0.0, 30.0), problem.y0, problem.yp0,
                                          0.01, args=problem.args),
                lambda: splinestep.solve(plain_fun, (0.0, 3.0), problem.y0, problem.yp0, 0.01,
                                         args=problem.args))

    sequential = [run() for run in runs()]
    with ThreadPoolExecutor(3) as pool:
        threaded = [future.result() for future in [pool.submit(run) for run in runs()]]
    for one, other in zip(sequential, threaded):
        assert one.status == other.status == 0
        assert np.array_equal(one.y, other.y) and np.array_equal(one.yp, other.yp)
    assert _compile._LOOPS and all(loop.targetoptions.get("nogil")
                                   for loop in _compile._LOOPS.values())


@njit
def _spring(t, y, yp, k, c):
    return (-k * y[0] - c * yp[0], -k * y[1])


@njit
def _spring_jac(t, y, yp, k, c):
    fy, fyp = np.zeros((2, 2)), np.zeros((2, 2))
    fy[0, 0] = fy[1, 1] = -k
    fyp[0, 0] = -c
    return fy, fyp


def test_runs_with_and_without_jac_share_one_compiled_loop():
    """Without jac the loop gets a stand-in of a jac's type (two empty
    matrices): a run with the jac compiles nothing more, calls it (njev),
    and gives what finite differences give to their accuracy; without it
    there is no jac call."""
    args = (4.0, 0.3)
    bare = splinestep.solve(_spring, (0.0, 5.0), [1.0, 0.5], [0.0, 1.0], 0.05, args=args,
                            iteration="newton")
    loops = set(_compile._LOOPS)
    with_jac = splinestep.solve(_spring, (0.0, 5.0), [1.0, 0.5], [0.0, 1.0], 0.05, args=args,
                                iteration="newton", jac=_spring_jac)
    assert set(_compile._LOOPS) == loops
    assert bare.success and with_jac.success
    assert bare.njev == 0 and with_jac.njev > 0
    assert bare.nfev > with_jac.nfev   # finite differences cost m evaluations a matrix
    assert np.max(np.abs(bare.y - with_jac.y)) < 1e-10


@njit
def _chain_packed(t, y, yp, stiffness, damping, scale):
    return scale * (stiffness @ y) - damping * yp


@njit
def _chain_tuple(t, y, yp, params):
    stiffness, damping, scale = params
    return scale * (stiffness @ y) - damping * yp


@njit
def _spring_three(t, y, yp, a, b, c):
    return (-a * y[0] - b * yp[0], -a * y[1], -c * y[2])


def test_a_new_compiled_fun_runs_the_loops_already_compiled_with_its_own_numbers():
    """A compiled fun reaches the loops through an adapter that calls it at
    its own address (its args in the run's buffer, a matrix among them, and
    F written into that buffer, which Newton's finite differences overwrite
    while F's value is still needed).  A new fun, of another length and
    number of args, compiles no loop; on the sweep, Newton and RK4 it gives
    what the plain-Python path gives with the same function (the same loops,
    numpy's arithmetic in place of numba's: equal counters, values to
    rounding); args in a tuple compile no loop either, and give bit for bit
    what the same arithmetic gives with the args apart."""
    m = 4
    stiffness = (np.diag(-2.0 * np.ones(m)) + np.diag(np.ones(m - 1), 1)
                 + np.diag(np.ones(m - 1), -1))
    y0, yp0 = np.linspace(0.1, 0.4, m), np.zeros(m)
    runs = [lambda f, a, y0=y0, yp0=yp0: splinestep.solve(f, (0.0, 3.0), y0, yp0, 0.01, args=a),
            lambda f, a, y0=y0, yp0=yp0: splinestep.solve(f, (0.0, 3.0), y0, yp0, 0.01, args=a,
                                                          iteration="newton"),
            lambda f, a, y0=y0, yp0=yp0: splinestep.rk4(f, (0.0, 3.0), y0, yp0, 0.01, args=a)]
    for run in runs:   # the loops, compiled or loaded, for adapted funs
        res = run(_spring_three, (1.0, 0.1, 2.0), y0=np.array([1.0, 0.5, 0.2]),
                  yp0=np.zeros(3))
        assert res.success
    loops = set(_compile._LOOPS)
    args = (stiffness, 0.05, 3.0)
    packed = [run(_chain_packed, args) for run in runs]
    plain = [run(_chain_packed.py_func, args) for run in runs]
    assert set(_compile._LOOPS) == loops
    for a, b in zip(packed, plain):
        assert a.path == "compiled" and b.path == "plain"
        assert_same(a, b)
    direct = splinestep.rk4(_chain_tuple, (0.0, 3.0), y0, yp0, 0.01, args=(args,))
    assert set(_compile._LOOPS) == loops   # a tuple among the args: no loop of its own
    assert direct.path == "compiled" and direct.nfev == packed[2].nfev
    for key in ("y", "yp", "ypp"):
        np.testing.assert_array_equal(packed[2][key], direct[key])
    # and they are the chain's, y'' = 3 K y - 0.05 y' (scipy at rtol 1e-12):
    # within the sweep's O(h^2) error (2e-5 at h = 0.01), where a matrix
    # packed or read back wrongly is off by the size of y (0.1)
    from scipy.integrate import solve_ivp
    exact = solve_ivp(lambda t, u: np.concatenate([u[m:], 3.0 * stiffness @ u[:m] - 0.05 * u[m:]]),
                      (0.0, 3.0), np.concatenate([y0, yp0]), rtol=1e-12, atol=1e-14).y[:m, -1]
    assert np.max(np.abs(packed[0].y[:, -1] - exact)) < 1e-4
