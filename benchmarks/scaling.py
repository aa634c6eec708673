"""Cost against the number of equations: the chain of m masses on every path.

The problem is :func:`splinestep.problems.chain`: y'' = K y with K = (m +
1)^2 tridiag(1, -2, 1), both ends fixed, over 3.125 periods of the slowest
mode, at the step omega_m h = 1 (omega_m the fastest frequency; order 4
takes the same h), with the exact modal solution as reference.  For m = 10,
100, 1,000, 10,000 and 100,000 it measures each path of splinestep
(fixed-point sweep, RK4, Verlet, order 4, Newton with a dense and with a
sparse Jacobian; adaptive knots are benchmarks/controller.py's) and the
other members of Newmark's family
on their natural paths (Fox-Goodwin and central difference by the sweep;
average acceleration, HHT and generalized-alpha by Newton with SuperLU)
beside

- a numpy Newmark(1/6, 1/2) with scipy's ``splu`` (:func:`newmark`: the
  floor for a linear problem, one product with K and one sparse solve a
  step),
- scipy's DOP853 and its Radau given the sparse Jacobian of the first-order
  form (rtol 1e-6, atol 1e-9), stepped through their solver objects so
  that their steps are counted,

for the time per step (wall clock: the difference of runs of n and 2n
steps over their difference of steps, each the median of :data:`REPEATS`,
so that a run's fixed costs do not count, n doubled from
:data:`PROBE_STEPS` until the longer run takes :data:`TIMED` seconds;
a path that cannot be cut short: the whole run over its steps), the peak memory of a run
(``tracemalloc``, which sees numpy's and numba's allocations, over
:data:`MEMORY_STEPS` steps: with only the end reported no buffer grows
with the steps) and the largest error at the end against the exact
solution.  The end is at 3.125 periods of the slowest mode (:data:`PERIODS`),
6.25 of the second, whose phase error (eight times the first's for a
second-order method, relative to its amplitude) then shows in full: at a
whole number of periods from rest the phase errors cancel at the end (the
error there is 2.5 to 2e4 times below the largest over the span).  A run
whose whole span would take longer than :data:`BUDGET` seconds is left at the timed steps, its error left out with the reason; a
path that cannot run at that m is skipped with the reason.  splinestep's
runs here skip the step-too-large check (``check=False``), whose cost the
last table gives.  Two more tables: Newton with the sparse Jacobian densified for
the compiled LU against SuperLU (the crossover that
:data:`splinestep._linalg.SPARSE_FROM` encodes), and the step-too-large
check's share of a run (the fixed-point sweep's) at each m.

Prints the tables and writes them into the site's Speed page,
website/speed.md, between ``<!-- begin scaling -->`` and ``<!-- end
scaling -->``; ``--quick`` stops at m = 1,000 and leaves the page alone.
Run with ``make bench``.
"""

import os
import platform
import statistics
import sys
import time
import tracemalloc
import warnings

import numpy as np
from scipy import sparse
from scipy.integrate import DOP853, Radau
from scipy.sparse.linalg import splu

import splinestep
from splinestep import _linalg, spline
from splinestep import problems
from speed_page import write_section

SIZES = (10, 100, 1_000, 10_000, 100_000)
BUDGET = 60.0
# The span, in periods of the slowest mode (see the module's docstring).
PERIODS = 3.125
PROBE_STEPS = 4
MEMORY_STEPS = 5
REPEATS = 3
TIMED = 0.2
SCIPY_TOL = dict(rtol=1e-6, atol=1e-9)
DENSE_UP_TO = 2_000
CROSSOVER_SIZES = (10, 30, 60, 100, 150, 200, 300, 1_000)


def newmark(K, t_span, y0, yp0, h, steps=None):
    """Newmark's method with beta = 1/6, gamma = 1/2 (the linear
    acceleration method, which is the spline step) for y'' = K y, K sparse:
    I - dt^2/6 K factorised by SuperLU for each step size, then per step one
    product with K and one solve.  Steps of h from t_span[0], the last cut
    to end at t_span[1] (``steps`` of them instead, when given, past the
    span if need be).  Returns (steps taken, y at the end, the time
    reached)."""
    t0, tf = t_span if steps is None else (t_span[0], t_span[0] + steps * h)
    n = max(1, int(np.ceil((tf - t0) / h - 1e-9)))
    m = y0.size
    K = K.tocsr()
    lu, factored_for = None, None
    y, yp = np.array(y0, dtype=float), np.array(yp0, dtype=float)
    a = K @ y
    t = t0
    for _ in range(n):
        dt = min(h, tf - t)
        if dt != factored_for:
            lu = splu(sparse.identity(m, format="csc") - (dt * dt / 6.0) * K.tocsc())
            factored_for = dt
        base = y + dt * yp + (dt * dt / 3.0) * a
        a_new = lu.solve(K @ base)
        y = base + (dt * dt / 6.0) * a_new
        yp = yp + 0.5 * dt * (a + a_new)
        a = a_new
        t = tf if tf - t - dt <= 1e-9 * h else t + dt
    return n, y, t


