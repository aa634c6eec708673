"""The compiled path cannot lie: it calls the user's own compiled function,
checks every value it reads, stops on Ctrl-C, passes args as numba types
them, and compiles an adapter once per kind of function and machine.  Each
test reproduces a way the path once gave a wrong answer with status 0, or
promised what it did not do (website/fast-path.md states what each test
backs)."""

import gc
import os
import signal
import subprocess
import sys
import textwrap
import time
import weakref
from pathlib import Path

import numpy as np
import pytest
from numba import float32, jit, njit

import splinestep
from splinestep import _adapters, _compile

ROOT = Path(__file__).resolve().parents[1]


def run_python(code, tmp_path, env=None, **kwargs):
    """``code`` run by this Python in a new process, in ``tmp_path``, with
    the adapter cache of this session (or ``env``'s)."""
    environment = {**os.environ, "PYTHONPATH": str(ROOT / "src"), **(env or {})}
    return subprocess.run([sys.executable, "-c", textwrap.dedent(code)], cwd=tmp_path,
                          env=environment, capture_output=True, text=True, timeout=600,
                          **kwargs)


# 1. A jac (or fun) whose shape changes after t0 -----------------------------

@njit
def _oscillators(t, y, yp):
    return -y


@njit
def _shrinking_jac(t, y, yp):
    n = y.shape[0] if t == 0.0 else 1   # right at t0, (1, 1) after
    return -np.eye(n), np.zeros((n, n))


def _shrinking_jac_plain(t, y, yp):
    n = y.shape[0] if t == 0.0 else 1
    return -np.eye(n), np.zeros((n, n))


@pytest.mark.parametrize("m", [3, 50])
def test_a_jac_whose_shape_changes_after_t0_fails_on_both_paths_with_one_message(m):
    """Read past the matrices' end, this run once reached the end with
    status 0 and an error of 0.04 against cos t; now the compiled run stops
    at the first step, as the plain one does, with the plain path's
    sentence."""
    runs = [splinestep.solve(f, (0.0, 10.0), np.ones(m), np.zeros(m), 0.01,
                             iteration="newton", jac=j)
            for f, j in ((_oscillators, _shrinking_jac),
                         (_oscillators.py_func, _shrinking_jac_plain))]
    said = (f"Step 1 (from t = 0 to t = 0.01) failed: jac did not return two arrays of shape "
            f"({m}, {m}) of real numbers at t = 0.01")
    for res in runs:
        assert res.status == -1 and not res.success
        assert res.message.startswith(said), res.message
        assert res.nstep == 0 and res.y.shape == (m, 1)
    assert [r.path for r in runs] == ["compiled", "plain"]


@njit
def _jac_empty_later(t, y, yp):
    n = y.shape[0] if t == 0.0 else 0
    return -np.eye(n), np.zeros((n, n))


@njit
def _jac_nan_later(t, y, yp):
    a = -np.eye(y.shape[0])
    if t > 0.0:   # the first Newton matrix (a linear problem's only one)
        a[0, 0] = np.nan
    return a, np.zeros_like(a)


def test_a_jac_returning_empty_or_nan_matrices_later_is_a_failure_not_finite_differences():
    empty = splinestep.solve(_oscillators, (0.0, 1.0), np.ones(2), np.zeros(2), 0.1,
                             iteration="newton", jac=_jac_empty_later)
    assert empty.status == -1 and "of shape (2, 2)" in empty.message
    assert "dF/dy has shape (0, 0)" in empty.message
    nan = splinestep.solve(_oscillators, (0.0, 1.0), np.ones(2), np.zeros(2), 0.1,
                           iteration="newton", jac=_jac_nan_later)
    assert nan.status == -1 and "jac returned a value that is not finite in its dF/dy" \
        in nan.message and "t = 0.1" in nan.message
    plain = splinestep.solve(_oscillators.py_func, (0.0, 1.0), np.ones(2), np.zeros(2), 0.1,
                             iteration="newton", jac=_jac_nan_later.py_func)
    assert plain.status == -1 and plain.message == nan.message


@njit
def _fun_shrinking(t, y, yp):
    return -y if t < 0.25 else -y[:1]


