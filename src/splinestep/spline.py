"""Cubic-spline time stepping for y'' = F(t, y, y').

On each interval [t_i, t_{i+1}] (h = t_{i+1} - t_i) the solution is the cubic

    s_i(t) = a_i + b_i (t - t_i) + c_i (t - t_i)^2 + d_i (t - t_i)^3,

continuous with its first two derivatives at the knots and satisfying the
ODE at every knot.  With z = y''(t_{i+1}) = 2 c_{i+1} the unknown of the step,

    d_i     = (z - y''_i) / (6 h)                        (report eq. 8)
    a_{i+1} = y_i + h y'_i + h^2 (y''_i / 3 + z / 6)      (eq. 6)
    b_{i+1} = y'_i + h (y''_i + z) / 2                     (eq. 7)
    z       = F(t_{i+1}, a_{i+1}, b_{i+1})                 (eq. 9, with c = y''/2)

which is Newmark's method with beta = 1/6, gamma = 1/2 (the "linear
acceleration" method).  The step equation is solved by the report's
fixed-point iteration (start from d_i = 0, i.e. z = y''_i) or by Newton's
method.

:func:`solve` is the front door: it validates the arguments, chooses the
step (one spline step, or a composition of them) and the controller
(constant knots, or error control) and runs the one driver
(:mod:`splinestep.driver`); ``iteration="global"`` solves all knots at once
instead (:func:`splinestep.bvp.newton`).
"""

import warnings

import numpy as np

from . import _adapters, _base, _linalg, bvp, controllers, driver
from . import check as _check
from .events import Tracker
from .members import member as _member
from .step import FIXED_POINT, NEWTON

ITERATIONS = ("fixed-point", "newton", "global")

# Symmetric compositions raising the order of a symmetric one-step method
# (weights of the sub-steps, each a multiple of the step): Yoshida's triple
# jump for order 4 and his 7-stage solution A for order 6.  Their sub-steps
# leave the step (the triple jump reaches t + 1.35 h and t - 0.35 h), so
# a step that would reach outside the span (the first and last of a uniform
# grid) takes Suzuki's fractal compositions
# instead (S4(h) = S2(p h)^2 S2((1 - 4p) h) S2(p h)^2, p = 1/(4 - 4^(1/3)),
# and S6 the same of S4 with p = 1/(4 - 4^(1/5))): 5 and 25 sub-steps, each
# ending within [t, t + h] (Suzuki 1990; Hairer, Lubich and Wanner, Sec. II.4).
_CBRT2 = 2.0 ** (1.0 / 3.0)
_YOSHIDA6 = (0.784513610477560, 0.235573213359357, -1.17767998417887)
COMPOSITIONS = {
    2: (1.0,),
    4: (1.0 / (2.0 - _CBRT2), -_CBRT2 / (2.0 - _CBRT2), 1.0 / (2.0 - _CBRT2)),
    6: _YOSHIDA6 + (1.0 - 2.0 * sum(_YOSHIDA6),) + _YOSHIDA6[::-1],
}


def _suzuki(inner, p):
    """Suzuki's fractal step: ``inner`` at p, p, 1 - 4p, p, p of the step."""
    return tuple(w * v for w in (p, p, 1.0 - 4.0 * p, p, p) for v in inner)


_SUZUKI4 = _suzuki((1.0,), 1.0 / (4.0 - 4.0 ** (1.0 / 3.0)))
INSIDE_COMPOSITIONS = {
    2: (1.0,),
    4: _SUZUKI4,
    6: _suzuki(_SUZUKI4, 1.0 / (4.0 - 4.0 ** (1.0 / 5.0))),
}


def _slots(weights, distinct):
    """For each weight the index of its size among ``distinct`` (extended
    as new sizes appear): sub-steps of one size share a kept Newton matrix."""
    for w in weights:
        if w not in distinct:
            distinct.append(w)
    return np.array([distinct.index(w) for w in weights], dtype=np.int64)


def composition(order):
    """(weights, slots, inside, inside_slots) of the composition of
    ``order``: the sub-steps' sizes as fractions of the step, each with the
    index of its distinct size, and the same for the composition whose
    sub-steps stay inside the step (:data:`INSIDE_COMPOSITIONS`)."""
    weights, inside, distinct = COMPOSITIONS[order], INSIDE_COMPOSITIONS[order], []
    return (np.array(weights), _slots(weights, distinct), np.array(inside),
            _slots(inside, distinct))


