"""The solver at many equations: the chain of m masses
(splinestep.problems.chain, y'' = K y, K = (m + 1)^2 tridiag(1, -2, 1)).

Memory and evaluation counts grow linearly with m on every path (asserted
as ratios, never as times); each path's error against the exact modal
solution falls with h as its order says; Newton takes a sparse or constant
Jacobian; the fixed-point test holds at the rounding level of a stiff F;
the step-too-large check stays cheap at large m and still sees an unstable
step; the first adaptive step is never below the rounding floor."""

import tracemalloc
from pathlib import Path
import warnings

import numpy as np
import pytest
from scipy import sparse

import splinestep
from splinestep import _linalg, check
from splinestep import problems


def short_run(problem, steps, path, **options):
    """``steps`` steps of ``path`` on ``problem`` at its step, only the end
    reported (no knot stored)."""
    end = steps * problem.h
    kwargs = dict(args=problem.args, t_eval=np.array([end]))
    if path in ("rk4", "verlet"):
        return getattr(splinestep, path)(problem.fun, (0.0, end), problem.y0, problem.yp0,
                                         problem.h, **kwargs)
    h = None if options.get("adaptive") else problem.h
    options = {k: v for k, v in options.items() if k != "adaptive"}
    if h is None:
        options.update(rtol=1e-3, atol=1e-6)
    return splinestep.solve(problem.fun, (0.0, end), problem.y0, problem.yp0, h, **kwargs,
                            **options)


PATHS = {
    "fixed point": ("spline", {}),
    "rk4": ("rk4", {}),
    "verlet": ("verlet", {}),
    "order 4": ("spline", dict(order=4)),
    "adaptive": ("spline", dict(adaptive=True)),
    "Newton, sparse jac": ("spline", dict(iteration="newton", jac="sparse")),
}


def run_path(name, m, steps=10, **extra):
    path, options = PATHS[name]
    problem = problems.chain(m)
    if options.get("jac") == "sparse":
        options = dict(options, jac=problem.jac)
    return short_run(problem, steps, path, **options, **extra)


def peak(run):
    tracemalloc.start()
    try:
        result = run()
        return tracemalloc.get_traced_memory()[1], result
    finally:
        tracemalloc.stop()


@pytest.mark.parametrize("name", list(PATHS))
def test_memory_grows_linearly_with_m(name):
    """Peak allocation (numpy's and numba's, tracemalloc) of a short run at
    m = 2000 against m = 1000: at most 2.2 times (an m x m buffer would make
    it 4; at m = 100,000 one took 80 GB).  The step-too-large check runs
    (Arnoldi steps above 64 components)."""
    run_path(name, 200)    # compile or load the loop outside the measure
    small, res_small = peak(lambda: run_path(name, 1000))
    large, res_large = peak(lambda: run_path(name, 2000))
    assert res_small.success and res_large.success
    assert large / small <= 2.2, (small, large)


@pytest.mark.parametrize("name", list(PATHS))
def test_evaluations_per_step_do_not_grow_with_m(name):
    """F's evaluations per step attempt at m = 3000 against m = 300 stay
    within 1.25 times: the work of a step is a few evaluations of F, O(m)
    each (the check's evaluations are counted apart, below)."""
    counts = []
    for m in (300, 3000):
        extra = {} if PATHS[name][0] in ("rk4", "verlet") else dict(check=False)
        res = run_path(name, m, steps=40, **extra)
        assert res.success, res.message
        counts.append(res.nfev / (res.nstep + res.n_rejected + res.n_failed))
    assert counts[1] <= 1.25 * counts[0], counts


