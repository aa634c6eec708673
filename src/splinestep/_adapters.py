"""How a compiled loop calls the user's own compiled ``fun`` and ``jac``.

The step loops are compiled once per machine, for every right-hand side at
once: they call ``fun`` through a function of one fixed signature,
``adapter(t, y, yp, token) -> int64`` (and ``jac`` through one returning
two matrices).  ``token`` is the address of the run's buffer
(:class:`Buffer`), which holds, in this order:

- F's value, m floats, which the adapter writes and the loop reads
  (:func:`splinestep._base.evaluate`);
- a header of :data:`HEADER` 8-byte slots: the interrupt flag, the
  addresses of the user's compiled ``fun`` and ``jac``, and why a value was
  refused (what, at which t, of which shape);
- the extra arguments ``args``: numbers as they are (an int as int64, a
  float as float64, a bool as 0/1, a numpy scalar with its bits), an array
  as its address and shape, a tuple as its members, in order.

The adapter calls the user's function at the address in the header: the
machine code the user's dispatcher holds for these argument types, the code
a call from Python runs too (numba's first-class function call through its
``jit_addr``).  It is never a second compilation of the user's source, so
what numba does with globals, ``locals=``, ``recompile()`` and compile
options is what every call of the run does, at t0 and in every step alike.
Each array argument is the caller's own memory, read with its dtype and
shape; what the user's function changes in it, the caller sees.

An adapter is compiled once per *kind* of function: the numba type of the
user's function (its argument and return types) and the layout of ``args``
(their types, not their values nor their arrays' lengths).  Its source is
written as a module into the adapter cache folder (:func:`cache_folder`) and
compiled there with numba's on-disk cache, so a second process, and a second
function of the same kind, loads it instead of compiling it.  An adapter
holds no reference to any user function, so nothing the user made is kept
alive by it.

On every call the adapter checks what the loop will read: F's length and
shape, ``jac``'s two (m, m) shapes and finite values.  A refused value is
recorded in the header (what, t, shape), and the loop sees a value of the
wrong length (F) or NaN matrices (``jac``), as on the plain path; the front
door turns the record into the plain path's sentence (:meth:`Buffer.reason`).

References
----------
.. [1] numba documentation, "First-class function objects",
   https://numba.readthedocs.io/en/stable/reference/types.html
"""

import base64
import contextlib
import hashlib
import importlib.util
import numbers
import os
import pickle
import sys
import tempfile
import threading
import weakref
from pathlib import Path

import numpy as np
from numba import carray, njit, typeof, types
from numba.core import cgutils
from numba.core.errors import NumbaError
from numba.extending import intrinsic, overload

from ._base import Adapted, address_as, as_vector, float_pointer, wrong_length

# The header's slots, after F's m values.
INTERRUPT = 0      # set by the front door on Ctrl-C: the adapter stops the run
FUN_ADDRESS = 1    # the user's compiled fun (its jit address)
JAC_ADDRESS = 2    # the user's compiled jac, or 0
WHY = 3            # 0, or one of the codes below
WHEN = 4           # the t of the refused value (a float)
SHAPE = 5          # its number of dimensions, then up to two lengths (slots 6, 7)
PART = 8           # which of jac's matrices was refused (0: dF/dy, 1: dF/dyp)
HEADER = 9

FUN_SHAPE = 1      # fun returned a value of the wrong shape
JAC_SHAPE = 2      # jac returned a matrix of the wrong shape
JAC_NOT_FINITE = 3  # jac returned a matrix with a value that is not finite
INTERRUPTED = 4    # the run was interrupted (Ctrl-C)


# Integer addresses as pointers to int64, and as void pointers (numba.carray
# with a dtype).
int_pointer = address_as(types.CPointer(types.int64), "int_pointer")
void_pointer = address_as(types.voidptr, "void_pointer")


@intrinsic
def function_at(typingctx, function_type, address):
    """The first-class function of type ``function_type`` (a FunctionType,
    given as a global) whose compiled code is at ``address`` (its jit
    address: numba's calling convention, so an exception it raises reaches
    the caller)."""
    ftype = function_type.instance_type

    def codegen(context, builder, sig, args):
        value = cgutils.create_struct_proxy(ftype)(context, builder)
        pointer = context.get_value_type(types.voidptr)
        value.jit_addr = builder.inttoptr(args[1], pointer)
        value.c_addr = cgutils.get_null_value(pointer)
        value.py_addr = cgutils.get_null_value(pointer)
        return value._getvalue()
    return ftype(function_type, address), codegen


