"""Speed of splinestep beside scipy, numba and C, in one run on one machine.

Prints one table (and writes it into the site's Speed page, website/speed.md,
between the markers ``<!-- begin bench -->`` and ``<!-- end bench -->``):

- time per right-hand-side evaluation of the compiled loops (splinestep's
  spline and RK4), against a C loop of the bare spline-step arithmetic
  (benchmarks/spline_step.c, compiled here with the system's C compiler) and
  the same arithmetic in numba (benchmarks/numba_reference.py), with the
  right-hand side inlined and through a function pointer, which splits the
  compiled loop's time into its parts;
- time per evaluation of the plain-Python paths for a right-hand side that
  returns an array, the way one writes it first, against scipy's solve_ivp
  (RK45, DOP853) on the same function;
- process times: importing splinestep, the first solve of a new process
  with numba's disk cache warm and with it empty, numba's own first-call
  cost, and the CPU seconds of compiling every path for a new compiled
  right-hand-side type (benchmarks/compile_time.py);
- the hot loop (Kepler, a fun returning an array and one returning a
  tuple) beside the same run with the package of commit 987c56f, whose
  loops were separate (before the one driver), extracted by ``git
  archive`` into build/;
- the two commands as a reader meets them: a fresh clone of the committed
  state (``git clone`` of this repository), ``make reproduce`` (which
  installs .venv from environment.txt, uv's and pip's download caches as
  they are, and
  compiles the loops into an empty numba cache), then ``make test``, then
  both again warm, then ``make test RERUN=1``; with each notebook's wall,
  CPU and compile seconds in the fresh clone's ``make reproduce`` and each
  test file's seconds.

Times are medians of several runs; ratios compare rows of the same run.
``python benchmarks/speed.py --quick`` skips the two commands and leaves
website/speed.md alone.  Run with ``make bench``.
"""

import os
import platform
import re
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
from numba import njit

from splinestep import problems

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path[:0] = [str(HERE), str(ROOT / "scripts")]
import compile_time  # noqa: E402
import numba_reference  # noqa: E402
from speed_page import write_section  # noqa: E402

SWEEPS = 2               # fixed-point sweeps per step in the compiled rows, as in C
COMPILED_STEPS = 1_000_000
PLAIN_STEPS = 20_000
REPEATS = 5
PLAIN_REPEATS = 3


def kepler_array(t, y, yp, mu):
    """The Kepler force as one writes it first: array in, array out."""
    return -mu * y / np.linalg.norm(y) ** 3


def rigid_array(t, w, wp, i1, i2, i3, beta):
    """The rigid body's w'' = alpha(w) w - beta w', array in, array out."""
    alpha = np.array([
        w[2] ** 2 * (i2 - i3) * (i3 - i1) / (i1 * i2) + w[1] ** 2 * (i2 - i3) * (i1 - i2) / (i1 * i3),
        w[0] ** 2 * (i3 - i1) * (i1 - i2) / (i2 * i3) + w[2] ** 2 * (i2 - i3) * (i3 - i1) / (i2 * i1),
        w[1] ** 2 * (i1 - i2) * (i2 - i3) / (i3 * i1) + w[0] ** 2 * (i1 - i2) * (i3 - i1) / (i3 * i2)])
    return alpha * w - beta * wp


@njit(cache=True)
def kepler_njit_array(t, y, yp, mu):
    """problems.kepler.kepler_rhs's arithmetic, returning a new array (as
    most compiled right-hand sides are written) instead of a tuple."""
    r2 = y[0] * y[0] + y[1] * y[1]
    w2 = mu / (r2 * np.sqrt(r2))
    out = np.empty(2)
    out[0] = -w2 * y[0]
    out[1] = -w2 * y[1]
    return out


