"""Compile each step loop once per machine, not once per function.

A numba loop that receives the right-hand side as an ordinary argument is
specialised on that function's identity: every new ``fun`` compiles the
whole loop again (seconds), and such a loop cannot be cached on disk, since
its cache index would pickle the type of a function from the caller's module.

Here a loop receives ``fun`` (and ``jac``) as a first-class function type,
``FunctionType(ret(float64, float64[::1], float64[::1], *args))``, which
names only the signature.  Every right-hand side reaches the loops through
functions of one such signature, ``(t, y, yp, token)``: a compiled one
through its adapter (:mod:`splinestep._adapters`), which calls the user's
own compiled code, a plain one through the trampolines into the
interpreter (:func:`python_callbacks`).  So the loops are compiled once per
machine for all of them, and numba's on-disk cache, keyed on that signature,
on the source file and on numba's version, serves every later process.  The
call through a function pointer cannot be inlined; ``make bench`` measures
its cost per evaluation.  A run started from the main thread runs in a
worker thread, so that Ctrl-C interrupts it (:func:`interruptible`).

numba stamps a cached function with the contents of its own source file
only, so a loop compiled with a constant from another module of the package
would outlive a change of that constant.  Here a function of the package is
stamped with the contents of its module and of every module of the package
that module imports, directly or not (:func:`source_stamp`): a change to any
of them recompiles it, a cache written by one version of that code is never
loaded by another, and an edit of a module it does not depend on (an
analysis module, a test problem it never calls) recompiles nothing.

References
----------
.. [1] numba documentation, "First-class function objects" and "Notes on
   caching", https://numba.readthedocs.io
"""

import _thread
import ast
import contextlib
import contextvars
import hashlib
import itertools
import threading
import time
from pathlib import Path

import numpy as np
from numba import njit, objmode, typeof, types
from numba.core import caching, event

from . import _adapters
from ._base import Adapted, is_adapted

# The parts of numba's on-disk cache (numba.core.caching) that this module
# extends: not all of them public, so each is checked here, and a numba
# without one is refused with a message rather than failing later.
NUMBA_CACHE_PARTS = ("CacheImpl._locator_classes", "IndexDataCacheFile.save",
                     "IndexDataCacheFile.load", "UserProvidedCacheLocator",
                     "_SourceFileBackedLocatorMixin.from_function")


def missing_numba_parts(module=caching):
    """The names of :data:`NUMBA_CACHE_PARTS` that ``module`` lacks."""
    def has(name):
        found = module
        for part in name.split("."):
            found = getattr(found, part, None)
            if found is None:
                return False
        return True
    return [name for name in NUMBA_CACHE_PARTS if not has(name)]


if missing_numba_parts():   # pragma: no cover (tests/test_install.py runs it in a subprocess)
    import numba
    raise ImportError(
        f"splinestep extends numba's on-disk cache, and numba {numba.__version__} lacks "
        f"numba.core.caching.{', numba.core.caching.'.join(missing_numba_parts())}; "
        f"splinestep is tested with numba 0.62 to 0.68 (pyproject.toml's bound)")


PACKAGE = Path(__file__).resolve().parent


def _module_files(base, parts):
    """The file of module ``parts`` below folder ``base``: ``x.py`` or ``x/__init__.py``."""
    target = base.joinpath(*parts)
    return [p for p in (target.with_suffix(".py"), target / "__init__.py") if p.is_file()]


def _import_statements(tree):
    """The import statements of a module, at any depth of its statements
    (in functions, classes, conditionals and handlers too); expressions,
    which hold no import statement, are not visited."""
    todo = [tree]
    while todo:
        node = todo.pop()
        if isinstance(node, (ast.Import, ast.ImportFrom)):
            yield node
        for field in ("body", "orelse", "finalbody", "handlers", "cases"):
            todo.extend(getattr(node, field, None) or ())


_IMPORTS = {}


def package_imports(path):
    """The files of this package that the module at ``path`` imports
    directly (``from .x import f``, ``from . import x``, ``from .. import
    problems``, ``import splinestep.x``).  Read once per process and
    version of the file (its size and modification time)."""
    path = Path(path)
    status = path.stat()
    key = (path, status.st_size, status.st_mtime_ns, PACKAGE)
    if key not in _IMPORTS:
        _IMPORTS[key] = _package_imports(path)
    return _IMPORTS[key]


