"""Time-reversible variable steps (Hairer and Soderlind, 2005).

An error-controlled step size depends on the error estimate, which is not
symmetric in time: stepping back does not retrace the steps, and the
bounded energy error of a fixed step is lost (notebook 08 shows the drift).
Hairer and Soderlind keep it by making the step size itself the output of a
symmetric recursion.  With a step-size function s(y) (the steps are
proportional to s: small where s is small, so that the density of steps is
proportional to 1/s) and G = -(d/dt) ln s along the solution, a control variable rho
follows the leapfrog recursion

    rho_{1/2} = rho_0 + eps G(y_0) / 2,    rho_0 = 1,
    h_n = eps / rho_{n+1/2},       (y_n, y'_n) -> (y_{n+1}, y'_{n+1}) by the spline step,
    rho_{n+3/2} = rho_{n+1/2} + eps G(y_{n+1})

(the increments change sign backwards in time), so that
rho ~ s(y_0) / s(y) and h ~ eps s(y) / s(y_0).  The step and the
recursion are both symmetric, so the whole map is: run backwards, it retraces
its knots.  For the Kepler problem s = r^(3/2) (steps proportional to the
local orbital time scale) gives G = -(3/2) (q . q') / |q|^2.

References
----------
.. [1] E. Hairer, G. Soderlind, "Explicit, time reversible, adaptive step
   size control", SIAM J. Sci. Comput. 26 (2005) 1838-1851.
"""

import warnings

import numpy as np

from . import _base, controllers, driver
from .spline import run_spline
from .step import FIXED_POINT, NEWTON


_OPTIONS = dict(iteration="fixed-point", tol=1e-12, max_iter=50, jac=None, max_steps=10**7,
                check=True)


def solve_reversible(fun, t_span, y0, yp0, eps, control, *, rho0=1.0, args=(), t_eval=None,
                     events=None, dense_output=True, **options):
    """Integrate y'' = F(t, y, y') with the spline step at the time-reversible
    step sizes of Hairer and Soderlind.

    Parameters
    ----------
    fun, t_span, y0, yp0, args, t_eval, events
        As for :func:`splinestep.solve` (forward or backward in time).
    eps : float
        The scale of the steps: each is eps / rho, the first
        eps / (rho0 + eps G(y0) / 2).
    control : callable
        ``control(t, y, yp, *args) -> G``, minus the time derivative of the
        logarithm of the step-size function s along the solution (see the module
        docstring); for Kepler with s = r^(3/2), -1.5 (y . yp) / |y|^2.
    rho0 : float
        The control variable at the start (the first step is about
        eps / rho0).  To retrace a run backwards from its knot k, start
        there with rho0 = rho[k - 1] + eps G(y_k) / 2.
    dense_output : bool
        Return the spline as ``sol`` (default True).
    **options
        ``iteration`` ("fixed-point" or "newton"), ``tol``, ``max_iter``,
        ``jac``, ``check`` as for :func:`splinestep.solve`, and
        ``max_steps`` (default 10**7): the run stops (status -1) after this
        many steps.  Any other name is a ValueError.

    Returns
    -------
    OdeResult
        As :func:`splinestep.solve`, with ``rho`` the control variable at the
        half steps (at the knots' steps; with ``t_eval`` the knots are not
        stored and ``rho`` is empty unless ``dense_output``).
    """
    opts = _base.check_options(options, _OPTIONS, "solve_reversible")
    iteration, tol, max_iter, jac = (opts[k] for k in ("iteration", "tol", "max_iter", "jac"))
    t0, tf = _base.check_span(t_span, backward=True)
    y0, yp0 = _base.check_state(y0, yp0)
    args = _base.check_args(args)
    t_eval = _base.check_t_eval(t_eval, t0, tf)
    for name, value in (("eps", eps), ("rho0", rho0), ("tol", tol)):
        if not (_base.is_real(value) and np.isfinite(value) and value > 0):
            raise ValueError(f"{name} must be positive and finite, got {value!r}")
    if not callable(control):
        raise ValueError("control must be callable")
    if iteration not in ("fixed-point", "newton"):
        raise ValueError(f"iteration must be 'fixed-point' or 'newton', got {iteration!r}")
    if not (_base.is_integer(max_iter) and max_iter >= 1):
        raise ValueError(f"max_iter must be an integer >= 1, got {max_iter!r}")
    if not callable(fun):
        raise ValueError("fun must be callable")
    jac = _base.check_jac_option(jac)
    check = _base.check_flag(opts["check"], "check")
    max_steps = _base.check_max_steps(opts["max_steps"])
    try:
        float(control(t0, y0.copy(), yp0.copy(), *args))
    except Exception as error:
        raise ValueError(f"control must return a number at t0; it raised "
                         f"{type(error).__name__}: {error}") from error
    mode = FIXED_POINT if iteration == "fixed-point" else NEWTON
    if jac is not None and mode == FIXED_POINT:
        warnings.warn("jac is not used by the fixed-point iteration; pass "
                      "iteration=\"newton\" to use it", UserWarning, stacklevel=2)
    step = driver.method(driver.SPLINE, mode, max_iter, True, tol, True)
    ctrl = controllers.reversible(tf, eps, rho0, max_steps)
    return run_spline(fun, jac if mode == NEWTON else None, args, step, ctrl, (t0, y0, yp0),
                      (t_eval, events, dense_output), max_iter, control=control, check=check)