@njit(cache=True)
def rigid_njit_array(t, w, wp, i1, i2, i3, beta):
    """problems.euler_top.rigid_body_rhs's arithmetic, returning an array."""
    out = np.empty(3)
    out[0] = (w[2] ** 2 * (i2 - i3) * (i3 - i1) / (i1 * i2)
              + w[1] ** 2 * (i2 - i3) * (i1 - i2) / (i1 * i3)) * w[0] - beta * wp[0]
    out[1] = (w[0] ** 2 * (i3 - i1) * (i1 - i2) / (i2 * i3)
              + w[2] ** 2 * (i2 - i3) * (i3 - i1) / (i2 * i1)) * w[1] - beta * wp[1]
    out[2] = (w[1] ** 2 * (i1 - i2) * (i2 - i3) / (i3 * i1)
              + w[0] ** 2 * (i1 - i2) * (i3 - i1) / (i3 * i2)) * w[2] - beta * wp[2]
    return out


CASES = {"kepler": (problems.cannonball(0.6), kepler_array, kepler_njit_array),
         "rigid": (problems.rigid_body("consistent"), rigid_array, rigid_njit_array)}


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


def compiled_rows(name, problem, njit_array, exe):
    """(label, evaluations, seconds) of the compiled loops, and the C time
    per evaluation (None without a C compiler)."""
    span, args = problem.t_span, problem.args
    t_eval = np.linspace(*span, 1000)
    h = (span[1] - span[0]) / COMPILED_STEPS

    def spline(fun=problem.fun):
        return splinestep.solve(fun, span, problem.y0, problem.yp0, h, args=args,
                                iterations=SWEEPS, t_eval=t_eval)

    def rk4():
        return splinestep.rk4(problem.fun, span, problem.y0, problem.yp0, h, args=args,
                              t_eval=t_eval)

    pointer = numba_reference.through_pointer(problem.fun, args)
    rows = []
    for label, run in (
            ("splinestep spline, compiled", lambda: spline().nfev),
            ("splinestep spline, compiled, fun returning an array",
             lambda: spline(njit_array).nfev),
            ("splinestep rk4, compiled", lambda: rk4().nfev),
            ("splinestep Verlet, compiled", lambda: splinestep.verlet(
                problem.fun, span, problem.y0, problem.yp0, h, args=args, t_eval=t_eval).nfev),
            ("numba, C's arithmetic, fun through a pointer", lambda: pointer(
                problem.fun, args, *span, COMPILED_STEPS, SWEEPS, problem.y0.copy(),
                problem.yp0.copy())),
            ("numba, C's arithmetic, fun inlined", lambda: numba_reference.INLINED(
                problem.fun, args, *span, COMPILED_STEPS, SWEEPS, problem.y0.copy(),
                problem.yp0.copy()))):
        run()  # compile (or load) outside the timing
        seconds, nfev = median_time(run, REPEATS)
        rows.append((label, nfev, seconds))
    c_per_eval = None
    if exe is not None:
        out = subprocess.run([str(exe), name, str(COMPILED_STEPS), str(SWEEPS), str(REPEATS)],
                             capture_output=True, text=True, check=True).stdout.split()
        ns_step, nfev = float(out[0]), int(out[1])
        c_final = np.array([float(v) for v in out[2:]])
        res = spline()
        final = np.concatenate([res.y[:, -1], res.yp[:, -1]])
        agree = np.max(np.abs(c_final - final)) / np.max(np.abs(final))
        if agree > 1e-10:
            raise RuntimeError(f"C and splinestep disagree: {agree:.1e}")
        rows.append(("C (gcc -O2 -march=native)", nfev, ns_step * COMPILED_STEPS * 1e-9))
        c_per_eval = ns_step * COMPILED_STEPS * 1e-9 / nfev
    return rows, c_per_eval


