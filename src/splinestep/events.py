"""Events: times at which g(t, y, y') = 0, located on the spline.

As in scipy's ``solve_ivp``, an event is a function ``g(t, y, yp)`` (called
with ``*args`` too) that may carry two attributes:

- ``terminal`` (bool or int, default False): stop the integration at the
  first (or the ``terminal``-th) zero;
- ``direction`` (float, default 0): count only zeros where g goes from
  negative to positive (> 0), from positive to negative (< 0), or both (0).

The driver (:mod:`splinestep.driver`) hands each accepted step to a
:class:`Tracker` as it is taken.  ``g`` is evaluated at the new knot; a zero
exactly at the initial time is not an event (a ball launched from the
ground has not landed).  On a step where it changes sign, the zero is found
by Brent's method on g along the step's interpolant, the one that gives the
dense output and ``t_eval`` (:func:`splinestep.driver.dense_state`): for the
spline the interval's cubic, which is the solution the stepper computed
there; for a composition of order 4 or 6 the quintic Hermite through both
knots, of the run's order; for RK4 and Verlet the cubic Hermite.  An event
time is a root of the dense output to the bracketing tolerance, and a
terminal event ends the run there.

References
----------
.. [1] L. F. Shampine, S. Thompson, "Event location for ordinary
   differential equations", Comput. Math. Appl. 39 (2000) 43-54.
"""

import numpy as np

from .driver import dense_state

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


class Tracker:
    """The events of one run, fed step by step by the driver.

    :meth:`start` evaluates every event at the initial state; :meth:`step`
    looks for zeros on one accepted step and records them, in the order of
    time; it returns (1, t) when a terminal event has reached its count at
    t (its state written into ``out``), (0, nan) otherwise, and (2, nan)
    when an event function raised (kept in :attr:`error`, which the front
    door raises once the compiled loop has returned).
    """

    def __init__(self, events):
        self.events = events
        self.g_old = None
        self.error = None

    @classmethod
    def of(cls, events, args, t0, y0, yp0):
        """The tracker of a front door's ``events`` argument (validated by
        :func:`check_events`), started at (t0, y0, yp0); None without events."""
        events = check_events(events, args)
        if not events:
            return None
        tracker = cls(events)
        tracker.start(t0, y0, yp0)
        return tracker

    def start(self, t0, y0, yp0):
        self.g_old = [ev(t0, y0, yp0) for ev in self.events]

    def step(self, t, t_new, kind, state, out):
        try:
            return self._step(t, t_new, kind, state, out)
        except Exception as error:  # raised again by the front door
            self.error = error
            return 2, np.nan

    def _step(self, t, t_new, kind, state, out):
        start, end = state[:3], state[3:]
        g_new = [ev(t_new, end[0], end[1]) for ev in self.events]
        dt = t_new - t

        def at(time):
            return dense_state(kind, time - t, dt, *start, *end)

        hits = []
        for ev, a, b in zip(self.events, self.g_old, g_new):
            if ev.done or not ev.active(a, b):
                continue
            if b == 0:
                t_root = t_new
            else:
                from scipy.optimize import brentq   # here: scipy takes 0.3 s to import
                lo, hi = sorted((t, t_new))
                t_root = brentq(lambda time, ev=ev: ev(time, *at(time)[:2]), lo, hi,
                                xtol=XTOL * max(1.0, abs(hi)), rtol=XTOL)
            hits.append((abs(t_root - t), t_root, ev))
        self.g_old = g_new
        for _, t_root, ev in sorted(hits, key=lambda hit: hit[0]):
            found = end if t_root == t_new else np.array(at(t_root))
            ev.times.append(t_root)
            ev.states.append((found[0].copy(), found[1].copy(), found[2].copy()))
            if ev.done:
                out[:] = found
                return 1, t_root
        return 0, np.nan

    def attach(self, result):
        """The zeros as scipy's ``t_events``, ``y_events`` (and
        ``yp_events``): (k,), (k, m), (k, m) for k zeros, shape (0,) for
        none."""
        result.t_events = [np.array(ev.times) for ev in self.events]
        result.y_events = [np.array([s[0] for s in ev.states]) for ev in self.events]
        result.yp_events = [np.array([s[1] for s in ev.states]) for ev in self.events]