def record_shape(slots, m, t, g):
    """Record in the header that F's value ``g`` at t was refused (compiled
    code only)."""


@overload(record_shape)
def _record_shape(slots, m, t, g):
    def dims(g):
        return (1, len(g), 0)
    if isinstance(g, types.Array):
        if g.ndim == 0:
            def dims(g):
                return (0, 0, 0)
        elif g.ndim == 1:
            def dims(g):
                return (1, g.shape[0], 0)
        else:
            def dims(g):
                return (g.ndim, g.shape[0], g.shape[1])
    dims = njit(inline="always")(dims)

    def record(slots, m, t, g):
        ndim, n0, n1 = dims(g)
        slots[m + WHY] = FUN_SHAPE
        slots[m + WHEN] = _bits(t)
        slots[m + SHAPE], slots[m + SHAPE + 1], slots[m + SHAPE + 2] = ndim, n0, n1
    return record


@intrinsic
def _bits(typingctx, value):
    """The float64 ``value``'s 8 bytes as an int64 (to store it in a slot)."""
    signature = types.int64(types.float64)

    def codegen(context, builder, sig, args):
        return builder.bitcast(args[0], context.get_value_type(types.int64))
    return signature, codegen


def checked_matrix(slots, m, t, part, a):
    """``a`` as a C-ordered (m, m) float64 matrix, or NaN with the reason
    recorded in the header (compiled code only)."""


@overload(checked_matrix)
def _checked_matrix(slots, m, t, part, a):
    def refuse(slots, m, t, part, why, ndim, n0, n1):
        if part == 0 or slots[m + WHY] == 0:   # dF/dy's refusal is the one told
            slots[m + WHY] = why
            slots[m + WHEN] = _bits(t)
            slots[m + SHAPE], slots[m + SHAPE + 1], slots[m + SHAPE + 2] = ndim, n0, n1
            slots[m + PART] = part
        return np.full((m, m), np.nan)
    refuse = njit(inline="always")(refuse)

    if not (isinstance(a, types.Array) and isinstance(a.dtype, (types.Float, types.Integer))
            and a.ndim == 2):
        ndim = a.ndim if isinstance(a, types.Array) else -1
        return lambda slots, m, t, part, a: refuse(slots, m, t, part, JAC_SHAPE, ndim, 0, 0)
    same = a.layout == "C" and a.dtype == types.float64 and a.mutable

    def check(slots, m, t, part, a):
        if a.shape[0] != m or a.shape[1] != m:
            return refuse(slots, m, t, part, JAC_SHAPE, 2, a.shape[0], a.shape[1])
        for j in range(m):
            for k in range(m):
                if not abs(a[j, k]) < np.inf:
                    return refuse(slots, m, t, part, JAC_NOT_FINITE, 2, m, m)
        if same:
            return a
        out = np.empty((m, m))
        out[...] = a
        return out
    return check


# ----------------------------------------------------------------------------
# The layout of args in the buffer, and the expressions that read them back.

def _scalar_kind(value):
    """How a number travels in a slot: (its numba type's name, "f" for the
    float view or "i" for the int view), or None (not a number we pass)."""
    if isinstance(value, (bool, np.bool_)):
        return ("boolean", "i")
    if isinstance(value, np.generic):
        kind = value.dtype.kind
        if kind in "iu":
            return (value.dtype.name, "i")
        if kind == "f" and value.dtype.itemsize <= 8:
            return (value.dtype.name, "f")
        return None
    if isinstance(value, numbers.Integral):
        return ("int64", "i") if -2**63 <= value < 2**63 else None
    if isinstance(value, float):
        return ("float64", "f")
    return None