def plain_rows(problem, array_fun):
    """(label, evaluations, seconds) of the plain-Python paths."""
    span, args, m = problem.t_span, problem.args, problem.y0.size
    h = (span[1] - span[0]) / PLAIN_STEPS

    def first_order(t, u):
        return np.concatenate([u[m:], array_fun(t, u[:m], u[m:], *args)])

    rows = []
    for label, run in (
            ("splinestep spline, plain, array fun", lambda: splinestep.solve(
                array_fun, span, problem.y0, problem.yp0, h, args=args)),
            ("splinestep spline, plain, tuple fun", lambda: splinestep.solve(
                problem.fun.py_func, span, problem.y0, problem.yp0, h, args=args)),
            ("splinestep rk4, plain, array fun", lambda: splinestep.rk4(
                array_fun, span, problem.y0, problem.yp0, h, args=args)),
            ("scipy RK45, array fun (rtol 1e-8)", lambda: solve_ivp(
                first_order, span, np.concatenate([problem.y0, problem.yp0]), method="RK45",
                rtol=1e-8, atol=1e-10)),
            ("scipy DOP853, array fun (rtol 1e-8)", lambda: solve_ivp(
                first_order, span, np.concatenate([problem.y0, problem.yp0]), method="DOP853",
                rtol=1e-8, atol=1e-10))):
        seconds, res = median_time(run, PLAIN_REPEATS)
        assert res.success, res.message
        rows.append((label, res.nfev, seconds))
    return rows


FIRST_SOLVE = '''
import time
start = time.perf_counter()
import splinestep
from splinestep import problems
imported = time.perf_counter()
p = problems.cannonball(0.6)
start_solve = time.perf_counter()
p.solve("spline", h=1e-3)
solved = time.perf_counter()
p.solve("rk4", h=1e-3)
rk4_solved = time.perf_counter()
print(imported - start, solved - start_solve, rk4_solved - solved)
'''

NUMBA_FLOOR = '''
import time, numba, numpy, scipy.special
import floor_module
start = time.perf_counter()
floor_module.one(1.0)
print(time.perf_counter() - start)
'''


def new_process(code, env=None, path=()):
    env = dict(os.environ, **(env or {}))
    env["PYTHONPATH"] = os.pathsep.join([*path, str(HERE), env.get("PYTHONPATH", "")])
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True, env=env)
    return [float(v) for v in out.stdout.split()]


def process_rows():
    """(label, seconds) of process-level times."""
    rows = []
    warm = [new_process(FIRST_SOLVE) for _ in range(3)]
    imported, spline_s, rk4_s = (statistics.median(v) for v in zip(*warm))
    rows.append(("import splinestep (new process)", imported))
    rows.append(("first spline solve, new process, cache warm", spline_s))
    rows.append(("first rk4 solve, new process, cache warm", rk4_s))
    with tempfile.TemporaryDirectory() as folder:
        Path(folder, "floor_module.py").write_text(
            "from numba import njit\n@njit(cache=True)\ndef one(x):\n    return x + 1.0\n")
        new_process(NUMBA_FLOOR, path=[folder])
        floor = statistics.median(new_process(NUMBA_FLOOR, path=[folder])[0] for _ in range(3))
    rows.append(("numba's first call of any cached function", floor))
    with tempfile.TemporaryDirectory() as cache:
        _, cold_spline, cold_rk4 = new_process(FIRST_SOLVE, env={"NUMBA_CACHE_DIR": cache})
    rows.append(("first spline solve, cache empty (compiles the sweep's loop)", cold_spline))
    rows.append(("first rk4 solve after it (compiles the explicit loop)", cold_rk4))
    rows += compile_time.compile_rows()[0]
    return rows