def test_the_check_costs_a_bounded_number_of_evaluations_above_the_dense_size():
    """Without jac the check costs 2m + 1 evaluations at each of up to three
    states up to check.DENSE_UP_TO components, and above a number that does
    not depend on m (Arnoldi steps on Jacobian-vector products: here one
    evaluation at the state, KRYLOV_STEPS on dF/dy, one on dF/dy', which is
    zero)."""
    extra = {}
    for m in (check.DENSE_UP_TO, 200, 2000):
        problem = problems.chain(m)
        on = short_run(problem, 10, "spline")
        off = short_run(problem, 10, "spline", check=False)
        assert on.y.tolist() == off.y.tolist() and on.niter == off.niter
        extra[m] = on.nfev - off.nfev
    assert extra[check.DENSE_UP_TO] == 3 * (2 * check.DENSE_UP_TO + 1)
    assert extra[200] == extra[2000] == 3 * (check.KRYLOV_STEPS + 2)


ORDERS = {"fixed point": ("spline", {}, 2), "Newton, sparse jac": ("spline", "sparse", 2),
          "Newton, dense jac": ("spline", "dense", 2), "verlet": ("verlet", {}, 2),
          "rk4": ("rk4", {}, 4), "order 4": ("spline", dict(order=4), 4)}


@pytest.mark.parametrize("name", list(ORDERS))
def test_each_path_has_its_order_against_the_exact_modal_solution(name):
    """m = 20 over three periods of the slowest mode, at about omega_m h =
    1/4 and 1/8 (the span divided into N and 2N steps): the error at the end
    against the exact modal solution falls by 2^p (p = 2 for the spline
    step, Newton's or the sweep's, and Verlet; 4 for RK4 and the order-4
    composition), measured order within 0.2 (RK4's is 4.18 there, 4.30 at
    twice the steps, 4.10 at half)."""
    path, options, order = ORDERS[name]
    errors = []
    problem = problems.chain(20, omega_h=0.25)
    steps = int(np.ceil(problem.t_span[1] / problem.h))
    for n in (steps, 2 * steps):
        problem = problems.chain(20, omega_h=problem.t_span[1] / n * problems.chain_frequencies(20)[-1])
        if options in ("sparse", "dense"):
            K = problem.jac[0]
            jac = problem.jac if options == "sparse" else (K.toarray(), np.zeros((20, 20)))
            kwargs = dict(iteration="newton", jac=jac)
        else:
            kwargs = dict(options)
        res = _whole(problem, path, **kwargs)
        assert res.nstep == n
        exact = problem.exact(res.t[-1:])[0][:, 0]
        errors.append(np.max(np.abs(res.y[:, -1] - exact)))
    measured = np.log2(errors[0] / errors[1])
    assert abs(measured - order) < 0.2, (errors, measured)


def _whole(problem, path, **options):
    if path in ("rk4", "verlet"):
        return getattr(splinestep, path)(problem.fun, problem.t_span, problem.y0, problem.yp0,
                                         problem.h, args=problem.args)
    return splinestep.solve(problem.fun, problem.t_span, problem.y0, problem.yp0, problem.h,
                            args=problem.args, **options)


def test_the_chain_exact_solution_is_the_matrix_exponential():
    """The modal solution (discrete sine transform) against expm of the
    first-order system at m = 7, and K y against chain_rhs."""
    from scipy.linalg import expm
    m = 7
    problem = problems.chain(m, yp0=np.linspace(-1.0, 1.0, m))
    K = problems.chain_matrix(m).toarray()
    L = np.block([[np.zeros((m, m)), np.eye(m)], [K, np.zeros((m, m))]])
    u = expm(0.37 * L) @ np.concatenate([problem.y0, problem.yp0])
    y, yp = problem.exact(0.37)
    assert np.allclose(u[:m], y[:, 0], atol=1e-13) and np.allclose(u[m:], yp[:, 0], atol=1e-12)
    assert np.allclose(problem.fun(0.0, problem.y0, problem.yp0, *problem.args),
                       K @ problem.y0, rtol=0, atol=1e-10)
    assert np.allclose(np.sort(np.sqrt(-np.linalg.eigvalsh(K))), problems.chain_frequencies(m))


