# %% [markdown]
# # The report's suggested improvements, built and judged
#
# Section 5 of the report names three directions: "improved accuracy through
# adaptability", higher order, and obtaining "the coefficients at all points
# in a single sweep or set of iterations through the use of Newton's method
# and LU-decomposition".  This notebook builds each into the package and
# measures it against the uniform-step method and the baselines:
#
# 1. adaptive knots, with the spline's own error estimate, and the time-reversible
#    steps that keep the long-time behaviour;
# 2. order 4 and 6 by symmetric composition, beside Richardson extrapolation,
#    RK4 and DOP853;
# 3. the global Newton-LU sweep, and the boundary value problems it makes possible.
#
# One step serves all of them.  `splinestep.step` holds the spline step (its
# equation, the fixed-point sweep, Newton's method with a kept LU); the
# drivers only decide which knot comes next: `spline.solve` walks given or
# uniform knots (and composes sub-steps for order 4 and 6), `adaptive` asks
# `controllers` for the next step, `reversible` follows a symmetric
# recursion, and `bvp` writes the same step as residuals and solves all knots
# at once.

# %%
import sys
import warnings

import numpy as np
import pandas as pd
from scipy.integrate import solve_bvp as scipy_solve_bvp
from scipy.integrate import solve_ivp

sys.path.insert(0, "../scripts")  # outputs.py: the repository's data/, figures/ and plot style
import outputs
import splinestep
from splinestep import controllers, diagnostics, problems, step
from splinestep.extrapolation import richardson

plt = outputs.setup()

# %% [markdown]
# ## 1. Adaptive knots
# ### The error estimate
# One step from exact values misses $h^4 y''''/24$ in $y$ and $h^3 y''''/12$
# in $y'$ (notebook 06).  The estimate that Newmark codes use (Zienkiewicz
# and Xie, 1991) is proportional to $\beta - 1/6$ and vanishes for this
# method.  The spline has its own: its third derivative is constant on each
# interval, $j_i = (y''_{i+1} - y''_i)/h_i$, and its jump at a knot
# estimates the fourth derivative,
# $y'''' \approx (j_i - j_{i-1}) / \tfrac12 (h_i + h_{i-1})$.
# The controller (`splinestep.controllers`) accepts a step when these
# estimates are within $\mathrm{atol} + \mathrm{rtol}\,|y|$ (scipy's scaled
# RMS norm) and sizes the next one from them.  Below, along a Kepler orbit
# of eccentricity 0.9 ($\mu = 1$, launched at periapsis $r = 1$, one period),
# the estimate of each step against the error of the same step started from
# the exact solution.

# %%
orbit = problems.eccentric(0.9)
period = orbit.t_span[1]
run = orbit.solve(h="adaptive", rtol=1e-8, atol=1e-11)
estimate, _ = controllers.jump_estimates(run.t, run.ypp)
steps = np.arange(1, run.t.size - 1, 5)   # every fifth step (the estimate needs the one before)
true_error = []
for i in steps:
    start, start_yp = orbit.reference(run.t[i:i + 2])
    one = splinestep.solve(orbit.fun, (run.t[i], run.t[i + 1]), start[:, 0], start_yp[:, 0],
                           knots=run.t[i:i + 2], args=orbit.args, tol=1e-15)
    true_error.append(np.max(np.abs(one.y[:, -1] - start[:, 1])))
estimates = pd.DataFrame(dict(t=run.t[steps], h=np.diff(run.t)[steps],
                              r=np.hypot(*run.y[:, steps]), estimated=estimate[steps - 1],
                              true=np.array(true_error)))
outputs.save_data(estimates, "adaptive-estimate")
ratio = estimates.estimated / estimates.true
print(f"{run.nstep} steps over one period ({run.n_rejected} rejected); step sizes "
      f"{outputs.sci(np.diff(run.t).min())} to {outputs.sci(np.diff(run.t).max())}")
print(f"estimated / true local error: median {np.median(ratio):.2f}, "
      f"middle 90 % from {np.quantile(ratio, 0.05):.2f} to {np.quantile(ratio, 0.95):.2f}")

# %% [markdown]
# ### Work against precision on the eccentric orbit
# Final position error after one period against right-hand-side
# evaluations: uniform steps (one sweep per step, the cheapest uniform run,
# and iterated to convergence) and adaptive knots at tolerances
# $10^{-6} \dots 10^{-11}$ ($\mathrm{atol} = 10^{-3}\,\mathrm{rtol}$), each
# with one sweep per step and iterated.

# %%
exact_end, _ = orbit.reference(np.array([period]))
adaptive_work = []
for n in 8000 * 4 ** np.arange(4):
    for label, kwargs in (("uniform, 1 sweep", dict(iterations=1)), ("uniform, iterated", {})):
        res = orbit.solve(h=period / n, **kwargs)
        adaptive_work.append(dict(method=label, setting=period / n, nfev=res.nfev,
                                  final_error=np.max(np.abs(res.y[:, -1] - exact_end[:, 0]))))