def test_a_fun_whose_length_changes_fails_on_every_path_with_the_plain_sentence():
    """F's length is checked at every evaluation, finite differences of
    Newton's matrix among them (which read F's m values)."""
    for options in (dict(), dict(iteration="newton"), dict(iteration="newton", rtol=1e-6)):
        h = None if "rtol" in options else 0.1
        runs = [splinestep.solve(f, (0.0, 1.0), np.ones(3), np.zeros(3), h, **options)
                for f in (_fun_shrinking, _fun_shrinking.py_func)]
        for res in runs:
            assert res.status == -1
            assert "fun returned an array of shape (1,) at t = " in res.message, res.message
            assert "(expected shape (3,))" in res.message
        assert runs[0].message == runs[1].message
    rk4 = splinestep.rk4(_fun_shrinking, (0.0, 1.0), np.ones(3), np.zeros(3), 0.1)
    assert rk4.status == -1 and "fun returned an array of shape (1,)" in rk4.message


# 2. One copy of the user's function ---------------------------------------

RECOMPILE = """
import numpy as np, splinestep
from numba import njit
K = 1.0
@njit
def f(t, y, yp):
    return -K * y
first = splinestep.solve(f, (0.0, 10.0), 1.0, 0.0, h=0.01)
K = 4.0
f.recompile()
second = splinestep.solve(f, (0.0, 10.0), 1.0, 0.0, h=0.01)
print(second.ypp[0, 0], abs(second.y[0, -1] - np.cos(20.0)), abs(first.y[0, -1] - np.cos(10.0)))
"""


def test_recompile_with_a_changed_global_runs_the_new_function_at_t0_and_in_every_step(
        tmp_path):
    """After ``K = 4; f.recompile()`` the run once used K = 4 at t0 and K = 1
    in every step (error 0.96); now both are the recompiled function:
    F(t0) = -4 and the error is the method's, O(h^2) (h^2/24 w^3 t = 0.013 at
    w = 2, t = 10 is the bound of the spline's phase error)."""
    out = run_python(RECOMPILE, tmp_path)
    assert out.returncode == 0, out.stderr
    ypp0, error_second, error_first = map(float, out.stdout.split())
    assert ypp0 == -4.0
    assert error_second < 0.0134 and error_first < 1e-3


GLOBAL_ARRAY = """
import numpy as np, splinestep
from numba import njit
W = np.array([1.0])
@njit
def f(t, y, yp):
    return -W[0] * y
f(0.0, np.ones(1), np.zeros(1))     # compiled now: numba freezes W's values
W[0] = 4.0                          # changed in place afterwards
res = splinestep.solve(f, (0.0, 10.0), 1.0, 0.0, h=0.01)
print(res.ypp[0, 0], f(0.0, np.ones(1), np.zeros(1))[0], abs(res.y[0, -1] - np.cos(10.0)))
"""


def test_a_global_array_changed_after_compiling_reads_as_numba_froze_it_everywhere(tmp_path):
    """numba freezes a global array's values when it compiles; the run, at
    t0 and in every step, sees what a direct call sees (W = 1): not the
    mixture of old and new values it once saw."""
    out = run_python(GLOBAL_ARRAY, tmp_path)
    assert out.returncode == 0, out.stderr
    ypp0, direct, error = map(float, out.stdout.split())
    assert ypp0 == direct == -1.0 and error < 1e-3


@njit(locals={"k": float32})
def _float32_spring(t, y, yp):
    k = 0.1 * y[0] + 1.0   # rounded to float32 by locals=
    return (-k * y[0],)


@njit("UniTuple(float64, 1)(float64, float64[::1], float64[::1])")
def _declared(t, y, yp):
    return (-y[0],)


def test_locals_and_explicit_signatures_are_the_users_compiled_code():
    """float32 rounding asked by ``locals=`` happens in every step as at t0:
    the run equals, bit for bit, the same steps with F evaluated by calls
    of the compiled function from Python (the plain path calling it); a
    function compiled for an explicit signature runs that signature."""
    compiled = splinestep.solve(_float32_spring, (0.0, 5.0), 1.0, 0.0, 0.01)
    called = splinestep.solve(lambda t, y, yp: _float32_spring(t, y, yp), (0.0, 5.0), 1.0,
                              0.0, 0.01)
    assert compiled.path == "compiled" and called.path == "plain"
    np.testing.assert_array_equal(compiled.y, called.y)
    np.testing.assert_array_equal(compiled.ypp, called.ypp)
    declared = splinestep.solve(_declared, (0.0, np.pi), 1.0, 0.0, np.pi / 100)
    assert declared.success and abs(declared.y[0, -1] + 1.0) < 1e-3


