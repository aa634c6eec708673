"""What the steppers share: argument validation (in one place), the step grid,
the choice between the compiled and the plain-Python loop, and the assembly
of the result object."""

import numbers

import numpy as np
from numba.core import types
from numba.core.registry import CPUDispatcher
from numba.extending import overload

from .result import OdeResult

# Status codes returned by the step loops (the loops cannot raise with a
# message when compiled, so they report what went wrong as a code).
OK = 0
NOT_CONVERGED = 1
NON_FINITE = 2
BAD_SHAPE = 3
SINGULAR = 4

_FAILURES = {
    NOT_CONVERGED: "the iteration did not converge in {max_iter} iterations",
    NON_FINITE: "the right-hand side returned a value that is not finite",
    BAD_SHAPE: "the right-hand side returned an array of the wrong shape "
               "(expected shape ({m},))",
    SINGULAR: "the Newton matrix is singular or its solution is not finite",
}


def as_vector(g):
    """The value of ``fun`` as something indexable by component.

    Plain Python: an array (lists, tuples and scalars are converted, so a
    wrong shape is reported, not raised).  Compiled: the value itself, so a
    compiled ``fun`` may return a tuple of floats and spare the allocation of
    an array per evaluation."""
    return np.asarray(g, dtype=np.float64)


@overload(as_vector)
def _as_vector_compiled(g):
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
    if isinstance(g, types.UniTuple):
        return lambda g, m: len(g) != m
    return None  # anything else is a numba typing error naming the type


def check_state(y0, yp0):
    """Return y0 and yp0 as equal-length, finite float64 vectors."""
    y0 = np.atleast_1d(np.asarray(y0, dtype=float))
    yp0 = np.atleast_1d(np.asarray(yp0, dtype=float))
    if y0.ndim != 1:
        raise ValueError(f"y0 must be a scalar or a 1-D array, got shape {y0.shape}")
    if yp0.shape != y0.shape:
        raise ValueError(
            f"y0 and yp0 must have the same shape, got {y0.shape} and {yp0.shape}")
    if not np.all(np.isfinite(y0)):
        raise ValueError("y0 must be finite")
    if not np.all(np.isfinite(yp0)):
        raise ValueError("yp0 must be finite")
    return y0.copy(), yp0.copy()


def check_span(t_span):
    """Return (t0, tf) as floats with t0 < tf, both finite."""
    try:
        t0, tf = (float(v) for v in t_span)
    except (TypeError, ValueError):
        raise ValueError("t_span must be a pair of numbers (t0, tf)") from None
    if not (np.isfinite(t0) and np.isfinite(tf)):
        raise ValueError(f"t_span must be finite, got ({t0}, {tf})")
    if not tf > t0:
        raise ValueError(f"t_span must be increasing and non-empty, got ({t0}, {tf})")
    return t0, tf


def check_grid(t0, tf, h, knots):
    """Validate the step size or the knots.

    Returns ``(h, n, knots)``: a uniform grid is ``t_i = t0 + i h`` for
    ``i < n`` with ``t_n = tf`` (the last step is shortened when the span is
    not a multiple of h); ``knots`` is then an empty array.  For explicit
    knots, ``h`` is their largest spacing.
    """
    if (h is None) == (knots is None):
        raise ValueError("give exactly one of h and knots")
    if knots is not None:
        knots = np.asarray(knots, dtype=float)
        if knots.ndim != 1 or knots.size < 2:
            raise ValueError("knots must be a 1-D array of at least two times")
        if not np.all(np.isfinite(knots)):
            raise ValueError("knots must be finite")
        if not np.all(np.diff(knots) > 0):
            raise ValueError("knots must be strictly increasing")
        if knots[0] != t0 or knots[-1] != tf:
            raise ValueError(
                f"knots must start at t_span[0] = {t0} and end at t_span[1] = {tf}, "
                f"got {knots[0]} and {knots[-1]}")
        return float(np.max(np.diff(knots))), knots.size - 1, knots
    if not isinstance(h, numbers.Real) or isinstance(h, bool):
        raise ValueError(f"h must be a real number, got {h!r}")
    h = float(h)
    if not np.isfinite(h) or h <= 0:
        raise ValueError(f"h must be positive and finite, got {h}")
    span = tf - t0
    if h > span * (1 + 1e-12):
        raise ValueError(f"h = {h} is larger than the span {span}")
    n = int(np.ceil(span / h * (1 - 1e-12)))
    return h, max(n, 1), np.empty(0)


def check_t_eval(t_eval, t0, tf):
    """Return t_eval as a sorted float array inside [t0, tf] (or None)."""
    if t_eval is None:
        return None
    t_eval = np.atleast_1d(np.asarray(t_eval, dtype=float))
    if t_eval.ndim != 1 or t_eval.size == 0:
        raise ValueError("t_eval must be a non-empty 1-D array")
    if not np.all(np.isfinite(t_eval)):
        raise ValueError("t_eval must be finite")
    if np.any(np.diff(t_eval) < 0):
        raise ValueError("t_eval must be sorted in increasing order")
    if t_eval[0] < t0 or t_eval[-1] > tf:
        raise ValueError(f"t_eval must lie within t_span = ({t0}, {tf})")
    return t_eval


def check_args(args):
    if not isinstance(args, tuple):
        raise ValueError(f"args must be a tuple, got {type(args).__name__}")
    return args


def is_compiled(f):
    """True when ``f`` is a numba-compiled function (``numba.njit``)."""
    return isinstance(f, CPUDispatcher)


def select_loop(loop, *functions):
    """The compiled loop when every user function is compiled, else its
    plain-Python source (the same code, run by the interpreter)."""
    if all(f is None or is_compiled(f) for f in functions):
        return loop
    return loop.py_func


def build_result(out, t_eval, max_iter):
    """Turn the tuple returned by a step loop into an :class:`OdeResult`."""
    (status, fail_step, t_last, t_fail, nfev, njev, niter, nstep, n_knots, n_eval,
     T, Y, YP, YPP, YE, YPE, YPPE) = out
    m = Y.shape[1]
    if t_eval is None:
        t, y, yp, ypp = T[:n_knots], Y[:n_knots], YP[:n_knots], YPP[:n_knots]
    else:
        t, y, yp, ypp = t_eval[:n_eval], YE[:n_eval], YPE[:n_eval], YPPE[:n_eval]
    if status == OK:
        message = "The solver successfully reached the end of the integration interval."
    elif fail_step == 0:
        message = (f"The initial evaluation at t = {t_fail:.17g} failed: "
                   f"{_FAILURES[status].format(max_iter=max_iter, m=m)}.")
    else:
        message = (f"Step {fail_step} (from t = {t_last:.17g} to t = {t_fail:.17g}) "
                   f"failed: {_FAILURES[status].format(max_iter=max_iter, m=m)}. "
                   f"Returning the {nstep} steps completed before it.")
    return OdeResult(
        t=t.copy(), y=y.T.copy(), yp=yp.T.copy(), ypp=ypp.T.copy(), sol=None,
        nfev=int(nfev), njev=int(njev), niter=int(niter), nstep=int(nstep),
        status=0 if status == OK else -1, message=message, success=status == OK), \
        (T[:n_knots], Y[:n_knots], YP[:n_knots], YPP[:n_knots])
