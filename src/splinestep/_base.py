"""What the front doors share: argument validation (in one place, as
scipy's ``_ivp/common.py``), the step grid, and the choice between the
compiled and the plain-Python path."""

import ctypes
import numbers
import sys
import warnings
from typing import NamedTuple

import numpy as np
from numba import carray, typeof
from numba.core import types
from numba.core.registry import CPUDispatcher
from numba.extending import intrinsic, overload

from .status import short

# A last step shorter than this fraction of h is merged into the one before
# (a span that is a multiple of h up to rounding gets no sliver step).
SLIVER = 1e-9
# Relative step of the finite-difference Jacobians: sqrt(machine epsilon).
FD_STEP = 1.4901161193847656e-08
# The smallest rtol double precision can honour (scipy's solve_ivp: 100 eps).
RTOL_FLOOR = 100 * np.finfo(float).eps
# The default largest number of steps of a run (``max_steps``): a fixed grid
# of more is refused before it starts, adaptive knots stop there.
MAX_STEPS = 10**8
# A fixed grid of more steps than this gets a warning before it starts (it
# takes long, and storing every knot takes gigabytes).
MANY_STEPS = 10**8


def is_real(value):
    """A real number that is not a bool (True is not a tolerance)."""
    return isinstance(value, numbers.Real) and not isinstance(value, (bool, np.bool_))


def is_integer(value):
    """An integer that is not a bool (True is not a count)."""
    return isinstance(value, (int, np.integer)) and not isinstance(value, (bool, np.bool_))


def check_options(options, defaults, name):
    """The keyword ``options`` of the front door ``name`` merged into its
    ``defaults``; an unknown name is a ValueError naming it (scipy's
    solve_ivp passes its solver options the same way)."""
    unknown = sorted(set(options) - set(defaults))
    if unknown:
        raise ValueError(f"{name}() got unknown options {unknown}; the options are "
                         f"{sorted(defaults)}")
    return dict(defaults, **options)


def check_flag(value, name):
    """``value`` as a bool, or a ValueError naming ``name`` (1 and "yes"
    are not True)."""
    if not isinstance(value, (bool, np.bool_)):
        raise ValueError(f"{name} must be True or False, got {value!r}")
    return bool(value)


def check_max_steps(max_steps):
    """``max_steps`` as an int >= 1, or a ValueError naming it."""
    if not (is_integer(max_steps) and max_steps >= 1):
        raise ValueError(f"max_steps must be an integer >= 1, got {max_steps!r}")
    return int(max_steps)


def as_vector(g):
    """The value of ``fun`` as something indexable by component.

    Plain Python: an array (lists, tuples and scalars are converted, a
    scalar to shape (1,), so a wrong shape is reported, not raised).  Compiled: the value itself, so a
    compiled ``fun`` may return a tuple of floats and spare the allocation of
    an array per evaluation."""
    return np.atleast_1d(np.asarray(g, dtype=np.float64))


@overload(as_vector)
def _as_vector_compiled(g):
    if isinstance(g, types.Boolean):
        return lambda g: (1.0 if g else 0.0,)
    if isinstance(g, (types.Float, types.Integer)):
        return lambda g: (float(g),)  # a scalar is the one component of m = 1
    if isinstance(g, types.Array) and g.ndim == 0:
        return lambda g: (float(g[()]),)
    return lambda g: g


def wrong_length(g, m):
    """True unless ``g`` (from :func:`as_vector`) holds exactly m components."""
    return g.ndim != 1 or g.shape[0] != m


@overload(wrong_length)
def _wrong_length_compiled(g, m):
    if isinstance(g, types.Array):
        if g.ndim != 1:
            return lambda g, m: True
        return lambda g, m: g.shape[0] != m
    if isinstance(g, (types.UniTuple, types.List)):
        return lambda g, m: len(g) != m
    return None  # anything else is a numba typing error naming the type


class Adapted(NamedTuple):
    """The one extra argument of a loop whose ``fun`` is an adapter
    (:mod:`splinestep._adapters`) or a trampoline: ``token``, the address of
    the run's buffer, whose first m floats receive F's value."""
    token: int


def is_adapted(args):
    """True when a loop's ``args`` are ``(Adapted(token),)``."""
    return len(args) == 1 and isinstance(args[0], Adapted)


def _is_adapted(args):
    """:func:`is_adapted` of the numba type of ``args``."""
    return (isinstance(args, types.BaseTuple) and len(args) == 1
            and isinstance(args[0], types.BaseNamedTuple) and args[0].instance_class is Adapted)