def first_order(problem):
    """The chain as u' = (y', K y) for scipy, and its constant sparse
    Jacobian [[0, I], [K, 0]]."""
    m = problem.y0.size
    K = problems.chain_matrix(m)

    def system(t, u):
        return np.concatenate([u[m:], K @ u[:m]])
    return system, sparse.bmat([[None, sparse.identity(m)], [K, None]], format="csc")


def scipy_run(solver_class, problem, steps=None):
    """Steps of scipy's ``solver_class`` over the problem's span (``steps``
    of them instead, when given, past the span if need be): (steps taken, y
    at the last one, the time reached)."""
    system, J = first_order(problem)
    m = problem.y0.size
    options = dict(jac=J) if solver_class is Radau else {}
    t_bound = problem.t_span[1] * (1 if steps is None else 1e3)
    solver = solver_class(system, problem.t_span[0], np.concatenate([problem.y0, problem.yp0]),
                          t_bound, **SCIPY_TOL, **options)
    taken = 0
    while solver.status == "running" and (steps is None or taken < steps):
        message = solver.step()
        if solver.status == "failed":
            raise RuntimeError(message)
        taken += 1
    return taken, solver.y[:m], solver.t


def paths(problem):
    """{label: (run(steps) -> (steps, y at the end, time reached), why it is
    skipped or None, whether ``steps`` cuts the run short)}: steps=None runs
    the whole span.  splinestep runs without the step-too-large check,
    whose cost :func:`check_rows` measures apart."""
    p, m = problem, problem.y0.size

    def spline_run(steps, h=p.h, **options):
        end = p.t_span[1] if steps is None or h is None else steps * h
        res = splinestep.solve(p.fun, (p.t_span[0], end), p.y0, p.yp0, h, args=p.args,
                               t_eval=np.array([end]), check=False, **options)
        assert res.success, res.message
        return res.nstep, res.y[:, -1], end

    def baseline(name):
        def go(steps):
            end = p.t_span[1] if steps is None else steps * p.h
            res = getattr(splinestep, name)(p.fun, (p.t_span[0], end), p.y0, p.yp0, p.h,
                                            args=p.args, t_eval=np.array([end]))
            assert res.success, res.message
            return res.nstep, res.y[:, -1], end
        return go

    dense = (p.jac[0].toarray(), np.zeros((m, m))) if m <= DENSE_UP_TO else None
    return {
        "fixed-point sweep": (spline_run, None, True),
        "RK4": (baseline("rk4"), None, True),
        "Verlet": (baseline("verlet"), None, True),
        "order 4 (fixed point)": (lambda steps: spline_run(steps, order=4), None, True),
        "Newton, dense jac (compiled LU)": (
            lambda steps: spline_run(steps, iteration="newton", jac=dense),
            None if dense is not None else
            f"dense K: {8 * m * m / 2**30:.2g} GiB, its LU about {m ** 3 / 3:.1e} operations",
            True),
        "Newton, sparse jac": (
            lambda steps: spline_run(steps, iteration="newton", jac=p.jac), None, True),
        # Newmark's family, each member on its natural path: the explicit-like
        # members (beta < 1/4, stable at omega_m h = 1) by the sweep, the
        # unconditionally stable ones by Newton with SuperLU, the matrix
        # factorised once for the linear chain.
        "Fox-Goodwin (fixed point)": (
            lambda steps: spline_run(steps, method="fox-goodwin"), None, True),
        "central difference (fixed point)": (
            lambda steps: spline_run(steps, method="central-difference"), None, True),
        "average acceleration, sparse jac": (
            lambda steps: spline_run(steps, method="average-acceleration", iteration="newton",
                                     jac=p.jac), None, True),
        "HHT (alpha 0.1), sparse jac": (
            lambda steps: spline_run(steps, method="hht", iteration="newton", jac=p.jac),
            None, True),
        "generalized-alpha (rho 0.8), sparse jac": (
            lambda steps: spline_run(steps, method="generalized-alpha", iteration="newton",
                                     jac=p.jac), None, True),
        "numpy Newmark + splu (floor)": (
            lambda steps: newmark(p.jac[0], p.t_span, p.y0, p.yp0, p.h, steps), None, True),
        "scipy DOP853": (lambda steps: scipy_run(DOP853, p, steps), None, True),
        "scipy Radau, sparse jac": (lambda steps: scipy_run(Radau, p, steps), None, True),
    }


