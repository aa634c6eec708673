# %% [markdown]
# # Order 4 and 6: symmetric compositions of the spline step
#
# One of the report's directions (Sec. 5) is higher order through splines of
# higher degree; notebook 06 finds that they give no usable order.  Here
# higher order is built from the cubic step itself, by symmetric
# compositions of the spline step, beside Richardson extrapolation, RK4
# and DOP853.  What they give:
#
# * **the orders**: fitted slopes 3.98 to 4.00 (order 4) and 5.79 to 6.02
#   (order 6) on the four cannonball orbits and the rigid body; on the
#   ellipse at the report's step the largest position error falls from
#   $4.1 \times 10^{-3}$ to $1.8 \times 10^{-7}$ (order 4);
# * **over 10,000 orbits** the order-4 composition's energy error stays
#   level, as the report's method's, 356 times lower at the same step
#   $h = 0.08$ (where it spends about three times the evaluations); RK4 at the same work
#   starts lower and drifts past it near orbit 4290, but stays ahead in
#   position until both have lost the phase;
# * **at equal work** order 4 beats Richardson extrapolation of the
#   report's method (which needs 1.3 to 1.5 times the evaluations) but
#   not RK4 (which needs 0.21 to 0.28 times them) or DOP853.

# %%
import sys
import warnings

import numpy as np
import pandas as pd
from IPython.display import HTML, display

sys.path.insert(0, "../scripts")  # outputs.py: the repository's data/, figures/ and plot style
import outputs
import splinestep
from splinestep import problems
from splinestep import check
from splinestep.analysis import composition, diagnostics, long_time
from splinestep.analysis.extrapolation import richardson

plt = outputs.setup()

# %% [markdown]
# ## Order 4 and 6 by symmetric composition
# Higher-degree splines give no usable higher order (notebook 06).  What
# works: the spline step is
# symmetric (stepping back with $-h$ undoes it), so a symmetric composition of
# it raises the order and keeps the symmetry.  `solve(order=4)` takes each
# step as three spline steps of sizes $\gamma_1 h, \gamma_2 h, \gamma_1 h$
# with $\gamma_1 = 1/(2 - 2^{1/3})$, $\gamma_2 = -2^{1/3}/(2 - 2^{1/3})$
# (Yoshida's triple jump; the middle step goes backwards), `order=6` as
# seven (Yoshida's solution A).  Those sub-steps leave the step (order 4's
# reach $t + 1.35h$ and $t - 0.35h$), so a step that would evaluate $F$ outside
# the span (the first and last of a uniform grid) takes Suzuki's compositions of the same order
# instead (5 and 25 sub-steps, all inside the step).  Between knots the
# quintic through the knots' values and first two derivatives keeps the
# order.  The fitted
# slopes of the largest error at times between the knots against the exact
# solutions:

# %%
cases = {f"cannonball mu={mu:g}": problems.cannonball(mu) for mu in problems.CANNONBALL_MU}
cases["rigid body"] = problems.rigid_body("consistent")
STEPS = {4: np.array([0.08, 0.04, 0.02, 0.01]), 6: np.array([0.16, 0.08, 0.04])}
orders_table = composition.orders(cases, STEPS)   # the error between the knots too
outputs.save_data(orders_table, "composition-orders")
both = orders_table.assign(both=[f"{a:.2f} / {b:.2f}" for a, b in
                                 zip(orders_table.slope, orders_table.successive_slope)])
display(HTML(outputs.html_table(   # the fitted slope / the slope from successive differences
    both.pivot(index="problem", columns="order", values="both").rename(
        columns=lambda k: f"order {k}: exact / successive").reset_index(), text=outputs.readable)))

# %%
ellipse = cases["cannonball mu=0.6"]   # solved at the report's step, its default h = 0.01
t_report = np.arange(0.0, 50.0 + 1e-9, 0.08)   # compared every 0.08 (the largest step)
exact_report, _ = ellipse.reference(t_report)
at_report_step = {order: np.max(np.abs(ellipse.solve(order=order, t_eval=t_report).y
                                       - exact_report)) for order in (2, 4, 6)}