def _package_imports(path):
    found = set()
    for node in _import_statements(ast.parse(path.read_bytes())):
        if isinstance(node, ast.Import):
            for alias in node.names:
                parts = alias.name.split(".")
                if parts[0] == PACKAGE.name:
                    found.update(_module_files(PACKAGE.parent, parts))
            continue
        if not isinstance(node, ast.ImportFrom):
            continue
        if node.level:
            base = path.parent
            for _ in range(node.level - 1):
                base = base.parent
        elif (node.module or "").split(".")[0] == PACKAGE.name:
            base = PACKAGE.parent
        else:
            continue
        parts = [p for p in (node.module or "").split(".") if p]
        submodules = [f for alias in node.names for f in _module_files(base, parts + [alias.name])]
        found.update(submodules)
        if parts or len(submodules) < len(node.names):   # names from a module or __init__
            found.update(_module_files(base, parts))
    return {f.resolve() for f in found if f.resolve().is_relative_to(PACKAGE)}


def dependencies(path):
    """The module at ``path`` and every module of the package it imports,
    directly or through others."""
    done, todo = set(), [Path(path).resolve()]
    while todo:
        current = todo.pop()
        if current not in done:
            done.add(current)
            todo.extend(package_imports(current) - done)
    return done


_STAMPS = {}


def source_stamp(path):
    """The stamp of the cached numba functions defined in the module at
    ``path``: the contents of that module and of every module of the
    package it imports (:func:`dependencies`), so that a constant changed
    in ``_base.py`` recompiles the loops that use it, and an edit of a
    module no compiled function depends on (an analysis module) recompiles
    nothing.  Computed once per process and module."""
    if path in _STAMPS:   # as given, before the file system is asked
        return _STAMPS[path]
    given, path = path, Path(path).resolve()
    if path not in _STAMPS:
        digest = hashlib.sha256()
        for file in sorted(dependencies(path)):
            digest.update(file.relative_to(PACKAGE).as_posix().encode() + b"\0")
            digest.update(file.read_bytes())
        _STAMPS[path] = digest.hexdigest()
    _STAMPS[given] = _STAMPS[path]
    return _STAMPS[path]


class _PackageStamp:
    """A numba cache locator mixin: functions of this package are stamped
    with the contents of their module and of the package's modules it
    imports (:func:`source_stamp`)."""

    def get_source_stamp(self):
        return source_stamp(self._py_file)

    @classmethod
    def from_function(cls, py_func, py_file):
        if not Path(py_file).resolve().is_relative_to(PACKAGE):
            return None
        return super().from_function(py_func, py_file)


class _UserCache(_PackageStamp, caching.UserProvidedCacheLocator):
    """The package's compiled loops in the user's cache folder
    (:func:`splinestep._adapters.loops_folder`: ``SPLINESTEP_CACHE_DIR``,
    ``NUMBA_CACHE_DIR``/splinestep or ~/.cache/splinestep, then ``loops``),
    never beside the installed source: an uninstall leaves nothing in the
    package's folder, and a read-only install compiles once per user."""

    def __init__(self, py_func, py_file):
        super().__init__(py_func, py_file)
        self._cache_path = str(_adapters.loops_folder() / self.get_suitable_cache_subpath(py_file))

    @classmethod
    def from_function(cls, py_func, py_file):
        if not Path(py_file).resolve().is_relative_to(PACKAGE):
            return None
        # numba's source-file check and writable folder, not its NUMBA_CACHE_DIR condition
        return super(caching.UserProvidedCacheLocator, cls).from_function(py_func, py_file)


class _CompileTime(event.Listener):
    """The CPU seconds numba spends compiling in this process (its
    "numba:compile" events, nested ones counted once; loading from the
    cache is not compiling), for make reproduce's per-notebook costs."""

    def __init__(self):
        self.depth, self.seconds, self.start = 0, 0.0, 0.0

    def on_start(self, event):
        if self.depth == 0:
            self.start = time.process_time()
        self.depth += 1

    def on_end(self, event):
        self.depth -= 1
        if self.depth == 0:
            self.seconds += time.process_time() - self.start


_COMPILING = _CompileTime()
event.register("numba:compile", _COMPILING)


def compile_seconds():
    """CPU seconds numba has spent compiling in this process so far."""
    return _COMPILING.seconds