def median_time(run, repeats=REPEATS):
    times, out = [], None
    for _ in range(repeats):
        start = time.perf_counter()
        out = run()
        times.append(time.perf_counter() - start)
    return statistics.median(times), out


def peak_memory(run):
    """Peak bytes allocated by ``run()`` (tracemalloc)."""
    tracemalloc.start()
    try:
        run()
        return tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


def per_step(run):
    """(seconds per step, steps of the longer run, the time it reached):
    the difference of runs of n and 2n steps (past the problem's span if
    need be) divided by the difference of their steps, so that a run's
    fixed costs (checking its arguments, a first factorisation) do not
    count; n from :data:`PROBE_STEPS`, raised until the difference of the
    two runs is :data:`TIMED` / 2 seconds or more (the long run kept below
    :data:`BUDGET` / 4); single runs when they are long."""
    steps = PROBE_STEPS
    while True:
        short, (n_short, _, _) = median_time(lambda: run(steps), 1)
        repeats = REPEATS if 2 * short < 1.0 else 1
        if repeats > 1:
            short, (n_short, _, _) = median_time(lambda: run(steps), repeats)
        long, (n_long, _, t) = median_time(lambda: run(2 * steps), repeats)
        spent = long - short
        rate = max(spent, 0.0) / (n_long - n_short)
        if spent >= TIMED / 2 or steps >= 10**7 or 4 * long > BUDGET:
            return rate, n_long, t
        wanted = TIMED / (2 * rate) if rate > 0 else 4 * steps
        steps = int(min(max(2 * steps, 1.2 * wanted), BUDGET / (8 * rate) if rate > 0
                        else 4 * steps))


def measure(problem, run, truncatable):
    """(seconds per step, steps timed, peak bytes, error at the end or None,
    note) of one path on the problem."""
    t_end = problem.t_span[1]
    exact = problem.exact(np.array([t_end]))[0][:, 0]
    if not truncatable:   # whole runs: the first compiles (at the first m) or is long
        seconds, (steps, y, _) = median_time(lambda: run(None), 1)
        if seconds < BUDGET / 4:
            seconds, (steps, y, _) = median_time(lambda: run(None))
        memory = peak_memory(lambda: run(None))
        return seconds / steps, steps, memory, float(np.max(np.abs(y - exact))), ""
    run(MEMORY_STEPS)     # compile, load, warm up
    memory = peak_memory(lambda: run(MEMORY_STEPS))
    seconds, steps, t = per_step(run)
    estimate = seconds * steps * t_end / t
    if estimate > BUDGET:
        return (seconds, steps, memory, None,
                f"error not measured: the whole span, ~{steps * t_end / t:.2g} steps, would "
                f"take ~{estimate:.0f} s")
    _, (_, y, _) = median_time(lambda: run(None), 1)
    return seconds, steps, memory, float(np.max(np.abs(y - exact))), ""


def cost_rows(sizes):
    """One row per (path, m): the measurements of :func:`measure`, or the
    reason a path is skipped."""
    rows = []
    for m in sizes:
        problem = problems.chain(m, periods=PERIODS)
        for label, (run, skip, truncatable) in paths(problem).items():
            if skip is not None:
                rows.append((label, m, None, None, None, None, f"skipped: {skip}"))
                continue
            seconds, steps, memory, error, note = measure(problem, run, truncatable)
            rows.append((label, m, seconds, steps, memory, error, note))
            print(f"{label:<35} m = {m:>7,}: {seconds * 1e6:10.2f} us/step, "
                  f"{memory / 2**20:8.2f} MiB, error {error}", flush=True)
    return rows


def crossover_rows(sizes=CROSSOVER_SIZES):
    """Seconds per step of Newton with the chain's sparse Jacobian,
    densified for the compiled LU and factorised by SuperLU, at each m
    (:func:`per_step`)."""
    rows = []
    saved = _linalg.SPARSE_FROM
    try:
        for m in sizes:
            p = problems.chain(m, periods=PERIODS)
            times = []
            for threshold in (m + 1, m):   # densified, then SuperLU

                def run(steps):
                    _linalg.SPARSE_FROM = threshold
                    end = steps * p.h
                    res = splinestep.solve(p.fun, (0.0, end), p.y0, p.yp0, p.h, args=p.args,
                                           iteration="newton", jac=p.jac, check=False,
                                           t_eval=np.array([end]))
                    return res.nstep, res.y[:, -1], end
                run(PROBE_STEPS)
                times.append(per_step(run)[0])
            rows.append((m, *times))
    finally:
        _linalg.SPARSE_FROM = saved
    return rows