def solve(fun, t_span, y0, yp0, h=None, *, knots=None, t_eval=None, args=(), events=None,
          dense_output=False, order=2, method="spline", mass=None, iteration="fixed-point",
          iterations=None, tol=1e-12, max_iter=50, jac=None, rtol=None, atol=None,
          first_step=None, max_step=None, max_steps=_base.MAX_STEPS, reuse_jacobian=True,
          check=True, y_max=np.inf, **others):
    """Solve y'' = F(t, y, y') by cubic-spline time stepping.

    Each step extends a C2 cubic spline by one knot and satisfies the ODE at
    the new knot; the implicit unknown (the third-derivative coefficient
    d_i, equivalently y'' at the new knot) is found by fixed-point
    iteration, as in the report, or by Newton's method.

    Parameters
    ----------
    fun : callable
        ``fun(t, y, yp, *args) -> y''``, with y and yp arrays of shape (m,);
        it returns an array of shape (m,), a list or a tuple of m numbers,
        or a number when m = 1.  The stepping loop runs compiled; a
        ``numba.njit`` ``fun`` is called from it compiled (its own machine
        code, through a small adapter), a plain one through the interpreter (see the manual's page "The compiled fast path"); a
        compiled ``fun`` that returns a tuple spares an array allocation
        per evaluation.
    t_span : (float, float)
        Interval of integration (t0, tf); tf < t0 integrates backwards.
    y0 : float or array_like, shape (m,)
        Initial value (real).
    yp0 : float or array_like, shape (m,)
        Initial first derivative (real).
    h : float, optional
        Uniform step (positive; the direction comes from ``t_span``).  When
        the span is not a multiple of h, the last step is shortened to end
        exactly at tf; a last step shorter than 1e-9 h is merged into the
        one before, and an h larger than the span gives one step.
    knots : array_like, optional
        Knots t0 = knots[0], ..., knots[-1] = tf, strictly monotonic
        (instead of h).
    t_eval : array_like, optional
        Times in t_span, sorted in the direction of integration, at which to
        report the solution, evaluated from each step's interpolant as the
        run goes; the knots are then not stored (unless ``dense_output``).
    args : tuple, optional
        Extra arguments passed to ``fun``, ``jac`` and the events, as
        given: a plain ``fun`` receives the Python objects, a compiled one
        their numba types (an int as int64, an array with its dtype; see the
        manual's page "The compiled fast path").
    events : callable or list of callables, optional
        Functions ``g(t, y, yp, *args)`` whose zeros are located on each
        step's interpolant as the step is taken, with the optional
        attributes ``terminal`` and ``direction`` of scipy's ``solve_ivp``
        (see :mod:`splinestep.events`); a terminal event ends the run at its
        zero.
    dense_output : bool
        Return the spline itself as ``sol`` (for ``order`` 4 or 6 the quintic
        :class:`HermiteSolution` through the knots, of the run's order).
    order : {2, 4, 6}
        2: the report's method.  4 and 6: each step of size h is a symmetric
        composition of spline steps (Yoshida's triple jump, 3 sub-steps; his
        7-stage solution A) [3]_; symmetric like the spline step, so the
        long-time behaviour is kept.  A step whose sub-steps would leave
        t_span (the first and last of a uniform grid) takes Suzuki's
        composition of the same order instead (5 and 25 sub-steps, all
        inside the step), so F is never evaluated outside t_span.  ``t_eval``, events and ``sol`` use the
        quintic Hermite through the knots' values and first two derivatives:
        O(h^6) between knots in y, its nu-th derivative O(h^(6 - nu)), so y,
        y' and the events keep the order of the run (4 or 6) and y'' at
        order 6 is O(h^4) between knots.
    method : str, (float, float) or Member
        The member of Newmark's family that takes each step
        (:mod:`splinestep.members`): "spline" (the report's method, Newmark's
        linear acceleration, beta = 1/6, gamma = 1/2; the default),
        "average-acceleration" (1/4, 1/2), "fox-goodwin" (1/12, 1/2),
        "central-difference" (0, 1/2), "hht" (Hilber-Hughes-Taylor with
        alpha_f = 0.1 in Chung and Hulbert's convention, their alpha =
        -0.1), "generalized-alpha" (Chung-Hulbert, rho_inf = 0.8), a pair
        (beta, gamma), or a record of :func:`splinestep.members.newmark`,
        :func:`~splinestep.members.hht` or
        :func:`~splinestep.members.generalized_alpha`.  Every member runs
        on every path below but ``iteration="global"`` (the spline's only);
        ``order`` 4 and 6 compose the symmetric members (gamma = 1/2, no
        alpha).  The members other than the spline interpolate between
        knots by the quintic Hermite through both knots' y, y' and y''
        (``sol`` a :class:`HermiteSolution`); the alpha members' y'' at a
        knot is their own acceleration a_n, not F there, and their
        ``local_error_yp`` is NaN (their estimate is of y alone).
    mass : array_like, scipy.sparse matrix or vector, optional
        A constant mass matrix M: solve M y'' = F(t, y, y') (as structural
        codes write M y'' + C y' + K y = f(t): ``fun`` returns f - C y' - K
        y, ``jac`` is (-K, -C)).  M is factorised once (SuperLU when it is
        sparse with :data:`splinestep._linalg.SPARSE_FROM` components or
        more; a vector is a diagonal M); the step equation is the member's
        with F replaced by M^-1 F (one solve with M per evaluation of
        ``fun``), and Newton's matrix is M - gamma h dF/dy' - beta h^2
        dF/dy (times the alpha members' weights), built in Python from any
        ``jac``, sparse when M or the Jacobian is.  ``fun`` then runs as
        plain Python (``res.path == "plain"``); ``res.ypp`` holds M^-1 F
        (the alpha members' own acceleration a_n, as without ``mass``).
        Not with ``iteration="global"``.
    iteration : {"fixed-point", "newton", "global"}
        How the step equation is solved.  "fixed-point" is the report's
        scheme; it converges when beta h^2 |dF/dy| + gamma h |dF/dy'| < 1
        (h^2/6 and h/2 for the spline; times (1 - alpha_f)/(1 - alpha_m)
        for the alpha members).  "newton" uses Newton's method with an LU
        solve of I - beta h^2 dF/dy - gamma h dF/dy' (those weights again;
        M - ... with ``mass``) (exact ``jac``, or finite differences
        at m evaluations of F), the matrix kept across iterations and steps
        and rebuilt when convergence slows (``reuse_jacobian``).  On a linear
        problem, with an exact ``jac``, its first iteration solves the step
        equation to rounding error, and a second one confirms it, so a
        converged step costs 2 iterations (3 with the finite-difference
        Jacobian, which is off by about sqrt(eps)).  "global" solves the
        equations of all knots together by Newton's method with a sparse LU
        (:mod:`splinestep.bvp`), starting from one sweep per step; it gives
        the stepwise solution, without the step-size check (``local_error``
        is NaN, nothing warns), and a run whose starting sweep or Newton
        iteration fails returns its initial state only.  Its update
        converges when it is at most ``tol`` times the largest value or
        within 8 times the rounding level of F, a floor like the step's.  It makes the
        Jacobian dense, m x m blocks at every knot: about
        :data:`GLOBAL_BYTES` n m^2 bytes for n steps, and a run that would
        need more than a fifth of the memory free is refused (ValueError).
        On one processor it cannot pay: on the chain of masses, 10 steps
        take under a second at m = 100, a few seconds at m = 200 and about
        10 s at m = 400 (CPU time grows like m^3), and
        100 steps at m = 200 take 23 s and 3.7 GiB, where ``"newton"``
        with the sparse jac takes about 0.01 s; at m = 10,000 a single
        step would need 93 GiB.  It is the structure that parallel-in-time
        methods distribute (:mod:`splinestep.bvp`); large systems take the
        stepwise paths.
    iterations : int, optional
        Exactly this many iterations per step, with no convergence test
        (the report's "a few times").  By default iterate until converged.
    tol : float
        Convergence test: the change of the step's increments (of y and y'
        at the new knot) is at most ``tol`` times the size of the state
        (max norm); or, where that lies below the rounding level of F, the
        residual of the step equation is within a few times that level
        (F at a state known to rounding is known to about eps (|dF/dy| |y| +
        |dF/dy'| |y'|) only, which for a stiff F, the stiffness matrix of
        10,000 masses at omega h = 1, is above tol = 1e-12 of the state).
        The sweep measures the level with one evaluation of F when its
        change stops decreasing; Newton bounds it from its matrix.
    max_iter : int
        Iterations allowed per step before the run fails (when
        ``iterations`` is None).
    jac : callable or pair of matrices, optional
        ``jac(t, y, yp, *args) -> (dF/dy, dF/dyp)``, two (m, m) arrays or
        scipy.sparse matrices, or the pair (dF/dy, dF/dyp) itself when the
        Jacobian is constant (as scipy's ``solve_ivp`` takes a constant
        ``jac``), used by Newton's method (finite differences otherwise:
        m evaluations of F per matrix); unused, with a warning, by the
        fixed-point iteration.  A function returning dense arrays is called
        by the compiled loop, which factorises Newton's matrix by its own
        dense LU (O(m^3) a factorisation, O(m^2) a solve, 8 m^2 bytes).
        Constant or scipy.sparse matrices are turned into Newton's matrix in
        Python, called from the loop only when the matrix is (re)built:
        scipy.sparse ones from :data:`splinestep._linalg.SPARSE_FROM` = 120
        components on are factorised by SuperLU (``scipy.sparse.linalg.splu``),
        the factors kept across steps as the dense ones are, each Newton
        solve one call into Python (for the banded matrices of structural
        models O(m) time and memory); below, and constant dense ones at any
        m, they go to the compiled dense LU, which is faster there (the
        crossover measured on the chain of masses: per step 7.7 us dense
        against 8.6 us SuperLU at m = 100, 12 us against 9.7 us at m = 150,
        0.68 ms against 39 us at m = 1,000).  With such matrices a
        residual at the rounding level ends the iteration before a further
        solve, so that a step of a linear problem costs one solve.
    rtol, atol : float or array_like of shape (m,)
        Adaptive knots (neither ``h`` nor ``knots`` given): tolerances on
        the global error, by default 1e-3 and 1e-6 (a run with neither
        ``h``, ``knots`` nor ``rtol`` is adaptive at these; what that costs
        against scipy's default, ``make bench`` measures on the manual's
        Speed page).  Given with
        ``h`` or ``knots``, they (and ``first_step``, ``max_step``) are
        ignored with a warning that says so.  Each step's estimated local errors of y and y'
        (from the jump of the spline's third derivative,
        :mod:`splinestep.controllers`), per unit step and times the span
        |tf - t0|, must be at most atol + rtol |y| in scipy's scaled RMS
        norm, so that a run's local errors sum to at most the tolerance and
        its global error follows rtol in proportion (measured on five
        problems over rtol = 1e-3 ... 1e-8: the final error below rtol
        times the solution's scale in y, within 10 times in y'; a problem
        that amplifies errors, such as Pleiades, ends further off, about
        40 times rtol).  scipy's codes bound each step's error instead.
        The tolerance is spread over the whole of t_span, also when a
        terminal event ends the run early, and the work grows like
        |tf - t0|^(3/2) / rtol^(1/2): below about rtol = 1e-12 a run may
        exhaust ``max_steps``.  Where y or y' passes through
        zero, atol sets the scale.  ``res.t`` holds the knots chosen;
        ``res.n_rejected`` and ``res.n_failed`` count the steps rejected by
        the estimate and those whose equation could not be solved (both
        retried smaller).
    first_step, max_step : float
        Adaptive knots: the first step (chosen from y0, yp0 by default) and
        the largest step.  The first step is raised to the rounding floor,
        16 eps max(|t0|, |tf - t0|), as scipy raises its steps to its
        minimum (a run restarted at a located event, where y is zero to
        rounding, would otherwise propose a smaller one and stop at once).
    max_steps : int
        The most steps a run may take (default 10**8).  A fixed grid (``h``
        or ``knots``) of more steps is refused before it starts (ValueError);
        adaptive knots stop after this many step attempts (status -1).
    reuse_jacobian : bool
        Newton: keep the matrix and its LU factors while the iteration
        converges fast (simplified Newton [4]_); False rebuilds it at every
        iteration (full Newton).
    check : bool
        Run the step-too-large check (default True; see
        :mod:`splinestep.check` and Warns below).  Its cost does not depend
        on the number of steps: up to :data:`splinestep.check.DENSE_UP_TO`
        = 64 components, dense Jacobians at up to three states (2m + 1
        evaluations of F each without ``jac``) and the eigenvalues of 2m x 2m
        matrices, O(m^3) time and O(m^2) memory; above, Arnoldi steps on
        Jacobian-vector products, about 32 evaluations of F per state when
        F does not depend on y', up to about 80 when it does (or
        products with ``jac``'s matrices), O(m) memory.  Measured on the
        chain of masses over 3.125 periods of its slowest mode at omega_m h
        = 1 (``benchmarks/scaling.py``): about 1 ms at m = 10, 4 ms at
        m = 100, 6 ms at m = 1,000, 0.03 s at m = 10,000 and 0.3 s at
        m = 100,000, that is about 0.1 % of the run at m = 10,000 and 0.01 % at
        m = 100,000, but 3 % at m = 1,000 and most of the runs of a
        millisecond or so at m = 10 and 100.  False skips it: no warning
        and no evaluation (``local_error``, from the run itself, is still
        reported).
    y_max : float
        A bound on the solution: a run whose |y| exceeds ``y_max`` in any
        component at a knot stops there, failed (status -1, the message
        names the time), and returns the steps before it (default inf: no
        bound; a y0 beyond it is a ValueError).  Where the step-size check
        finds a blow-up it fails the run too, but not a run from the zero
        state, y0 = 0 and y'0 = 0, nor one of order 4 or 6, which keep the
        warning (:mod:`splinestep.check`); the bound holds on every
        stepwise run of ``solve``, checked or not.  Not with
        ``iteration="global"`` (ValueError).

    **others
        Any other keyword is a ValueError naming it.

    Returns
    -------
    OdeResult
        ``t`` (k,), ``y``, ``yp``, ``ypp`` (m, k), ``sol``, ``t_events``,
        ``y_events``, ``yp_events``, ``nfev``, ``njev``, ``niter``,
        ``nstep``, ``n_rejected``, ``n_failed``, ``local_error``,
        ``local_error_yp``, ``t_local_error`` (the run's own estimate: that
        of a spline step of the size taken, which for ``order`` 4 or 6
        overstates the local error; NaN for global runs), ``rho`` (None),
        ``method``, ``order``, ``path``, ``status`` (0 reached the end, 1 a
        terminal event, -1 failed), ``message``, ``success`` (status >= 0);
        the same keys as every solver of the package
        (:data:`splinestep.result.DEFAULTS`).  ``nfev`` counts every call
        of ``fun``: the first, at t0, and those of the step-too-large check
        (see ``check``) among them.  A failed run
        returns the steps completed before the failure and says in
        ``message`` which step failed and why.

    Warns
    -----
    UserWarning
        When the run's own error estimate says that the step is far too
        large for the solution (see :mod:`splinestep.check`); the message
        then says so too.  Every path but ``iteration="global"``.

    References
    ----------
    .. [1] N. M. Newmark, "A method of computation for structural dynamics",
       J. Eng. Mech. Div. ASCE 85 (1959) 67-94.
    .. [2] E. L. Wilson, I. Farhoomand, K. J. Bathe, "Nonlinear dynamic
       analysis of complex structures", Earthquake Eng. Struct. Dyn. 1 (1973)
       241-252 (the linear acceleration method).
    .. [3] H. Yoshida, "Construction of higher order symplectic integrators",
       Phys. Lett. A 150 (1990) 262-268; E. Hairer, C. Lubich, G. Wanner,
       "Geometric Numerical Integration", 2nd ed., Springer (2006), Sec. II.4
       and V.3.
    .. [4] E. Hairer, G. Wanner, "Solving Ordinary Differential Equations II",
       2nd ed., Springer (1996), Sec. IV.8.

    Examples
    --------
    >>> import numpy as np, splinestep
    >>> res = splinestep.solve(lambda t, y, yp: -y, (0, np.pi), 1.0, 0.0, h=np.pi / 100)
    >>> bool(abs(res.y[0, -1] + 1) < 1e-3)
    True
    """
    t0, tf = _base.check_span(t_span, backward=True)
    y0, yp0 = _base.check_state(y0, yp0)
    arguments = locals()   # the options as given, read by their names in _OPTIONS
    given = {name: arguments[name] for name in _OPTIONS}
    opts = _options(given, others, adaptive=h is None and knots is None)
    if np.max(np.abs(y0)) > opts["y_max"]:
        raise ValueError(f"y_max = {opts['y_max']:g} is below the largest |y0|, "
                         f"{np.max(np.abs(y0)):g}")
    adaptive = h is None and knots is None
    if not adaptive:
        h, n, knots = _base.check_grid(t0, tf, h, knots, opts["max_steps"])
    t_eval = _base.check_t_eval(t_eval, t0, tf)
    args = _base.check_args(args)
    member = _member(opts["method"])
    _check_choices(opts, order, adaptive, events, member)
    step, jac = _step(fun, opts, order, member)
    if opts["iteration"] == "global":
        return _solve_global(fun, t0, tf, y0, yp0, h, n, knots, t_eval, args, opts,
                             dense_output)
    if adaptive:
        ctrl = controllers.error_control(t0, tf, *_base.check_tolerances(
            opts["rtol"], opts["atol"], opts["first_step"], opts["max_step"],
            opts["max_steps"], y0.size), theta_max=controllers.contraction_target(
                member, step.iteration.mode == FIXED_POINT), y_max=opts["y_max"])
        if ctrl[0].first_step > abs(tf - t0):
            raise ValueError(f"first_step = {ctrl[0].first_step:g} exceeds the span "
                             f"{abs(tf - t0):g} of t_span")
        floor = controllers.rounding_floor(t0, t0, tf)
        if ctrl[0].max_step < floor:
            raise ValueError(f"max_step = {ctrl[0].max_step:g} is below the rounding floor "
                             f"{floor:.3g} of t_span (16 eps max(|t0|, |tf - t0|)): a step "
                             "that small does not change t reliably")
    else:
        ctrl = controllers.constant(tf, h, n, knots, opts["max_steps"], opts["y_max"])
    weights, slots, inside, inside_slots = composition(order)
    step = step._replace(weights=weights, slots=slots, inside=inside, inside_slots=inside_slots)
    mass = None if opts["mass"] is None else _linalg.Mass(opts["mass"], y0.size)
    return run_spline(fun, jac, args, step, ctrl, (t0, y0, yp0), (t_eval, events, dense_output),
                      opts["max_iter"], check=opts["check"], member=member, mass=mass)