# Tried first; other modules fall through to numba's own locators.
caching.CacheImpl._locator_classes[:0] = [_UserCache]


# numba saves a cache entry by reading the function's index, choosing a free
# data-file number, writing the index and then the data, with no lock between
# processes (numba issue #4807).  Two processes compiling the same loop for
# two signatures at once (pytest's workers, notebooks run side by side) can
# both choose number 1: the index then names one signature and the file holds
# the other's machine code, and the next process that loads it calls code
# compiled for other argument types (a segmentation fault).  For this
# package's functions, saving and loading hold a lock on the index, so each
# is one step as other processes see it.  Where the platform has no fcntl
# (Windows) or the file system no locks, numba's behaviour is kept: no lock.
try:
    import fcntl
except ImportError:   # pragma: no cover
    fcntl = None


@contextlib.contextmanager
def _index_locked(cache_file, mode):
    handle = _lock_file(cache_file) if fcntl is not None else None
    if handle is not None:
        try:
            fcntl.flock(handle, mode)
        except OSError:   # a file system without locks (some NFS, SMB, FUSE mounts)
            handle.close()
            handle = None
    if handle is None:   # numba's own behaviour: no lock
        yield
        return
    with handle:
        try:
            yield
        finally:
            fcntl.flock(handle, fcntl.LOCK_UN)


def _lock_file(cache_file):
    """The open lock file of a package function's cache index, or None (a
    function outside the package, or no cache folder yet: nothing to load).
    A lock file another user owns, which cannot be opened for writing, is
    locked through a read-only handle (flock does not need write access)."""
    if cache_file._source_stamp not in _STAMPS.values():
        return None
    path = cache_file._index_path + ".lock"
    for mode in ("a", "r"):
        try:
            return open(path, mode)
        except OSError:
            continue
    return None


_numba_save = caching.IndexDataCacheFile.save
_numba_load = caching.IndexDataCacheFile.load


def _save_locked(self, key, data):
    with _index_locked(self, fcntl.LOCK_EX if fcntl else None):
        return _numba_save(self, key, data)


def _load_locked(self, key):
    with _index_locked(self, fcntl.LOCK_SH if fcntl else None):
        return _numba_load(self, key)


caching.IndexDataCacheFile.save = _save_locked
caching.IndexDataCacheFile.load = _load_locked

VECTOR = types.float64[::1]
FLOAT = types.float64
INT = types.int64
BOOL = types.boolean
INT_VECTOR = types.int64[::1]

# (python loop, argument types) -> numba dispatcher compiled for those types
_LOOPS = {}
_LOOPS_LOCK = threading.Lock()


def function_type(f, arg_types):
    """The first-class type of the compiled function ``f`` called as
    ``f(t, y, yp, *args)``; compiles ``f`` for it if needed."""
    call = (FLOAT, VECTOR, VECTOR, *arg_types)
    f.compile(call)
    for signature in f.nopython_signatures:
        if tuple(signature.args) == call:
            return types.FunctionType(signature.return_type(*call))
    raise RuntimeError(f"{f} has no compiled version for {call}")  # pragma: no cover


def loop_types(fun, jac, args):
    """Types of the three leading arguments of every step loop:
    ``fun``, ``args`` and ``jac`` (None or a compiled function)."""
    args_type = typeof(args)
    arg_types = tuple(args_type) if len(args) else ()
    if is_adapted(args):
        arg_types = (INT,)   # fun(t, y, yp, token)
    fun_type = function_type(fun, arg_types)
    jac_type = types.none if jac is None else function_type(jac, arg_types)
    return fun_type, args_type, jac_type


def compiled(py_loop, arg_types):
    """``py_loop`` compiled (or loaded from the disk cache) for exactly
    ``arg_types``; one dispatcher per signature, kept for the process.

    A loop releases the GIL while it runs (``nogil``): two long solves in
    two threads proceed at once on two cores.  A plain-Python ``fun`` takes
    the GIL back for each of its calls (numba's objmode does), so only
    compiled right-hand sides run in parallel.  The generated arithmetic is
    the same with or without the flag."""
    key = (py_loop, tuple(arg_types))
    with _LOOPS_LOCK:   # two threads asking at once compile once
        if key not in _LOOPS:
            with _adapters.compiling_notice():
                _LOOPS[key] = njit(tuple(arg_types), cache=True, nogil=True)(py_loop)
        return _LOOPS[key]