def whole_trajectory_rows(repeats=5):
    """Seconds of the global Newton-LU sweep against the stepwise solve of
    the same knots, and of solve_bvp against scipy's on the Bratu problem,
    each pair timed side by side in this run."""
    from scipy.integrate import solve_bvp as scipy_bvp
    rows = []
    problem = problems.cannonball(0.6)
    problem.solve(iteration="global")   # compile and warm up
    stepwise, _ = median_time(lambda: problem.solve(iteration="newton"), repeats)
    whole, _ = median_time(lambda: problem.solve(iteration="global"), repeats)
    rows.append(["ellipse, 5000 steps: stepwise Newton", f"{stepwise * 1e3:.1f} ms", "1.00"])
    rows.append(["ellipse, 5000 steps: global Newton-LU sweep", f"{whole * 1e3:.1f} ms",
                 f"{whole / stepwise:.0f}"])
    fun, jac, args, _ = problems.bratu(1.0, "lower")
    for n in (41, 321):
        x = np.linspace(0.0, 1.0, n)
        ours, _ = median_time(lambda: splinestep.solve_bvp(fun, x, 0.0, 0.0, args=args,
                                                           tol=np.inf), repeats)
        theirs, _ = median_time(lambda: scipy_bvp(
            lambda s, u: np.vstack([u[1], -np.exp(u[0])]), lambda a, b: np.array([a[0], b[0]]),
            x, np.zeros((2, n)), tol=1e-8), repeats)
        rows.append([f"Bratu, {n} points: scipy solve_bvp (tol 1e-8)", f"{theirs * 1e3:.1f} ms",
                     "1.00"])
        rows.append([f"Bratu, {n} points: splinestep.solve_bvp (tol=inf: this mesh, no refinement)",
                     f"{ours * 1e3:.1f} ms",
                     f"{ours / theirs:.2f}"])
    return rows


def thread_rows(repeats=3):
    """Seconds of two long compiled solves (spline and Verlet, 3,000 orbits
    of the ellipse at h = 0.01) one after the other and in two threads: the
    loops release the GIL, so the pair takes about the longer of the two."""
    from concurrent.futures import ThreadPoolExecutor
    problem = problems.cannonball(0.6)
    t_end = 3000 * problems.orbit_elements(0.6)["period"]
    runs = (lambda: splinestep.solve(problem.fun, (0.0, t_end), problem.y0, problem.yp0, 0.01,
                                     args=problem.args, t_eval=np.array([t_end])),
            lambda: splinestep.verlet(problem.fun, (0.0, t_end), problem.y0, problem.yp0, 0.01,
                                      args=problem.args, t_eval=np.array([t_end])))

    def threaded():
        with ThreadPoolExecutor(2) as pool:
            return [future.result() for future in [pool.submit(run) for run in runs]]

    [run() for run in runs]   # compile
    one_by_one = min(median_time(lambda: [run() for run in runs], 1)[0] for _ in range(repeats))
    both = min(median_time(threaded, 1)[0] for _ in range(repeats))
    return [["ellipse, 3000 orbits: spline then Verlet, one thread", f"{one_by_one:.2f} s", "1.00"],
            ["ellipse, 3000 orbits: spline and Verlet in two threads", f"{both:.2f} s",
             f"{both / one_by_one:.2f}"]]


NOTEBOOK_LINE = re.compile(r"^notebooks/(\S+)\.py:\s+([\d.]+) s \(CPU ([\d.]+) s, of which "
                           r"compiling ([\d.]+) s\)$", re.M)


def command_rows():
    """The two commands on a fresh clone, then again with nothing changed
    (make reproduce then reruns nothing): rows (command, seconds) and
    {notebook: [seconds in the fresh clone's make reproduce]}."""
    env = {k: v for k, v in os.environ.items()
           if not k.startswith(("NUMBA_", "SPLINESTEP_", "VIRTUAL_ENV"))}
    runs = (("make reproduce, fresh clone: install, compile, run", "reproduce"),
            ("make test, right after (notebooks not run again)", "test"),
            ("make reproduce, again (nothing changed: nothing reruns)", "reproduce"),
            ("make test, again (warm)", "test"),
            ("make test RERUN=1 (every notebook under nbval too)", "test RERUN=1 JUNIT=1"))
    rows, notebooks, test_files = [], {}, {}
    with tempfile.TemporaryDirectory(prefix="splinestep-clone-") as folder:
        clone = Path(folder) / "splinestep"
        subprocess.run(["git", "clone", "--quiet", str(ROOT), str(clone)], check=True)
        for label, target in runs:
            start = time.perf_counter()
            done = subprocess.run(["make", *target.split()], cwd=clone, env=env,
                                  capture_output=True, text=True)
            seconds = time.perf_counter() - start
            if done.returncode:
                log = ROOT / "build" / f"bench-make-{target}.log"
                log.parent.mkdir(exist_ok=True)
                log.write_text(done.stdout + "\n" + done.stderr)
                raise RuntimeError(f"make {target} failed in the clone (its whole output: "
                                   f"{log}):\n{done.stdout[-3000:]}\n{done.stderr[-3000:]}")
            rows.append((label, seconds))
            for name, *values in NOTEBOOK_LINE.findall(done.stdout):
                notebooks.setdefault(name, []).append([float(v) for v in values])
            if "JUNIT=1" in target:
                test_files = seconds_per_test_file(clone / "build" / "junit.xml")
    rows.insert(2, ("both, fresh clone", rows[0][1] + rows[1][1]))
    return rows, notebooks, test_files


