"""The report's baseline: classical fourth-order Runge-Kutta on the
equivalent first-order system u = (y, y'), u' = (y', F(t, y, y'))."""

from ._explicit import RK4, run


def rk4(fun, t_span, y0, yp0, h, *, t_eval=None, args=(), max_steps=10**8):
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
        Interval of integration, t0 < tf.
    y0, yp0 : float or array_like, shape (m,)
        Initial value and first derivative.
    h : float
        Step.  The last step is shortened to end exactly at tf.
    t_eval : array_like, optional
        Sorted times at which to report the solution (cubic Hermite
        interpolation between steps); the steps are then not stored.
    args : tuple, optional
        Extra arguments passed to ``fun``.
    max_steps : int, optional
        A grid of more steps is refused before it starts (ValueError).

    Returns
    -------
    OdeResult
        As :func:`splinestep.solve`; ``ypp`` holds F at the reported
        points (interpolated between steps), ``niter`` is 0.

    References
    ----------
    .. [1] E. Hairer, S. P. Norsett, G. Wanner, "Solving Ordinary
       Differential Equations I", 2nd ed., Springer (1993), Sec. II.1.
    """
    return run(RK4, fun, t_span, y0, yp0, h, t_eval, args, max_steps)