for rtol in 10.0 ** -np.arange(6, 12):
    for label, kwargs in (("adaptive, 1 sweep", dict(iterations=1)), ("adaptive, iterated", {})):
        res = orbit.solve(h="adaptive", rtol=rtol, atol=rtol * 1e-3, **kwargs)
        adaptive_work.append(dict(method=label, setting=rtol, nfev=res.nfev,
                                  final_error=np.max(np.abs(res.y[:, -1] - exact_end[:, 0]))))
adaptive_work = pd.DataFrame(adaptive_work)
outputs.save_data(adaptive_work, "adaptive-work")
curves = {m: (g.nfev.to_numpy(), g.final_error.to_numpy())
          for m, g in adaptive_work.groupby("method", sort=False)}
gain_one = diagnostics.work_ratio_range(curves["uniform, 1 sweep"], curves["adaptive, 1 sweep"])
gain_iter = diagnostics.work_ratio_range(curves["uniform, iterated"],
                                         curves["adaptive, iterated"])
print(f"evaluations of the uniform run / of the adaptive run at equal final error: "
      f"one sweep {outputs.span(gain_one)}, iterated {outputs.span(gain_iter)}")

fig, (ax, bx) = plt.subplots(2, 1, figsize=(outputs.WIDTH, 8.4))
ax.semilogy(steps, estimates.true, "k.", markersize=4, label="true local error of the step")
ax.semilogy(steps, estimates.estimated, "C0-", linewidth=1.2,
            label="estimate from the jump of $y'''$")
ax.semilogy(steps, estimates.h, "C1--", linewidth=1.2, label="step size $h$")
ax.set_xlabel("step number (one period: periapsis at both ends, apoapsis in the middle)")
ax.set_ylabel("local error of $y$; step size")
ax.set_title("Adaptive knots on the Kepler orbit $e = 0.9$ (rtol $10^{-8}$)")
ax.set_ylim(1e-17, 10)
ax.legend(loc="lower center", ncol=2, fontsize=outputs.MIN_FONT)
styles = {"uniform, 1 sweep": "s--", "uniform, iterated": "s-", "adaptive, 1 sweep": "o--",
          "adaptive, iterated": "o-"}
for method, (nfev, error) in curves.items():
    bx.loglog(nfev, error, styles[method], color="C3" if "uniform" in method else "C0",
              markersize=5, label=method)
bx.set_xlabel("right-hand-side evaluations over one period")
bx.set_ylabel("position error after one period")
bx.set_title("Work against precision, $e = 0.9$")
bx.legend(loc="lower left", fontsize=outputs.MIN_FONT)
outputs.save_figure(fig, "adaptive-knots")

# %%
outputs.say(
    f"The estimate follows the true local error through the periapsis passage, where the "
    f"steps shrink to {outputs.sci(np.diff(run.t).min())}, and out to apoapsis, where they grow "
    f"to {outputs.sci(np.diff(run.t).max())} (median ratio {np.median(ratio):.2f}).  At equal "
    f"final error the uniform step needs {outputs.span(gain_one)} times the evaluations of the "
    f"adaptive knots (one sweep per step on both sides, the cheapest form of each), "
    f"{outputs.span(gain_iter)} times when both iterate to convergence: a tenfold saving for "
    f"the cheapest runs, and over part of the range for the iterated ones.")

# %% [markdown]
# ### A step whose equation has no solution
# Near a close encounter of the Pleiades problem (seven stars in the plane;
# Hairer, Norsett and Wanner's PLEI) $h^2/6\,\partial F/\partial y$
# has an eigenvalue near 1 and the step equation can lose its solution.
# Uniform steps, against a DOP853 reference (rtol $10^{-13}$):

# %%
pleiades = problems.pleiades()
exact_3, _ = pleiades.reference(np.array([3.0]))
pleiades_rows = []
for h in (1e-3, 2e-3, 2.5e-3, 2.9e-3, 3.5e-3, 5e-3, 1e-2):
    for iteration in ("fixed-point", "newton"):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # the too-large steps say so; the table shows it
            res = pleiades.solve(h=h, iteration=iteration)
        pleiades_rows.append(dict(
            run=f"uniform h = {h:g}", iteration=iteration, status=res.status, nfev=res.nfev,
            nstep=res.nstep, rejected=0, failed=0, t_end=res.t[-1],
            error=np.max(np.abs(res.y[:, -1] - exact_3[:, 0])) if res.success else np.nan,
            flagged="too large" in res.message))
