"""The error controller on the chain of masses: what its steps cost, and how
steady their number is.

The problem is :func:`splinestep.problems.chain` over 3.125 periods of its
slowest mode (the speed page's span), from its two slowest shapes at rest,
with rtol = 1e-3 and atol = 1e-8 (the speed page's adaptive row).  Where
the slow modes set the step (m up to a few hundred) the steps follow the
error estimate; beyond, the fixed-point sweep's convergence (omega_m h
below sqrt 6) bounds them, and the controller keeps them below the
contraction the sweep has shown (:mod:`splinestep.controllers`), so their
number grows like m.  Newton's steps (the sparse Jacobian, SuperLU) are
bounded by the spline's stability limit instead, where the error estimate
allows (between the solution's turning points); at m = 10,000 Newton's run
is not timed: near the turning points it rejects about a third of its
steps and refactorises its matrix at nearly every one (an hour's run).

For each path and m the table gives the accepted steps, the evaluations of
F, the steps rejected by the error estimate and those whose equation failed
(both retried smaller; a failed step's evaluations are the failed
iterations), the error at the end against the exact modal solution, and the
steps per mass.  A second table runs the sweep at m = 1,000 with rtol and
the span moved a little (the span with rtol in proportion, since rtol
bounds the local errors per unit step times the span): a controller that
cycles between growth and failure changes its step count by tens of per
cent under such changes.

Prints the tables and writes them into the site's Speed page,
website/speed.md, between ``<!-- begin controller -->`` and ``<!-- end
controller -->``.  Run with ``make bench``.
"""

import sys
import time

import numpy as np

import splinestep
from splinestep import problems
from speed_page import write_section

PERIODS = 3.125
TOL = dict(rtol=1e-3, atol=1e-8)
RUNS = (("fixed-point sweep", {}, (100, 1_000, 3_000, 10_000)),
        ("Newton, sparse jac", {"iteration": "newton"}, (1_000,)))
# rtol and the span moved by these factors (the sweep at STEADY_M).
STEADY_M = 1_000
RTOL_FACTORS = (1 - 1e-6, 1.0, 1 + 1e-6)
SPAN_FACTORS = (0.95, 1.0, 1.05)


def run(m, rtol_factor=1.0, span_factor=1.0, **options):
    """(result, seconds, error at the end) of one adaptive run on the chain."""
    p = problems.chain(m, periods=PERIODS)
    tf = p.t_span[1] * span_factor
    if options.get("iteration") == "newton":
        options = dict(options, jac=p.jac)
    start = time.perf_counter()
    res = splinestep.solve(p.fun, (0.0, tf), p.y0, p.yp0, args=p.args, check=False,
                           t_eval=np.array([tf]), rtol=TOL["rtol"] * rtol_factor,
                           atol=TOL["atol"], **options)
    seconds = time.perf_counter() - start
    assert res.success, res.message
    exact = p.exact(np.array([tf]))[0][:, 0]
    return res, seconds, float(np.max(np.abs(res.y[:, -1] - exact)))


def cost_table():
    lines = ["| path | m | steps | evaluations | rejected | failed | error at the end | "
             "steps per mass | seconds |", "|---|---|---|---|---|---|---|---|---|"]
    for label, options, sizes in RUNS:
        run(10, **options)   # compile or load
        for m in sizes:
            res, seconds, error = run(m, **options)
            attempts = res.nstep + res.n_rejected + res.n_failed
            lines.append(f"| {label} | {m:,} | {res.nstep:,} | {res.nfev:,} | "
                         f"{res.n_rejected:,} ({100 * res.n_rejected / attempts:.1f} %) | "
                         f"{res.n_failed:,} | {error:.2g} | {res.nstep / m:.1f} | "
                         f"{seconds:.3g} |")
            print(lines[-1], flush=True)
    return lines


def steady_table():
    lines = ["| change (sweep, m = 1,000) | steps | evaluations |", "|---|---|---|"]
    counts = {}
    for what, factors in (("rtol", RTOL_FACTORS), ("span", SPAN_FACTORS)):
        for factor in factors:
            # The span moves with rtol: rtol bounds the local errors per unit
            # step times the span (splinestep.controllers).
            kwargs = ({"rtol_factor": factor} if what == "rtol" else
                      {"rtol_factor": factor, "span_factor": factor})
            res, _, _ = run(STEADY_M, **kwargs)
            counts.setdefault(what, []).append(res.nstep / (factor if what == "span" else 1))
            label = f"rtol x {factor:.7g}" if what == "rtol" else f"span and rtol x {factor:g}"
            lines.append(f"| {label} | {res.nstep:,} | {res.nfev:,} |")
            print(lines[-1], flush=True)
    spread = {what: 100 * (max(c) - min(c)) / min(c) for what, c in counts.items()}
    lines.append("")
    lines.append(f"Steps per unit time spread by {spread['rtol']:.2g} % under rtol x (1 "
                 f"+/- 1e-6) and by {spread['span']:.2g} % under the span and rtol x (1 +/- "
                 "0.05).")
    return lines


def main():
    text = "\n".join(cost_table() + [""] + steady_table())
    print(text)
    write_section("controller", text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
