"""Compile, or load from numba's disk cache, the package's three step loops
before the notebooks run (``make reproduce`` calls :func:`warm`): the whole
driver in one process, the sweep's and the explicit baselines' loops in
another, at once.  Every right-hand side whose extra arguments are numbers
or float arrays, and every plain one, runs these same loops, so the
notebooks that start together then load them instead of each compiling the
same loop at the same time.  With the cache warm it costs the two
processes' start-up."""

import os
import subprocess
import sys
import time


def _families():
    """{name: the solves that compile or load that family of loops}.  The
    package is imported here, in the child process only: the process that
    calls :func:`warm` later builds the website's API page from the
    package's docstrings as they are then."""
    import splinestep
    from numba import njit

    @njit
    def spring(t, y, yp, k):
        return (-k * y[0],)

    return {
        "driver": lambda: [splinestep.solve(spring, (0.0, 1.0), 1.0, 0.0, 0.1, args=(1.0,),
                                            iteration="newton")],
        "sweep and explicit": lambda: [
            splinestep.solve(spring, (0.0, 1.0), 1.0, 0.0, 0.1, args=(1.0,)),
            splinestep.rk4(spring, (0.0, 1.0), 1.0, 0.0, 0.1, args=(1.0,))],
    }


FAMILIES = ("driver", "sweep and explicit")


def warm():
    """Run each family's solves in its own process, all at once; returns
    the wall seconds.  A failure is raised with what the process printed."""
    start = time.perf_counter()
    processes = [subprocess.Popen([sys.executable, __file__, name], stdout=subprocess.PIPE,
                                  stderr=subprocess.STDOUT, text=True, env=os.environ.copy())
                 for name in FAMILIES]
    for process in processes:
        output, _ = process.communicate()
        if process.returncode:
            raise RuntimeError(f"compiling the step loops failed:\n{output}")
    return time.perf_counter() - start


if __name__ == "__main__":
    for result in _families()[sys.argv[1]]():
        assert result.success and result.path == "compiled", result.message