def check_rows(sizes):
    """(m, the step-too-large check's seconds, the whole run's) for the
    fixed-point sweep over the chain's whole span: the check timed inside a
    run, the run's steps from :func:`per_step` times their number."""
    rows = []
    report = spline._check.report
    spent = [0.0]

    def timed(*args, **kwargs):
        start = time.perf_counter()
        try:
            return report(*args, **kwargs)
        finally:
            spent[0] += time.perf_counter() - start
    spline._check.report = timed
    try:
        for m in sizes:
            p = problems.chain(m, periods=PERIODS)
            run = paths(p)["fixed-point sweep"][0]
            seconds, _, _ = per_step(run)
            steps = np.ceil(p.t_span[1] / p.h)
            splinestep.solve(p.fun, (0.0, 10 * p.h), p.y0, p.yp0, p.h, args=p.args,
                             t_eval=np.array([10 * p.h]))   # the check's first call
            spent[0] = 0.0
            splinestep.solve(p.fun, (0.0, 10 * p.h), p.y0, p.yp0, p.h, args=p.args,
                             t_eval=np.array([10 * p.h]))
            rows.append((m, spent[0], seconds * steps + spent[0]))
    finally:
        spline._check.report = report
    return rows


def table(header, rows):
    lines = ["| " + " | ".join(header) + " |",
             "|" + "|".join("---:" if i else "---" for i in range(len(header))) + "|"]
    return lines + ["| " + " | ".join(row) + " |" for row in rows]


def _time(seconds):
    return "-" if seconds is None else (f"{seconds * 1e6:.3g} us" if seconds < 1e-3
                                        else f"{seconds * 1e3:.3g} ms")


def _bytes(n):
    return "-" if n is None else (f"{n / 2**10:.0f} KiB" if n < 2**20 else f"{n / 2**20:.1f} MiB")


def render(rows, crossover, checks, sizes, machine):
    """The Markdown tables of the measurements."""
    lines = [f"Measured by `make bench` (benchmarks/scaling.py) on {machine}.", ""]
    labels = list(dict.fromkeys(r[0] for r in rows))
    cost = {(r[0], r[1]): r for r in rows}
    lines += ["**Time per step against m** (the chain, omega_m h = 1; per component in "
              "brackets, ns)", ""]
    body = []
    for label in labels:
        cells = []
        for m in sizes:
            r = cost[(label, m)]
            cells.append("skipped" if r[2] is None else
                         f"{_time(r[2])} ({r[2] / m * 1e9:.3g})")
        body.append([label] + cells)
    lines += table(["path"] + [f"m = {m:,}" for m in sizes], body) + [""]
    lines += ["**Every run**: steps timed, peak memory, largest error at the end against the "
              "exact modal solution", ""]
    body = []
    for label, m, per_step, steps, memory, error, note in rows:
        body.append([label, f"{m:,}", _time(per_step), "-" if steps is None else f"{steps:,}",
                     _bytes(memory), "-" if error is None else f"{error:.2g}", note])
    lines += table(["path", "m", "time per step", "steps timed", "peak memory", "error",
                    "note"], body) + [""]
    lines += ["**Newton with a sparse jac**: densified for the compiled LU, or factorised by "
              f"SuperLU (from m = {_linalg.SPARSE_FROM} by default)", ""]
    lines += table(["m", "dense compiled LU, per step", "SuperLU, per step", "ratio"],
                   [[f"{m:,}", _time(d), _time(s), f"{s / d:.2f}" if d > 0 else "-"]
                    for m, d, s in crossover])
    lines += ["", "**The step-too-large check's share** of the fixed-point sweep's run over "
              "the chain's whole span, the run's time its time per step times its steps (its "
              "fixed costs left out; at m = 10 and 100 they are about as large as the steps', "
              "so that there the check's share of a whole solve is smaller than the table's: "
              "see the paragraph above the tables)", ""]
    lines += table(["m", "check", "whole run", "share"],
                   [[f"{m:,}", f"{c:.3g} s", f"{w:.3g} s", f"{c / w:.2%}"]
                    for m, c, w in checks])
    return "\n".join(lines)


def main(quick=False):
    sizes = tuple(m for m in SIZES if not quick or m <= 1_000)
    machine = (f"{platform.machine()}, {os.cpu_count()} cores, Python "
               f"{platform.python_version()}, numpy {np.__version__}, "
               f"numba {__import__('numba').__version__}, "
               f"scipy {__import__('scipy').__version__}")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        rows = cost_rows(sizes)
        crossover = crossover_rows()
        checks = check_rows(sizes)
    text = render(rows, crossover, checks, sizes, machine)
    print(text)
    if not quick:
        write_section("scaling", text)
    return 0


if __name__ == "__main__":
    sys.exit(main(quick="--quick" in sys.argv))