for rtol in (1e-6, 1e-8):
    for iteration in ("fixed-point", "newton"):
        res = pleiades.solve(h="adaptive", rtol=rtol, atol=rtol, iteration=iteration)
        pleiades_rows.append(dict(
            run=f"adaptive rtol = {rtol:g}", iteration=iteration, status=res.status,
            nfev=res.nfev, nstep=res.nstep, rejected=res.n_rejected, failed=res.n_failed,
            t_end=res.t[-1], error=np.max(np.abs(res.y[:, -1] - exact_3[:, 0])),
            flagged=False))
pleiades_table = pd.DataFrame(pleiades_rows)
outputs.save_data(pleiades_table, "pleiades-steps")
for row in pleiades_table.itertuples():
    outcome = (f"reaches t = 3, error {row.error:.1g}" + (" (flagged: step too large)"
                                                          if row.flagged else "")
               if row.status == 0 else f"fails at t = {row.t_end:.3f}")
    print(f"{row.run:<22} {row.iteration:<12} {outcome}")
retry = splinestep.solve(lambda t, y, yp: -y, (0.0, 10.0), 1.0, 0.0, rtol=1e-8, atol=1e-10,
                         first_step=3.0)
print(f"y'' = -y from a first step of 3 (omega h > sqrt 6): {retry.n_failed} failed step "
      f"equation(s) retried smaller, status {retry.status}, error at t = 10 "
      f"{outputs.sci(abs(retry.y[0, -1] - np.cos(10.0)))}")

# %%
uniform = pleiades_table[pleiades_table.run.str.startswith("uniform")].copy()
uniform["h"] = uniform.run.str.split("= ").str[1].astype(float)
failing = sorted(set(uniform[uniform.status != 0].h))
reaching = sorted(set(uniform[(uniform.status == 0) & (uniform.h > min(failing))].h))
wrong = uniform[(uniform.status == 0) & (uniform.h > min(failing))]
adaptive_rows = pleiades_table[pleiades_table.run.str.startswith("adaptive")]
outputs.say(
    f"The uniform steps fail at h = {', '.join(f'{h:g}' for h in failing)}, the sweep and "
    f"Newton alike, at a close encounter; in between, h = "
    f"{' and '.join(f'{h:g}' for h in reaching)} reach t = 3 with errors of "
    f"{wrong.error.min():.1f} to {wrong.error.max():.1f}, flagged by the run's own check "
    f"(status 0 with a warning).  Failure does not set in above one step size: whether a "
    f"step equation loses its solution depends on where the knots fall relative to the close "
    f"encounters.  The adaptive knots "
    f"reach t = 3 in every run ({int(adaptive_rows.failed.sum())} failed step equations: the "
    f"error estimate shrinks the step before the equation fails), with errors "
    f"{outputs.sci(adaptive_rows.error.min())} to {outputs.sci(adaptive_rows.error.max())}.  "
    f"When a step equation does fail, as on the oscillator started with a step past "
    f"$\\sqrt 6$, it is retried smaller and the run goes on.")

# %% [markdown]
# ### Newton's method with a kept matrix
# Full Newton rebuilds a finite-difference Jacobian at every iteration:
# $m$ extra evaluations each time.  Like RADAU5, the package's Newton keeps the matrix
# $I - h^2/6\,\partial F/\partial y - h/2\,\partial F/\partial y'$ and its LU
# factors across iterations and steps, and rebuilds them when an iteration
# contracts too slowly, fails, or the step changes by more than a set
# fraction (`splinestep.step`); a step that fails with a kept matrix is
# redone with full Newton.  On Pleiades at $h = 10^{-3}$:

# %%
print(f"rebuilt when an update is more than {step.SLOW_RATE} times the one before, or the "
      f"step differs by more than {step.STEP_CHANGE:.0%} from the matrix's; "
      f"m = {pleiades.y0.size} components")
newton_rows = []
for label, reuse in (("full Newton", False), ("kept matrix", True)):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # h = 1e-3 is too large here too (table above)
        res = pleiades.solve(iteration="newton", reuse_jacobian=reuse)
    newton_rows.append(dict(method=label, nfev=res.nfev, nstep=res.nstep, niter=res.niter,
                            error=np.max(np.abs(res.y[:, -1] - exact_3[:, 0]))))
with warnings.catch_warnings():
    warnings.simplefilter("ignore")
    sweep = pleiades.solve()
newton_rows.append(dict(method="fixed-point sweep", nfev=sweep.nfev, nstep=sweep.nstep,
                        niter=sweep.niter, error=np.max(np.abs(sweep.y[:, -1] - exact_3[:, 0]))))
newton_table = pd.DataFrame(newton_rows)
outputs.save_data(newton_table, "newton-reuse")
for row in newton_table.itertuples():
    print(f"{row.method:<18} {row.nfev / row.nstep:5.2f} evaluations and "
          f"{row.niter / row.nstep:.2f} iterations per step")