def seconds_per_test_file(junit):
    """{test file: (tests, seconds)} from pytest's JUnit XML (seconds summed
    over the two workers: CPU-bound, so about CPU seconds)."""
    import xml.etree.ElementTree as ET
    files = {}
    for case in ET.parse(junit).iter("testcase"):
        parts = case.get("classname", "").split(".")
        name = "/".join(parts[:2]) if parts[0] == "tests" else parts[0]
        count, seconds = files.get(name, (0, 0.0))
        files[name] = (count + 1, seconds + float(case.get("time", 0.0)))
    return dict(sorted(files.items(), key=lambda item: -item[1][1]))


# The hot loop beside the separate loops of commit 987c56f (before the one
# driver), the same script and right-hand sides in new processes, alternated.
REFERENCE_COMMIT = "987c56f"
HOT_LOOP = '''
import sys, time
import numpy as np
from numba import njit
import splinestep

@njit
def kepler_array(t, y, yp):
    r = np.sqrt(y[0] ** 2 + y[1] ** 2)
    return -y / r ** 3

@njit
def kepler_tuple(t, y, yp):
    r2 = y[0] * y[0] + y[1] * y[1]
    f = -1.0 / (r2 * np.sqrt(r2))
    return (f * y[0], f * y[1])

fun = kepler_array if sys.argv[1] == "array" else kepler_tuple
y0, v0, te = np.array([1.0, 0.0]), np.array([0.0, 1.0]), np.linspace(0.0, 1000.0, 11)
splinestep.solve(fun, (0, 1000), y0, v0, h=0.001, t_eval=te)
best = []
for _ in range(5):
    start = time.perf_counter()
    sol = splinestep.solve(fun, (0, 1000), y0, v0, h=0.001, t_eval=te)
    best.append(time.perf_counter() - start)
print(min(best) / sol.nfev)
'''


def reference_rows(rounds=3):
    """(label, ns per evaluation, ratio) of the Kepler run (h = 0.001, t in
    [0, 1000], 11 requested times, the step-size check on) with this
    package and with commit 987c56f's, for a fun returning an array and
    one returning a tuple; each the best of 5 solves in a new process,
    the median of ``rounds`` processes alternated with the other's."""
    folder = ROOT / "build" / f"bench-{REFERENCE_COMMIT}"
    if not (folder / "src").is_dir():
        folder.mkdir(parents=True, exist_ok=True)
        archive = subprocess.run(["git", "-C", str(ROOT), "archive", REFERENCE_COMMIT, "src"],
                                 capture_output=True)
        if archive.returncode:
            return [(f"commit {REFERENCE_COMMIT} not in this clone's history", None, None)]
        subprocess.run(["tar", "-x", "-C", str(folder)], input=archive.stdout, check=True)
    old_env = {"PYTHONPATH": str(folder / "src"), "NUMBA_CACHE_DIR": str(folder / "cache")}

    def per_eval(kind, env):
        out = subprocess.run([sys.executable, "-c", HOT_LOOP, kind], capture_output=True,
                             text=True, check=True, env=dict(os.environ, **env))
        return float(out.stdout.split()[-1])

    rows = []
    for kind in ("array", "tuple"):
        old, new = [], []
        for _ in range(rounds):
            old.append(per_eval(kind, old_env))
            new.append(per_eval(kind, {}))
        old, new = statistics.median(old), statistics.median(new)
        rows += [(f"fun returns {'an array' if kind == 'array' else 'a tuple'}: "
                  f"commit {REFERENCE_COMMIT} (separate loops)", old * 1e9, 1.0),
                 (f"fun returns {'an array' if kind == 'array' else 'a tuple'}: this package",
                  new * 1e9, new / old)]
    return rows