# Plain-Python right-hand sides.  The compiled loop calls them through two
# compiled trampolines (cached like the loops), which switch to the
# interpreter for the call itself (numba's objmode) and find the Python
# function by a key passed as the loop's one argument.  So the loop runs
# compiled for every ``fun``, with no compilation per function, and a call
# costs the function itself plus the switch (``make bench`` measures it).
_FUNS = {}
_JACS = {}
_KEYS = itertools.count()


def _call_fun(key, t, y, yp):
    return _FUNS[key](t, y, yp)


def _call_jac(key, t, y, yp):
    return _JACS[key](t, y, yp)


@njit(cache=True)
def _python_fun(t, y, yp, token):
    # An adapter (_base.evaluate): the Python side writes F into the run's
    # buffer and returns 0, or 1 for a value of the wrong length.
    with objmode(status="int64"):
        status = _call_fun(token, t, y, yp)
    return status


def _call_scalar(key, t, y, yp):
    return float(_FUNS[key](t, y, yp))


@njit(cache=True)
def _python_scalar(t, y, yp, key):
    # Through a module function, as _python_fun: a global read inside the
    # object-mode block would be frozen into the on-disk cache.
    with objmode(g="float64"):
        g = _call_scalar(key, t, y, yp)
    return g


@njit(cache=True)
def _python_jac(t, y, yp, token):
    with objmode(fy="float64[:, ::1]", fyp="float64[:, ::1]"):
        fy, fyp = _call_jac(token, t, y, yp)
    return fy, fyp


# Why a plain ``fun`` or ``jac`` last returned a value the loop cannot use,
# by the key of its callbacks: the loop sees only a wrong shape or a NaN, the
# front door reads the sentence here (:func:`reason`) when the run failed
# with that code (an adaptive run may have recovered from an earlier one).
_REASONS = {}


def fun_value_reason(value, t, m):
    """None when ``value``, what a plain ``fun`` returned at t, is m real
    numbers (a scalar is the one component of m = 1); otherwise why not, as
    a run's message says it."""
    try:
        array = np.asarray(value)
    except (TypeError, ValueError):
        array = np.asarray(None)
    if value is None or array.dtype.kind not in "iufb":
        what = ("complex values" if array.dtype.kind == "c" else
                "None" if value is None else f"a {type(value).__name__}")
        return (f"fun returned {what} at t = {t:.10g} (it must return an array "
                f"of {m} real numbers)")
    if np.atleast_1d(array).shape != (m,):
        return (f"fun returned an array of shape {array.shape} at t = {t:.10g} (expected "
                f"shape ({m},))")
    return None


def jac_value_reason(value, t, m, finite=False):
    """None when ``value``, what a plain ``jac`` returned at t, is two (m, m)
    arrays of real numbers (``finite`` ones, when asked); otherwise why
    not."""
    try:
        parts = [np.asarray(part) for part in value]
    except TypeError:
        parts = []
    if len(parts) != 2 or any(part.ndim > 2 or part.dtype.kind not in "iuf"
                              or np.atleast_2d(part).shape != (m, m) for part in parts):
        return (f"jac did not return two arrays of shape ({m}, {m}) of real numbers at "
                f"t = {t:.10g}")
    for name, part in zip(("dF/dy", "dF/dyp"), parts):
        if finite and not np.all(np.isfinite(part)):
            return f"jac returned a value that is not finite in its {name} at t = {t:.10g}"
    return None


def _written(key, t, fun, args, y, yp, out, buffer):
    """The value of a plain ``fun`` at (t, y, yp) written into the run's
    buffer ``out``: 0.  What no step can use (:func:`fun_value_reason`) is
    not written: 1, which the loop reports as the wrong shape, and its
    reason is kept for the message.  After an interrupt, 1 without calling
    ``fun``."""
    if buffer.slots[buffer.m + _adapters.INTERRUPT]:
        buffer.slots[buffer.m + _adapters.WHY] = _adapters.INTERRUPTED
        return 1
    value = fun(t, y, yp, *args)
    reason = fun_value_reason(value, t, out.shape[0])
    if reason is not None:
        _REASONS[key] = reason
        return 1
    out[:] = np.atleast_1d(np.asarray(value).astype(np.float64))
    return 0


