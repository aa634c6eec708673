"""The method's theory, derived by sympy: local errors, the two-step
recurrence and its order, the oscillator's amplification matrix, the
higher-degree splines' recurrences, and the modified potential and energy
of the Verlet conjugacy.

Each derivation returns sympy expressions (:func:`latex` and :func:`aligned`
typeset them); the functions after them measure the same constants with the
package, on the oscillator y'' = -omega^2 y and the two-step recurrence.
``notebooks/05_theory`` shows the derivations and the measurements, and
``tests/test_theory.py`` checks every constant against a measurement.  Needs
sympy (``pip install splinestep[theory]``).

References
----------
.. [1] P. Henrici, "Discrete Variable Methods in Ordinary Differential
   Equations", Wiley (1962), Ch. 6 (multistep methods for y'' = f(t, y)).
.. [2] E. Hairer, S. P. Norsett, G. Wanner, "Solving Ordinary Differential
   Equations I", 2nd ed., Springer (1993), Secs. II.3 and III.10.
.. [3] E. Hairer, C. Lubich, G. Wanner, "Geometric Numerical Integration",
   2nd ed., Springer (2006), Chs. IX and XI.
.. [4] F. R. Loscalzo, T. D. Talbot, "Spline function approximations for
   solutions of ordinary differential equations", SIAM J. Numer. Anal. 4
   (1967) 433-445.
"""

import warnings

import numpy as np
from . import require

sp = require("sympy", __name__)

from .. import problems
from ..spline import solve
from .diagnostics import recurrence_fit

h, x, zeta = sp.symbols("h x zeta")
# Derivatives y^(j) of the exact solution at t_i, and F's partial
# derivatives dF/dy = p, dF/dy' = q (scalars: the leading terms are the
# same per component).
Y = sp.symbols("y0:7")
p, q = sp.symbols("p q")


def _taylor(j, step, order=7):
    """y^(j)(t_i + step) as a Taylor polynomial in ``step``."""
    return sum(Y[j + k] * step ** k / sp.factorial(k) for k in range(order - j))


def local_errors(order=5):
    """Leading terms of the one-step errors of the spline step started
    from exact values: (err_y, err_yp), series in h.

    The step solves z = F(t + h, a(z), b(z)) with a(z) = y + h y' + h^2
    (y''/3 + z/6), b(z) = y' + h (y'' + z)/2.  Writing the exact values as
    Taylor series and z = y''(t + h) + dz, where F's change is linearised
    (dz = p da + q db, exact to the orders shown), gives the errors
    a - y(t + h) and b - y'(t + h)."""
    da, db = sp.symbols("da db")
    z_exact = _taylor(2, h)
    dz = p * da + q * db
    a = Y[0] + h * Y[1] + h ** 2 * (Y[2] / 3 + (z_exact + dz) / 6)
    b = Y[1] + h * (Y[2] + z_exact + dz) / 2
    solution = sp.solve([sp.Eq(da, a - _taylor(0, h)), sp.Eq(db, b - _taylor(1, h))], [da, db])
    return tuple(sp.series(solution[v], h, 0, order + (v is da)).removeO().expand()
                 for v in (da, db))


def two_step():
    """For y'' = f(t, y): eliminate y' from two consecutive steps.

    Returns (rho, sigma, residual): the characteristic polynomials of
    sum_j alpha_j y_{n+j} = h^2 sum_j beta_j f_{n+j} (in zeta, j = 0, 1, 2),
    and the residual of that relation on the step equations with symbolic
    y_n, y'_n, f_n (zero when the elimination is right)."""
    yy = sp.symbols("Y0:3")
    vv = sp.symbols("V0:3")
    ff = sp.symbols("f0:3")
    # two steps: n -> n+1 and n+1 -> n+2
    step_y = [sp.Eq(yy[j + 1], yy[j] + h * vv[j] + h ** 2 * (ff[j] / 3 + ff[j + 1] / 6))
              for j in range(2)]
    step_v = [sp.Eq(vv[j + 1], vv[j] + h * (ff[j] + ff[j + 1]) / 2) for j in range(2)]
    alpha = (1, -2, 1)
    beta = (sp.Rational(1, 6), sp.Rational(2, 3), sp.Rational(1, 6))
    lhs = sum(a * yy[j] for j, a in enumerate(alpha)) - h ** 2 * sum(
        b * ff[j] for j, b in enumerate(beta))
    known = sp.solve(step_y + step_v[:1], [yy[1], yy[2], vv[1]], dict=True)[0]
    residual = sp.simplify(lhs.subs(known))
    rho = sum(a * zeta ** j for j, a in enumerate(alpha))
    sigma = sum(b * zeta ** j for j, b in enumerate(beta))
    return rho, sigma, residual