full, kept = newton_table.iloc[0], newton_table.iloc[1]
outputs.say(
    f"Evaluations per step fall from {full.nfev / full.nstep:.1f} to "
    f"{kept.nfev / kept.nstep:.2f} ({full.nfev / kept.nfev:.0f} times fewer), as cheap as the "
    f"fixed-point sweep ({sweep.nfev / sweep.nstep:.2f}), with the same solution.")

# %% [markdown]
# ## 2. The long-time picture of variable steps
# A fixed step keeps the energy error bounded (notebook 06); adaptive knots
# lose it, since the step sizes depend on an error estimate that is not
# symmetric in time.  Hairer and Soderlind (2005) restore it: the step is
# $\varepsilon/\rho$, with the control variable $\rho$ updated by a
# leapfrog recursion $\rho_{n+1/2} = \rho_{n-1/2} + \varepsilon G(y_n)$,
# $G = -\tfrac{d}{dt}\ln s$ for a step density $s$; here $s = r^{3/2}$,
# $G = -\tfrac32\, q\cdot q'/|q|^2$ (`splinestep.solve_reversible`).  Step and
# recursion are symmetric, so the whole method is.  The energy error at each
# apoapsis over 300 orbits of the $e = 0.9$ orbit:

# %%
ORBITS = 300
long_orbit = problems.eccentric(0.9, orbits=ORBITS)
apoapsis = (np.arange(ORBITS) + 0.5) * period
energy = long_orbit.invariants["energy"]
e0 = energy(long_orbit.y0[:, None], long_orbit.yp0[:, None])[0]


def kepler_control(t, y, yp, mu):
    return -1.5 * np.dot(y, yp) / np.dot(y, y)


EPS = 1e-2
reversible = splinestep.solve_reversible(long_orbit.fun, long_orbit.t_span, long_orbit.y0,
                                         long_orbit.yp0, EPS, kepler_control,
                                         args=long_orbit.args)
controlled = long_orbit.solve(h="adaptive", rtol=1e-6, atol=1e-9, dense_output=True)
long_rows = []
for label, res in (("reversible steps", reversible), ("adaptive knots, rtol 1e-6", controlled)):
    error = np.abs(energy(res.sol(apoapsis), res.sol(apoapsis, 1)) - e0)
    long_rows.append(pd.DataFrame(dict(method=label, orbit=np.arange(1, ORBITS + 1),
                                       energy_error=error, nfev_per_orbit=res.nfev / ORBITS)))
long_table = pd.concat(long_rows, ignore_index=True)
outputs.save_data(long_table, "variable-step-energy")
rev_err = long_table[long_table.method == "reversible steps"].energy_error.to_numpy()
ctl_err = long_table[long_table.method != "reversible steps"].energy_error.to_numpy()
print(f"reversible: {reversible.nfev / ORBITS:.0f} evaluations per orbit, energy error at "
      f"apoapsis from {rev_err.min():.3e} to {rev_err.max():.3e}")
print(f"adaptive:   {controlled.nfev / ORBITS:.0f} evaluations per orbit, energy error at the "
      f"first apoapsis {outputs.sci(ctl_err[0], 1)}, largest over the last 30 orbits "
      f"{outputs.sci(ctl_err[-30:].max(), 1)}")

fig, ax = plt.subplots(figsize=(outputs.WIDTH, 4.2))
ax.loglog(np.arange(1, ORBITS + 1), ctl_err, "C3.-", markersize=3, linewidth=0.8,
          label=f"adaptive knots, rtol $10^{{-6}}$ ({controlled.nfev / ORBITS:.0f} evaluations "
                "per orbit)")
ax.loglog(np.arange(1, ORBITS + 1), rev_err, "C0-", linewidth=1.5,
          label=f"reversible steps, $\\varepsilon = {EPS:g}$ "
                f"({reversible.nfev / ORBITS:.0f} per orbit)")
ax.set_xlabel("orbit number")
ax.set_ylabel("$|H - H_0|$ at apoapsis")
ax.set_title("Variable steps over 300 orbits of the Kepler orbit $e = 0.9$")
ax.legend(loc="upper left", fontsize=outputs.MIN_FONT)
outputs.save_figure(fig, "variable-step-energy")

# %%
outputs.say(
    f"The reversible steps keep the energy error at apoapsis at "
    f"{outputs.sci(rev_err.mean())} for all 300 orbits (it varies by "
    f"{outputs.sci(rev_err.max() - rev_err.min(), 1)}) at {reversible.nfev / ORBITS:.0f} "
    f"evaluations per orbit; the error-controlled knots, at {controlled.nfev / ORBITS:.0f}, "
    f"wander from {outputs.sci(ctl_err[0], 1)} to {outputs.sci(ctl_err[-30:].max(), 1)}.  For long runs of a conservative problem, the "
    f"reversible steps are the adaptive method to use; the price is choosing the step "
    f"density $s$ by hand.")