# The memory of iteration="global" per step and per m^2 (its dense Jacobian
# blocks, the sparse matrix of the whole trajectory and SuperLU's factors):
# measured on the chain of masses, 980 bytes at m = 100 and 200.
GLOBAL_BYTES = 1000

_OPTIONS = dict(method="spline", mass=None, iteration="fixed-point", iterations=None, tol=1e-12, max_iter=50, jac=None,
                rtol=1e-3, atol=1e-6, first_step=None, max_step=np.inf,
                max_steps=_base.MAX_STEPS, reuse_jacobian=True, check=True, y_max=np.inf)


# Options of adaptive knots only: with h or knots they are ignored, and said so.
ADAPTIVE_ONLY = ("rtol", "atol", "first_step", "max_step")


def _options(given, others, adaptive):
    """The keyword options of :func:`solve`, the adaptive ones at their
    defaults where not given; an unknown name is a ValueError naming it,
    and an adaptive option given with a fixed grid a warning."""
    _base.check_options(others, _OPTIONS, "solve")
    ignored = [name for name in ADAPTIVE_ONLY if given[name] is not None and not adaptive]
    if ignored:
        warnings.warn(f"{' and '.join(ignored)} {'applies' if len(ignored) == 1 else 'apply'} "
                      "to adaptive knots only (neither h nor knots given) and "
                      f"{'is' if len(ignored) == 1 else 'are'} ignored with a fixed grid",
                      UserWarning, stacklevel=3)
    opts = dict(_OPTIONS, **{k: v for k, v in given.items()
                             if v is not None or k not in ADAPTIVE_ONLY})
    opts["max_steps"] = _base.check_max_steps(opts["max_steps"])
    opts["check"] = _base.check_flag(opts["check"], "check")
    y_max = opts["y_max"]
    number = isinstance(y_max, (int, float, np.integer, np.floating))
    if isinstance(y_max, (bool, np.bool_)) or not number or not y_max > 0:
        raise ValueError(f"y_max must be a positive number (inf: no bound), got {y_max!r}")
    opts["y_max"] = float(y_max)
    return opts