def layout(args):
    """(the layout of ``args``: a hashable tree of kinds, one per argument,
    each ("scalar", type, view), ("array", dtype, ndim) or ("tuple", kinds);
    the number of slots they take), or a ValueError naming what cannot be
    passed."""
    def kind(value, where):
        if isinstance(value, tuple) and hasattr(value, "_fields"):
            raise ValueError(f"{where} is a namedtuple ({type(value).__name__}), which a "
                             "compiled fun would be passed as a plain tuple: pass a tuple "
                             "and read it by index")
        if isinstance(value, tuple):
            return ("tuple", tuple(kind(v, f"{where}[{i}]") for i, v in enumerate(value)))
        if isinstance(value, np.ndarray):
            if value.dtype.kind not in "biuf" or value.dtype.itemsize > 8:
                raise ValueError(f"{where} is an array of dtype {value.dtype}, which a "
                                 "compiled fun cannot be passed here (pass a real, integer "
                                 "or boolean array)")
            return ("array", value.dtype.name, value.ndim)
        scalar = _scalar_kind(value)
        if scalar is None:
            raise ValueError(f"{where} is a {type(value).__name__} ({value!r:.40}); a compiled "
                             "fun takes numbers, numpy arrays, or tuples of them")
        return ("scalar",) + scalar
    kinds = tuple(kind(v, f"args[{i}]") for i, v in enumerate(args))
    return kinds, _count(kinds)


def _count(kinds):
    return sum(1 if k[0] == "scalar" else 1 + k[2] if k[0] == "array" else _count(k[1])
               for k in kinds)


def _expressions(kinds, offset=0):
    """(the source expression of each argument, read from the slots after
    the header, which start at ``m + HEADER + offset``; the slots used)."""
    out = []
    for kind in kinds:
        at = f"m + {HEADER + offset}"
        if kind[0] == "scalar":
            _, name, view = kind
            read = f"{'values' if view == 'f' else 'slots'}[{at}]"
            out.append(f"{read} != 0" if name == "boolean" else
                       read if name in ("float64", "int64") else f"np.{name}({read})")
            offset += 1
        elif kind[0] == "array":
            _, dtype, ndim = kind
            shape = "".join(f"slots[m + {HEADER + offset + 1 + d}], " for d in range(ndim))
            dtype = "bool_" if dtype == "bool" else dtype
            out.append(f"carray(void_pointer(slots[{at}]), ({shape}), np.{dtype})")
            offset += 1 + ndim
        else:
            inner, offset = _expressions(kind[1], offset)
            out.append("(" + "".join(e + ", " for e in inner) + ")")
    return out, offset


def _fill(slots, values, args, at):
    """Write ``args`` into the int and float views of the buffer from slot
    ``at`` on (the layout of :func:`layout`); returns the next slot."""
    for value in args:
        if isinstance(value, tuple):
            at = _fill(slots, values, value, at)
        elif isinstance(value, np.ndarray):
            slots[at] = value.ctypes.data
            slots[at + 1:at + 1 + value.ndim] = value.shape
            at += 1 + value.ndim
        else:
            _, view = _scalar_kind(value)
            if view == "f":   # a float32 travels as the float64 of the same value
                values[at] = float(value)
            else:   # an unsigned 64-bit integer as the int64 of the same bits
                slots[at] = np.asarray(value).astype(np.int64)
            at += 1
    return at


def passable(args):
    """``args`` as a compiled loop passes them: an array that is not
    C-contiguous or not writeable becomes a C-contiguous copy (the user's
    function is given that copy at t0 and in every step); the rest as they
    are.  A ValueError names an argument that cannot be passed."""
    def converted(value):
        if isinstance(value, tuple):
            return tuple(converted(v) for v in value)
        if isinstance(value, np.ndarray) and not value.dtype.isnative:
            value = value.astype(value.dtype.newbyteorder("="))
        if isinstance(value, np.ndarray) and not (value.flags.c_contiguous
                                                  and value.flags.writeable
                                                  and value.flags.aligned):
            return np.array(value, order="C")
        return value
    layout(args)   # the ValueError of what cannot be passed, named as given
    return tuple(converted(v) for v in args)


# ----------------------------------------------------------------------------
# The adapters' source, one module per kind of function, and its cache folder.

_PRELUDE = """\
# An adapter of splinestep, generated for one kind of compiled function.
# {stamp}
import base64, pickle
import numpy as np
from numba import carray, njit
from splinestep._adapters import (as_vector, checked_matrix, float_pointer, function_at,
                                  int_pointer, record_shape, void_pointer, wrong_length)
from splinestep._base import Adapted

FUNCTION = pickle.loads(base64.b64decode({function!r}))
"""