# %% [markdown]
# ## 3. Order 4 and 6 that keep what is good
# Higher-degree splines give no usable higher order (notebook 06).  What
# works: the spline step is
# symmetric (stepping back with $-h$ undoes it), so a symmetric composition of
# it raises the order and keeps the symmetry.  `solve(order=4)` takes each
# step as three spline steps of sizes $\gamma_1 h, \gamma_2 h, \gamma_1 h$
# with $\gamma_1 = 1/(2 - 2^{1/3})$, $\gamma_2 = -2^{1/3}/(2 - 2^{1/3})$
# (Yoshida's triple jump; the middle step goes backwards), `order=6` as
# seven (Yoshida's solution A); between knots the quintic through the
# knots' values and first two derivatives keeps the order.  The fitted
# slopes of the largest error at times between the knots against the exact
# solutions:

# %%
orders_rows = []
cases = {f"cannonball mu={mu:g}": problems.cannonball(mu) for mu in problems.CANNONBALL_MU}
cases["rigid body"] = problems.rigid_body("consistent")
STEPS = {4: np.array([0.08, 0.04, 0.02, 0.01]), 6: np.array([0.16, 0.08, 0.04])}
for name, problem in cases.items():
    t_check = np.linspace(problem.t_span[0], problem.t_span[1], 137)
    exact, _ = problem.reference(t_check)
    for order, hs in STEPS.items():
        errors = [np.max(np.abs(problem.solve(h=h, order=order, t_eval=t_check).y - exact))
                  for h in hs]
        orders_rows.append(dict(problem=name, order=order,
                                slope=np.polyfit(np.log(hs), np.log(errors), 1)[0],
                                largest_error=errors[0], smallest_error=errors[-1]))
orders_table = pd.DataFrame(orders_rows)
outputs.save_data(orders_table, "composition-orders")
print(orders_table.pivot(index="problem", columns="order", values="slope").round(3)
      .to_string())

# %%
ellipse = cases["cannonball mu=0.6"]
t_report = np.arange(0.0, 50.0 + 1e-9, 0.08)
exact_report, _ = ellipse.reference(t_report)
at_report_step = {order: np.max(np.abs(ellipse.solve(order=order, t_eval=t_report).y
                                       - exact_report)) for order in (2, 4, 6)}
for order, error in at_report_step.items():
    print(f"ellipse, dt = 0.01, order {order}: max position error {error:.1e}")
slopes4 = orders_table[orders_table.order == 4].slope
outputs.say(
    f"Order 4 fits slopes {slopes4.min():.2f} to {slopes4.max():.2f} on the four cannonball "
    f"orbits and the rigid body, order 6 "
    f"{orders_table[orders_table.order == 6].slope.min():.2f} to "
    f"{orders_table[orders_table.order == 6].slope.max():.2f}.  On the ellipse at the report's "
    f"step the largest position error falls from {outputs.sci(at_report_step[2])} (the "
    f"report's method) to {outputs.sci(at_report_step[4])} and "
    f"{outputs.sci(at_report_step[6])}.")

# %% [markdown]
# ### Long time, and the cost against the other routes
# The energy error of the ellipse over 10,000 orbits, sampled over whole
# orbits at logarithmically spaced orbit numbers as in notebook 06, at a
# step five times the report's to keep the notebook quick; then the work
# against precision over $t \in [0, 50]$: the compositions, Richardson
# extrapolation of the report's method
# ($(4 y_{h/2} - y_h)/3$, `splinestep.extrapolation`), RK4 and DOP853.

# %%
period_ellipse = problems.orbit_elements(0.6)["period"]
LONG_ORBITS = 10_000
windows = np.unique(np.round(np.logspace(0, np.log10(LONG_ORBITS), 17)).astype(int)) - 1
samples = ((windows[:, None] + np.arange(64)[None, :] / 64) * period_ellipse).ravel()
energy_ellipse = ellipse.invariants["energy"]
long_energy = []
LONG_STEP = 0.05
for order in (2, 4):
    res = splinestep.solve(ellipse.fun, (0.0, samples[-1]), ellipse.y0, ellipse.yp0, LONG_STEP,
                           args=ellipse.args, order=order, t_eval=samples)
    error = np.abs(energy_ellipse(res.y, res.yp) - (0.5 - 0.6)).reshape(windows.size, 64)
    long_energy.append(pd.DataFrame(dict(order=order, orbit=windows + 1,
                                         energy_error=error.max(axis=1))))