def evaluate(fun, args, t, y, yp):
    """F(t, y, y') in a compiled loop, as something indexable by component
    (compiled code only): ``as_vector(fun(t, y, yp, *args))``, or, when
    ``args`` is ``(Adapted(token),)``, the adapter's call ``fun(t, y, yp,
    token)``, which writes F into the first m floats at the address
    ``token`` and returns 0 (1: F had the wrong length; an empty array is
    returned).  Those floats are one buffer per run, read as an array with
    no reference count: a caller reads it before the next evaluation.
    Called from Python (a loop run uncompiled), the same."""
    if is_adapted(args):
        token = args[0].token
        n = y.shape[0] * (1 - fun(t, y, yp, token))
        return np.ctypeslib.as_array((ctypes.c_double * n).from_address(token)) if n \
            else np.empty(0)
    return as_vector(fun(t, y, yp, *args))


@overload(evaluate, inline="always")
def _evaluate_compiled(fun, args, t, y, yp):
    if _is_adapted(args):
        def adapted(fun, args, t, y, yp):
            token = args[0].token
            # status 0: the m values; 1: none (no branch, which inlining keeps simple)
            return carray(float_pointer(token), y.shape[0] * (1 - fun(t, y, yp, token)))
        return adapted
    return lambda fun, args, t, y, yp: as_vector(fun(t, y, yp, *args))


def jacobian(jac, args, t, y, yp):
    """``jac(t, y, yp, *args)`` in a compiled loop, or ``jac(t, y, yp,
    token)`` for an adapter (:func:`evaluate`)."""
    if is_adapted(args):
        return jac(t, y, yp, args[0].token)
    return jac(t, y, yp, *args)


@overload(jacobian)
def _jacobian_compiled(jac, args, t, y, yp):
    if _is_adapted(args):
        return lambda jac, args, t, y, yp: jac(t, y, yp, args[0].token)
    return lambda jac, args, t, y, yp: jac(t, y, yp, *args)


def address_as(pointer_type, name):
    """A compiled function (an intrinsic named ``name``) that turns an
    integer address into ``pointer_type`` (for ``numba.carray``)."""
    def cast(typingctx, address):
        def codegen(context, builder, sig, args):
            return builder.inttoptr(args[0], context.get_value_type(sig.return_type))
        return pointer_type(types.int64), codegen
    cast.__name__ = cast.__qualname__ = name
    return intrinsic(cast)


float_pointer = address_as(types.CPointer(types.float64), "float_pointer")


def check_state(y0, yp0):
    """Return y0 and yp0 as equal-length, finite float64 vectors."""
    y0 = _real_array(y0, "y0")
    yp0 = _real_array(yp0, "yp0")
    if y0.ndim != 1:
        raise ValueError(f"y0 must be a scalar or a 1-D array, got shape {y0.shape}")
    if y0.size == 0:
        raise ValueError("y0 must have at least one component (scipy accepts an empty "
                         "state; a spline of nothing has no steps to take)")
    if yp0.shape != y0.shape:
        raise ValueError(
            f"y0 and yp0 must have the same shape, got {y0.shape} and {yp0.shape}")
    if not np.all(np.isfinite(y0)):
        raise ValueError("y0 must be finite")
    if not np.all(np.isfinite(yp0)):
        raise ValueError("yp0 must be finite")
    return y0.copy(), yp0.copy()


def _real_array(value, name):
    """``value`` as an at-least-1-D float64 array; complex or non-numeric
    values are a ValueError naming ``name``."""
    try:
        array = np.asarray(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a real number or an array of them") from None
    if np.iscomplexobj(array):
        raise ValueError(f"{name} must be real: complex values are not supported "
                         "(split a complex equation into its real and imaginary parts)")
    if array.dtype == bool:
        raise ValueError(f"{name} must be a real number or an array of them, not a boolean")
    try:
        return np.atleast_1d(array.astype(float))
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a real number or an array of them, "
                         f"got {type(value).__name__}") from None




def check_span(t_span, backward=False):
    """Return (t0, tf) as finite floats with t0 < tf, or t0 != tf when
    ``backward`` integration is allowed."""
    try:
        pair = tuple(t_span)
        t0, tf = (float(v) for v in pair)
    except (TypeError, ValueError):
        raise ValueError("t_span must be a pair of numbers (t0, tf)") from None
    if any(isinstance(v, (bool, np.bool_)) for v in pair):
        raise ValueError(f"t_span must be a pair of numbers (t0, tf), got {pair!r} "
                         "(booleans are not numbers)")
    if not (np.isfinite(t0) and np.isfinite(tf)):
        raise ValueError(f"t_span must be finite, got ({t0}, {tf})")
    if backward and tf == t0:
        raise ValueError(f"t_span must be non-empty, got ({t0}, {tf})")
    if not backward and not tf > t0:
        raise ValueError(f"t_span must be increasing and non-empty, got ({t0}, {tf})")
    return t0, tf