_BODY = {
    "fun": """
@njit(cache=True, nogil=True)
def adapted(t, y, yp, token):
    m = y.shape[0]
    values = carray(float_pointer(token), m + {size})
    slots = carray(int_pointer(token), m + {size})
    if slots[m + {interrupt}] != 0:
        slots[m + {why}] = {interrupted}
        return 1
    f = function_at(FUNCTION, slots[m + {address}])
    g = as_vector(f(t, y, yp{params}))
    if wrong_length(g, m):
        record_shape(slots, m, t, g)
        return 1
    for j in range(m):
        values[j] = g[j]
    return 0
""",
    "jac": """
@njit(cache=True, nogil=True)
def adapted(t, y, yp, token):
    m = y.shape[0]
    values = carray(float_pointer(token), m + {size})
    slots = carray(int_pointer(token), m + {size})
    if slots[m + {why}] == {jac_shape} or slots[m + {why}] == {jac_not_finite}:
        slots[m + {why}] = 0   # the last call's refusal is the one told
    f = function_at(FUNCTION, slots[m + {address}])
    fy, fyp = f(t, y, yp{params})
    return checked_matrix(slots, m, t, 0, fy), checked_matrix(slots, m, t, 1, fyp)
"""}


def cache_folder():
    """Where the adapters' modules and numba's cache of them are written:
    ``SPLINESTEP_CACHE_DIR``, else ``NUMBA_CACHE_DIR``/splinestep, else the
    user's cache folder (``XDG_CACHE_HOME`` or ~/.cache on Linux,
    ~/Library/Caches on macOS, ``LOCALAPPDATA`` on Windows)/splinestep,
    each with ``adapters`` below it; a temporary folder of this process when
    none of them can be written."""
    if os.environ.get("SPLINESTEP_CACHE_DIR"):
        base = Path(os.environ["SPLINESTEP_CACHE_DIR"])
    elif os.environ.get("NUMBA_CACHE_DIR"):
        base = Path(os.environ["NUMBA_CACHE_DIR"]) / "splinestep"
    elif sys.platform == "win32":   # pragma: no cover
        base = Path(os.environ.get("LOCALAPPDATA", Path.home())) / "splinestep"
    elif sys.platform == "darwin":   # pragma: no cover
        base = Path.home() / "Library" / "Caches" / "splinestep"
    else:
        base = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "splinestep"
    return base / "adapters"


_LOOPS_FOLDERS = {}


def loops_folder():
    """Where numba caches the package's compiled step loops: ``loops``
    beside :func:`cache_folder` (or a temporary folder of this process when
    that cannot be written).  Probed once per process and folder, not at
    each of the package's compiled functions."""
    wanted = cache_folder().parent / "loops"
    if wanted not in _LOOPS_FOLDERS:
        _LOOPS_FOLDERS[wanted] = _writable_folder(wanted)
    return _LOOPS_FOLDERS[wanted]


_TEMPORARY = []


def _writable_folder(folder=None):
    folder = cache_folder() if folder is None else folder
    try:
        folder.mkdir(parents=True, exist_ok=True)
        probe = tempfile.NamedTemporaryFile(dir=folder, delete=True)
        probe.close()
        return folder
    except OSError:
        if not _TEMPORARY:
            _TEMPORARY.append(Path(tempfile.mkdtemp(prefix="splinestep-cache-")))
        (_TEMPORARY[0] / folder.name).mkdir(exist_ok=True)
        return _TEMPORARY[0] / folder.name


def source(kind, function, kinds, stamp):
    """The module source of the ``kind`` ("fun" or "jac") adapter for a
    user function of numba type ``function`` and args of layout ``kinds``;
    ``stamp`` is that of the package code the adapter is made of (this
    module and those it imports: ``splinestep._compile.source_stamp``), so
    that a changed package never loads an adapter another version wrote."""
    params, size = _expressions(kinds)
    return _PRELUDE.format(stamp=stamp, function=base64.b64encode(pickle.dumps(function))) \
        + _BODY[kind].format(size=HEADER + size, interrupt=INTERRUPT, why=WHY,
                             interrupted=INTERRUPTED, jac_shape=JAC_SHAPE,
                             jac_not_finite=JAC_NOT_FINITE,
                             address=FUN_ADDRESS if kind == "fun" else JAC_ADDRESS,
                             params="".join(", " + p for p in params))


# A compilation (or a load from the cache) that takes longer than this, in
# seconds, is said on stderr, once per process: a load takes less.
COMPILE_NOTICE_AFTER = 2.0
_NOTICED = []