def _check_choices(opts, order, adaptive, events, member):
    """The ValueErrors of the choices that exclude each other."""
    iteration = opts["iteration"]
    if order != 2 and not member.symmetric:
        raise ValueError(f"order={order} composes symmetric steps only (gamma = 1/2, no "
                         f"alpha); method {member.describe()} is not")
    if iteration == "global" and opts["y_max"] < np.inf:
        raise ValueError('iteration="global" takes no y_max (it solves every knot at once); '
                         'pass iteration="newton"')
    if iteration == "global" and opts["mass"] is not None:
        raise ValueError('iteration="global" takes no mass matrix; pass iteration='
                         '"fixed-point" or "newton"')
    if iteration == "global" and not member.is_spline:
        raise ValueError('iteration="global" solves the spline\'s relations only; method '
                         f"{member.name!r} takes iteration=\"fixed-point\" or \"newton\"")
    if iteration not in ITERATIONS:
        raise ValueError(f"iteration must be one of {ITERATIONS}, got {iteration!r}")
    if not _base.is_integer(order) or order not in COMPOSITIONS:
        raise ValueError(f"order must be one of {tuple(COMPOSITIONS)}, got {order!r}")
    _base.check_flag(opts["reuse_jacobian"], "reuse_jacobian")
    if adaptive and order != 2:
        raise ValueError(f"order={order} needs h or knots: the adaptive knots control "
                         "the error of the order-2 step")
    if iteration == "global" and adaptive:
        raise ValueError('iteration="global" needs h or knots')
    no_events = events is None or (isinstance(events, (list, tuple)) and len(events) == 0)
    if iteration == "global" and (order != 2 or not no_events
                                  or opts["iterations"] is not None):
        raise ValueError('iteration="global" takes neither order > 2, events nor '
                         "iterations")


