# %% [markdown]
# # Newton's cannonball: Figures 1a and 2a
#
# The report's first test (Sec. 3.1) is the Kepler problem
#
# $$\ddot{\mathbf x} = -\frac{\mu}{|\mathbf x|^3}\,\mathbf x ,$$
#
# for $\mu \in \{0.4, 0.5, 0.6, 1\}$ on $t \in [0, 50]$ with $\Delta t = 0.01$.
# The report does not print the launch; $\mathbf x(0) = (1, 0)$,
# $\dot{\mathbf x}(0) = (0, 1)$ gives energy $H = \tfrac12 - \mu$ and so exactly
# the hyperbolic, parabolic, elliptic and circular orbits it names.
# The invariants are $H = \tfrac12|\dot{\mathbf x}|^2 - \mu/|\mathbf x|$
# (eq. 13 as printed omits $\mu$) and $M = x\dot y - y\dot x$ (eq. 14).
# The reference is the exact solution (universal-variable Kepler equation,
# checked in the tests against the classical Kepler, Barker and hyperbolic
# equations).

# %%
import sys

import numpy as np
import pandas as pd

sys.path.insert(0, "../scripts")  # outputs.py: the repository's data/, figures/ and plot style
import outputs
from splinestep import problems

plt = outputs.setup()
MUS = problems.CANNONBALL_MU
runs = {}
for mu in MUS:
    problem = problems.cannonball(mu)
    runs[mu] = {m: problem.solve(m) for m in ("spline", "rk4")}
    for method, res in runs[mu].items():
        assert res.success, res.message
    elements = problems.orbit_elements(mu)
    print(f"mu = {mu:.1f} ({problems.ORBIT_TYPES[mu]:>10}): energy {elements['energy']:+.2f}, "
          f"eccentricity {elements['eccentricity']:.3f}; {runs[mu]['spline'].nstep} steps, "
          f"spline {runs[mu]['spline'].nfev / runs[mu]['spline'].nstep:.2f} "
          f"evaluations per step, RK4 {runs[mu]['rk4'].nfev / runs[mu]['rk4'].nstep:.2f}")
per_step = np.array([runs[mu]["spline"].nfev / runs[mu]["spline"].nstep for mu in MUS])
outputs.say(
    f"The spline stepper iterates each step until the change is below $10^{{-12}}$ of "
    f"the state (the default `tol`).  At $\\Delta t = 0.01$ that takes "
    f"{per_step.min():.2f} to {per_step.max():.2f} evaluations per step (one per sweep: each "
    f"sweep evaluates $F$ once and tests the change it made), {per_step.min() / 4:.0%} to "
    f"{per_step.max() / 4:.0%} of RK4's four.")

# %% [markdown]
# ## Figure 1a: the four trajectories

# %%
rows = []
fig, axes = plt.subplots(2, 2, figsize=(outputs.WIDTH, 5.0))
separation = {}
for ax, mu in zip(axes.flat, MUS):
    problem = problems.cannonball(mu)
    t = runs[mu]["spline"].t
    exact, _ = problem.exact(t)
    # The exact orbit first, as a wide light band, over one period where the orbit closes
    # (it repeats: the circle 7.96 times in t <= 50); the numerical solutions on top of it.
    period = problems.orbit_elements(mu)["period"]
    lap = t <= period if np.isfinite(period) else slice(None)
    ax.plot(exact[0, lap], exact[1, lap], color="0.6", linewidth=5, solid_capstyle="butt",
            label="exact (one period)")
    ax.plot(*runs[mu]["spline"].y, color=outputs.METHOD_STYLE["spline"]["color"], linewidth=1.3,
            label="cubic spline")
    marks = slice(0, None, 250)  # RK4 every 2.5 time units: markers that leave the line visible
    ax.plot(*runs[mu]["rk4"].y[:, marks], "x", color=outputs.METHOD_STYLE["rk4"]["color"],
            markersize=6, markeredgewidth=1.4, label="RK4 (every 2.5 time units)")
    ax.plot(0, 0, "k*", markersize=9, label="centre of attraction")
    ax.set_title(f"$\\mu = {mu:g}$ ({problems.ORBIT_TYPES[mu]})")
    ax.set_aspect("equal", adjustable="datalim")
    ax.xaxis.set_major_locator(plt.MaxNLocator(5))
    # the largest distance between a numerical and the exact orbit, as a share of the panel
    width = np.ptp(exact[0]) if np.ptp(exact[0]) > np.ptp(exact[1]) else np.ptp(exact[1])
    separation[mu] = max(np.max(np.hypot(*(runs[mu][m].y - exact))) for m in runs[mu]) / width
    stride = slice(None, None, 10)
    rows.append(pd.DataFrame({
        "mu": mu, "t": t[stride],
        "x_spline": runs[mu]["spline"].y[0, stride], "y_spline": runs[mu]["spline"].y[1, stride],
        "x_rk4": runs[mu]["rk4"].y[0, stride], "y_rk4": runs[mu]["rk4"].y[1, stride],
        "x_exact": exact[0, stride], "y_exact": exact[1, stride]}))