@contextlib.contextmanager
def compiling_notice():
    """Within it, numba compiles or loads from its cache; if that takes
    longer than :data:`COMPILE_NOTICE_AFTER` seconds, one line on stderr
    says what is happening (once per process; ``SPLINESTEP_QUIET=1``
    silences it)."""
    if _NOTICED or os.environ.get("SPLINESTEP_QUIET", "") not in ("", "0"):
        yield
        return
    timer = threading.Timer(COMPILE_NOTICE_AFTER, _notice)
    timer.daemon = True
    timer.start()
    try:
        yield
    finally:
        timer.cancel()


def _notice():
    if not _NOTICED:
        _NOTICED.append(True)
        print("splinestep: numba is compiling the step loops this run needs, once per user "
              f"and installation (20 s of CPU time or more), into {cache_folder().parent}; "
              "later runs load them (SPLINESTEP_QUIET=1 silences this line)",
              file=sys.stderr, flush=True)


_ADAPTERS = {}
_LOCK = threading.Lock()
FIXED = (types.float64, types.float64[::1], types.float64[::1], types.int64)


def _module(name, text, function):
    """The adapter defined by the module source ``text``, named ``name``:
    imported from the cache folder (written there first if absent), and
    compiled, or loaded from numba's cache beside it.  A module whose
    function type is not ``function`` (a type whose text names two types)
    is not used: the adapter is then compiled in this process alone."""
    folder = _writable_folder()
    path = folder / f"{name}.py"
    if not path.is_file():
        handle, temporary = tempfile.mkstemp(dir=folder, suffix=".tmp")
        with os.fdopen(handle, "w") as file:
            file.write(text)
        os.chmod(temporary, 0o644)
        os.replace(temporary, path)   # atomic: another process reads all or nothing
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module   # numba's cache finds the adapter's globals by its name
    spec.loader.exec_module(module)
    if module.FUNCTION != function:   # pragma: no cover - two types of one text
        module = type(sys)(name + "_here")
        exec(compile(text.replace("cache=True", "cache=False"), name, "exec"),
             module.__dict__)
    with compiling_notice():
        module.adapted.compile(FIXED)
    return module.adapted


def adapter(kind, function, kinds, stamp):
    """The ``kind`` adapter for a compiled function of numba type ``function``
    and args of layout ``kinds``: once per process and kind of function,
    loaded from the cache folder when another process compiled it."""
    key = (kind, function, kinds, stamp)
    with _LOCK:
        if key not in _ADAPTERS:
            text = source(kind, function, kinds, stamp)
            # named by what it is made of (the pickled type's bytes vary
            # between processes, its text does not)
            name = "splinestep_adapter_" + hashlib.sha256(
                repr((kind, str(function), kinds, stamp)).encode()).hexdigest()[:24]
            try:
                _ADAPTERS[key] = _module(name, text, function)
            except NumbaError as error:
                raise ValueError(_refusal(kind, function, error)) from error
        return _ADAPTERS[key]


def _refusal(kind, function, error):
    returned = function.signature.return_type
    if kind == "fun":
        return (f"fun is compiled to return {returned}, which is not m real numbers (an "
                f"array, a tuple of floats, or a number when m = 1): {str(error)[:300]}")
    return (f"jac is compiled to return {returned}, which is not two (m, m) matrices: "
            f"{str(error)[:300]}")


def signature_of(f, arg_types, name):
    """The numba type (a FunctionType) of the compiled ``f`` called as
    ``f(t, y, yp, *args)`` with ``args`` of numba types ``arg_types``: the
    signature a call from Python with these arguments runs.  Compiles ``f``
    for it if needed; a ValueError naming ``name`` when ``f``'s explicit
    signatures exclude it."""
    call = (types.float64, types.float64[::1], types.float64[::1], *arg_types)
    try:
        f.compile(call)
    except RuntimeError:   # explicit signatures only: compilation disabled
        pass
    except (NumbaError, TypeError) as error:
        raise ValueError(f"{name} cannot be compiled for (t, y, yp, *args) of types {call}: "
                         f"{str(error)[:300]}") from error
    for signature in f.nopython_signatures:
        if tuple(signature.args) == call:
            return types.FunctionType(signature.return_type(*call))
    raise ValueError(f"{name} is compiled with explicit signatures "
                     f"{[str(s) for s in f.nopython_signatures]}, none of them for the types "
                     f"a run calls it with, {call}: add that signature, or let numba compile "
                     "it lazily (njit without a signature)")