def _step(fun, opts, order, member):
    """The step's :class:`splinestep.driver.Method` (weights to be set) of
    the :class:`splinestep.members.Member` ``member`` and the ``jac`` it
    uses, from the validated options."""
    tol, max_iter, iterations, jac = (opts["tol"], opts["max_iter"], opts["iterations"],
                                      opts["jac"])
    if not (_base.is_real(tol) and np.isfinite(tol) and tol > 0):
        raise ValueError(f"tol must be positive and finite, got {tol!r}")
    if not (_base.is_integer(max_iter) and max_iter >= 1):
        raise ValueError(f"max_iter must be an integer >= 1, got {max_iter!r}")
    if iterations is not None and not (_base.is_integer(iterations) and iterations >= 1):
        raise ValueError(f"iterations must be None or an integer >= 1, got {iterations!r}")
    if not callable(fun):
        raise ValueError("fun must be callable")
    jac = _base.check_jac_option(jac)
    mode = FIXED_POINT if opts["iteration"] == "fixed-point" else NEWTON
    if jac is not None and mode == FIXED_POINT:
        warnings.warn("jac is not used by the fixed-point iteration; pass "
                      "iteration=\"newton\" to use it", UserWarning, stacklevel=3)
        jac = None
    until_converged = iterations is None
    kind = driver.SPLINE if order == 2 else driver.COMPOSED
    return driver.method(kind, mode, max_iter if until_converged else iterations,
                         until_converged, tol, opts["reuse_jacobian"],
                         scheme=member.scheme()), jac