for ax in axes[1]:
    ax.set_xlabel("$x$ (launch radius = 1)")
for ax in axes[:, 0]:
    ax.set_ylabel("$y$ (launch radius = 1)")
handles, labels = axes[0, 0].get_legend_handles_labels()
fig.legend(handles, labels, loc="outside right upper", frameon=False,
           title="Newton's cannonball,\n$t \\in [0, 50]$, $\\Delta t = 0.01$", title_fontsize=11)
outputs.save_data(pd.concat(rows), "cannonball-trajectories")
outputs.save_figure(fig, "cannonball-trajectories")

# %%
worst = max(separation, key=separation.get)
outputs.say(
    f"The exact orbit is the grey band, drawn once per period; the spline's line and RK4's "
    f"crosses lie on it for all four orbits: the claim of Fig. 1a holds.  The largest distance "
    f"between a numerical and the exact position is {separation[worst]:.2%} of the panel's "
    f"width ($\\mu = {worst:g}$, the spline): {900 * separation[worst]:.1f} pixel even if the "
    f"panel were 900 pixels wide.  The errors are quantified below.")

# %% [markdown]
# ## Figure 2a: error histories
#
# Three errors, each against the exact flow: the energy error
# $|H(t) - H(0)|$, the angular-momentum error $|M(t) - M(0)|$ and the
# position error $|\mathbf x(t) - \mathbf x_{\rm exact}(t)|$.  The spline is
# on the left, RK4 on the right, on the same axes; colour and marker are the
# orbit.  The downward spikes are zero crossings of a signed error.

# %%
errors = []
for mu in MUS:
    problem = problems.cannonball(mu)
    for method, res in runs[mu].items():
        exact, _ = problem.exact(res.t)
        energy = problem.invariants["energy"](res.y, res.yp)
        momentum = problem.invariants["angular momentum"](res.y, res.yp)
        errors.append(pd.DataFrame({
            "mu": mu, "method": method, "t": res.t,
            "r": np.hypot(res.y[0], res.y[1]),
            "energy_error": np.abs(energy - energy[0]),
            "momentum_error": np.abs(momentum - momentum[0]),
            "position_error": np.hypot(*(res.y - exact))}))
errors = pd.concat(errors, ignore_index=True)

fig, axes = plt.subplots(3, 2, figsize=(outputs.WIDTH, 5.0), sharex=True, sharey="row")
columns = {"energy_error": "energy\n$|H(t) - H(0)|$",
           "momentum_error": "ang. momentum\n$|M(t) - M(0)|$",
           "position_error": "position\n$|\\mathbf{x} - \\mathbf{x}_{\\rm exact}|$"}