def error_constants(rho_coeffs, sigma_coeffs, up_to=7):
    """C_k of a linear multistep method for y'' = f (Henrici's order
    conditions): L[y](t) = sum_k C_k h^k y^(k)(t), with
    C_k = sum_j alpha_j j^k / k! - sum_j beta_j j^(k-2) / (k-2)!.
    The method has order p when C_0 = ... = C_{p+1} = 0; C_{p+2} is its
    error constant (taken about t_n, the first point)."""
    out = []
    for k in range(up_to):
        c = sum(a * sp.Integer(j) ** k for j, a in enumerate(rho_coeffs)) / sp.factorial(k)
        if k >= 2:
            c -= sum(b * sp.Integer(j) ** (k - 2)
                     for j, b in enumerate(sigma_coeffs)) / sp.factorial(k - 2)
        out.append(sp.nsimplify(c))
    return out


def amplification(beta=sp.Rational(1, 6)):
    """The matrix M with (y_{n+1}, h y'_{n+1}) = M (y_n, h y'_n) for
    Newmark's method (gamma = 1/2, parameter ``beta``) on y'' = -omega^2 y,
    as a function of x = omega h."""
    y0, v0, z = sp.symbols("y_n v_n z")           # v = h y'
    ypp0 = -x ** 2 * y0 / h ** 2
    a = y0 + v0 + h ** 2 * ((sp.Rational(1, 2) - beta) * ypp0 + beta * z)
    zsol = sp.solve(sp.Eq(z, -x ** 2 / h ** 2 * a), z)[0]
    y1 = sp.simplify(a.subs(z, zsol))
    v1 = sp.simplify(v0 + h ** 2 * (ypp0 + zsol) / 2)
    return sp.Matrix([[sp.diff(y1, y0), sp.diff(y1, v0)], [sp.diff(v1, y0), sp.diff(v1, v0)]])


def period_error(cos_theta, terms=2):
    """T_h / T - 1 = x / theta - 1 as a series in x (``terms`` terms),
    where cos(theta) = ``cos_theta`` (an expression in x) is the rotation
    per step: theta = x (1 + a_1 x^2 + a_2 x^4 + ...), with the a_k matched
    order by order in cos(theta) - cos_theta = 0."""
    a = sp.symbols(f"a1:{terms + 1}")
    theta = x * (1 + sum(ak * x ** (2 * k + 2) for k, ak in enumerate(a)))
    top = 2 * terms + 3
    mismatch = sp.expand(sp.series(sp.cos(theta) - cos_theta, x, 0, top).removeO())
    values = {}
    for k, ak in enumerate(a):
        values[ak] = sp.solve(mismatch.coeff(x, 2 * k + 4).subs(values), ak)[0]
    ratio = sp.series(x / theta.subs(values), x, 0, 2 * terms + 1).removeO()
    return sp.expand(ratio - 1)