for order, error in at_report_step.items():
    print(f"ellipse, dt = 0.01, order {order}: max position error {error:.1e}")

# %% [markdown]
# A second way for order 4, without the exact solution: the difference
# from a run at half the step, times 16/15.

# %%
half_step_4 = ellipse.solve(h=0.005, order=4, t_eval=t_report).y
richardson_4 = np.max(np.abs(ellipse.solve(order=4, t_eval=t_report).y - half_step_4)) * 16 / 15
print(f"order 4 at dt = 0.01 from the run at dt = 0.005 (no exact solution): {richardson_4:.1e}")

# %% [markdown]
# Is order 6's error at this step in the asymptotic range?  Halving the
# step, and solving each step equation more tightly, tell.

# %%
order6_floor = {(h, tol): np.max(np.abs(ellipse.solve(h=h, order=6, t_eval=t_report, tol=tol).y
                                        - exact_report))
                for h, tol in ((0.02, 1e-12), (0.01, 1e-15))}
tighter = order6_floor[(0.01, 1e-15)] / at_report_step[6]
assert 0.5 < tighter < 2   # a floor of the run: printed to its first digit, which is stable
print(outputs.wrapped(
    f"order 6: dt = 0.02 -> 0.01 divides the error by "
    f"{order6_floor[(0.02, 1e-12)] / at_report_step[6]:.0f} (order 6: 64); at dt = 0.01 the "
    f"error with the step equation solved to 1e-15 over that with the default 1e-12: "
    f"{tighter:.0f}"))

# %% [markdown]
# Order 4 fits slopes 3.98 to 4.00 on the four cannonball orbits and the
# rigid body, order 6 5.79 to 6.02; the successive differences of the
# runs, which do not use the exact solutions, give 3.98 to 4.00 and 5.71 to
# 6.04.  On the ellipse at the report's step the largest position error
# falls from $4.1 \times 10^{-3}$ (the report's method) to
# $1.8 \times 10^{-7}$ and $1.4 \times 10^{-12}$.  The order-6 value is at
# a floor, not in the asymptotic range: halving the step from 0.02 divides
# the error by only 8, and solving each step equation a thousand times more
# tightly does not lower it either.  It measures a floor of the run (seven
# implicit sub-steps in each of its steps), not the order.

# %% [markdown]
# ### The cost against the other routes
# The work against precision over the report's run, $t \in [0, 50]$,
# $h = 0.08 \dots 0.005$: the compositions, Richardson extrapolation of the
# report's method ($(4 y_{h/2} - y_h)/3$, `splinestep.analysis.extrapolation`),
# RK4, and scipy's DOP853 at rtol $10^{-4} \dots 10^{-12}$ (atol = rtol/100).

# %%
routes = {f"spline, order {order}": (lambda h, order=order: ellipse.solve(h=h, order=order,
                                                                          t_eval=t_report))
          for order in (2, 4, 6)}
routes["Richardson (order 2 at h, h/2)"] = lambda h: richardson(
    ellipse.fun, ellipse.t_span, ellipse.y0, ellipse.yp0, h, t_eval=t_report, args=ellipse.args)
routes["RK4"] = lambda h: ellipse.solve("rk4", h=h, t_eval=t_report)
work = pd.DataFrame(diagnostics.work_precision(
    ellipse, t_report, exact_report, (0.08, 0.04, 0.02, 0.01, 0.005), routes,
    10.0 ** -np.arange(4, 13), ("DOP853",)))
outputs.save_data(work, "composition-work")

# %% [markdown]
# From these curves, the ratio of evaluations at equal error, read where
# both curves of a pair reach (`diagnostics.work_ratio_range`):

# %%
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

# %% [markdown]
# To reach the same error, Richardson extrapolation of the report's method,
# the classical route to order 4, needs 1.3 to 1.5 times the evaluations of
# the order-4 composition: the composition wins there.  RK4 needs 0.21 to
# 0.28 times the evaluations of order 4 (each composed step costs three
# implicit steps) and 0.98 to 1.6 times those of order 6; DOP853 0.065 to
# 0.077 times those of order 6.  The curves:

# %% jupyter={"source_hidden": true}
fig, bx = plt.subplots(figsize=(outputs.WIDTH, 3.6))
short = {"Richardson (order 2 at h, h/2)": "Richardson (2 at h, h/2)", "scipy DOP853": "DOP853"}
for method, (nfev, error) in work_curves.items():
    color, marker = outputs.style_of(method)
    bx.loglog(nfev, error, color=color, marker=marker, markersize=4, label=short.get(method, method),
              linestyle="-" if method.startswith("spline") else "--")
bx.set_xlabel("right-hand-side evaluations over $t \\in [0, 50]$")
bx.set_ylabel("max position error")
bx.set_title("Work against precision, ellipse $\\mu = 0.6$", loc="left")
fig.legend(loc="outside lower center", fontsize=outputs.MIN_FONT, ncol=3, handlelength=1.6,
           columnspacing=0.8, frameon=False)
outputs.save_figure(fig, "composition-work")

# %% [markdown]
# On this short run DOP853 wins against both compositions and RK4 against
# order 4, while order 6 costs about what RK4 does at low accuracy and less
# at high.  The composition's one advantage shows only over long runs.

# %% [markdown]
# ### Long time: 10,000 orbits
# The ellipse over 10,000 orbits at $h = 0.08$ (the largest step of the
# work-precision comparison above): the report's method, the order-4
# composition, and RK4 at the composition's work (its step stretched to
# spend the same evaluations).  As in notebook 08, each run is sampled over
# whole orbits at logarithmically spaced orbit numbers, at every one of its
# steps in them.  (Both spline runs end flagged by their step-size check;
# notebook 12 examines whether rightly.)

# %%
period_ellipse = problems.orbit_elements(0.6)["period"]
LONG_ORBITS, LONG_STEP = 10_000, 0.08
windows = np.unique(np.round(np.logspace(0, np.log10(LONG_ORBITS), 17)).astype(int)) - 1
t_long = LONG_ORBITS * period_ellipse
long_runs, check_sums = {}, {}
for order in (2, 4):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")   # the check's verdict is in the result's message
        res = splinestep.solve(ellipse.fun, (0.0, t_long), ellipse.y0, ellipse.yp0, LONG_STEP,
                               args=ellipse.args, order=order,
                               t_eval=long_time.orbit_steps(windows, LONG_STEP, period_ellipse))
    long_runs[f"spline, order {order}"] = res
    check_sums[order] = long_time.accumulated_estimate(res)   # the check's sums, for the end

# %% [markdown]
# RK4 at the same work: its step is chosen so that it spends the order-4
# composition's evaluations.

# %%
rk4_step = 4 * LONG_STEP / (long_runs["spline, order 4"].nfev / (t_long / LONG_STEP))
long_runs["RK4, same work"] = splinestep.rk4(
    ellipse.fun, (0.0, t_long), ellipse.y0, ellipse.yp0, rk4_step, args=ellipse.args,
    t_eval=long_time.orbit_steps(windows, rk4_step, period_ellipse))

# %% [markdown]
# The largest energy error and position error in each sampled orbit:

# %%
energy_ellipse = ellipse.invariants["energy"]
exact_y, exact_yp = ellipse.reference(np.linspace(0.0, period_ellipse, 4001))
threshold = {"y": check.ACCUMULATED_FRACTION * np.max(np.abs(exact_y)),   # the step-size
             "yp": check.ACCUMULATED_FRACTION * np.max(np.abs(exact_yp))}  # check's
