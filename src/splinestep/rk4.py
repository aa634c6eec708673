"""The report's baseline: classical fourth-order Runge-Kutta on the
equivalent first-order system u = (y, y'), u' = (y', F(t, y, y'))."""

import numpy as np

from . import _adapters, _base, controllers, driver
from .driver import RK4
from .events import Tracker


def rk4(fun, t_span, y0, yp0, h, *, t_eval=None, args=(), events=None, max_steps=10**8):
    """Classical fourth-order Runge-Kutta for y'' = F(t, y, y').

    The report's comparison method: RK4 on the first-order system
    u = (y, y'), with the same uniform step as the spline method (it
    evaluates F four times per step, at the ends and twice at the midpoint).

    Parameters
    ----------
    fun : callable
        ``fun(t, y, yp, *args) -> y''``; the loop runs compiled and calls a
        ``numba.njit`` function directly, a plain one through the
        interpreter.
    t_span : (float, float)
        Interval of integration (t0, tf); tf < t0 integrates backwards.
    y0 : float or array_like, shape (m,)
        Initial value.
    yp0 : float or array_like, shape (m,)
        Initial first derivative.
    h : float
        Step.  The last step is shortened to end exactly at tf.
    t_eval : array_like, optional
        Sorted times at which to report the solution (cubic Hermite
        interpolation between steps); the steps are then not stored.
    args : tuple, optional
        Extra arguments passed to ``fun`` (and the events).
    events : callable or list of callables, optional
        As for :func:`splinestep.solve`, located on the cubic Hermite
        interpolant of each step.
    max_steps : int, optional
        A grid of more steps is refused before it starts (ValueError).

    Returns
    -------
    OdeResult
        As :func:`splinestep.solve`; ``niter`` is 0.  At the steps ``ypp``
        is F; between them (``t_eval``) y and y' come from cubic Hermite
        interpolation (O(h^4)) and ``ypp`` is the derivative of y''s
        interpolant, one order lower (O(h^3)), not F there.

    References
    ----------
    .. [1] E. Hairer, S. P. Norsett, G. Wanner, "Solving Ordinary
       Differential Equations I", 2nd ed., Springer (1993), Sec. II.1.
    """
    return run_baseline(RK4, fun, t_span, y0, yp0, h, t_eval, args, events, max_steps)


def run_baseline(kind, fun, t_span, y0, yp0, h, t_eval, args, events, max_steps):
    """The front door of :func:`splinestep.rk4` and :func:`splinestep.verlet`
    (``kind`` RK4 or VERLET of :mod:`splinestep.driver`): validate, run the
    driver with the constant controller, return the :class:`OdeResult`."""
    t0, tf = _base.check_span(t_span, backward=True)
    y0, yp0 = _base.check_state(y0, yp0)
    h, n, _ = _base.check_grid(t0, tf, h, None, _base.check_max_steps(max_steps))
    t_eval = _base.check_t_eval(t_eval, t0, tf)
    args = _base.check_args(args)
    if not callable(fun):
        raise ValueError("fun must be callable")
    path = _base.choose_path(fun, None, args)
    if path == "compiled":
        args = _adapters.passable(args)
    ypp0 = _base.check_fun(fun, t0, y0, yp0, args)
    tracker = Tracker.of(events, args, t0, y0, yp0)
    ctrl = controllers.constant(tf, h, n, np.empty(0), max_steps)
    out, reason = driver.run(path, fun, None, args, driver.method(kind), ctrl,
                             (t_eval, t_eval is None, tracker), (t0, y0, yp0, ypp0))
    name = "rk4" if kind == driver.RK4 else "verlet"
    result = driver.result_of(out, t_eval, 0, ctrl[0], reason, path=path,
                              order=4 if kind == driver.RK4 else 2, method=name)
    if tracker is not None:
        tracker.attach(result)
    return result