long_energy = pd.concat(long_energy, ignore_index=True)
outputs.save_data(long_energy, "composition-energy")
growth = {order: diagnostics.loglog_interp(g.orbit, g.energy_error, [10.0])[0]
          for order, g in long_energy.groupby("order")}
for order, g in long_energy.groupby("order"):
    tail = g[g.orbit >= 10]
    exponent = np.polyfit(np.log(tail.orbit), np.log(tail.energy_error), 1)[0]
    print(f"order {order}: energy error {outputs.sci(g.energy_error.iloc[0])} in the first "
          f"orbit, {outputs.sci(g.energy_error.iloc[-1])} in orbit {LONG_ORBITS}; growth "
          f"exponent {exponent:+.2f}")

# %%
work = []
for h in (0.08, 0.04, 0.02, 0.01, 0.005):
    for order in (2, 4, 6):
        res = ellipse.solve(h=h, order=order, t_eval=t_report)
        work.append(dict(method=f"spline, order {order}", setting=h, nfev=res.nfev,
                         max_error=np.max(np.abs(res.y - exact_report))))
    res = richardson(ellipse.fun, ellipse.t_span, ellipse.y0, ellipse.yp0, h, t_eval=t_report,
                     args=ellipse.args)
    work.append(dict(method="Richardson (order 2 at h, h/2)", setting=h, nfev=res.nfev,
                     max_error=np.max(np.abs(res.y - exact_report))))
    res = ellipse.solve("rk4", h=h, t_eval=t_report)
    work.append(dict(method="RK4", setting=h, nfev=res.nfev,
                     max_error=np.max(np.abs(res.y - exact_report))))
rhs = ellipse.fun.py_func


def first_order(t, u):
    return np.concatenate([u[2:], rhs(t, u[:2], u[2:], *ellipse.args)])


for tol in 10.0 ** -np.arange(4, 13):
    sol = solve_ivp(first_order, (0, 50), np.r_[ellipse.y0, ellipse.yp0], method="DOP853",
                    rtol=tol, atol=tol * 1e-2, t_eval=t_report)
    work.append(dict(method="scipy DOP853", setting=tol, nfev=sol.nfev,
                     max_error=np.max(np.abs(sol.y[:2] - exact_report))))
work = pd.DataFrame(work)
outputs.save_data(work, "composition-work")
work_curves = {m: (g.nfev.to_numpy(), g.max_error.to_numpy())
               for m, g in work.groupby("method", sort=False)}
pairs = [("spline, order 4", "Richardson (order 2 at h, h/2)"), ("spline, order 4", "RK4"),
         ("spline, order 6", "RK4"), ("spline, order 6", "scipy DOP853")]
comparison = []
for method, baseline in pairs:
    lo, hi = diagnostics.work_ratio_range(work_curves[baseline], work_curves[method])
    comparison.append(dict(method=method, baseline=baseline, ratio_min=lo, ratio_max=hi))
    print(f"evaluations of {baseline} / of {method} at equal error: {lo:.2g} to {hi:.2g}")
comparison = pd.DataFrame(comparison)
outputs.save_data(comparison, "composition-ratios")

fig, (ax, bx) = plt.subplots(2, 1, figsize=(outputs.WIDTH, 8.4))
for order, g in long_energy.groupby("order"):
    ax.loglog(g.orbit, g.energy_error, "o-", color="C0" if order == 2 else "C2", markersize=4,
              label=f"spline, order {order}")
ax.set_xlabel(f"orbit number (ellipse $\\mu = 0.6$, $h = {LONG_STEP:g}$)")
ax.set_ylabel("largest $|H - H_0|$ in the orbit")
ax.set_title("Energy error over 10,000 orbits")
ax.set_ylim(1e-8, 1e-2)
ax.legend(loc="center right", fontsize=outputs.MIN_FONT)
markers = {"spline, order 2": ("C0", "o-"), "spline, order 4": ("C2", "o-"),
           "spline, order 6": ("C4", "o-"), "Richardson (order 2 at h, h/2)": ("C1", "D--"),
           "RK4": ("C3", "s--"), "scipy DOP853": ("C5", "v--")}
for method, (nfev, error) in work_curves.items():
    color, style = markers[method]
    bx.loglog(nfev, error, style, color=color, markersize=4, label=method)
bx.set_xlabel("right-hand-side evaluations over $t \\in [0, 50]$")
bx.set_ylabel("max position error")
bx.set_title("Work against precision, ellipse $\\mu = 0.6$")
bx.set_ylim(1e-15, 1.0)
bx.legend(loc="lower left", fontsize=outputs.MIN_FONT, ncol=2)
outputs.save_figure(fig, "composition")

