"""CPU seconds numba spends compiling the package's loops for a compiled
right-hand side of a type it has not met: every path once (uniform sweep,
Newton, Newton with jac, order 4, adaptive knots, time-reversible steps,
RK4, Verlet), in a new process.

In an empty numba cache the first type also compiles everything that does
not depend on ``fun`` (the first row); a second type then costs only what
is compiled per type (the second row).  ``python benchmarks/compile_time.py``
prints both with each path's share; :mod:`speed` puts the totals in the
bench table of website/speed.md.
"""

import os
import subprocess
import sys
import tempfile

CODE = r'''
import sys, time
import numpy as np
from numba import njit
import splinestep
extra = int(sys.argv[1])   # a number of extra arguments no run has compiled for
names = ", ".join(f"c{k}" for k in range(extra))
source = f"""
def rhs(t, y, yp, a, b, {names}):
    return (-a * y[0] - b * yp[0], -a * y[1])

def jac(t, y, yp, a, b, {names}):
    fy = np.zeros((2, 2))
    fyp = np.zeros((2, 2))
    fy[0, 0] = -a
    fy[1, 1] = -a
    fyp[0, 0] = -b
    return fy, fyp
"""
space = {"np": np}
exec(source, space)
rhs, jac = njit(space["rhs"]), njit(space["jac"])
y0, yp0, args = [1.0, 0.5], [0.0, 1.0], (1.0, 0.1) + (0.0,) * extra
paths = {
    "uniform sweep": lambda: splinestep.solve(rhs, (0, 1), y0, yp0, 0.1, args=args),
    "Newton": lambda: splinestep.solve(rhs, (0, 1), y0, yp0, 0.1, args=args,
                                       iteration="newton"),
    "Newton with jac": lambda: splinestep.solve(rhs, (0, 1), y0, yp0, 0.1, args=args,
                                                iteration="newton", jac=jac),
    "order 4": lambda: splinestep.solve(rhs, (0, 1), y0, yp0, 0.1, args=args, order=4),
    "adaptive": lambda: splinestep.solve(rhs, (0, 1), y0, yp0, args=args),
    "reversible": lambda: splinestep.solve_reversible(
        rhs, (0, 1), y0, yp0, 0.1, lambda t, y, yp, *a: 0.0, args=args),
    "rk4": lambda: splinestep.rk4(rhs, (0, 1), y0, yp0, 0.1, args=args),
    "verlet": lambda: splinestep.verlet(rhs, (0, 1), y0, yp0, 0.1, args=args),
}
for name, run in paths.items():
    start = time.process_time()
    res = run()
    assert res.success, res.message
    print(name, time.process_time() - start, sep="\t")
'''


def measure(cache, extra):
    """{path: CPU seconds} for a right-hand side with ``extra`` more
    arguments, in a new process using the numba cache folder ``cache``."""
    env = dict(os.environ, NUMBA_CACHE_DIR=cache)
    out = subprocess.run([sys.executable, "-c", CODE, str(extra)], env=env, check=True,
                         capture_output=True, text=True).stdout
    return {name: float(value) for name, value in
            (line.split("\t") for line in out.strip().splitlines())}


def compile_rows():
    """(label, CPU seconds) of the first and of a second compiled type, every path."""
    with tempfile.TemporaryDirectory() as cache:
        first = measure(cache, 0)
        second = measure(cache, 1)
    return [("first compiled fun type, every path (with and without jac), cache empty "
             "(CPU s)", sum(first.values())),
            ("a new compiled fun type, every path (with and without jac) (CPU s)",
             sum(second.values()))], first, second


if __name__ == "__main__":
    rows, first, second = compile_rows()
    for name in first:
        print(f"{name:16s} first {first[name]:6.2f}  new type {second[name]:6.2f}")
    for label, seconds in rows:
        print(f"{label}: {seconds:.1f}")