def run_spline(fun, jac, args, step, ctrl, start, output, max_iter, control=None,
               check=True, member=None, mass=None):
    """The spline stepper on the driver, with every check: the front door
    of :func:`solve` and :func:`splinestep.solve_reversible` once their
    arguments are valid and their step and controller chosen.  ``start`` is
    (t0, y0, yp0), ``output`` (t_eval or None, events, dense_output);
    ``check`` runs the step-too-large check (:mod:`splinestep.check`).

    A ``jac`` given as constant matrices, or returning scipy.sparse ones,
    has its Newton matrices built in Python (:class:`splinestep._linalg.Matrices`):
    factorised by SuperLU from :data:`splinestep._linalg.SPARSE_FROM`
    components, else densified for the compiled LU.  ``member`` is the
    :class:`splinestep.members.Member` the step takes (the spline's when
    None); ``mass`` a :class:`splinestep._linalg.Mass`, whose runs see
    M^-1 F as their F (a plain function) and build every Newton matrix in
    Python, M - wy dF/dy - wyp dF/dy'.  The order is that of the
    composition of :data:`COMPOSITIONS` with the step's number of sub-steps."""
    member = _member("spline") if member is None else member
    order = next(o for o, w in COMPOSITIONS.items() if len(w) == step.weights.size)
    t0, y0, yp0 = start
    t_eval, events, dense_output = output
    kind = None if jac is None else _base.check_jac(jac, t0, y0, yp0, args)
    matrices = None
    given = fun
    if mass is not None:
        fun = mass.apply(fun)
    if kind == "sparse" or (kind is not None and (not callable(jac) or mass is not None)):
        matrices = _linalg.Matrices(
            jac, args, y0.size, (kind == "sparse" or (mass is not None and mass.sparse))
            and y0.size >= _linalg.SPARSE_FROM, mass)
    loop_jac = None if matrices is not None else jac
    path = _base.choose_path(fun, loop_jac, args)
    if path == "compiled":
        args = _adapters.passable(args)
    ypp0 = _base.check_fun(fun, t0, y0, yp0, args)
    tracker = Tracker.of(events, args, t0, y0, yp0)
    store = t_eval is None or dense_output
    out, reason = driver.run(path, fun, loop_jac, args, step, ctrl, (t_eval, store, tracker),
                             (t0, y0, yp0, ypp0), control, matrices)
    if matrices is not None and matrices.reason is not None and reason is None:
        reason = matrices.reason
    result = driver.result_of(out, t_eval, max_iter, ctrl[0], reason, path=path,
                              order=min(order, member.order) if order == 2 else order,
                              method=member.name, njev=int(callable(jac)),
                              dense_output=dense_output, iteration=step.iteration.mode,
                              interpolant=member.interpolant if order == 2 else None)
    if tracker is not None:
        tracker.attach(result)
    def retake(t, y, yp, h):
        """(y, y') at t + h after one more step of h from (t, y, y'), or None."""
        again = run_spline(given, jac, args, step, controllers.constant(t + h, h, 1, (), 1),
                           (t, y, yp), (np.array([t + h]), None, False), max_iter,
                           check=False, member=member, mass=mass)
        return (again.y[:, -1], again.yp[:, -1]) if again.status == 0 else None

    # For a composition the jumps measure the local error of a spline step of
    # size h, which overstates the composition's: the check still sees a step
    # far too large for the solution, and no reasonable one.
    _check.report(result, out, fun, None if mass is not None else jac, args, (t0, y0, yp0),
                  member, check, retake if order == 2 else None)
    return result


