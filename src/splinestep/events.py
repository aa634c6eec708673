"""Events: times at which g(t, y, y') = 0, located on the spline.

As in scipy's ``solve_ivp``, an event is a function ``g(t, y, yp)`` (called
with ``*args`` too) that may carry two attributes:

- ``terminal`` (bool or int, default False): stop the integration at the
  first (or the ``terminal``-th) zero;
- ``direction`` (float, default 0): count only zeros where g goes from
  negative to positive (> 0), from positive to negative (< 0), or both (0).

``g`` is evaluated at the knots; a zero exactly at the initial time is not
an event (a ball launched from the ground has not landed).  On an interval where it changes sign, the
zero is found by Brent's method on g along the interval's cubic, which is the
solution the stepper computed there (not an interpolation of it), so an
event time is a root of the dense output to the bracketing tolerance.

References
----------
.. [1] L. F. Shampine, S. Thompson, "Event location for ordinary
   differential equations", Comput. Math. Appl. 39 (2000) 43-54.
"""

import numpy as np

# Bracketing tolerance of an event time: a few units of rounding of t.
XTOL = 4 * np.finfo(float).eps


class Event:
    """One user event function with its ``terminal`` count and ``direction``."""

    def __init__(self, fun, args):
        if not callable(fun):
            raise ValueError(f"events must be callables, got {type(fun).__name__}")
        self.fun = fun
        self.args = args
        # As in scipy: None, False and 0 are not terminal; True is the first
        # zero, a positive integer n the n-th.
        terminal = getattr(fun, "terminal", None)
        if isinstance(terminal, (bool, np.bool_)):
            self.max_count = 1 if terminal else None
        elif terminal is None or (isinstance(terminal, (int, np.integer)) and terminal == 0):
            self.max_count = None
        elif isinstance(terminal, (int, np.integer)) and terminal > 0:
            self.max_count = int(terminal)
        else:
            raise ValueError(f"an event's terminal attribute must be a bool, None or a "
                             f"non-negative integer, got {terminal!r}")
        direction = getattr(fun, "direction", 0)
        try:
            direction = float(direction)
        except (TypeError, ValueError):
            raise ValueError(f"an event's direction attribute must be a number, "
                             f"got {direction!r}") from None
        if not np.isfinite(direction):
            raise ValueError(f"an event's direction attribute must be finite (its sign "
                             f"counts), got {direction!r}")
        self.direction = float(np.sign(direction))
        self.times = []
        self.states = []

    def __call__(self, t, y, yp):
        value = self.fun(t, y, yp, *self.args)
        try:
            return float(value)
        except (TypeError, ValueError):
            raise ValueError(f"an event function must return a real number, got "
                             f"{type(value).__name__}") from None

    def active(self, g_old, g_new):
        """Does the interval from g_old to g_new hold a zero of this event?
        A zero at a knot belongs to the interval it ends (so it is counted
        once), and a zero at the initial time is not an event."""
        up = g_old < 0 <= g_new
        down = g_old > 0 >= g_new
        if self.direction > 0:
            return up
        if self.direction < 0:
            return down
        return up or down

    @property
    def done(self):
        return self.max_count is not None and len(self.times) >= self.max_count


def check_events(events, args):
    """A list of :class:`Event` from a callable, a sequence of them or None."""
    if events is None:
        return []
    if callable(events):
        events = [events]
    try:
        events = list(events)
    except TypeError:
        raise ValueError(f"events must be a callable or a sequence of callables, got "
                         f"{type(events).__name__}") from None
    return [Event(fun, args) for fun in events]


def cubic_state(t_a, y_a, yp_a, ypp_a, jerk, t):
    """y, y', y'' at t on the interval starting at t_a, whose third
    derivative is ``jerk``: the spline's own cubic."""
    s = t - t_a
    y = y_a + s * (yp_a + s * (0.5 * ypp_a + s * jerk / 6.0))
    yp = yp_a + s * (ypp_a + 0.5 * s * jerk)
    ypp = ypp_a + s * jerk
    return y, yp, ypp


def locate(events, T, Y, YP, YPP, g_first=None):
    """Scan the knots T (with values Y, YP, YPP, one row per knot) for the
    events' zeros, in the order of time.

    Appends each zero found to its event's ``times`` and ``states``;
    stops after a terminal event has reached its count.  ``g_first`` holds
    the events' values at T[0] when a previous scan computed them.
    Returns ``(index, t, y, yp, ypp, g_last)``: the interval and state of a
    terminal event (``index`` None if none) and the events' values at the
    last knot scanned.
    """
    if T.size == 0:  # the run failed at its start
        return (None, None, None, None, None, g_first)
    g_old = [ev(T[0], Y[0], YP[0]) for ev in events] if g_first is None else list(g_first)
    for i in range(1, T.size):
        g_new = [ev(T[i], Y[i], YP[i]) for ev in events]
        jerk = (YPP[i] - YPP[i - 1]) / (T[i] - T[i - 1])
        hits = []
        for ev, a, b in zip(events, g_old, g_new):
            if ev.done or not ev.active(a, b):
                continue
            if b == 0:
                t_root = T[i]
            else:
                def g_on_cubic(t, ev=ev):
                    y, yp, _ = cubic_state(T[i - 1], Y[i - 1], YP[i - 1], YPP[i - 1], jerk, t)
                    return ev(t, y, yp)
                from scipy.optimize import brentq   # here: scipy takes 0.3 s to import
                lo, hi = sorted((T[i - 1], T[i]))
                t_root = brentq(g_on_cubic, lo, hi, xtol=XTOL * max(1.0, abs(hi)),
                                rtol=XTOL)
            hits.append((abs(t_root - T[i - 1]), t_root, ev))
        for _, t_root, ev in sorted(hits, key=lambda hit: hit[0]):
            state = cubic_state(T[i - 1], Y[i - 1], YP[i - 1], YPP[i - 1], jerk, t_root)
            ev.times.append(t_root)
            ev.states.append(state)
            if ev.done:
                return (i - 1, t_root, *state, g_new)
        g_old = g_new
    return (None, None, None, None, None, g_old)