@njit("float64[::1](float64, float64[::1], float64[::1], float64)")
def _declared_float_arg(t, y, yp, k):
    return -k * y


def test_a_signature_that_excludes_the_runs_types_is_a_value_error_naming_fun():
    with pytest.raises(ValueError, match="fun is compiled with explicit signatures"):
        splinestep.solve(_declared_float_arg, (0.0, 1.0), 1.0, 0.0, 0.1, args=(2,))
    ok = splinestep.solve(_declared_float_arg, (0.0, 1.0), 1.0, 0.0, 0.1, args=(2.0,))
    assert ok.success and ok.path == "compiled"


def test_an_object_mode_function_runs_on_the_plain_path():
    @jit(forceobj=True)
    def f(t, y, yp):
        return -y
    res = splinestep.solve(f, (0.0, np.pi), 1.0, 0.0, np.pi / 100)
    assert res.path == "plain" and res.success and abs(res.y[0, -1] + 1.0) < 1e-3


# 3. Interruptible ---------------------------------------------------------

INTERRUPTED = """
import signal, sys, time, numpy as np, splinestep
from numba import njit
# Ctrl-C as in a terminal: a job started in the background without job
# control (make test &) passes SIGINT on ignored, and Python then keeps it so
signal.signal(signal.SIGINT, signal.default_int_handler)
@njit
def f(t, y, yp):
    return -y
fun = f if sys.argv[1] == "compiled" else f.py_func
splinestep.solve(fun, (0.0, 1.0), 1.0, 0.0, 0.1)        # compile or load first
print("ready", flush=True)
start = time.perf_counter()
try:
    res = splinestep.solve(fun, (0.0, 1e7), 1.0, 0.0, 0.1, t_eval=[1e7], check=False)
    print("finished", res.status, flush=True)
except KeyboardInterrupt:
    print("interrupted", time.perf_counter() - start, flush=True)
res = splinestep.solve(fun, (0.0, np.pi), 1.0, 0.0, np.pi / 100)
print("alive", res.status, abs(res.y[0, -1] + 1.0) < 1e-3, flush=True)
"""


@pytest.mark.parametrize("path", ["compiled", "plain"])
def test_ctrl_c_mid_solve_raises_keyboard_interrupt_and_the_process_goes_on(tmp_path, path):
    """SIGINT one second into a run of 10^8 steps (minutes) raises
    KeyboardInterrupt in the caller; the process then solves again.  (A
    compiled run once ended in a segmentation fault, a plain one in a
    TypeError.)"""
    script = tmp_path / "interrupted.py"
    script.write_text(INTERRUPTED)
    child = subprocess.Popen([sys.executable, str(script), path], stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True,
                             env=dict(os.environ, PYTHONPATH=str(ROOT / "src")))
    assert child.stdout.readline().strip() == "ready"
    time.sleep(1.0)
    child.send_signal(signal.SIGINT)
    out, err = child.communicate(timeout=300)
    assert child.returncode == 0, err
    lines = out.split("\n")
    assert lines[0].startswith("interrupted"), out + err
    assert lines[1] == "alive 0 True"