MU_MARKERS = {0.4: "o", 0.5: "s", 0.6: "^", 1.0: "D"}
for row, (column, label) in zip(axes, columns.items()):
    for ax, method in zip(row, ("spline", "rk4")):
        for k, mu in enumerate(MUS):
            sel = errors[(errors.mu == mu) & (errors.method == method)]
            # markers staggered in time, so that a curve hidden under another shows its own
            ax.semilogy(sel.t[1:], sel[column][1:], color=outputs.MU_COLORS[mu], linewidth=1.0,
                        marker=MU_MARKERS[mu], markersize=4.5, markevery=(300 + 150 * k, 600))
    # y from the data: the top just above the largest error, the bottom below every curve's
    # lowest tenth (the zero crossings' spikes run off it)
    values = errors[column][errors.t > 0]
    low = errors[errors.t > 0].groupby(["mu", "method"])[column].quantile(0.1).min() / 3
    row[0].set_ylim(low, 3 * values.max())
    row[0].yaxis.set_major_locator(plt.LogLocator(numticks=4))
    row[0].set_ylabel(label)
    if values.max() > 1e-3:
        for ax in row:
            ax.axhline(1e-3, color="k", linewidth=1.2, linestyle="--")
        row[1].text(49, 1.4e-3, "report's bound $10^{-3}$", ha="right", va="bottom",
                    fontsize=outputs.MIN_FONT)
axes[0, 0].set_title("cubic spline, $\\Delta t = 0.01$")
axes[0, 1].set_title("RK4, $\\Delta t = 0.01$")
for ax in axes[-1]:
    ax.set_xlabel("time $t$")
from matplotlib.lines import Line2D  # noqa: E402
legend = [Line2D([], [], color=outputs.MU_COLORS[mu], marker=MU_MARKERS[mu], markersize=4.5,
                 label=f"$\\mu = {mu:g}$ ({problems.ORBIT_TYPES[mu]})") for mu in MUS]
fig.legend(handles=legend, loc="outside upper center", ncol=4, columnspacing=1.0,
           handlelength=1.8, frameon=False)
outputs.save_data(errors.iloc[::5], "cannonball-error-histories")
outputs.save_figure(fig, "cannonball-error-histories")

# %% [markdown]
# ### How large are the errors? (Section 5: "they do not exceed $10^{-3}$")

# %%
summary = errors.groupby(["mu", "method"])[list(columns)].max().reset_index()
summary["nstep"] = [runs[row.mu][row.method].nstep for row in summary.itertuples()]
summary["nfev"] = [runs[row.mu][row.method].nfev for row in summary.itertuples()]
outputs.save_data(summary, "cannonball-max-errors")
for row in summary.itertuples():
    print(f"mu = {row.mu:.1f} {row.method:>6}: max energy error {row.energy_error:.2e}, "
          f"max momentum error {row.momentum_error:.2e}, "
          f"max position error {row.position_error:.2e}")
spline = summary[summary.method == "spline"].set_index("mu")
rk4 = summary[summary.method == "rk4"].set_index("mu")
ratios = spline[list(columns)] / rk4[list(columns)]
ellipse = errors[(errors.mu == 0.6) & (errors.method == "spline")]
above = ellipse.t[ellipse.position_error > 1e-3]
below_after = ellipse.t[(ellipse.t > above.min()) & (ellipse.position_error <= 1e-3)]
print(f"ellipse, spline: position error first above 1e-3 at t = {above.min():.2f}, "
      + (f"last below it after that at t = {below_after.max():.2f}" if len(below_after)
         else f"above it from then to t = {ellipse.t.max():g}"))
lo, hi = ratios.stack().idxmin(), ratios.stack().idxmax()
outputs.say(
    f"The spline's energy and angular-momentum errors stay below "
    f"{outputs.sci(max(spline.energy_error.max(), spline.momentum_error.max()), 1)} on all "
    f"four orbits.  Its position error is a different matter: on the ellipse it first "
    f"exceeds $10^{{-3}}$ at $t = {above.min():.2f}$ and reaches "
    f"{outputs.sci(spline.position_error[0.6])}, because a second-order phase error "
    f"accumulates along the orbit.  RK4 at the same step is more accurate on every "
    f"measure and every orbit, by a factor from {ratios.min().min():.0f} "
    f"($\\mu = {lo[0]:g}$, {lo[1].replace('_', ' ')}) to {outputs.sci(ratios.max().max(), 1)} "
    f"($\\mu = {hi[0]:g}$, {hi[1].replace('_', ' ')}).")