def test_sparse_and_constant_jacobians_give_the_dense_newton_solution():
    """Newton with jac as the constant sparse pair (SuperLU above
    SPARSE_FROM, densified below), as a constant dense pair, as a function
    returning sparse matrices, and as a compiled-style dense function: the
    same solution to rounding; a constant jac is never called (njev 0),
    a function once per matrix built plus once at the start."""
    for m in (50, _linalg.SPARSE_FROM + 50):
        problem = problems.chain(m)
        K = problems.chain_matrix(m)
        zero = sparse.csr_matrix((m, m))
        runs = {
            "constant sparse": problem.jac,
            "constant dense": (K.toarray(), np.zeros((m, m))),
            "function, sparse": lambda t, y, yp, scale: (K, zero),
            "function, dense": lambda t, y, yp, scale: (K.toarray(), np.zeros((m, m))),
        }
        results = {}
        for name, jac in runs.items():
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")   # the plain dense jac makes the loop plain
                res = short_run(problem, 30, "spline", iteration="newton", jac=jac)
            assert res.success, (name, res.message)
            results[name] = res
        reference = results["function, dense"].y[:, -1]
        for name, res in results.items():
            assert np.max(np.abs(res.y[:, -1] - reference)) < 1e-12, name
        assert results["constant sparse"].njev == 0
        assert results["function, sparse"].njev >= 2


def test_a_sparse_jac_is_validated_naming_what_is_wrong():
    """A constant pair of the wrong shape, a non-finite sparse part, and a
    jac that is neither: ValueErrors naming jac and the part (a scipy.sparse
    matrix is accepted, not taken for an array of shape ())."""
    f = lambda t, y, yp: -y   # noqa: E731
    y0 = np.ones(3)
    with pytest.raises(ValueError, match=r"jac must be a pair .* its dF/dy has shape \(2, 2\)"):
        splinestep.solve(f, (0, 1), y0, 0 * y0, 0.1, iteration="newton",
                         jac=(sparse.identity(2), sparse.identity(2)))
    bad = sparse.identity(3, format="csr")
    bad.data[0] = np.nan
    with pytest.raises(ValueError, match="its dF/dyp at t = 0 is not"):
        splinestep.solve(f, (0, 1), y0, 0 * y0, 0.1, iteration="newton",
                         jac=lambda t, y, yp: (sparse.identity(3), bad))
    with pytest.raises(ValueError, match="jac must be None, a callable or a pair"):
        splinestep.solve(f, (0, 1), y0, 0 * y0, 0.1, iteration="newton", jac="sparse")
    res = splinestep.solve(f, (0, 1), y0, 0 * y0, 0.1, iteration="newton",
                           jac=lambda t, y, yp: (-sparse.identity(3), sparse.csr_matrix((3, 3))))
    assert res.success and np.allclose(res.y[:, -1], np.cos(1.0), atol=1e-3)


@pytest.mark.parametrize("value", [1, "no", None])
def test_check_option_is_validated(value):
    with pytest.raises(ValueError, match="check must be True or False"):
        splinestep.solve(lambda t, y, yp: -y, (0, 1), 1.0, 0.0, 0.1, check=value)