INTERRUPTED_EARLY = """
import signal, sys, threading, time, numpy as np, splinestep
from numba import njit
@njit
def f(t, y, yp):
    return -y
fun = f if sys.argv[1] == "compiled" else f.py_func
splinestep.solve(fun, (0.0, 1.0), 1.0, 0.0, 0.1, t_eval=[1.0], check=False)
start = time.perf_counter()
splinestep.solve(fun, (0.0, 1.0), 1.0, 0.0, 0.1, t_eval=[1.0], check=False)
setup = time.perf_counter() - start          # the front door's work before the loop runs

def interrupt(*_):
    raise KeyboardInterrupt

signal.signal(signal.SIGALRM, interrupt)
wrong = 0
for k in range(1, 61):
    try:
        signal.setitimer(signal.ITIMER_REAL, 2.0 * setup * k / 60)
        splinestep.solve(fun, (0.0, 1e7), 1.0, 0.0, 0.1, t_eval=[1e7], check=False)
    except KeyboardInterrupt:
        pass
    signal.setitimer(signal.ITIMER_REAL, 0.0)
    res = splinestep.solve(fun, (0.0, np.pi), 1.0, 0.0, np.pi / 100)
    wrong += res.status != 0 or not abs(res.y[0, -1] + 1.0) < 1e-3
time.sleep(0.5)
cpu, wall = time.process_time(), time.perf_counter()
time.sleep(1.0)                              # a run left going would spend this second
busy = (time.process_time() - cpu) / (time.perf_counter() - wall)
print(wrong, int(busy > 0.5), flush=True)
"""


@pytest.mark.parametrize("path", ["compiled", "plain"])
def test_an_interrupt_anywhere_in_the_front_door_leaves_no_run_behind(tmp_path, path):
    """An interrupt at 60 moments spread over twice the front door's own
    work (checks, the loop's lookup, the worker's start): each run stops,
    none keeps running (the process is idle the second after), and the
    next solve is right.  (A run interrupted inside ``Thread.start`` once
    went on writing into its freed buffer: the next solve returned wrong
    values with status 0, or the process hung; and a signal the kernel
    handed to the worker thread left the main thread asleep in its wait
    until the whole run of 10^8 steps had ended.)"""
    script = tmp_path / "interrupted_early.py"
    script.write_text(INTERRUPTED_EARLY)
    out = subprocess.run([sys.executable, str(script), path], capture_output=True, text=True,
                         timeout=120, env=dict(os.environ, PYTHONPATH=str(ROOT / "src")))
    assert out.returncode == 0, out.stderr
    assert out.stdout.split() == ["0", "0"]   # every solve right, no run left going


def test_ctrl_c_in_a_jupyter_kernel_interrupts_the_cell_and_the_kernel_survives():
    jupyter_client = pytest.importorskip("jupyter_client")
    manager, client = jupyter_client.manager.start_new_kernel(
        kernel_name="python3", env=dict(os.environ, PYTHONPATH=str(ROOT / "src")))
    try:
        warm = ("import numpy as np, splinestep\nfrom numba import njit\n"
                "f = njit(lambda t, y, yp: -y)\n"
                "splinestep.solve(f, (0.0, 1.0), 1.0, 0.0, 0.1).status")
        for _ in range(5):   # a request the kernel aborts while it starts up is sent again
            reply = client.execute_interactive(warm, timeout=300)["content"]
            if reply["status"] != "aborted":
                break
            time.sleep(1.0)
        assert reply["status"] == "ok", reply
        # stop_on_error=False: the kernel must not abort the request sent after the error
        message = client.execute("splinestep.solve(f, (0.0, 1e7), 1.0, 0.0, 0.1, "
                                 "t_eval=[1e7], check=False)", stop_on_error=False)
        time.sleep(2.0)
        manager.interrupt_kernel()
        reply = client.get_shell_msg(timeout=120)
        assert reply["parent_header"]["msg_id"] == message
        assert reply["content"]["status"] == "error"
        assert reply["content"]["ename"] == "KeyboardInterrupt"
        after = client.execute_interactive("splinestep.solve(f, (0.0, 1.0), 1.0, 0.0, "
                                           "0.1).status", timeout=120)
        assert after["content"]["status"] == "ok" and manager.is_alive()
    finally:
        client.stop_channels()
        manager.shutdown_kernel(now=True)


# 4. Adapters: once per kind of function and machine, nothing kept alive ----

GENERATED_MODULE = """
from numba import njit
@njit(cache=True)
def f(t, y, yp, c):
    return ({body},)
"""