def spline_step_matrix(degree, lam=None, c=None, first_order=False):
    """The linear map of the C^{k-1} spline of degree k = ``degree``
    collocating y'' = lam y - c y' (damping c; or, with ``first_order``,
    y' = lam y) at every knot, on the state (p, p', ..., p^{(k-1)}) at the
    knot.

    Returns the k x k matrix (entries in h, lam, c; the symbols ``lambda``
    and ``c`` where ``lam`` and ``c`` are not given)."""
    k = degree
    lam = sp.Symbol("lambda") if lam is None else lam
    c = sp.Symbol("c") if c is None else c
    D = sp.symbols(f"D0:{k}")
    z = sp.Symbol("z")
    base = [sum(D[l] * h ** (l - j) / sp.factorial(l - j) for l in range(j, k)) for j in range(k)]
    weight = [sp.factorial(k) / sp.factorial(k - j) * h ** (k - j) for j in range(k)]
    order = 1 if first_order else 2                # the collocated derivative
    g = (z - base[order]) / weight[order]
    new = [base[j] + weight[j] * g for j in range(k)]
    rhs = lam * new[0] if first_order else lam * new[0] - c * new[1]
    zsol = sp.solve(sp.Eq(z, rhs), z)[0]
    new = [sp.cancel(e.subs(z, zsol)) for e in new]
    return sp.Matrix([[sp.diff(new[i], D[j]) for j in range(k)] for i in range(k)])


def characteristic_at_zero(degree, first_order=False):
    """The characteristic polynomial of the degree-k spline's recurrence in
    the limit h -> 0 (zero-stability: its roots), factored."""
    # With F = 0 (y'' = 0) the map is the h -> 0 limit of every linear F's
    # (F enters with factors h^2 and h), and its polynomial is free of h.
    M = spline_step_matrix(degree, lam=0, c=0, first_order=first_order)
    return sp.factor(M.charpoly(zeta).as_expr())