def check_grid(t0, tf, h, knots, max_steps=MAX_STEPS):
    """Validate the step size or the knots.

    Returns ``(h, n, knots)``: a uniform grid is ``t_i = t0 + i h`` for
    ``i < n`` with ``t_n = tf``; ``h`` carries the direction of
    integration (negative when tf < t0) and ``knots`` is an empty array.
    The last step is shortened when the span is not a multiple of h; a
    last step shorter than ``SLIVER`` h is merged into the one before it,
    and a step larger than the span becomes one step over the span.  For
    explicit knots, ``h`` is their largest spacing (signed).  A grid of
    more than ``max_steps`` steps is a ValueError: it is refused before it
    starts, instead of running for hours or exhausting memory.
    """
    if h is not None and knots is not None:
        raise ValueError("give h or knots, not both (neither: adaptive knots)")
    direction = 1.0 if tf > t0 else -1.0
    if knots is not None:
        knots = _real_array(knots, "knots")
        if knots.ndim != 1 or knots.size < 2:
            raise ValueError("knots must be a 1-D array of at least two times")
        if not np.all(np.isfinite(knots)):
            raise ValueError("knots must be finite")
        if not np.all(direction * np.diff(knots) > 0):
            raise ValueError("knots must be strictly monotonic, in the direction of t_span")
        if knots[0] != t0 or knots[-1] != tf:
            raise ValueError(
                f"knots must start at t_span[0] = {t0} and end at t_span[1] = {tf}, "
                f"got {knots[0]} and {knots[-1]}")
        if knots.size - 1 > max_steps:
            raise ValueError(f"knots make {knots.size - 1} steps, more than max_steps = "
                             f"{max_steps}")
        return direction * float(np.max(np.abs(np.diff(knots)))), knots.size - 1, knots
    if not isinstance(h, numbers.Real) or isinstance(h, bool):
        raise ValueError(f"h must be a real number, got {h!r}")
    h = float(h)
    if not np.isfinite(h) or h <= 0:
        raise ValueError(f"h must be positive and finite, got {h} "
                         "(the direction of integration comes from t_span)")
    span = abs(tf - t0)
    ratio = span / h
    if not ratio <= max_steps + 1:  # also an infinite ratio (h = 1e-300)
        raise ValueError(f"h = {h:g} over a span of {span:g} makes {ratio:.3g} steps, more "
                         f"than max_steps = {max_steps}: pass a larger h (or a larger "
                         "max_steps)")
    whole = np.floor(ratio)
    n = int(whole) + (ratio - whole > SLIVER)
    n = max(n, 1)
    if n > max_steps:  # the sliver rule's extra step past a whole max_steps
        raise ValueError(f"h = {h:g} over a span of {span:g} makes {n} steps, more than "
                         f"max_steps = {max_steps}: pass a larger h (or a larger max_steps)")
    if n > MANY_STEPS:
        warnings.warn(f"h = {h:g} over a span of {span:g} makes {n:.3g} steps; this takes "
                      "long, and storing every knot needs "
                      f"{24 * n / 2**30:.3g} GiB per component (pass t_eval to store fewer)",
                      UserWarning, stacklevel=3)
    return direction * min(h, span), n, np.empty(0)


def _tolerance(value, name, m):
    """``value`` (a number or one per component) as a positive, finite (m,)
    vector; anything else is a ValueError naming ``name``."""
    array = _real_array(value, name)
    if array.shape not in ((1,), (m,)) or np.ndim(value) > 1:
        raise ValueError(f"{name} must be a number or an array of shape ({m},), "
                         f"got shape {np.shape(value)}")
    if not np.all(np.isfinite(array) & (array > 0)):
        raise ValueError(f"{name} must be positive and finite, got {value!r}")
    return np.array(np.broadcast_to(array, (m,)), dtype=float)


