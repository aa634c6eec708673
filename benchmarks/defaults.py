"""What solve's defaults cost, at the error they reach, beside scipy's.

``splinestep.solve`` with neither ``h``, ``knots`` nor ``rtol`` is adaptive
at rtol = 1e-3, atol = 1e-6, on the global error (the error per unit step
times the span, :mod:`splinestep.controllers`); scipy's ``solve_ivp``
without options is RK45 at rtol = 1e-3, atol = 1e-6 on each step's error.
For three problems with exact solutions the table gives each default's
evaluations of F and its final error (the largest component of y at tf),
then the evaluations RK45 needs to reach the spline default's error (rtol
tightened by factors of 10^(1/4), atol = rtol / 1000, the first run at or
below that error), and those of the spline with one fixed-point sweep per
step (``iterations=1``), the cheapest form of the same default.

Prints the table and writes it into the site's Speed page,
website/speed.md, between ``<!-- begin defaults -->`` and ``<!-- end
defaults -->``.  Run with ``make bench``.
"""

import warnings

import numpy as np
from scipy.integrate import solve_ivp

import splinestep
from speed_page import write_section

PROBLEMS = {
    "oscillator y'' = -y, t in [0, 10]": (
        lambda t, y, yp: -y, (0.0, 10.0), [1.0], [0.0], lambda t: np.array([np.cos(t)])),
    "damped y'' = -y - 0.1 y', t in [0, 20]": (
        lambda t, y, yp: -y - 0.1 * yp, (0.0, 20.0), [1.0], [0.0],
        lambda t: np.array([np.exp(-0.05 * t) * (np.cos(np.sqrt(0.9975) * t)
                                                 + 0.05 / np.sqrt(0.9975)
                                                 * np.sin(np.sqrt(0.9975) * t))])),
    "Kepler e = 0.5, one period": None,
}


def kepler():
    problem = splinestep.problems.eccentric(0.5)
    return (problem.fun, problem.t_span, problem.y0, problem.yp0,
            lambda t: problem.reference(np.array([t]))[0][:, 0], problem.args)


def first_order(fun, args, m):
    def f(t, u):
        return np.concatenate([u[m:], np.asarray(fun(t, u[:m], u[m:], *args), float).ravel()])
    return f


def rows():
    out = []
    for name, spec in PROBLEMS.items():
        fun, span, y0, yp0, exact, *rest = spec if spec is not None else kepler()
        args = rest[0] if rest else ()
        m = len(y0)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            spline = splinestep.solve(fun, span, y0, yp0, args=args)
            sweep = splinestep.solve(fun, span, y0, yp0, args=args, iterations=1)
        target = exact(span[1])
        error = np.max(np.abs(spline.y[:, -1] - target))
        sweep_error = np.max(np.abs(sweep.y[:, -1] - target))
        f = first_order(fun, args, m)
        u0 = np.r_[y0, yp0]
        rk = solve_ivp(f, span, u0)
        rk_error = np.max(np.abs(rk.y[:m, -1] - target))
        needed = None
        for k in range(40):
            rtol = 1e-3 * 10.0 ** (-k / 4)
            run = solve_ivp(f, span, u0, rtol=rtol, atol=rtol * 1e-3)
            if np.max(np.abs(run.y[:m, -1] - target)) <= error:
                needed = (run.nfev, rtol)
                break
        out.append([name, f"{spline.nfev:,} / {error:.1e}", f"{sweep.nfev:,} / {sweep_error:.1e}",
                    f"{rk.nfev:,} / {rk_error:.1e}",
                    "-" if needed is None else f"{needed[0]:,} (rtol {needed[1]:.1e})"])
    return out


def render(table):
    head = ["problem", "spline default: evaluations / error",
            "spline default, 1 sweep: evaluations / error",
            "scipy default (RK45): evaluations / error",
            "RK45 to the spline default's error"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    lines += ["| " + " | ".join(row) + " |" for row in table]
    return "\n".join(lines)


if __name__ == "__main__":
    text = render(rows())
    print(text)
    write_section("defaults", text)