# %% [markdown]
# ### Where along the orbit does the error change? (Section 5)
# The report attributes the "unusual error corresponding with the
# trajectory" to the regions of highest curvature.  "Curvature" has two
# readings here, and we measure both:
#
# * the curvature of the **path** in the plane,
#   $\kappa = |\dot{\mathbf x} \times \ddot{\mathbf x}| / |\dot{\mathbf x}|^3$
#   (1 / length);
# * the curvature of the **solution** $\mathbf x(t)$ as a function of time, its
#   second derivative: the acceleration $|\mathbf x''| = \mu / r^2$
#   (length / time$^2$), which the spline's quadratic coefficient carries.
#
# Beside them, the fourth derivative $|\mathbf x''''|$ (length / time$^4$),
# which sets the step's local error, $h^4 \mathbf x''''/24$ to leading order (`01_method`).  On
# the ellipse ($\mu = 0.6$) we compute all three along the exact orbit, in
# closed form (`problems.acceleration_derivatives`), beside the rate at which
# the spline's energy error changes, over the first orbit.  The three have
# different units, so each is compared with itself: its largest value on the
# arc around periapsis ($r < 1.5$) against its largest value on the arc
# around apoapsis ($r > 4.5$), and in the figure its value along the orbit
# divided by its value at apoapsis.

# %%
res = runs[0.6]["spline"]
problem = problems.cannonball(0.6)
elements = problems.orbit_elements(0.6)
period = elements["period"]
x_exact, v_exact = problem.exact(res.t)
acceleration, _, fourth = problems.acceleration_derivatives(x_exact, v_exact, 0.6)
curvature = problems.path_curvature(v_exact, acceleration)
x2 = np.hypot(*acceleration)
x4 = np.hypot(*fourth)
r = np.hypot(*x_exact)
energy_error = problem.invariants["energy"](res.y, res.yp) - elements["energy"]
rate = np.abs(np.diff(energy_error)) / np.diff(res.t)  # per unit time, on each step
middle = 0.5 * (res.t[1:] + res.t[:-1])
first = middle < period
one = res.t <= period
apoapsis = np.argmin(np.abs(res.t - period / 2))
r_mid = 0.5 * (r[1:] + r[:-1])
near = r_mid < 1.5
x_err = np.hypot(*(res.y - x_exact))
peak = np.argmax(x_err)
# The arc around periapsis (r < 1.5) against the arc around apoapsis (r > 4.5)
# over the first orbit: the largest value of each quantity in each arc.
peri_arc, apo_arc = first & (r_mid < 1.5), first & (r_mid > 4.5)


def arc_ratio(values):
    values = values[1:] if values.size == r.size else values
    return values[peri_arc].max() / values[apo_arc].max()


log_corr = {name: np.corrcoef(np.log(values[1:][first]), np.log(rate[first]))[0, 1]
            for name, values in (("curvature", curvature), ("acceleration", x2), ("x4", x4))}
location = pd.DataFrame({
    "quantity": ["time_share_r_lt_1_5", "energy_variation_share_r_lt_1_5",
                 "curvature_ratio_arcs", "min_curvature", "r_min_curvature",
                 "acceleration_ratio_apsides", "acceleration_ratio_arcs",
                 "x4_ratio_arcs", "energy_rate_ratio_arcs",
                 "log_correlation_rate_curvature", "log_correlation_rate_acceleration",
                 "log_correlation_rate_x4",
                 "energy_error_apoapsis", "energy_error_next_periapsis",
                 "max_position_error", "t_max_position_error", "r_max_position_error"],
    "value": [near.mean(), np.abs(np.diff(energy_error))[near].sum()
              / np.abs(np.diff(energy_error)).sum(),
              arc_ratio(curvature), curvature[one].min(),
              r[np.argmin(np.where(one, curvature, np.inf))],
              x2[one].max() / x2[one].min(), arc_ratio(x2),
              arc_ratio(x4), arc_ratio(rate), log_corr["curvature"], log_corr["acceleration"],
              log_corr["x4"], abs(energy_error[apoapsis]),
              abs(energy_error[np.argmin(np.abs(res.t - period))]),
              x_err[peak], res.t[peak], r[peak]]})