def check_tolerances(rtol, atol, first_step, max_step, max_steps, m):
    """Validate the adaptive driver's settings; returns (rtol and atol as
    (m,) vectors, first_step (0 when chosen automatically), max_step,
    max_steps)."""
    rtol_array = _tolerance(rtol, "rtol", m)
    if np.any(rtol_array < RTOL_FLOOR):  # as scipy's solve_ivp: float64 cannot reach it
        warnings.warn(f"At least one element of rtol is below {RTOL_FLOOR:g}, which double "
                      f"precision cannot reach; it is raised to {RTOL_FLOOR:g}", UserWarning,
                      stacklevel=3)
        rtol_array = np.maximum(rtol_array, RTOL_FLOOR)
    atol_array = _tolerance(atol, "atol", m)
    if first_step is None:
        first_step = 0.0
    elif not (is_real(first_step) and np.isfinite(first_step)
              and first_step > 0):
        raise ValueError(f"first_step must be None or a positive finite number, "
                         f"got {first_step!r}")
    if not (is_real(max_step) and max_step > 0) or np.isnan(max_step):
        raise ValueError(f"max_step must be a positive number (inf: no limit), "
                         f"got {max_step!r}")
    max_steps = check_max_steps(max_steps)
    return (rtol_array, atol_array,
            float(first_step), float(max_step), int(max_steps))


def check_t_eval(t_eval, t0, tf):
    """Return t_eval as a sorted float array inside [t0, tf] (or None)."""
    if t_eval is None:
        return None
    if np.ndim(t_eval) != 1:  # as scipy: a scalar is not a list of times
        raise ValueError(f"t_eval must be a 1-D array of times, got shape {np.shape(t_eval)}")
    t_eval = _real_array(t_eval, "t_eval")
    if t_eval.ndim != 1 or t_eval.size == 0:
        raise ValueError("t_eval must be a non-empty 1-D array")
    if not np.all(np.isfinite(t_eval)):
        raise ValueError("t_eval must be finite")
    direction = 1.0 if tf >= t0 else -1.0
    if np.any(direction * np.diff(t_eval) < 0):
        raise ValueError("t_eval must be sorted in the direction of t_span")
    if np.any(direction * (t_eval - t0) < 0) or np.any(direction * (t_eval - tf) > 0):
        raise ValueError(f"t_eval must lie within t_span = ({t0}, {tf})")
    return t_eval


def check_args(args):
    """``args`` as given, a tuple, each passed to ``fun`` as it is (numba
    types an int as int64 and a float as float64, as a call from Python
    does); a complex number or array is a ValueError."""
    if not isinstance(args, tuple):
        raise ValueError(f"args must be a tuple, got {type(args).__name__}")
    for value in args:
        if isinstance(value, numbers.Complex) and not isinstance(value, numbers.Real):
            raise ValueError("args must be real: complex values are not supported")
        if isinstance(value, np.ndarray) and value.dtype.kind == "c":
            raise ValueError("args must be real: complex arrays are not supported")
    return args


def _describe(value):
    if value is None:
        return "None"
    shape = np.shape(value) if isinstance(value, (np.ndarray, list, tuple)) else None
    kind = type(value).__name__
    return f"a {kind} of shape {shape}" if shape is not None else f"a {kind}"


def _call_at_start(name, f, t0, y0, yp0, args):
    """``f(t0, y0, yp0, *args)``; an exception (a numba typing error among
    them) becomes a ValueError naming ``name``, chained to the original."""
    try:
        return f(t0, y0.copy(), yp0.copy(), *args)
    except Exception as error:
        raise ValueError(f"{name} raised {type(error).__name__} at t0 = {short(t0)}: "
                         f"{error}") from error


def _compiled_return_type(fun, values):
    """The return type numba gave a compiled ``fun`` for the argument types
    of ``values`` (the types the run calls it with); None for a plain fun or
    a signature numba did not compile under those types."""
    if not is_compiled(fun):
        return None
    try:
        key = tuple(typeof(v) for v in values)
    except ValueError:
        return None
    compiled = fun.overloads.get(key)
    return None if compiled is None else compiled.signature.return_type


def check_fun(fun, t0, y0, yp0, args):
    """Call ``fun`` once at the start, from Python, and refuse what no step
    could use: ``None``, the wrong shape, complex or non-numeric values.
    A scalar is accepted when m = 1.  Returns the value as an array."""
    m = y0.shape[0]
    value = _call_at_start("fun", fun, t0, y0, yp0, args)
    returned = _compiled_return_type(fun, (float(t0), y0, yp0) + tuple(args))
    if isinstance(returned, types.Optional):
        raise ValueError("fun is compiled with a value that may be None (numba types it as "
                         "optional); a compiled fun must return its values on every branch")
    if isinstance(returned, types.Tuple) and not isinstance(returned, types.UniTuple):
        raise ValueError(f"fun is compiled with a value of type {returned}, a tuple of mixed "
                         "types; a compiled fun returns a tuple of float64 (write 0.0, not 0, "
                         "and no float32)")
    try:
        array = np.asarray(value)
    except (TypeError, ValueError):
        array = np.asarray(None)
    if value is None or array.dtype.kind not in "iufcb":
        raise ValueError(f"fun must return an array of shape ({m},) (the second derivative), "
                         f"got {_describe(value)}")
    if array.dtype.kind == "c":
        raise ValueError("fun returned complex values; only real equations are supported "
                         "(split a complex equation into its real and imaginary parts)")
    if array.shape not in ((m,), () if m == 1 else (m,)):
        raise ValueError(f"fun must return an array of shape ({m},) (the second derivative), "
                         f"got {_describe(value)}")
    return np.atleast_1d(array.astype(float))