def _matrices(key, t, value, m):
    """(dF/dy, dF/dyp) of a plain ``jac`` as new (m, m) float arrays; what
    is not two such arrays (:func:`jac_value_reason`) becomes NaN, which the
    loop reports as a failed Newton solve, and its reason is kept for the
    message."""
    reason = jac_value_reason(value, t, m, finite=True)
    if reason is not None:
        _REASONS[key] = reason
        return np.full((m, m), np.nan), np.full((m, m), np.nan)
    return tuple(np.array(part, dtype=np.float64, ndmin=2) for part in value)


def reason(loop_args, buffer):
    """Why the run's ``fun`` or ``jac`` last returned a value the loop could
    not use, as the plain path says it, or None."""
    return _REASONS.pop(loop_args[0].token, None) or buffer.reason()


@contextlib.contextmanager
def python_callbacks(fun, jac, args, m):
    """Within the block, ``(fun, jac, args, buffer)`` for a step loop that
    calls the plain-Python ``fun`` and ``jac`` (or None) with ``args``, for
    m equations: the trampolines, of the adapters' signature
    (:func:`loop_callables`), whose token, the address of the run's
    :class:`splinestep._adapters.Buffer`, is also the key that finds the
    Python functions."""
    buffer = _adapters.Buffer(m)
    out, key = buffer.values[:m], buffer.token
    _FUNS[key] = lambda t, y, yp: _written(key, t, fun, args, y, yp, out, buffer)
    if jac is not None:
        _JACS[key] = lambda t, y, yp: _matrices(key, t, jac(t, y, yp, *args), m)
    try:
        yield (_python_fun, no_jacobian(1) if jac is None else _python_jac, (Adapted(key),),
               buffer)
    finally:
        _FUNS.pop(key, None)
        _JACS.pop(key, None)
        _REASONS.pop(key, None)


def scalar_callable(path, f, args):
    """A context giving a scalar function ``f(t, y, yp, *args)`` (a step-size
    control) in the form a compiled loop calls it: ``(f, args)`` when ``f``
    is compiled and the loop runs on the compiled path, else a trampoline
    into the interpreter and the number that finds ``f``.  Without ``f``
    (None), the trampoline with a key that finds nothing: the loop never
    calls it, and shares its compiled code with runs whose ``f`` is plain."""
    if f is None:
        return contextlib.nullcontext((_python_scalar, (-1.0,)))
    if path == "compiled" and isinstance(f, type(_python_scalar)):
        return contextlib.nullcontext((f, args))
    return _scalar_callback(f, args)


@contextlib.contextmanager
def _scalar_callback(f, args):
    key = float(next(_KEYS))
    _FUNS[key] = lambda t, y, yp: f(t, y, yp, *args)
    try:
        yield _python_scalar, (key,)
    finally:
        _FUNS.pop(key, None)


# Without a jac, the loop is given :func:`no_jacobian`'s function, which
# returns two empty matrices and has the type a jac of the same arguments
# returning two C-ordered matrices has: so the loop compiled for a ``fun``
# serves its runs with and without such a jac (one loop, not two).  The
# Newton step sees the empty matrices and takes finite differences (a given
# jac was checked at the start to return two (m, m) matrices, m >= 1, so it
# never returns empty ones).
_NO_JACOBIAN = {}
_NO_JACOBIAN_SOURCE = """
def no_jacobian(t, y, yp{params}):
    empty = np.empty((0, 0))
    return empty, empty
"""


def no_jacobian(n_args):
    """The compiled stand-in for a missing ``jac`` taking ``n_args`` extra
    arguments (one per arity, for the process; a few hundredths of a second
    to compile for a new type of arguments)."""
    if n_args not in _NO_JACOBIAN:
        space = {"np": np}
        params = "".join(f", a{k}" for k in range(n_args))
        exec(_NO_JACOBIAN_SOURCE.format(params=params), space)
        _NO_JACOBIAN[n_args] = njit(space["no_jacobian"])
    return _NO_JACOBIAN[n_args]


