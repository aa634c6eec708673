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
        # solve runs the sweep's loop, rk4 the explicit one: two loops, both
        # loaded from the cache for this signature
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


def test_a_cache_stamp_covers_the_modules_a_loop_imports_and_no_other(tmp_path, monkeypatch):
    """numba's own stamp covers a function's file only; ours covers the
    modules of the package it imports, directly or not: a constant changed
    in _base.py invalidates driver.py's loop, an edit of an analysis module
    or of a test problem invalidates nothing the loop is made of."""
    import shutil
    loop = splinestep.driver._drive
    locator = _compile._UserCache.from_function(loop, loop.__code__.co_filename)
    original = locator.get_source_stamp()
    assert original == _compile.source_stamp(_compile.PACKAGE / "driver.py")
    copy = tmp_path / "splinestep"
    shutil.copytree(_compile.PACKAGE, copy, ignore=shutil.ignore_patterns("__pycache__"))
    monkeypatch.setattr(_compile, "PACKAGE", copy)

    def stamps():
        monkeypatch.setattr(_compile, "_STAMPS", {})
        return {name: _compile.source_stamp(copy / name)
                for name in ("driver.py", "step.py", "analysis/conjugacy.py", "problems/chain.py")}

    def edited(name, old, new):
        path = copy / name
        text = path.read_text()
        assert old in text
        path.write_text(text.replace(old, new))
        return stamps()

    first = stamps()
    assert first["driver.py"] == original   # the copy stamps as the original
    theory = edited("analysis/theory.py", '"""The method', '"""An edit. The method')
    assert theory == first
    chain = edited("problems/chain.py", "import numpy as np", "import numpy as np  # an edit")
    assert {k: v for k, v in chain.items() if k != "problems/chain.py"} == \
        {k: v for k, v in first.items() if k != "problems/chain.py"}
    assert chain["problems/chain.py"] != first["problems/chain.py"]
    base = edited("_base.py", "SLIVER = 1e-9", "SLIVER = 1e-8")
    assert all(base[name] != chain[name] for name in base)   # every one imports _base


CONTROL_MODULE = '''
import numpy as np

def control(t, y, yp):
    return -1.5 * np.dot(y, yp) / np.dot(y, y)
'''

RUN_CONTROL = '''
import sys
sys.path.insert(0, {folder!r})
import splinestep
from {module} import control
res = splinestep.solve_reversible(lambda t, y, yp: -y / (y @ y) ** 1.5, (0.0, 6.0),
                                  [1.0, 0.0], [0.0, 1.0], 0.05, control)
assert res.success, res.message
print(res.nstep)
'''


def test_a_plain_control_is_not_frozen_into_the_cache(tmp_path):
    """A plain-Python step-size control from one process's module must not
    end up in numba's cache: a later process that never saw that module
    loads the same compiled loops (a global read inside the object-mode
    trampoline would have pickled the first process's function)."""
    counts = []
    for module in ("control_first", "control_second"):
        folder = tmp_path / module
        folder.mkdir()
        (folder / f"{module}.py").write_text(CONTROL_MODULE)
        code = textwrap.dedent(RUN_CONTROL.format(folder=str(folder), module=module))
        out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
        assert out.returncode == 0, out.stderr[-2000:]
        counts.append(int(out.stdout.split()[-1]))
    assert counts[0] == counts[1] > 0


def test_two_processes_saving_two_signatures_at_once_keep_each_its_own_code(tmp_path, monkeypatch):
    """numba's save reads the index, picks a free data-file number, writes
    the index, then the data, with no lock: two writers of one function's
    cache that both read the index before either writes it pick the same
    number, and one signature's entry is lost or names the other's code
    (numba issue #4807, a segfault on the next load).  Here the window after
    reading the index is held open while a second writer (a thread with its
    own lock handle, as another process has) saves another key; each key
    must load its own data."""
    import threading
    import time

    from numba.core import caching

    numba_load_index = caching.IndexDataCacheFile._load_index

    def slow_load_index(self):
        overloads = numba_load_index(self)
        time.sleep(0.2)
        return overloads

    monkeypatch.setattr(caching.IndexDataCacheFile, "_load_index", slow_load_index)

    def cache_file():
        return caching.IndexDataCacheFile(str(tmp_path), "loop",
                                           _compile.source_stamp(_compile.PACKAGE / "driver.py"))

    def save(key):
        cache_file().save(key, ("code for", key))

    writers = [threading.Thread(target=save, args=(key,)) for key in ("a", "b")]
    for writer in writers:
        writer.start()
        time.sleep(0.05)
    for writer in writers:
        writer.join()
    assert [cache_file().load(key) for key in ("a", "b")] == [("code for", "a"),
                                                              ("code for", "b")]


def test_a_file_system_without_locks_saves_and_loads_as_numba_does(tmp_path, monkeypatch):
    """Where flock fails (some NFS, SMB or FUSE mounts: ENOLCK), the cache
    is saved and loaded without a lock, as numba itself does, not refused."""
    import errno

    from numba.core import caching

    def no_locks(handle, mode):
        raise OSError(errno.ENOLCK, "No locks available")

    monkeypatch.setattr(_compile.fcntl, "flock", no_locks)
    cache_file = caching.IndexDataCacheFile(str(tmp_path), "loop",
                                           _compile.source_stamp(_compile.PACKAGE / "driver.py"))
    cache_file.save("key", ("code for", "key"))
    assert cache_file.load("key") == ("code for", "key")
