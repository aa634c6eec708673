"""Compile each step loop once per machine, not once per function.

A numba loop that receives the right-hand side as an ordinary argument is
specialised on that function's identity: every new ``fun`` compiles the
whole loop again (seconds), and such a loop cannot be cached on disk, since
its cache index would pickle the type of a function from the caller's module.

Here a loop receives ``fun`` (and ``jac``) as a first-class function type,
``FunctionType(ret(float64, float64[::1], float64[::1], *args))``, which
names only the signature.  A loop is compiled once per combination of these
signatures and of the argument types, and numba's on-disk cache, keyed on
that signature, on the source file and on numba's version, serves every
later process, whichever module or notebook defines ``fun``.  The call
through a function pointer cannot be inlined; ``make bench`` measures its
cost per evaluation.

References
----------
.. [1] numba documentation, "First-class function objects" and "Notes on
   caching", https://numba.readthedocs.io
"""

from numba import njit, typeof, types

VECTOR = types.float64[::1]
FLOAT = types.float64
INT = types.int64
BOOL = types.boolean

# (python loop, argument types) -> numba dispatcher compiled for those types
_LOOPS = {}


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
    fun_type = function_type(fun, arg_types)
    jac_type = types.none if jac is None else function_type(jac, arg_types)
    return fun_type, args_type, jac_type


def compiled(py_loop, arg_types):
    """``py_loop`` compiled (or loaded from the disk cache) for exactly
    ``arg_types``; one dispatcher per signature, kept for the process."""
    key = (py_loop, tuple(arg_types))
    if key not in _LOOPS:
        _LOOPS[key] = njit(tuple(arg_types), cache=True)(py_loop)
    return _LOOPS[key]