outputs.save_data(location, "cannonball-error-location")
for row in location.itertuples():
    print(f"{row.quantity:<34} {row.value:10.{2 if 'ratio' in row.quantity else 3}g}")
# The acceleration mu / r^2 in closed form: (r_apo / r_peri)^2 = ((1 + e) / (1 - e))^2 between
# the apsides; (4.5 / r_peri)^2 between the arcs' largest values (at r = 1 and r = 4.5).
e = elements["eccentricity"]
r_peri, r_apo = elements["a"] * (1 - e), elements["a"] * (1 + e)
value = location.set_index("quantity").value
# Knots every 0.01 miss an apsis by at most |r''| 0.005^2 / 2 <= 5e-6 of r (|r''| <= 0.4), and
# pass r = 4.5 by at most |r'| 0.01 < 1.4e-3 (|r'| = 0.13 there): the ratios within 1e-4, 1e-3.
closed = {"acceleration_ratio_apsides": ((r_apo / r_peri) ** 2, 1e-4),
          "acceleration_ratio_arcs": ((4.5 / r_peri) ** 2, 1e-3)}
for name, (exact_ratio, tolerance) in closed.items():
    print(f"{name}: sampled {value[name]:.3f}, closed form {exact_ratio:.3f}")
    assert abs(value[name] / exact_ratio - 1) < tolerance, name

fig, (ax_r, *axes) = plt.subplots(3, 1, figsize=(outputs.WIDTH, 5.0), sharex=True,
                                  gridspec_kw=dict(height_ratios=[1, 2, 2]))
ax_r.plot(res.t[one], r[one], color="k")
ax_r.set_ylabel("distance $r$")
ax_r.set_yticks([1, 3, 5])
quantities = (("path curvature $\\kappa$", curvature, "C1", "-"),
              ("acceleration $|\\mathbf{x}''| = \\mu / r^2$", x2, "C4", "--"),
              ("$|\\mathbf{x}''''|$, which sets the local error", x4, "C2", "-."))
for label, values, color, style in quantities:
    axes[0].semilogy(res.t[one], values[one] / values[apoapsis], color=color, linestyle=style,
                     linewidth=1.6, label=label)
axes[0].set_ylabel("value / its value\nat apoapsis")
axes[1].semilogy(middle[first], rate[first], color="C0", label="spline's energy-error rate")
axes[1].set_ylabel("energy-error rate\n$|\\Delta H_{\\rm err}| / \\Delta t$")
axes[1].set_xlabel("time $t$ (one orbit of the ellipse, $\\mu = 0.6$)")
for ax in (ax_r, *axes):
    for arc, shade in ((r < 1.5, "C3"), (r > 4.5, "0.5")):
        edges = np.flatnonzero(np.diff(np.r_[0, (arc & one).astype(int), 0]))
        for start, stop in zip(edges[::2], edges[1::2]):
            ax.axvspan(res.t[start], res.t[stop - 1], color=shade, alpha=0.15, linewidth=0)
for arc, text in ((r < 1.5, "$r < 1.5$"), (r > 4.5, "$r > 4.5$")):
    band = np.flatnonzero(arc & one)
    band = band[: np.argmax(np.diff(np.r_[band, band[-1] + 2]) > 1) + 1]   # the first band
    axes[1].text(res.t[band].mean(), 0.04, text, ha="center", va="bottom",
                 transform=axes[1].get_xaxis_transform(), fontsize=outputs.MIN_FONT)