long_energy = []
for method, res in long_runs.items():
    y_ref, yp_ref = ellipse.reference(res.t)
    windowed = {"energy_error": np.abs(energy_ellipse(res.y, res.yp) - (0.5 - 0.6)),
                "position_error": np.max(np.abs(res.y - y_ref), axis=0),
                "velocity_error": np.max(np.abs(res.yp - yp_ref), axis=0)}
    per_orbit = pd.DataFrame(windowed).groupby(np.floor(res.t / period_ellipse).astype(int) + 1)
    long_energy.append(per_orbit.max().rename_axis("orbit").reset_index().assign(
        method=method, nfev=res.nfev)[["method", "orbit", "nfev", *windowed]])
long_energy = pd.concat(long_energy, ignore_index=True)
outputs.save_data(long_energy, "composition-energy")

# %% [markdown]
# For each run: the evaluations per orbit, the energy and position errors
# in the first and the last orbits, and the energy error's growth
# exponent.

# %%
growth = {m: g.set_index("orbit") for m, g in long_energy.groupby("method", sort=False)}
for method, g in growth.items():
    tail = g[g.index >= 10]
    exponent = np.polyfit(np.log(tail.index), np.log(tail.energy_error), 1)[0]
    print(outputs.wrapped(
        f"{method:<16} {g.nfev.iloc[0] / LONG_ORBITS:6.0f} evaluations per "
        f"orbit; energy error {outputs.plain(g.energy_error.iloc[0])} in the first orbit, "
        f"{outputs.plain(g.energy_error.iloc[-1])} in orbit {LONG_ORBITS} (growth exponent "
        f"{outputs.signed(exponent)}); position error {outputs.plain(g.position_error.iloc[0])}, "
        f"{outputs.plain(g.position_error.loc[100])} in orbit 100, "
        f"{outputs.plain(g.position_error.iloc[-1])} in orbit {LONG_ORBITS}"))

# %% [markdown]
# The energy error of both spline runs stays where it starts (growth
# exponents 0.00); RK4 at the same work starts far lower and drifts
# (exponent 0.96).  The position errors all grow, as the phase drifts, to
# the size of the orbit (semi-major axis 3) by orbit 10,000.  Where RK4's
# energy error passes the composition's, two ways: on the sampled curve,
# and on the line $a + c\,(k - 1)$ fitted to RK4's error in orbit $k$:

# %%
level_4 = growth["spline, order 4"].energy_error.max()
rk4_long = growth["RK4, same work"]
crossing_sampled = long_time.crossing(rk4_long.index, rk4_long.energy_error, level_4)
rk4_drift, rk4_start = np.polyfit(rk4_long.index - 1, rk4_long.energy_error, 1)
crossing_fitted = 1 + (level_4 - rk4_start) / rk4_drift
print(outputs.wrapped(
    f"RK4, same work: energy error {rk4_start:.3e} + {rk4_drift:.3e} (orbit - 1); it "
    f"exceeds the order-4 composition's largest ({outputs.plain(level_4, 3)}) from orbit "
    f"{outputs.round_sig(crossing_sampled, 3):.0f} (sampled curve) or "
    f"{outputs.round_sig(crossing_fitted, 3):.0f} (fitted line)"))

# %% [markdown]
# The energy levels side by side, and the position errors:

# %%
position_ratio = (rk4_long.position_error / growth["spline, order 4"].position_error)
print(outputs.wrapped(
    f"energy level: order 2 / order 4 "
    f"{growth['spline, order 2'].energy_error.max() / level_4:.0f}; RK4 / order 4 at orbit "
    f"{LONG_ORBITS}: {rk4_long.energy_error.iloc[-1] / level_4:.1f}; position error, order 4 / "
    f"RK4: {1 / position_ratio.iloc[0]:.0f} in the first orbit, "
    f"{1 / position_ratio.loc[100]:.0f} in orbit 100"))

# %% [markdown]
# The composition's energy error is 356 times lower than the report's
# method's.  RK4 passes it only from orbit 4290, and at orbit 10,000 its
# energy error is 2.3 times the composition's.  The position error favours
# RK4: at the same work it is 790 times smaller in the first orbit and 78
# times in orbit 100.
#
# For the comparison: the position errors at orbit 10,000 are those of
# three runs that have all lost the phase, and tell nothing of the
# methods; the first orbit and orbit 100 do.  Where RK4's energy error
# passes the composition's, near orbit 4290, the velocities of both runs
# are far off (both past the step-size check's threshold in $y'$; notebook
# 12): the composition's bounded energy pays only in runs whose phase is
# lost anyway.

