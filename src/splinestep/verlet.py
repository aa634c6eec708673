"""The second baseline: Stormer-Verlet in its velocity form, the standard
second-order method for y'' = f(y), to which the spline stepper is
conjugate (see ``notebooks/05_theory``)."""

from .driver import VERLET
from .rk4 import run_baseline


def verlet(fun, t_span, y0, yp0, h, *, t_eval=None, args=(), events=None, max_steps=10**8):
    """Velocity Verlet for y'' = F(t, y, y').

    One evaluation of F per step::

        y_{n+1}  = y_n + h y'_n + h^2/2 y''_n
        y''_{n+1} = F(t_{n+1}, y_{n+1}, y'_n + h y''_n)
        y'_{n+1} = y'_n + h/2 (y''_n + y''_{n+1})

    For F = f(t, y) this is the Stormer-Verlet (leapfrog) method: symmetric,
    symplectic, of order 2.  When F depends on y', the predictor
    y'_n + h y''_n stands in for y'_{n+1}; it is O(h^2) off, which changes
    y'_{n+1} by O(h^3) per step, so the method stays of order 2 (no longer
    symmetric).

    Parameters
    ----------
    fun, t_span, y0, yp0, h, t_eval, args, events, max_steps
        As for :func:`splinestep.rk4` (one evaluation of F per step).

    Returns
    -------
    OdeResult
        As :func:`splinestep.rk4`.

    References
    ----------
    .. [1] L. Verlet, "Computer 'experiments' on classical fluids. I.",
       Phys. Rev. 159 (1967) 98-103.
    .. [2] E. Hairer, C. Lubich, G. Wanner, "Geometric numerical integration
       illustrated by the Stormer-Verlet method", Acta Numerica 12 (2003)
       399-450.
    """
    return run_baseline(VERLET, fun, t_span, y0, yp0, h, t_eval, args, events, max_steps)