# dispatcher -> {argument types: (its compile result then, numba type,
# address)}: a run's lookups of the user's function, repeated only when the
# dispatcher holds another compilation (after ``recompile()``).  Weak: a
# function is not kept alive by having been run.
_TYPED = weakref.WeakKeyDictionary()


def typed(f, arg_types, name):
    """(the numba type of the compiled ``f`` called with args of numba types
    ``arg_types`` (:func:`signature_of`), the address of its machine code
    (:func:`jit_address`)) as the dispatcher holds them now."""
    call = (types.float64, types.float64[::1], types.float64[::1], *arg_types)
    known = _TYPED.setdefault(f, {}).get(arg_types)
    current = f.overloads.get(call)
    if known is not None and current is not None and known[0] is current:
        return known[1], known[2]
    function = signature_of(f, arg_types, name)
    address = jit_address(f, function)
    _TYPED[f][arg_types] = (f.overloads.get(call), function, address)
    return function, address


def jit_address(f, function):
    """The address of the machine code the dispatcher ``f`` holds now for the
    signature of ``function`` (numba's calling convention)."""
    result = f.get_compile_result(function.signature)
    return result.library.get_pointer_to_function(result.fndesc.llvm_func_name)


class Buffer:
    """The run's buffer (see the module's docstring): F's value, the
    header, and the packed ``args``; ``token`` is its address."""

    def __init__(self, m, args=(), n_slots=0):
        self.m = m
        self.values = np.zeros(m + HEADER + n_slots)
        self.slots = self.values.view(np.int64)
        self.args = args   # referenced while the run reads their memory
        if args:
            _fill(self.slots, self.values, args, m + HEADER)
        self.token = self.values.ctypes.data

    def interrupt(self):
        """Ask the run to stop at its next evaluation of fun."""
        self.slots[self.m + INTERRUPT] = 1

    @property
    def interrupted(self):
        return self.slots[self.m + WHY] == INTERRUPTED

    def reason(self):
        """The sentence for the value the adapter last refused, as the plain
        path says it, or None."""
        m, why = self.m, self.slots[self.m + WHY]
        if why in (0, INTERRUPTED):
            return None
        t = float(self.values[m + WHEN])
        ndim, n0, n1 = self.slots[m + SHAPE:m + SHAPE + 3]
        if why == FUN_SHAPE:
            shape = (() if ndim == 0 else (int(n0),) if ndim == 1 else
                     (int(n0), int(n1)) + ((Ellipsis,) if ndim > 2 else ()))
            shape = str(shape).replace("Ellipsis", "...")
            return (f"fun returned an array of shape {shape} at t = {t:.10g} (expected "
                    f"shape ({m},))")
        part = ("dF/dy", "dF/dyp")[int(self.slots[m + PART])]
        if why == JAC_NOT_FINITE:
            return (f"jac returned a value that is not finite in its {part} at "
                    f"t = {t:.10g}")
        got = (f"shape ({int(n0)}, {int(n1)})" if ndim == 2 else
               f"{int(ndim)} dimensions" if ndim >= 0 else "no array")
        return (f"jac did not return two arrays of shape ({m}, {m}) of real numbers at "
                f"t = {t:.10g} (its {part} has {got})")


def adapted_callables(fun, jac, args, m, stamp):
    """``(fun's adapter, jac's adapter or None, (Adapted(token),), buffer)``
    for a run of m equations whose compiled ``fun`` (and ``jac``) take
    ``args`` (:func:`passable`); ``stamp`` as for :func:`source`."""
    kinds, n_slots = layout(args)
    arg_types = tuple(typeof(a) for a in args)
    function, fun_address = typed(fun, arg_types, "fun")
    buffer = Buffer(m, args, n_slots)
    buffer.slots[m + FUN_ADDRESS] = fun_address
    fun_adapter = adapter("fun", function, kinds, stamp)
    jac_adapter = None
    if jac is not None:
        jac_function, jac_address = typed(jac, arg_types, "jac")
        buffer.slots[m + JAC_ADDRESS] = jac_address
        jac_adapter = adapter("jac", jac_function, kinds, stamp)
    return fun_adapter, jac_adapter, (Adapted(buffer.token),), buffer