def test_check_false_skips_the_warning_and_its_evaluations():
    """y'' = -y at h = 1 over 20 units warns (the summed local errors); with
    check=False it does not, and spends no evaluation on the check (the
    local error estimate is still reported)."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        on = splinestep.solve(lambda t, y, yp: -y, (0, 20), 1.0, 0.0, 1.0)
        off = splinestep.solve(lambda t, y, yp: -y, (0, 20), 1.0, 0.0, 1.0, check=False)
    assert len([w for w in caught if "too large" in str(w.message)]) == 1
    assert "too large" in on.message and "too large" not in off.message
    assert on.nfev - off.nfev == 3 * 3 and off.local_error == on.local_error


@pytest.mark.parametrize("jac", ["sparse", None])
def test_the_scalable_check_sees_an_unstable_step_and_not_a_stable_one(jac):
    """m = 300 (above check.DENSE_UP_TO: Arnoldi steps) with Newton: at
    omega_m h = 3.3 (below sqrt(12), stable) the linearised step is not
    flagged; at omega_m h = 3.6 it is, with the sparse jac and with
    Jacobian-vector products of F."""
    for omega_h, expected in ((3.3, False), (3.6, True)):
        problem = problems.chain(300, omega_h=omega_h)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            res = short_run(problem, 8, "spline", iteration="newton",
                            jac=problem.jac if jac else None)
        assert res.success
        flagged = any("linearised equation grows" in str(w.message) for w in caught)
        assert flagged is expected, (omega_h, [str(w.message) for w in caught])


def test_the_fixed_point_sweep_converges_at_the_rounding_level_of_a_stiff_f():
    """m = 10,000 at omega_m h = 1 (contraction 1/6 per sweep): F = K y is
    known only to about eps (m + 1)^2 |y|, above the default tol = 1e-12 of
    the state, so the change stalls above the test.  The sweep now measures
    that level (one evaluation) and accepts the step: a few sweeps a step,
    not 50 and a failure."""
    res = short_run(problems.chain(10_000), 30, "spline", check=False)
    assert res.success, res.message
    assert res.nfev / res.nstep < 6


def test_messages_blame_the_contraction_condition_only_when_it_fails():
    """A sweep that diverges (omega h = 3, contraction 1.5) is told the
    condition; one that contracts but is cut off by max_iter is told to
    raise max_iter, with its measured factor."""
    f = lambda t, y, yp: -y   # noqa: E731
    diverging = splinestep.solve(f, (0, 3), 1.0, 0.0, 3.0, max_iter=20)
    assert diverging.status == -1
    assert "did not contract" in diverging.message and "converges when" in diverging.message
    short = splinestep.solve(f, (0, 3), 1.0, 0.0, 1.0, max_iter=3)
    assert short.status == -1 and "converge in 3 iterations" in short.message
    assert "contracted" in short.message and "raise max_iter" in short.message
    assert "did not contract" not in short.message


def test_the_first_adaptive_step_is_raised_to_the_rounding_floor():
    """Started where y is zero to rounding (a located event), scipy's rule
    of thumb gives a first step below the rounding floor, which stopped the
    run at once (status -1, 0 steps); raised to the floor it runs."""
    res = splinestep.solve(lambda t, y, yp: -9.81, (0, 8.15), 1.02e-14, 7.17, rtol=1e-6,
                           atol=1e-9)
    assert res.success and res.nstep > 10
    assert abs(res.y[0, -1] - (1.02e-14 + 7.17 * 8.15 - 9.81 * 8.15 ** 2 / 2)) < 1e-6


def test_a_bouncing_ball_restarted_at_each_bounce_matches_the_exact_bounce_times():
    """A ball dropped from 1 m (g = 9.81), restarted at each bounce (a
    terminal event) from the event's state with its velocity reversed and
    multiplied by e = 0.8: 40 bounces, each at the exact time to 1e-11 (it
    stopped after three when a restart's first step fell below the floor)."""
    g, e = 9.81, 0.8

    def ground(t, y, yp):
        return y[0]
    ground.terminal, ground.direction = True, -1
    t, y, v, times = 0.0, 1.0, 0.0, []
    while len(times) < 40:
        res = splinestep.solve(lambda t, y, yp: -g, (t, 10.0), y, v, rtol=1e-8, atol=1e-10,
                               events=ground)
        assert res.status == 1, res.message
        t, y, v = res.t_events[0][0], res.y_events[0][0][0], -e * res.yp_events[0][0][0]
        times.append(t)
    speed, exact = np.sqrt(2 * g), [np.sqrt(2 / g)]
    for _ in range(39):
        speed *= e
        exact.append(exact[-1] + 2 * speed / g)
    assert np.max(np.abs(np.array(times) - exact)) < 1e-11


def test_a_singular_sparse_newton_matrix_fails_with_where_and_why():
    """F = c y with c = 6 / h^2 makes Newton's matrix I - h^2/6 c I zero:
    SuperLU refuses it, and the run ends with status -1 saying at which
    step and why."""
    m, h = _linalg.SPARSE_FROM, 0.01
    c = 6.0 / h ** 2
    jac = (c * sparse.identity(m, format="csr"), sparse.csr_matrix((m, m)))
    res = splinestep.solve(lambda t, y, yp: c * y, (0.0, 0.1), np.ones(m), np.zeros(m), h,
                           iteration="newton", jac=jac, check=False)
    assert res.status == -1 and res.nstep == 0
    assert res.message.startswith("Step 1 (from t = 0 to t = 0.01) failed: Newton's matrix "
                                  "could not be built at t = 0.01: RuntimeError")


@pytest.mark.parametrize("h", [0.01, None], ids=["uniform", "adaptive"])
def test_knots_beyond_the_free_memory_end_the_run_with_status_minus_1(monkeypatch, h):
    """Storing every knot of a large system over a long span would exhaust
    the memory (m = 10,000 over a million steps: 240 GB): the run stops
    where the free memory is used (here 50 knots, as if no more were free)
    with status -1, the knots stored so far, which are those of the whole
    run, and a message that says to pass t_eval, not with a MemoryError."""
    from splinestep import driver
    problem = problems.chain(3)
    whole = splinestep.solve(problem.fun, (0, 5), problem.y0, problem.yp0, h, args=problem.args,
                             check=False)
    assert whole.success and whole.t.size > 60
    monkeypatch.setattr(driver, "max_knots", lambda m: 50)
    cut = splinestep.solve(problem.fun, (0, 5), problem.y0, problem.yp0, h, args=problem.args,
                           check=False)
    assert cut.status == -1 and "t_eval" in cut.message and "memory" in cut.message
    assert cut.t.size == 50 and np.array_equal(cut.t, whole.t[:50])
    assert np.array_equal(cut.y, whole.y[:, :50])
    # a cap of exactly the run's knots is room enough
    monkeypatch.setattr(driver, "max_knots", lambda m: whole.t.size)
    exact = splinestep.solve(problem.fun, (0, 5), problem.y0, problem.yp0, h,
                             args=problem.args, check=False)
    assert exact.status == 0 and np.array_equal(exact.y, whole.y)


@pytest.mark.skipif(not Path("/proc/self/status").exists(), reason="needs Linux's /proc")
def test_the_knot_cap_sees_an_address_space_limit():
    """Under ``ulimit -v`` (here 1 GiB above the process's size) the memory
    the machine has free is not what the process may allocate: driver.max_knots takes the smaller, so a run
    storing every knot stops with status -1 before the limit, not with a
    MemoryError from inside the loop."""
    import subprocess
    import sys
    code = ("import resource, numpy as np, splinestep\n"
            "from splinestep import driver, problems\n"
            "size = next(int(l.split()[1]) * 1024 for l in open('/proc/self/status')\n"
            "            if l.startswith('VmSize:'))\n"
            "resource.setrlimit(resource.RLIMIT_AS, (size + 2**30, resource.RLIM_INFINITY))\n"
            "p = problems.chain(2000)\n"
            "res = splinestep.solve(p.fun, p.t_span, p.y0, p.yp0, p.h, args=p.args, check=False)\n"
            "print(res.status, res.t.size, 'dense_output' in res.message)\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr[-2000:]
    status, knots, named = out.stdout.split()
    whole = int(np.ceil(problems.chain(2000).t_span[1] / problems.chain(2000).h)) + 1
    assert status == "-1" and named == "True" and 1000 < int(knots) < whole


def test_a_run_storing_its_knots_warns_nothing():
    """Reading what memory is free (driver.max_knots) leaves no file open:
    a run that warns nothing else emits no warning at all (a ResourceWarning
    would be taken for the step-size check's by a caller that records
    every warning, as notebook 01 does)."""
    problem = problems.chain(3)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        res = splinestep.solve(problem.fun, (0, 1), problem.y0, problem.yp0, 0.01,
                               args=problem.args)
    assert res.success and res.t.size == 101
    assert [str(w.message) for w in caught] == []