# %% jupyter={"source_hidden": true}
fig, ax = plt.subplots(figsize=(outputs.WIDTH, 3.9))
for method, g in growth.items():
    color = outputs.style_of(method)[0]
    ax.loglog(g.index, g.energy_error, "o-", color=color, markersize=4, label=method)
    ax.loglog(g.index, g.position_error, "x:", color=color, markersize=4)
ax.axhline(threshold["y"], color="0.45", linestyle="--", linewidth=1,
           label="check's threshold in $y$, $0.3\\,\\max|y|$")
ax.set_xlabel(f"orbit number (ellipse $\\mu = 0.6$; spline $h = {LONG_STEP:g}$)")
ax.set_ylabel("largest error in the orbit")
ax.set_title("10,000 orbits: $|H - H_0|$ (o, solid), position error (x, dotted)", loc="left")
ax.set_ylim(1e-10, 1e6)   # room above the curves for the key
ax.legend(loc="upper center", fontsize=outputs.MIN_FONT, ncol=2, handlelength=1.6,
          columnspacing=0.8)
outputs.save_figure(fig, "composition-long")

# %% [markdown]
# The two spline runs' energy errors (solid) are level lines; RK4's climbs
# through the composition's near orbit 4290.  The position errors (dotted)
# all climb to the size of the orbit, through the step-size check's
# threshold (dashed grey; notebook 12 gives the check's verdict on these runs).
#
# Why the composition's energy error stays bounded is not explained here.
# It is symmetric but not conjugate to Verlet (its sub-steps differ, so no
# single change of variables as in notebook 05 applies); the likely reason
# is its reversibility, since reversible methods on integrable problems
# keep modified invariants nearly constant (Hairer, Lubich and Wanner,
# Ch. XI), which we have not measured.

# %% [markdown]
# ## What orders 4 and 6 buy
# Order 4 by composition beats the classical route to order 4 from the
# report's method, Richardson extrapolation, and keeps the bounded energy
# error over long runs.  It does not beat RK4 at equal work on this orbit:
# RK4 stays ahead of order 4 in position until both have lost the phase,
# and the composition's one advantage over RK4, an energy error that does
# not grow, pays at this work only beyond about 4300 orbits, in runs long
# enough that both have lost their position and the step-size check flags
# the composition's run (RK4 has no check).  Order 6, on the short run,
# costs about what RK4 does at low accuracy and less at high; it was not
# run over long times.

# %% [markdown]
# ## For notebook 12: the step-size check on these runs
# Both spline runs end flagged by the step-size check; notebook 12, which
# studies the check, examines whether rightly, and finds the flags right
# but late for the report's method.  The cell below writes what it needs
# to `data/composition-check.csv`: for each run, the orbit where its
# error passes the check's threshold (0.3 of the solution's size), and for
# the spline runs the orbit where the check's own sum would, extrapolated
# from the sum at the end of the run.

# %%
check_rows = []
for method, g in long_energy.groupby("method", sort=False):
    per_orbit = {"y": g.position_error.to_numpy(), "yp": g.velocity_error.to_numpy()}
    found = check_sums.get(int(method[-1])) if method.startswith("spline") else None
    check_rows.append(dict(
        method=method, threshold_y=threshold["y"], threshold_yp=threshold["yp"],
        **{f"orbit_{k}": long_time.crossing(windows + 1, per_orbit[k], threshold[k])
           for k in per_orbit},
        orbit_check_sum=np.nan if found is None
        else LONG_ORBITS * found["fraction"] * found["yp_scale"] / found["sum_yp"],
        final_y=per_orbit["y"][-1], final_yp=per_orbit["yp"][-1]))
outputs.save_data(pd.DataFrame(check_rows), "composition-check")