ax_r.set_title(f"periapsis ($r = {r_peri:.0f}$) at both ends, apoapsis ($r = {r_apo:.0f}$) "
                  f"in the middle", fontsize=outputs.MIN_FONT + 0.5)
fig.legend(loc="outside upper center", ncol=2, handlelength=2.4, frameon=False,
           title="Spline on the ellipse: where the energy error changes", title_fontsize=12)
outputs.save_figure(fig, "cannonball-error-location")

# %%
outputs.say(
    f"**The path's curvature.**  Its largest value near periapsis ($r < 1.5$) and near "
    f"apoapsis ($r > 4.5$) is the same (ratio {value['curvature_ratio_arcs']:.2f}; the "
    f"curvature is smallest, {value['min_curvature']:.3f}, at "
    f"$r = {value['r_min_curvature']:.2f}$), but the largest rate at which the energy error "
    f"changes near periapsis is {outputs.sci(value['energy_rate_ratio_arcs'])} times the "
    f"largest near apoapsis; over the first orbit the logarithm of that rate correlates with "
    f"$\\log\\kappa$ at {value['log_correlation_rate_curvature']:.2f}.  In this reading the "
    f"report's explanation fails: the spline has no difficulty at apoapsis, where the path "
    f"is as curved as at periapsis.")
outputs.say(
    f"**The solution's curvature, the acceleration.**  $\\mu / r^2$ is "
    f"{value['acceleration_ratio_apsides']:.0f} times larger at periapsis "
    f"($r = {r_peri:.0f}$) than at apoapsis ($r = {r_apo:.0f}$; the largest values on the "
    f"two arcs are in ratio {value['acceleration_ratio_arcs']:.2f}), and the logarithm of the "
    f"energy error's rate correlates with its logarithm at "
    f"{value['log_correlation_rate_acceleration']:.2f}.  In this reading the report is "
    f"right: the error is made where the acceleration is high.  But its rate grows far "
    f"more steeply than the acceleration: between the arcs the rate varies "
    f"{outputs.sci(value['energy_rate_ratio_arcs'])} times, the acceleration "
    f"{value['acceleration_ratio_arcs']:.0f} times and the fourth derivative that sets the "
    f"local error, $|\\mathbf x''''|$, {outputs.sci(value['x4_ratio_arcs'])} times "
    f"(log-correlation {value['log_correlation_rate_x4']:.2f}).  "
    f"{value['energy_variation_share_r_lt_1_5']:.0%} of the energy error's variation "
    f"happens at $r < 1.5$, in {value['time_share_r_lt_1_5']:.0%} of the time (both over "
    f"$t \\in [0, 50]$, which holds two periapsis passages).")

outputs.say(
    f"The energy error is not accumulated noise either: it jumps as the body passes "
    f"periapsis, stays on a plateau ({outputs.sci(value['energy_error_apoapsis'])} at "
    f"apoapsis) for the rest of the orbit, and falls back to "
    f"{outputs.sci(value['energy_error_next_periapsis'])} at the next periapsis, "
    f"$t = {period:.2f}$.  The position error is largest, "
    f"{outputs.sci(value['max_position_error'])}, at $t = "
    f"{value['t_max_position_error']:.2f}$ ($r = "
    f"{value['r_max_position_error']:.2f}$), near that periapsis.")

# %% [markdown]
# This is the signature of a method that conserves a nearby *modified*
# energy (Newmark's method with $\gamma = 1/2$ is symplectic for a modified
# symplectic form, Kane, Marsden, Ortiz & West 2000): the difference
# $H - \tilde H = O(h^2)$ depends on where the body is on the orbit, not on
# how long it has flown.  So the report is right that the error follows the
# trajectory.  Whether it is right about why depends on what "curvature"
# means: the error changes where the solution curves most in time (the
# acceleration, and still more its derivatives, large near periapsis), not
# where the path is most curved (the path's curvature is equal at both
# apsides, and the error does not change at apoapsis).