def modified_potential(V, Q, order=4):
    """The potential V~ of the force f~(Q) = f(q(Q)), q - h^2 f(q)/6 = Q,
    f = -V'(q), for a one-dimensional V (an expression in the symbol Q):
    the series in h up to h^order, by fixed-point substitution."""
    f = -sp.diff(V, Q)
    qq = Q
    for _ in range(order // 2 + 1):
        qq = sp.series(Q + h ** 2 / 6 * f.subs(Q, qq), h, 0, order + 1).removeO()
    force = sp.series(f.subs(Q, qq), h, 0, order + 1).removeO()
    return sp.expand(-sp.integrate(force, Q))


def verlet_in_other_variables():
    """The two-step relation of the spline stepper in q,
    q0 - 2 q1 + q2 = h^2 (f0 + 4 f1 + f2) / 6, subtracted from Stormer-
    Verlet's in Q = q - h^2 f(q) / 6, Q0 - 2 Q1 + Q2 = h^2 f1, simplified:
    zero when the two are the same relation."""
    q0, q1, q2, f0, f1, f2 = sp.symbols("q0 q1 q2 f0 f1 f2")
    spline = h ** 2 * (f0 + 4 * f1 + f2) / 6 - (q0 - 2 * q1 + q2)
    Q = [qi - h ** 2 * fi / 6 for qi, fi in ((q0, f0), (q1, f1), (q2, f2))]
    verlet = h ** 2 * f1 - (Q[0] - 2 * Q[1] + Q[2])
    return sp.simplify(verlet - spline)


def two_step_oscillator(y0, y1, h, steps, omega=1.0):
    """The spline stepper's two-step method on y'' = -omega^2 y, from given
    starting values: ``y_{n+1} - 2 y_n + y_{n-1} = h^2 (f_{n+1} + 4 f_n + f_{n-1})/6``
    with ``f = -omega^2 y``, solved for ``y_{n+1}`` (it is linear), for
    ``steps`` steps.  Returns ``y_0, ..., y_steps``.

    The starting values are free, so that the hypotheses of the convergence
    theorem on them (Hairer, Norsett and Wanner I, Sec. III.10) can be tried
    one at a time.
    """
    if steps < 1:
        raise ValueError(f"steps must be at least 1, got {steps}")
    x2 = (omega * h) ** 2
    factor = (2 - 2 * x2 / 3) / (1 + x2 / 6)
    y = np.empty(steps + 1)
    y[0], y[1] = y0, y1
    for n in range(1, steps):
        y[n + 1] = factor * y[n] - y[n - 1]
    return y


# Typesetting: the derivations as LaTeX, for IPython.display.Math.

# y0, y1, ... (the derivatives y^(j)(t_i)) as y^{(j)}.
LATEX_NAMES = {symbol: f"y^{{({j})}}" for j, symbol in enumerate(Y)}


def latex(expr, order=None):
    """LaTeX of an expression of this module's symbols.

    Parameters
    ----------
    expr : sympy expression or matrix
        E.g. a local error of :func:`local_errors` or a polynomial of
        :func:`two_step`.
    order : str, optional
        sympy's term order: None (sympy's, descending powers) or
        ``"rev-lex"``, which writes a series in ascending powers (the
        leading term of a local error first).

    Returns
    -------
    str
        The LaTeX, with the derivatives ``y4`` written as ``y^{(4)}``.
    """
    return sp.latex(expr, symbol_names=LATEX_NAMES, order=order)


def aligned(rows, order=None):
    """Equations one under the other, aligned at their equals signs.

    Parameters
    ----------
    rows : sequence of (str, str or sympy expression)
        The left side of each equation (LaTeX) and its right side: LaTeX,
        or an expression typeset by :func:`latex`.
    order : str, optional
        The term order of those expressions (:func:`latex`).

    Returns
    -------
    str
        A LaTeX ``aligned`` block, for ``IPython.display.Math``.
    """
    lines = [f"{left} &= {right if isinstance(right, str) else latex(right, order)}"
             for left, right in rows]
    return "\\begin{aligned}" + " \\\\ ".join(lines) + "\\end{aligned}"


# Measurements of the derived constants, made with the package.

def oscillator_run(x, y0, v0, steps, tol=1e-15):
    """Newton-solved steps of y'' = -y at h = omega h = ``x``.

    Parameters
    ----------
    x : float
        The step, which is omega h for omega = 1.
    y0, v0 : float or array_like
        Starting values of y and of h y' (one component per starting
        vector: a run of several components makes several runs at once).
    steps : int
        Number of steps.
    tol : float, optional
        Newton's tolerance.  The step equation is linear, so that Newton's
        first iteration solves it and ``tol`` only decides when the
        rounding-sized corrections after it count as converged: past
        omega h of about 7 they exceed 1e-15 of the state.

    Returns
    -------
    OdeResult
        The run of ``splinestep.solve`` (``iteration="newton"``).  Its
        step-too-large warning is not raised: these steps go past the
        stability limit on purpose.
    """
    y0, v0 = np.atleast_1d(np.asarray(y0, float)), np.atleast_1d(np.asarray(v0, float))
    osc = problems.harmonic(omega=1.0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return solve(osc.fun, (0.0, steps * x), y0, v0 / x, x, args=osc.args, jac=osc.jac,
                     iteration="newton", tol=tol)


def oscillator_step_matrix(x, tol=1e-15):
    """The measured matrix M of one step, (y_1, h y'_1) = M (y_0, h y'_0).

    Parameters
    ----------
    x : float
        omega h.
    tol : float, optional
        Newton's tolerance (:func:`oscillator_run`).

    Returns
    -------
    ndarray, shape (2, 2)
        Its columns are one Newton-solved step (:func:`oscillator_run`)
        from (1, 0) and from (0, 1): the measured counterpart of
        :func:`amplification`.

    Raises
    ------
    RuntimeError
        If the step fails (its message says why).
    """
    res = oscillator_run(x, [1.0, 0.0], [0.0, 1.0], 1, tol)
    if not res.success:
        raise RuntimeError(f"the step at omega h = {x} failed: {res.message}")
    return np.array([res.y[:, -1], x * res.yp[:, -1]])


def oscillator_period_error(x, steps=400):
    """The measured relative period error T_h / T - 1 at omega h = ``x``.

    Parameters
    ----------
    x : float
        omega h, below the stability limit sqrt(12).
    steps : int, optional
        Length of the run whose samples are fitted.

    Returns
    -------
    float
        ``x / theta - 1``, with the rotation per step theta fitted to the
        computed samples (:func:`splinestep.analysis.diagnostics.recurrence_fit`)
        of a Newton-solved run from y = 1, y' = 0.  Its step-too-large
        warning (from omega h = 0.25 on over 400 steps) is not raised.
    """
    problem = problems.harmonic(omega=1.0, t_span=(0.0, steps * x), h=x)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = problem.solve(iteration="newton", tol=1e-15)
    return x / recurrence_fit(res.y[0])[1] - 1


def sweep_converges(x, max_iter=100_000):
    """Whether the fixed-point sweep solves one step of y'' = -y at omega h = ``x``.

    Parameters
    ----------
    x : float
        omega h.
    max_iter : int, optional
        Sweeps allowed.  Near the limit sqrt(6) the sweep's factor x^2/6 is
        close to 1, so the largest ``x`` that converges approaches sqrt(6)
        from below as ``max_iter`` grows.

    Returns
    -------
    bool
        True when the run succeeds within ``max_iter`` sweeps.
    """
    problem = problems.harmonic(omega=1.0, t_span=(0.0, x), h=x)
    return problem.solve(max_iter=max_iter).success


def bisect(predicate, lo, hi, steps=30):
    """Where ``predicate`` switches from False to True on [lo, hi].

    Parameters
    ----------
    predicate : callable
        A function of one float, False at ``lo`` and True at ``hi``.
    lo, hi : float
        The bracket.
    steps : int, optional
        Halvings of the bracket.

    Returns
    -------
    float
        The midpoint of the last bracket.
    """
    for _ in range(steps):
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if predicate(mid) else (mid, hi)
    return 0.5 * (lo + hi)


def two_step_order(start, steps, t_end):
    """The fitted order of :func:`two_step_oscillator` on y'' = -y.

    Parameters
    ----------
    start : callable
        ``start(h)`` returns the starting values (y_0, y_1) for the step h;
        the exact solution is cos t.
    steps : array_like
        The steps h.
    t_end : float
        Each run goes to ``t_end``.

    Returns
    -------
    float
        The slope of log(max_n |y_n - cos(n h)|) against log h.
    """
    steps = np.asarray(steps, float)
    errors = []
    for step in steps:
        y = two_step_oscillator(*start(step), step, int(round(t_end / step)))
        errors.append(np.max(np.abs(y - np.cos(step * np.arange(y.size)))))
    return np.polyfit(np.log(steps), np.log(errors), 1)[0]


def relation_residual(problem, run):
    """The largest residual of the two-step relation on a run's knots.

    Parameters
    ----------
    problem : Problem
        A problem y'' = f(t, y) of ``splinestep.problems`` (its ``fun`` is
        evaluated afresh at each knot: the stored y'' would make the
        relation an identity).
    run : OdeResult
        A run at the uniform step ``problem.h``, with every knot stored.

    Returns
    -------
    float
        max |y_{n+1} - 2 y_n + y_{n-1} - h^2 (f_{n+1} + 4 f_n + f_{n-1}) / 6|
        over the knots and components.
    """
    f = np.column_stack([problem.fun(t, y, yp, *problem.args)
                         for t, y, yp in zip(run.t, run.y.T, run.yp.T)])
    return np.max(np.abs(run.y[:, 2:] - 2 * run.y[:, 1:-1] + run.y[:, :-2]
                         - problem.h ** 2 * (f[:, 2:] + 4 * f[:, 1:-1] + f[:, :-2]) / 6))


def constants_table(frame):
    """Derived constants against their measurements, as a table of text.

    Parameters
    ----------
    frame : pandas.DataFrame
        One row per constant: ``quantity`` (text), ``exact`` (the derived
        value, a sympy number), ``measured`` (float) and ``digits`` (the
        significant digits of both values that a run reproduces).

    Returns
    -------
    pandas.DataFrame
        Columns ``quantity``, ``derived`` (the exact value as sympy writes
        it, products without ``*``: ``2 + sqrt(3)``, ``2sqrt(3)``), ``derived value`` and
        ``measured``, the two numbers at the row's digits (``%#g``: trailing
        zeros kept, so that every value shows the digits it was measured to;
        an exact 0 as ``0``).
    """
    pd = require("pandas", __name__)
    return pd.DataFrame({
        "quantity": list(frame["quantity"]),
        "derived": [sp.sstr(value, order="rev-lex").replace("*", "") for value in frame["exact"]],
        "derived value": [f"{float(v):#.{d}g}" if v != 0 else "0"
                          for v, d in zip(frame["exact"], frame["digits"])],
        "measured": [f"{v:#.{d}g}" for v, d in zip(frame["measured"], frame["digits"])]})