@njit
def _oscillator(t, y, yp):
    return (-y[0],)


def small_solve_rows(repeats=300):
    """(label, ms, ratio to RK45) of a small solve's whole cost: the
    oscillator y'' = -y over (0, 10) in 100 steps (h = 0.1) beside scipy's
    RK45 on the same problem at its default tolerances; the best of
    ``repeats`` calls each, alternated, after one call to compile or load."""
    runs = {
        "spline, compiled fun (step-size check on)":
            lambda: splinestep.solve(_oscillator, (0.0, 10.0), 1.0, 0.0, 0.1),
        "spline, compiled fun, check=False":
            lambda: splinestep.solve(_oscillator, (0.0, 10.0), 1.0, 0.0, 0.1, check=False),
        "rk4, compiled fun": lambda: splinestep.rk4(_oscillator, (0.0, 10.0), 1.0, 0.0, 0.1),
        "scipy RK45": lambda: solve_ivp(lambda t, u: [u[1], -u[0]], (0.0, 10.0), [1.0, 0.0]),
    }
    best = {label: np.inf for label in runs}
    for run in runs.values():
        run()
    for _ in range(repeats):
        for label, run in runs.items():
            start = time.perf_counter()
            run()
            best[label] = min(best[label], time.perf_counter() - start)
    rk45 = best["scipy RK45"]
    return [(label, seconds * 1e3, seconds / rk45) for label, seconds in best.items()]


GENERATED_FUN = """
from numba import njit
@njit(cache=True)
def f(t, y, yp, c):
    return ({body},)
"""

FIRST_GENERATED_SOLVE = """
import time, numpy as np
import splinestep, generated
start = time.process_time()
generated.f(0.0, np.ones({m}), np.zeros({m}), 0.1)   # numba's floor: f from its cache
floor = time.process_time()
splinestep.solve(generated.f, (0.0, 1.0), np.ones({m}), np.zeros({m}), 0.01, args=(0.1,))
print(floor - start, time.process_time() - floor)
"""


def generated_fun_rows(m=40):
    """(label, CPU seconds) of the first solve of a generated m-component
    ``fun`` (cache=True) in a new process: numba's floor (loading ``fun``
    from its cache) and the solve beyond it, with the adapter cache empty
    and warm (the median of three new processes)."""
    body = ", ".join(f"-(1.0 + {k} * 0.01) * y[{k}] - c * yp[{k}]" for k in range(m))
    with tempfile.TemporaryDirectory() as folder:
        Path(folder, "generated.py").write_text(GENERATED_FUN.format(body=body))
        env = {"SPLINESTEP_CACHE_DIR": str(Path(folder, "cache"))}
        code = FIRST_GENERATED_SOLVE.format(m=m)
        _, cold = new_process(code, env=env, path=[folder])
        warm = [new_process(code, env=env, path=[folder]) for _ in range(3)]
    floor, beyond = (statistics.median(v) for v in zip(*warm))
    return [(f"{m}-component generated fun: numba's floor (its first call, cached)", floor),
            (f"its first solve beyond that floor, adapter cache empty", cold),
            (f"its first solve beyond that floor, adapter cache warm", beyond)]


def table(header, rows):
    lines = ["| " + " | ".join(header) + " |",
             "|" + "|".join("---:" if i else "---" for i in range(len(header))) + "|"]
    return lines + ["| " + " | ".join(row) + " |" for row in rows]