SOLVE_IN_NEW_PROCESS = """
import time, numpy as np
start = time.process_time()
import splinestep
from splinestep import _adapters, _compile
import generated
imported = time.process_time()
generated.f(0.0, np.ones({m}), np.zeros({m}), 0.1)      # numba's floor: load f from its cache
floor = time.process_time()
res = splinestep.solve(generated.f, (0.0, 1.0), np.ones({m}), np.zeros({m}), 0.01, args=(0.1,))
solved = time.process_time()
(adapter,) = _adapters._ADAPTERS.values()
print(res.status, adapter.stats.cache_hits.get(adapter.signatures[0], 0),
      adapter.stats.cache_misses.get(adapter.signatures[0], 0), solved - floor)
"""


def test_a_cached_user_function_loads_its_adapter_in_a_new_process(tmp_path):
    """A 40-component generated ``fun`` with ``cache=True``: the first
    process compiles its adapter into the adapter cache, a second process
    loads it (numba's cache hit, no miss); its first solve's CPU seconds
    beyond loading ``fun`` itself are printed for make bench."""
    m = 40
    body = ", ".join(f"-(1.0 + {k} * 0.01) * y[{k}] - c * yp[{k}]" for k in range(m))
    (tmp_path / "generated.py").write_text(GENERATED_MODULE.format(body=body))
    env = {"SPLINESTEP_CACHE_DIR": str(tmp_path / "cache"), "PYTHONPATH":
           os.pathsep.join([str(ROOT / "src"), str(tmp_path)])}
    runs = [run_python(SOLVE_IN_NEW_PROCESS.format(m=m), tmp_path, env) for _ in range(2)]
    for out in runs:
        assert out.returncode == 0, out.stderr
    first, second = (out.stdout.split() for out in runs)
    assert first[:3] == ["0", "0", "1"]    # compiled in the first process
    assert second[:3] == ["0", "1", "0"]   # loaded in the second
    written = sorted(p.name for p in (tmp_path / "cache" / "adapters").glob("*.py"))
    assert len(written) == 1


def _factory(k):
    @njit
    def f(t, y, yp, scale):
        return -k * scale[0] * y
    return f


def test_functions_of_one_kind_share_an_adapter_and_die_with_their_last_reference():
    """40 functions from a factory share one adapter (one kind: the same
    argument and return types), arrays of any length among the args too;
    none of them is kept alive by the package once its run is over."""
    before = dict(_adapters._ADAPTERS)
    refs = []
    for k in range(40):
        f = _factory(float(k % 3 + 1))
        res = splinestep.solve(f, (0.0, 0.5), np.ones(2), np.zeros(2), 0.1,
                               args=(np.ones(k % 5 + 1),))
        assert res.success
        refs.append(weakref.ref(f))
        del f
    new = set(_adapters._ADAPTERS) - set(before)
    assert len(new) <= 1   # one kind (none when an earlier test made it)
    gc.collect()
    assert sum(ref() is not None for ref in refs) == 0


# 5. Arguments as numba sees them ------------------------------------------

@njit
def _indexed(t, y, yp, order, big, flags, pair):
    out = np.empty_like(y)
    offset = float(big - (big - 1))      # 1.0 exactly in int64; 0.0 after a float round trip
    for k in range(y.shape[0]):
        out[k] = -y[order[k]] * offset * (2.0 if flags[k] else 1.0) * pair[0] + pair[1]
    return out


def test_integer_and_boolean_arrays_big_integers_and_mixed_tuples_pass_with_their_types():
    args = (np.array([1, 0]), 2**62 + 1, np.array([True, False]), (1, 0.0))
    compiled = splinestep.solve(_indexed, (0.0, 1.0), [1.0, 2.0], [0.0, 0.0], 0.01, args=args)
    plain = splinestep.solve(_indexed.py_func, (0.0, 1.0), [1.0, 2.0], [0.0, 0.0], 0.01,
                             args=args)
    assert compiled.success and compiled.path == "compiled"
    assert compiled.ypp[:, 0].tolist() == [-4.0, -1.0]    # -2 y[1], -y[0]
    np.testing.assert_allclose(compiled.y, plain.y, rtol=1e-13, atol=1e-15)


@njit
def _counting(t, y, yp, calls):
    calls[0] += 1
    return -y