def loop_callables(path, fun, jac, args, m):
    """A context giving the ``(fun, jac, args, buffer)`` a step loop is
    called with, for m equations, and the run's
    :class:`splinestep._adapters.Buffer`: on the compiled path the adapters
    that call the user's own compiled ``fun`` and ``jac``
    (:func:`splinestep._adapters.adapted_callables`), on the plain path the
    trampolines into the interpreter; both of the one signature
    ``(t, y, yp, token)``, so that every right-hand side runs the same
    compiled loops.  Without a ``jac``, :func:`no_jacobian`'s stand-in."""
    if path == "plain":
        return python_callbacks(fun, jac, args, m)
    return _adapted_callables(fun, jac, args, m)


@contextlib.contextmanager
def _adapted_callables(fun, jac, args, m):
    fun_adapter, jac_adapter, loop_args, buffer = _adapters.adapted_callables(
        fun, jac, args, m, source_stamp(_adapters.__file__))
    # The loop runs while ``buffer`` (and the arrays of args) are referenced
    # here: the addresses in it stay valid.
    yield (fun_adapter, no_jacobian(1) if jac_adapter is None else jac_adapter, loop_args,
           buffer)


# Newton's matrices built outside the loop (a constant Jacobian, or one
# whose matrices are scipy.sparse): the Newton step asks the run's
# :class:`splinestep._linalg.Matrices`, found by its key, to build the matrix
# of a slot (factorised there by SuperLU, or written into the loop's dense
# buffer, which the loop factorises) and, when sparse, to solve with it.
# At m in the thousands the factorisation dominates such a call, so the
# switch to the interpreter costs nothing measurable there.
_MATRICES = {}


def _call_matrix(key, slot, t, y, yp, wy, wyp, lu):
    return _MATRICES[key].build(slot, t, y, yp, wy, wyp, lu)


def _call_solve(key, slot, b):
    _MATRICES[key].solve(slot, b)


@njit(cache=True)
def external_matrix(key, slot, t, y, yp, wy, wyp, lu):
    """(status, njev, contraction bound) of building slot ``slot``'s Newton
    matrix I - wy dF/dy - wyp dF/dy' at (t, y, yp) in Python."""
    with objmode(code="int64", njev="int64", bound="float64"):
        code, njev, bound = _call_matrix(key, slot, t, y, yp, wy, wyp, lu)
    return code, njev, bound


@njit(cache=True)
def external_solve(key, slot, b):
    """Solve with slot ``slot``'s matrix factorised in Python, in place."""
    with objmode():
        _call_solve(key, slot, b)


@contextlib.contextmanager
def external_matrices(builder):
    """Within the block, the key by which the loop finds ``builder`` (a
    :class:`splinestep._linalg.Matrices`; -1.0 for None: the loop builds its
    matrices itself)."""
    with _registered(_MATRICES, builder) as key:
        yield key


@contextlib.contextmanager
def _registered(registry, item):
    """Within the block, the key (a float, as the compiled loop passes it)
    under which ``item`` is in ``registry``; -1.0 for None."""
    if item is None:
        yield -1.0
        return
    key = float(next(_KEYS))
    registry[key] = item
    try:
        yield key
    finally:
        registry.pop(key, None)


# Events.  The driver calls :func:`python_events` after each accepted step;
# it finds the run's :class:`splinestep.events.Tracker` by its key and asks
# it whether the step holds a zero (1: a terminal one, whose time it returns
# and whose state it writes into ``out``; 2: an event function raised).
_TRACKERS = {}


def _call_events(key, t, t_new, kind, state, out):
    return _TRACKERS[key].step(t, t_new, kind, state, out)


@njit(cache=True)
def python_events(key, t, t_new, kind, state, out):
    with objmode(stop="int64", t_event="float64"):
        stop, t_event = _call_events(key, t, t_new, kind, state, out)
    return stop, t_event


@contextlib.contextmanager
def event_tracker(tracker):
    """Within the block, the key by which the driver finds ``tracker``
    (-1.0 for None: no events)."""
    with _registered(_TRACKERS, tracker) as key:
        yield key


# The main thread's wait on a run is cut into slices this long, at whose
# ends Python runs the handlers of signals any thread received.
POLL = 0.05