def main(quick=False):
    machine = (f"{platform.machine()}, {os.cpu_count()} cores, Python "
               f"{platform.python_version()}, numpy {np.__version__}, "
               f"numba {__import__('numba').__version__}")
    exe = compile_c()
    lines = [f"Measured by `make bench` on {machine}.", ""]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # short compile runs are flagged, rightly
        for name, (problem, array_fun, njit_array) in CASES.items():
            compiled, c_per_eval = compiled_rows(name, problem, njit_array, exe)
            plain = plain_rows(problem, array_fun)
            rk45 = next(s / n for label, n, s in plain if label.startswith("scipy RK45"))
            rows = []
            for label, nfev, seconds in compiled:
                per = seconds / nfev
                rows.append([label, f"{nfev:,}", f"{per * 1e9:.1f} ns",
                             f"{per / c_per_eval:.2f} x C" if c_per_eval else "-"])
            for label, nfev, seconds in plain:
                per = seconds / nfev
                rows.append([label, f"{nfev:,}", f"{per * 1e6:.2f} us",
                             f"{per / rk45:.2f} x RK45"])
            lines += [f"**{problem.name}**, t in {problem.t_span}; compiled spline rows do "
                      f"{SWEEPS} fixed-point sweeps per step, as the C loop; plain spline rows "
                      "iterate to convergence", ""]
            lines += table(["implementation", "evaluations", "time per evaluation", "ratio"],
                           rows)
            lines.append("")
    lines += ["**Whole-trajectory solves** (each pair in the same run)", ""]
    lines += table(["solve", "time", "ratio to the first of its pair"],
                   whole_trajectory_rows() + thread_rows())
    lines.append("")
    lines += ["**The hot loop against the separate loops of commit 987c56f** (Kepler, "
              "h = 0.001, t in [0, 1000], 11 requested times; best of 5 solves per process, "
              "median of 3 processes, alternated)", ""]
    lines += table(["loop", "time per evaluation", "ratio to 987c56f"],
                   [[label, "-" if ns is None else f"{ns:.1f} ns",
                     "-" if ratio is None else f"{ratio:.3f}"]
                    for label, ns, ratio in reference_rows()])
    lines.append("")
    lines += ["**Small solves**: the oscillator y'' = -y over (0, 10) in 100 steps beside "
              "scipy's RK45 (default tolerances) on the same problem; best of 300 calls each, "
              "alternated", ""]
    lines += table(["solve", "time", "ratio to RK45"],
                   [[label, f"{ms:.3f} ms", f"{ratio:.2f}"]
                    for label, ms, ratio in small_solve_rows()])
    lines.append("")
    process = process_rows() + generated_fun_rows()
    lines += table(["process", "seconds"], [[label, f"{s:.2f}"] for label, s in process])
    if not quick:
        commands, notebooks, test_files = command_rows()
        lines += ["", "**The two commands** on a fresh clone of the committed state "
                  "(the download caches of uv and pip as they were)", ""]
        lines += table(["command", "seconds"], [[label, f"{s:.0f}"] for label, s in commands])
        lines += ["", "**Each notebook** in the fresh clone's `make reproduce` (two at a time; "
                  "12 and 14, which read the others' data, from the moment the others are done): "
                  "wall seconds, "
                  "its kernel's CPU seconds and the part of them numba spent compiling", ""]
        lines += table(["notebook", "wall, s", "CPU, s", "compiling, s"],
                       [[name, *(f"{v:.1f}" for v in values[0])]
                        for name, values in sorted(notebooks.items())])
        lines += ["", "**Each test file** in `make test RERUN=1` (seconds summed over its "
                  "tests, on two workers)", ""]
        lines += table(["test file", "tests", "seconds"],
                       [[name, str(count), f"{seconds:.1f}"]
                        for name, (count, seconds) in test_files.items()])
    text = "\n".join(lines)
    print(text)
    if not quick:
        write_section("bench", text)
    return 0


if __name__ == "__main__":
    sys.exit(main(quick="--quick" in sys.argv))