def test_an_array_in_args_is_the_callers_own_memory_in_every_call():
    """Every evaluation, the one at t0 and the step-size check's among them,
    reaches the caller's array, on both paths alike."""
    for fun in (_counting, _counting.py_func):
        calls = np.zeros(1, dtype=np.int64)
        res = splinestep.solve(fun, (0.0, 1.0), 1.0, 0.0, 0.1, args=(calls,), check=False)
        assert calls[0] == res.nfev
    strided = np.zeros(4, dtype=np.int64)[::2]   # not contiguous: a copy is passed
    res = splinestep.solve(_counting, (0.0, 1.0), 1.0, 0.0, 0.1, args=(strided,))
    assert res.success and strided[0] == 0


@njit
def _bool_value(t, y, yp):
    return y[0] > 10.0      # False: F = 0 while y stays below 10


@njit
def _zero_d(t, y, yp):
    return np.array(-y[0])


def test_a_bool_or_zero_d_array_returned_for_one_equation_runs_as_on_the_plain_path():
    for fun in (_bool_value, _zero_d):
        compiled = splinestep.solve(fun, (0.0, 1.0), 1.0, 0.5, 0.1)
        plain = splinestep.solve(fun.py_func, (0.0, 1.0), 1.0, 0.5, 0.1)
        assert compiled.success and plain.success and compiled.path == "compiled"
        np.testing.assert_allclose(compiled.y, plain.y, rtol=1e-14)


def test_args_no_compiled_function_can_take_are_a_value_error_naming_them():
    with pytest.raises(ValueError, match=r"args\[1\] is a str"):
        splinestep.solve(_counting, (0.0, 1.0), 1.0, 0.0, 0.1, args=(np.zeros(1), "x"))
    with pytest.raises(ValueError, match=r"args\[0\]\[1\] is a list"):
        splinestep.solve(_counting, (0.0, 1.0), 1.0, 0.0, 0.1, args=((1.0, [2.0]),))


@njit
def _after_tuples(t, y, yp, a, pair, c, nested, w, scale):
    return (-w * w * y[0] * scale[0] * a + pair[0] + pair[1] + c + nested[1][0]
            - nested[1][1][0],)


def test_arguments_after_a_tuple_are_read_from_their_own_slots():
    """A tuple before other arguments (a pair, then a nested mixed tuple
    holding an array, then numbers and an array): every argument is read
    where it was written, so the run is y'' = -4 y, whose solution is
    cos 2t (the sweep's error at h = 0.001 over (0, 2) is below 1e-5), and
    equal to the plain path's to rounding."""
    args = (1.0, (0.5, -0.5), 0.0, (np.float32(1.0), (3, np.array([3.0]))), 2.0,
            np.array([1.0]))
    compiled = splinestep.solve(_after_tuples, (0.0, 2.0), 1.0, 0.0, 1e-3, args=args)
    plain = splinestep.solve(_after_tuples.py_func, (0.0, 2.0), 1.0, 0.0, 1e-3, args=args)
    assert compiled.success and compiled.path == "compiled"
    assert np.max(np.abs(compiled.y[0] - np.cos(2.0 * compiled.t))) < 1e-5
    np.testing.assert_allclose(compiled.y, plain.y, rtol=0, atol=1e-13)
    rk4 = splinestep.rk4(_after_tuples, (0.0, 2.0), 1.0, 0.0, 1e-2, args=args)
    assert np.max(np.abs(rk4.y[0] - np.cos(2.0 * rk4.t))) < 1e-7


def test_a_namedtuple_is_refused_and_a_big_endian_array_is_passed_native():
    from collections import namedtuple
    Pair = namedtuple("Pair", "a b")
    with pytest.raises(ValueError, match=r"args\[0\] is a namedtuple"):
        splinestep.solve(_counting, (0.0, 1.0), 1.0, 0.0, 0.1, args=(Pair(1.0, 2.0),))
    swapped = np.array([1.0], dtype=">f8")
    res = splinestep.solve(_declared_float_arg.py_func, (0.0, 1.0), 1.0, 0.0, 0.1,
                           args=(1.0,))
    big = splinestep.solve(_scaled, (0.0, 1.0), 1.0, 0.0, 0.1, args=(swapped,))
    assert big.success and big.path == "compiled"
    np.testing.assert_allclose(big.y, res.y, rtol=1e-14)


@njit
def _scaled(t, y, yp, k):
    return -k[0] * y