# %%
c = comparison.set_index(["method", "baseline"])
rich = c.loc[("spline, order 4", "Richardson (order 2 at h, h/2)")]
rk4_4 = c.loc[("spline, order 4", "RK4")]
rk4_6 = c.loc[("spline, order 6", "RK4")]
dop_6 = c.loc[("spline, order 6", "scipy DOP853")]
outputs.say(
    f"The compositions keep the bounded energy error of the report's method: no growth over "
    f"10,000 orbits, at a level {outputs.sci(growth[2] / growth[4])} times lower for order 4.  "
    f"To reach the same error over $t \\in [0, 50]$, Richardson extrapolation of the "
    f"report's method, the classical route to order 4, needs "
    f"{outputs.span((rich.ratio_min, rich.ratio_max), 2)} times the evaluations of the "
    f"order-4 composition: the composition wins.  RK4 needs "
    f"{outputs.span((rk4_4.ratio_min, rk4_4.ratio_max), 2)} times the evaluations of order 4 "
    f"(each composed step costs three implicit steps) and "
    f"{outputs.span((rk4_6.ratio_min, rk4_6.ratio_max), 2)} times those of order 6; DOP853 "
    f"{outputs.span((dop_6.ratio_min, dop_6.ratio_max), 2)} times those of order 6.  On short runs the explicit methods win; the compositions win where the "
    f"report's method wins, on long runs of conservative problems, where RK4 and DOP853 "
    f"drift.")

# %% [markdown]
# ## 4. The single Newton-LU sweep
# `iteration="global"` solves the equations of all knots together: the step
# relations of each interval and the collocation at each knot, $3m$ unknowns
# per knot, by Newton's method with a sparse LU (SuperLU in its natural
# order keeps the band of the block-bidiagonal Jacobian).  It starts from one
# fixed-point sweep per step.

# %%
global_rows = []
global_cases = {"cannonball mu=0.6": ellipse,
                "oscillator omega=3": problems.harmonic(3.0, (0.0, 20.0), 0.05),
                "rigid body": cases["rigid body"]}
for name, problem in global_cases.items():
    stepwise = problem.solve(iteration="newton", tol=1e-14)
    whole = problem.solve(iteration="global", tol=1e-13)
    global_rows.append(dict(problem=name, knots=whole.t.size, status=whole.status,
                            newton_iterations=whole.niter, nfev=whole.nfev,
                            nfev_stepwise=stepwise.nfev,
                            max_difference=np.max(np.abs(whole.y - stepwise.y))))
global_table = pd.DataFrame(global_rows)
outputs.save_data(global_table, "global-sweep")
for row in global_table.itertuples():
    print(f"{row.problem:<20} {row.knots} knots: {row.newton_iterations} global Newton "
          f"iterations, {row.nfev} evaluations (stepwise {row.nfev_stepwise}); largest "
          f"difference from the stepwise solution {outputs.sci(row.max_difference, 1)}")

# %%
outputs.say(
    f"The global solve gives the stepwise solution to "
    f"{outputs.sci(global_table.max_difference.max(), 1)} in {global_table.newton_iterations.min()} "
    f"to {global_table.newton_iterations.max()} Newton iterations, each of which evaluates "
    f"$F$ and its Jacobian at every knot: "
    f"{(global_table.nfev / global_table.nfev_stepwise).min():.1f} to "
    f"{(global_table.nfev / global_table.nfev_stepwise).max():.1f} times the stepwise "
    f"evaluations, and a sparse factorisation of the whole trajectory.  On one processor it "
    f"does not pay (`make bench` times it).  What it would need is the structure of "
    f"parallel-in-time methods: the knots' evaluations and the factorisation split over "
    f"processors, as in parareal and multigrid-reduction-in-time, with a cheap coarse "
    f"propagator for the guess.  Its natural use is elsewhere: problems that stepping cannot "
    f"solve at all.")

# %% [markdown]
# ## 5. Boundary value problems
# The same equations with $y$ given at both ends instead of $y$ and $y'$ at
# the start: `splinestep.solve_bvp(fun, x, ya, yb)`.  The Bratu problem
# $y'' + \lambda e^y = 0$, $y(0) = y(1) = 0$, $\lambda = 1$, has two
# solutions, $y = -2\ln\left(\cosh((x - \tfrac12)\theta/2)/\cosh(\theta/4)\right)$
# for the two roots of $\theta = \sqrt{2\lambda}\cosh(\theta/4)$; the
# guesses $0.1\sin\pi x$ and $4\sin\pi x$ find one each.  Beside it, scipy's
# `solve_bvp` (collocation with mesh refinement, tol $10^{-8}$) from the
# same mesh and guesses.

