"""Richardson extrapolation of the spline stepper: the classical route to
order 4, beside the symmetric compositions of ``solve(order=4)``.

The global error of a symmetric method has an expansion in even powers of
the step, e(t) = h^2 e_2(t) + h^4 e_4(t) + ..., so the runs at h and h/2
combine to (4 y_{h/2} - y_h) / 3 with error O(h^4) (Hairer, Norsett and
Wanner I, Sec. II.8).  Values between knots come from each run's spline,
whose interpolation error is O(h^4) too.
"""

import numpy as np

from ..spline import solve


def richardson(fun, t_span, y0, yp0, h, *, t_eval, args=(), **kwargs):
    """(4 y_{h/2} - y_h) / 3 at ``t_eval`` from two uniform spline runs.

    Returns the :class:`OdeResult` of the run at h/2 with ``y``, ``yp``,
    ``ypp`` replaced by the extrapolated values and ``nfev``, ``niter``,
    ``nstep`` the sums over both runs; a failure of either run is returned
    as it is.  Further keywords go to :func:`splinestep.solve`.
    """
    coarse = solve(fun, t_span, y0, yp0, h, t_eval=t_eval, args=args, **kwargs)
    if not coarse.success:
        return coarse
    fine = solve(fun, t_span, y0, yp0, h / 2, t_eval=t_eval, args=args, **kwargs)
    if not fine.success:
        return fine
    for name in ("y", "yp", "ypp"):
        fine[name] = (4.0 * np.asarray(fine[name]) - np.asarray(coarse[name])) / 3.0
    for name in ("nfev", "niter", "nstep"):
        fine[name] = fine[name] + coarse[name]
    fine.local_error = fine.local_error_yp = fine.t_local_error = np.nan
    fine.order = 4
    return fine