def interruptible(call, buffer):
    """``call()``, the run of a compiled loop, made interruptible: in the
    main thread it runs in a worker thread while the main thread waits, so
    that Ctrl-C (SIGINT) reaches Python at once.  The run is then told to
    stop (the flag in its ``buffer``, which the adapter and the plain
    trampoline read at every evaluation of fun), it ends at its next
    evaluation, and KeyboardInterrupt is raised here, in a script as in a
    Jupyter kernel, which survives.  In another thread (where no
    KeyboardInterrupt is delivered) ``call()`` runs where it is.  The
    worker runs in a copy of the caller's context (numpy's ``errstate`` is
    one; numpy before 2 keeps it per thread, and the worker takes the
    caller's), and what ``call()`` raises is raised here.

    The interrupt may arrive at any bytecode of the main thread, and the
    signal itself at any thread of the process (the kernel may hand it to
    the worker, which leaves the main thread asleep in its wait).  So the
    main thread waits in slices of :data:`POLL` seconds, at whose ends
    Python runs the handlers of the signals received; the worker is started
    by ``_thread.start_new_thread``, one call with no Python-level lock to
    be left held (``threading.Thread.start`` waits on an Event, whose lock
    an interrupt can leave taken); it says that it has finished in ``box``,
    not by a lock the main thread might already hold; and it holds the
    run's memory itself (``call``, whose closure references the loop's
    arrays, and ``buffer``, which references the packed ``args``): were it
    ever left running, it would stop at its first evaluation, since the
    flag is set whenever the wait ends by an exception, and write only into
    memory it keeps alive."""
    if threading.current_thread() is not threading.main_thread():
        return call()
    box = {}
    finished = _thread.allocate_lock()
    finished.acquire()
    context = contextvars.copy_context()   # numpy's errstate (numpy >= 2), among others
    errors = np.geterr()   # numpy < 2 keeps errstate per thread, not in the context

    def target(call=call, buffer=buffer):   # the worker's own references
        try:
            with np.errstate(**errors):
                box["out"] = context.run(call)
        except BaseException as error:   # re-raised in the caller's thread
            box["error"] = error
        finally:
            box["done"] = True
            finished.release()

    started = False
    try:
        started = _thread.start_new_thread(target, ()) is not None
        while not finished.acquire(timeout=POLL):
            pass
    except BaseException as error:
        buffer.interrupt()
        while started and "done" not in box:   # the worker ends at its next evaluation
            try:
                finished.acquire(timeout=POLL)
            except KeyboardInterrupt:
                pass
        if isinstance(error, KeyboardInterrupt):
            raise KeyboardInterrupt("the run was interrupted") from None
        raise
    if "error" in box:
        raise box["error"]
    return box["out"]


def _type_key(value):
    """What decides the numba type of a setting ``value`` (an array's dtype,
    dimensions and flags; a tuple's members; a number's kind), quicker to
    compute than ``numba.typeof``: the key of :data:`_DRIVER_TYPES`."""
    if isinstance(value, np.ndarray):
        flags = value.flags
        return (value.dtype.str, value.ndim, flags.c_contiguous, flags.f_contiguous,
                flags.writeable, flags.aligned)
    if isinstance(value, tuple):
        return (type(value), tuple(_type_key(v) for v in value))
    if isinstance(value, int) and not -2**63 <= value < 2**63:
        return (int, value > 0)
    return type(value)


# (driver, the loop's fun, jac and control, key of the settings' types) ->
# the argument types of the compiled driver: computed once per kind of run.
_DRIVER_TYPES = {}


def compiled_driver(drive, fun, jac, args, control, control_args, *records):
    """The driver compiled (or loaded from the disk cache) for the types of
    ``fun``, ``args``, ``jac``, ``control`` and the settings ``records``.
    ``fun`` and ``jac`` are the adapters or trampolines of one signature;
    the types are computed once per kind of run (:func:`_type_key`), not
    per solve."""
    key = None
    if control is _python_scalar:   # a user's compiled control is typed each time
        key = (drive, fun, jac, _type_key(args), _type_key(control_args),
               tuple(_type_key(r) for r in records))
    arg_types = _DRIVER_TYPES.get(key) if key is not None else None
    if arg_types is None:
        fun_type, args_type, jac_type = loop_types(fun, jac, args)
        control_type = function_type(control, tuple(typeof(control_args)))
        arg_types = ((fun_type, args_type, jac_type, control_type, typeof(control_args))
                     + tuple(typeof(r) for r in records))
        if key is not None:
            _DRIVER_TYPES[key] = arg_types
    return compiled(drive, arg_types)