def is_sparse(value):
    """True when ``value`` is a scipy.sparse matrix or array (without
    importing scipy: a program that made one has imported it)."""
    sparse = sys.modules.get("scipy.sparse")
    return sparse is not None and sparse.issparse(value)


def jac_parts_reason(value, m, t):
    """None when ``value`` is a pair (dF/dy, dF/dyp) of (m, m) arrays or
    scipy.sparse matrices of finite real numbers; otherwise why not, as a
    message says it (at time ``t``, or of the constant ``jac`` when None)."""
    expected = (f"a pair (dF/dy, dF/dyp) of arrays or scipy.sparse matrices of shape "
                f"({m}, {m})")
    where = "" if t is None else f" at t = {t:.10g}"
    if not isinstance(value, (tuple, list)) or len(value) != 2:
        return f"jac must {'be' if t is None else 'return'} {expected}, got {_describe(value)}"
    for name, part in zip(("dF/dy", "dF/dyp"), value):
        if is_sparse(part):
            shape, data, kind = part.shape, part.tocsr().data, part.dtype.kind
        else:
            try:
                data = np.asarray(part)
            except (TypeError, ValueError):
                data = np.asarray(None)
            shape, kind = data.shape, data.dtype.kind
        if shape != (m, m):
            return (f"jac must {'be' if t is None else 'return'} {expected}; its {name} "
                    f"has shape {shape}{where}")
        if kind not in "iuf" or not np.all(np.isfinite(data)):
            return (f"jac must {'be' if t is None else 'return'} {expected} of finite real "
                    f"numbers; its {name}{where} is not")
    return None


def check_jac_option(jac):
    """``jac`` as given to a front door: None, a callable, or the constant
    pair (dF/dy, dF/dyp) as a tuple or list of two matrices (dense or
    scipy.sparse), as scipy's solve_ivp takes a constant Jacobian; anything
    else is a ValueError naming it.  A constant pair is returned as a tuple."""
    if jac is None or callable(jac):
        return jac
    if isinstance(jac, (tuple, list)) and len(jac) == 2:
        return tuple(jac)
    raise ValueError("jac must be None, a callable or a pair (dF/dy, dF/dyp) of constant "
                     f"matrices, got {_describe(jac)}")


def check_jac(jac, t0, y0, yp0, args):
    """Call ``jac`` once at the start (or read a constant pair) and check
    that it gives two finite (m, m) matrices, dF/dy and dF/dyp, dense or
    scipy.sparse.  Returns "sparse" when either is sparse, else "dense"."""
    m = y0.shape[0]
    value = jac if not callable(jac) else _call_at_start("jac", jac, t0, y0, yp0, args)
    reason = jac_parts_reason(value, m, None if not callable(jac) else t0)
    if reason is not None:
        raise ValueError(reason)
    return "sparse" if any(is_sparse(part) for part in value) else "dense"


def is_compiled(f):
    """True when ``f`` is a numba-compiled function (``numba.njit``)."""
    return isinstance(f, CPUDispatcher)


def choose_path(fun, jac, args):
    """"compiled" when ``fun`` (and ``jac``, if any) are numba-compiled in
    nopython mode, else "plain".  A compiled ``fun`` slowed down by a plain
    ``jac`` gets a warning."""
    if not is_compiled(fun) or _object_mode(fun):
        return "plain"
    if jac is not None and (not is_compiled(jac) or _object_mode(jac)):
        warnings.warn("fun is compiled but jac is plain Python, so the loop calls both "
                      "through the interpreter (the plain path, slower per evaluation); "
                      "compile jac with numba.njit too",
                      UserWarning, stacklevel=4)
        return "plain"
    return "compiled"


def _object_mode(f):
    """True for a numba function compiled in object mode
    (``jit(forceobj=True)``): the loop calls it from Python, as a plain one."""
    return bool(f.targetoptions.get("forceobj"))
