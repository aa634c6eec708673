"""Speed of splinestep beside scipy and a C loop, in one run on one machine.

For the Kepler case (mu = 0.6, t in [0, 50]) and the rigid body (consistent
rates, t in [0, 80]) it times, as medians of several runs: splinestep's
compiled and plain-Python loops, rk4 compiled and plain, scipy's solve_ivp
RK45 and DOP853 (plain-Python right-hand side, rtol 1e-8), and a C loop of
the same spline-step arithmetic (benchmarks/spline_step.c, compiled here
with the system's C compiler; skipped with a message when there is none).
The spline runs do SWEEPS fixed-point sweeps per step, like the C loop.
Plain-Python and scipy runs use fewer steps; time per evaluation is the
comparable figure.  Run with `make bench`.
"""

import os
import platform
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp

import splinestep
from splinestep import problems

HERE = Path(__file__).resolve().parent
SWEEPS = 2
COMPILED_STEPS = 1_000_000
PLAIN_STEPS = 20_000
REPEATS = 5
CASES = {"kepler": problems.cannonball(0.6), "rigid": problems.rigid_body("consistent")}


def median_time(run, repeats):
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        out = run()
        times.append(time.perf_counter() - start)
    return statistics.median(times), out


def compile_c():
    cc = shutil.which(os.environ.get("CC", "cc")) or shutil.which("gcc")
    if cc is None:
        return None
    exe = Path(tempfile.mkdtemp(prefix="splinestep-bench-")) / "spline_step"
    subprocess.run([cc, "-O2", "-march=native", "-o", str(exe), str(HERE / "spline_step.c"),
                    "-lm"], check=True)
    return exe


FIRST_CALL = '''
import time, splinestep
from splinestep import problems
p = problems.cannonball(0.6)
start = time.perf_counter()
p.solve("spline", h=1.0)
print(time.perf_counter() - start)
'''


def first_call_seconds():
    """Seconds of the first compiled solve in a new process (compilation
    included, imports excluded)."""
    out = subprocess.run([sys.executable, "-c", FIRST_CALL], capture_output=True, text=True,
                         check=True).stdout
    return float(out.split()[-1])


def main():
    print(f"machine: {platform.machine()}, {os.cpu_count()} cores, {platform.processor() or ''} "
          f"Python {platform.python_version()}, numpy {np.__version__}\n")
    exe = compile_c()
    if exe is None:
        print("no C compiler found: the C loop is skipped\n")
    for name, problem in CASES.items():
        span = problem.t_span
        t_eval = np.linspace(*span, 1000)
        rows = []

        def spline(fun, n):
            return lambda: splinestep.solve(fun, span, problem.y0, problem.yp0,
                                            (span[1] - span[0]) / n, args=problem.args,
                                            iterations=SWEEPS, t_eval=t_eval)

        def rk4(fun, n):
            return lambda: splinestep.rk4(fun, span, problem.y0, problem.yp0,
                                          (span[1] - span[0]) / n, args=problem.args,
                                          t_eval=t_eval)

        with warnings.catch_warnings():  # 10 steps are far too large: only to compile
            warnings.simplefilter("ignore")
            spline(problem.fun, 10)()  # compile outside the timing
            rk4(problem.fun, 10)()
        for label, run, n, repeats in (
                ("splinestep compiled", spline(problem.fun, COMPILED_STEPS), COMPILED_STEPS, REPEATS),
                ("splinestep plain Python", spline(problem.fun.py_func, PLAIN_STEPS), PLAIN_STEPS, 3),
                ("rk4 compiled", rk4(problem.fun, COMPILED_STEPS), COMPILED_STEPS, REPEATS),
                ("rk4 plain Python", rk4(problem.fun.py_func, PLAIN_STEPS), PLAIN_STEPS, 3)):
            seconds, res = median_time(run, repeats)
            assert res.success, res.message
            rows.append((label, res.nstep, res.nfev, seconds))
            if label == "splinestep compiled":
                final = np.concatenate([res.y[:, -1], res.yp[:, -1]])

        rhs, args, m = problem.fun.py_func, problem.args, problem.y0.size

        def first_order(t, u):
            return np.concatenate([u[m:], rhs(t, u[:m], u[m:], *args)])

        for method in ("RK45", "DOP853"):
            seconds, sol = median_time(lambda: solve_ivp(
                first_order, span, np.concatenate([problem.y0, problem.yp0]), method=method,
                rtol=1e-8, atol=1e-10), 3)
            rows.append((f"scipy solve_ivp {method}", sol.t.size - 1, sol.nfev, seconds))

        c_per_eval = None
        if exe is not None:
            out = subprocess.run([str(exe), name, str(COMPILED_STEPS), str(SWEEPS), str(REPEATS)],
                                 capture_output=True, text=True, check=True).stdout.split()
            ns_step, nfev = float(out[0]), int(out[1])
            c_final = np.array([float(v) for v in out[2:]])
            agree = np.max(np.abs(c_final - final)) / np.max(np.abs(final))
            rows.append(("C loop (gcc -O2 -march=native)", COMPILED_STEPS, nfev,
                         ns_step * COMPILED_STEPS * 1e-9))
            c_per_eval = ns_step * COMPILED_STEPS / nfev

        print(f"{problem.name}, t in {span}, {SWEEPS} fixed-point sweeps per spline step")
        print(f"{'implementation':<32} {'steps':>9} {'evaluations':>12} {'ns/step':>10} "
              f"{'ns/eval':>10} {'x C (per eval)':>15}")
        for label, steps, nfev, seconds in rows:
            per_eval = 1e9 * seconds / nfev
            ratio = f"{per_eval / c_per_eval:15.1f}" if c_per_eval else f"{'-':>15}"
            print(f"{label:<32} {steps:>9d} {nfev:>12d} {1e9 * seconds / steps:>10.1f} "
                  f"{per_eval:>10.1f} {ratio}")
        if exe is not None:
            print(f"C and compiled splinestep final states agree to {agree:.1e} (relative)")
        if name == "kepler":
            compile_s = first_call_seconds()
            per_step = {label: seconds / steps for label, steps, _, seconds in rows}
            saving = per_step["splinestep plain Python"] - per_step["splinestep compiled"]
            print(f"first compiled solve in a new process: {compile_s:.1f} s; compiling "
                  f"pays for runs of more than {compile_s / saving:.2g} steps")
        print()
    return 0


if __name__ == "__main__":
    sys.exit(main())