def _solve_global(fun, t0, tf, y0, yp0, h, n, knots, t_eval, args, opts, dense_output):
    """``solve(..., iteration="global")``: the initial value problem on the
    given knots, solved by :func:`splinestep.bvp.newton` on the whole
    trajectory from the guess of one fixed-point sweep per step (the
    stepper's cheapest pass).  The guess's step-size check is not
    reported: it would judge the guess, not the solution.  A run whose
    starting sweep or Newton iteration fails returns its first knot only (no step of the
    solution is completed before the whole trajectory is)."""
    if knots.size == 0:
        knots = t0 + h * np.arange(n + 1)
        knots[-1] = tf
    m, steps, free = y0.size, knots.size - 1, driver._free_memory()
    need = GLOBAL_BYTES * steps * m * m
    if free is not None and need > free / 5:
        raise ValueError(
            f"iteration=\"global\" would need about {need / 2**30:.3g} GiB for m = {m} "
            f"components over {steps} step{'s' if steps != 1 else ''} (a dense m x m block "
            f"at every knot: about {GLOBAL_BYTES} n m^2 bytes), more than a fifth of the memory free "
            f"({free / 2**30:.3g} GiB); take iteration=\"newton\", the same solution one "
            "step at a time in O(m) memory with a sparse jac")
    jac = opts["jac"]
    if jac is not None:
        _base.check_jac(jac, t0, y0, yp0, args)
        if not callable(jac):   # constant matrices: the whole trajectory's blocks are dense
            parts = tuple(part.toarray() if _base.is_sparse(part) else np.asarray(part, float)
                          for part in jac)
            jac = lambda t, y, yp, *a: parts   # noqa: E731
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        guess = solve(fun, (t0, tf), y0, yp0, knots=knots, args=args, iterations=1)
    U = np.stack([guess.y.T, guess.yp.T, guess.ypp.T], axis=1)
    start = U[:1].copy()    # Newton moves the iterate's first knot too
    hint = "try a smaller h, or iteration='newton'"
    if guess.success:
        status, message, niter, nfev, njev = bvp.newton(
            fun, jac, args, knots, U, [(0, 0, y0), (0, 1, yp0)], opts["tol"],
            opts["max_iter"], hint=hint)
    else:   # the guess is not the method's solution: nothing of it is kept
        status, message, niter, nfev, njev = -1, (
            "The starting sweep (one fixed-point iteration per step) failed: "
            f"{guess.message.split(' Returning')[0].removesuffix(' Try a smaller h.')} "
            f"{hint.capitalize()}"), guess.niter, 0, 0
    counts = (niter, nfev + guess.nfev, njev + int(jac is not None))
    if status != 0:
        return bvp.result(knots[:1], start, status,
                          message.rstrip(".") + ". Returning the initial state.", *counts,
                          dense_output=False)
    return bvp.result(knots, U, status, message, *counts, t_eval, dense_output)
