"""The step loops compile once per machine: a new process, with a right-hand
side from a module it has never seen, loads them from numba's disk cache."""

import subprocess
import sys
import textwrap

from numba.core import types

import splinestep
from splinestep import _compile

RHS_MODULE = '''
from numba import njit

@njit
def rhs(t, y, yp, mu):
    r2 = y[0] * y[0] + y[1] * y[1]
    w2 = mu / (r2 * r2 ** 0.5)
    return (-w2 * y[0], -w2 * y[1])
'''

RUN = '''
import sys
sys.path.insert(0, {folder!r})
import splinestep
from splinestep import _compile
from {module} import rhs
for solver in (splinestep.solve, splinestep.rk4):
    res = solver(rhs, (0.0, 1.0), [1.0, 0.0], [0.0, 1.0], 0.01, args=(1.0,))
    assert res.success and res.path == "compiled", res.message
loops = list(_compile._LOOPS.values())
print(len(loops), sum(d.stats.cache_hits.total() for d in loops),
      sum(d.stats.cache_misses.total() for d in loops))
'''


def run_in_new_process(folder, module):
    code = textwrap.dedent(RUN.format(folder=str(folder), module=module))
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    return [int(v) for v in out.stdout.split()]


def test_a_second_process_and_a_renamed_module_load_the_loops_from_the_cache(tmp_path):
    (tmp_path / "first_module.py").write_text(RHS_MODULE)
    (tmp_path / "renamed_module.py").write_text(RHS_MODULE)
    run_in_new_process(tmp_path, "first_module")  # compiles, if no process has before
    for module in ("first_module", "renamed_module"):
        loops, hits, misses = run_in_new_process(tmp_path, module)
        assert loops == 2 and hits == 2 and misses == 0


def test_loop_signatures_name_no_python_function():
    """A loop typed on a function's identity would pickle that function's
    module into the cache index: only first-class signatures are allowed."""
    splinestep.solve(splinestep.problems.cannonball(0.6).fun, (0, 1), [1.0, 0.0], [0.0, 1.0],
                     0.1, args=(0.6,))
    assert _compile._LOOPS
    for (_, signature) in _compile._LOOPS:
        for argument in signature:
            assert not isinstance(argument, types.Dispatcher)
        assert isinstance(signature[0], types.FunctionType)