# %%
bvp_rows = []
for branch, amplitude in (("lower", 0.1), ("upper", 4.0)):
    fun, jac, args, exact = problems.bratu(1.0, branch)
    for n in (11, 21, 41, 81, 161, 321):
        x = np.linspace(0.0, 1.0, n)
        guess = amplitude * np.sin(np.pi * x)[None]
        ours = splinestep.solve_bvp(fun, x, 0.0, 0.0, y_guess=guess, args=args)
        theirs = scipy_solve_bvp(lambda s, u: np.vstack([u[1], -np.exp(u[0])]),
                                 lambda a, b: np.array([a[0], b[0]]), x,
                                 np.vstack([guess, np.pi * amplitude * np.cos(np.pi * x)]),
                                 tol=1e-8)
        bvp_rows.append(dict(branch=branch, points=n, h=x[1], status=ours.status,
                             newton_iterations=ours.niter,
                             error=np.max(np.abs(ours.y - exact(x))),
                             scipy_status=theirs.status, scipy_points=theirs.x.size,
                             scipy_error=np.max(np.abs(theirs.sol(x)[0] - exact(x)))))
bvp_table = pd.DataFrame(bvp_rows)
outputs.save_data(bvp_table, "bvp-bratu")
bvp_orders = {b: np.polyfit(np.log(g.h), np.log(g.error), 1)[0]
              for b, g in bvp_table.groupby("branch")}
for b, g in bvp_table.groupby("branch"):
    print(f"{b} branch: fitted order {bvp_orders[b]:.3f}; Newton iterations "
          f"{g.newton_iterations.min()} to {g.newton_iterations.max()}; error at "
          f"{g.points.max()} points {outputs.sci(g.error.iloc[-1])}, scipy's "
          f"{outputs.sci(g.scipy_error.iloc[-1], 1)} on its {g.scipy_points.iloc[-1]} points")
linear = splinestep.solve_bvp(lambda t, y, yp: y, np.linspace(0.0, 1.0, 101), 0.0, 1.0)
linear_error = np.max(np.abs(linear.y[0] - np.sinh(linear.t) / np.sinh(1.0)))
print(f"y'' = y, y(0) = 0, y(1) = 1 on 101 points: {linear.niter} Newton iterations, error "
      f"{outputs.sci(linear_error)} (exact sinh x / sinh 1)")
no_solution = splinestep.solve_bvp(fun, np.linspace(0.0, 1.0, 41), 0.0, 0.0, args=(4.0,))
print(f"Bratu with lambda = 4 > {problems.boundary.LAMBDA_CRITICAL:.4f} (no solution): "
      f"status {no_solution.status}")

fig, (ax, bx) = plt.subplots(1, 2, figsize=(outputs.WIDTH, 3.6))
x_fine = np.linspace(0.0, 1.0, 201)
for branch, amplitude, color in (("lower", 0.1, "C0"), ("upper", 4.0, "C3")):
    fun, jac, args, exact = problems.bratu(1.0, branch)
    x = np.linspace(0.0, 1.0, 21)
    res = splinestep.solve_bvp(fun, x, 0.0, 0.0, y_guess=amplitude * np.sin(np.pi * x)[None],
                               args=args)
    ax.plot(x_fine, exact(x_fine)[0], "k-", linewidth=1)
    ax.plot(x, res.y[0], "o", color=color, markersize=4, label=f"{branch} branch, 21 points")
    g = bvp_table[bvp_table.branch == branch]
    bx.loglog(g.h, g.error, "o-", color=color, markersize=4, label=f"spline, {branch}")
    bx.loglog(g.h, g.scipy_error, "x--", color=color, markersize=5,
              label=f"scipy, {branch}")
ax.set_xlabel("$x$")
ax.set_ylabel("$y$ (line: exact)")
ax.set_title("Bratu, $\\lambda = 1$")
ax.set_ylim(-0.2, 5.8)
ax.legend(loc="upper center", fontsize=outputs.MIN_FONT)
bx.set_xlabel("mesh width $h$")
bx.set_ylabel("max error")
bx.set_title("Error against the exact solutions")
bx.set_ylim(1e-13, 1.0)
bx.legend(loc="lower center", bbox_to_anchor=(0.5, 0.28), ncol=2, fontsize=outputs.MIN_FONT)
outputs.save_figure(fig, "bvp-bratu")

# %%
outputs.say(
    f"Both branches are found from their guesses, at order {bvp_orders['lower']:.2f} (lower) "
    f"and {bvp_orders['upper']:.2f} (upper) in the mesh width, in "
    f"{bvp_table.newton_iterations.min()} to {bvp_table.newton_iterations.max()} Newton "
    f"iterations.  scipy's `solve_bvp` is of fourth order and refines its mesh until its "
    f"residual meets the tolerance, so it is more accurate for a given starting mesh; the "
    f"spline collocation is the simpler method, and keeps the mesh it is given, at second "
    f"order.  A problem without solution (Bratu at $\\lambda = 4$) ends with status "
    f"{no_solution.status} and a message, not an exception.")
