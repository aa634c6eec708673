# %% [markdown]
# # Euler's rigid body: Figures 1b and 2b
#
# The report's second test (Sec. 3.2) differentiates Euler's torque-free
# equations $I_1\dot\omega_1 = (I_2 - I_3)\,\omega_2\omega_3$ (and cyclic) once:
#
# $$\ddot\omega_i + \beta\dot\omega_i = \alpha_i(\boldsymbol\omega)\,\omega_i ,$$
#
# with $\alpha_i$ from eqs. 16-18 (checked: they are what the derivative
# gives), $I = (3, 2, 1)$, $\boldsymbol\omega(0) = (1, 0.01, 0.01)$,
# $t \in [0, 80]$, $\Delta t = 0.016$.  Two things the report leaves open:
#
# * $\beta$ is never defined; the torque-free body needs $\beta = 0$.
# * it prints $\dot{\boldsymbol\omega}(0) = 0$, but Euler's equations give
#   $\dot{\boldsymbol\omega}(0) = (10^{-4}/3,\,-0.01,\,0.01)$.  With the printed
#   rates the second-order system describes a motion that is *not* a rigid
#   body, and the energy of eq. 19 is not conserved by the equations.
#
# We run both.  The consistent case has an exact solution in Jacobi
# elliptic functions ($\omega_1 \propto \mathrm{dn}$, $\omega_2 \propto \mathrm{sn}$,
# $\omega_3 \propto \mathrm{cn}$); the printed case is compared with a DOP853
# solve at rtol $10^{-13}$, atol $10^{-14}$.  (The report does not say
# which panels of its Figs. 1 and 2 are the rigid body's; in the order of
# its Sec. 3, presumably 1b and 2b.)  What we find:
#
# * **With the printed rates the energy error is the equations'**: $E$
#   varies by $1.5 \times 10^{-4}$ along the accurate reference itself.
# * **With consistent rates both methods stay far below the report's
#   $10^{-3}$** over $t \in [0, 80]$: the spline's energy error reaches
#   $5.1 \times 10^{-7}$, RK4's $1.1 \times 10^{-11}$.
# * **The spline's energy error drifts** ($4.9 \times 10^{-6}$ at $t = 800$,
#   linearly): the report's second-order form is not conservative, so the
#   bounded energy error of the cannonball does not carry over.

# %%
import dataclasses
import sys

import numpy as np
import pandas as pd
import sympy as sp

sys.path.insert(0, "../scripts")  # outputs.py: the repository's data/, figures/ and plot style
import outputs
from splinestep import problems
from splinestep.problems import euler_top
from splinestep.analysis import diagnostics

plt = outputs.setup()

# %%
CASES = ("printed", "consistent")
runs = {}
references = {}  # (omega, omega') of the reference at the knots, computed once per case
for case in CASES:
    problem = problems.rigid_body(case)
    runs[case] = {m: problem.solve(m) for m in ("spline", "rk4")}
    for res in runs[case].values():
        assert res.success, res.message
    references[case] = problem.reference(runs[case]["spline"].t)
    print(f"{case:>10} initial rates {np.array2string(problem.yp0, precision=6)}: "
          f"reference = {problem.reference_kind}")

# %% [markdown]
# ## Figure 1b: the angular velocity

# %% jupyter={"source_hidden": true}
from matplotlib.lines import Line2D  # noqa: E402

fig, axes = plt.subplots(2, 2, figsize=(outputs.WIDTH, 5.0), sharex="col")
rows = []
coincide = {}
for (ax_major, ax_minor), case in zip(axes.T, CASES):
    problem = problems.rigid_body(case)
    res, rk4 = runs[case]["spline"], runs[case]["rk4"]
    ref, _ = references[case]
    # omega_1 as its deviation from 1, in 1e-6 rad / time unit; omega_3 wide and under omega_2,
    # thin, so that both show where the two coincide
    panels = ((0, ax_major, 1e6, 1.0), (2, ax_minor, 1.0, 0.0), (1, ax_minor, 1.0, 0.0))
    for i, ax, scale, shift in panels:  # the reference first, under both methods
        ax.plot(res.t, (ref[i] - shift) * scale, color="0.7", linewidth=4.5, solid_capstyle="butt")
    for i, ax, scale, shift in panels:
        wide = i == 2 and case == "printed"   # omega_3 under omega_2 where they coincide
        ax.plot(res.t, (res.y[i] - shift) * scale, color=f"C{i}", linewidth=2.6 if wide else 1.1)
        marks = diagnostics.extrema(rk4.y[i])
        ax.plot(rk4.t[marks], (rk4.y[i, marks] - shift) * scale, "x", color=f"C{i}",
                markersize=7 if wide else 4.5, markeredgewidth=1.3)
    coincide[case] = np.max(np.abs(ref[1] - ref[2]))
    ax_major.set_title("$\\dot\\omega(0) = 0$ (as printed)" if case == "printed"
                       else "$\\dot\\omega(0)$ from Euler's equations, $t \\geq 64$")
    if case != "printed":   # about 25 periods of omega_1 in 80 time units: t >= 64
        ax_minor.set_xlim(64, 80.5)
    ax_minor.set_xlabel("time $t$")
    stride = slice(None, None, 5)
    rows.append(pd.DataFrame({"case": case, "t": res.t[stride],
                              **{f"omega{i + 1}_spline": res.y[i, stride] for i in range(3)},
                              **{f"omega{i + 1}_rk4": rk4.y[i, stride] for i in range(3)},
                              **{f"omega{i + 1}_reference": ref[i, stride] for i in range(3)}}))
axes[1, 0].set_title(f"$\\omega_2$ lies on $\\omega_3$ (they differ by at most "
                     f"{outputs.sci(coincide['printed'])})", fontsize=outputs.MIN_FONT)
axes[1, 1].set_title("$\\omega_2$ and $\\omega_3$, $t \\geq 64$", fontsize=outputs.MIN_FONT)
axes[0, 0].set_ylabel("$\\omega_1 - 1$\n($10^{-6}$ rad / time unit)")
axes[1, 0].set_ylabel("$\\omega_2$, $\\omega_3$\n(rad / time unit)")
key = [Line2D([], [], color="k", linewidth=1.2, label="cubic spline"),
       Line2D([], [], color="k", marker="x", linestyle="none", markersize=5,
              label="RK4, at its maxima and minima"),
       Line2D([], [], color="0.7", linewidth=4.5, label="reference"),
       *[Line2D([], [], color=f"C{i}", linewidth=2.6 if i == 2 else 1.6,
                label=f"$\\omega_{i + 1}$") for i in range(3)]]
fig.legend(handles=key, loc="outside upper center", ncol=3, frameon=False,
           title="Rigid body, $I = (3, 2, 1)$, $\\omega(0) = (1, 0.01, 0.01)$, "
                 "$\\Delta t = 0.016$", title_fontsize=11)
outputs.save_data(pd.concat(rows), "rigid-body-angular-velocity")
outputs.save_figure(fig, "rigid-body-angular-velocity")

# %%
amplitude = {case: np.max(np.abs(references[case][0][1:]), axis=1) for case in CASES}
swing = {case: np.ptp(references[case][0][0]) for case in CASES}
print(outputs.wrapped(
    f"omega_1 varies by at most {max(swing.values()):.1e}; amplitudes of omega_2, omega_3: "
    + ", ".join(f"{case} {amplitude[case][0]:.4f} and {amplitude[case][1]:.4f}"
                for case in CASES)
    + f"; printed case: |omega_2 - omega_3| <= {coincide['printed']:.0e}, 1 - omega_1 "
    f"at t = {runs['printed']['spline'].t[-1]:.0f}: {1 - references['printed'][0][0, -1]:.1e}"))

# %% [markdown]
# The body spins about its axis of largest moment, a stable motion:
# $\omega_1$ varies by at most $3.3 \times 10^{-5}$ while
# $\omega_2, \omega_3$ oscillate with amplitudes 0.0100 and 0.0100
# (printed rates) or 0.0141 and 0.0141 (consistent rates): with the printed
# rates it is a different motion, in which $\omega_2$ and $\omega_3$ stay
# within $2 \times 10^{-5}$ of each other, so that one curve covers the
# other, and $\omega_1$ does not oscillate about 1 but falls slowly, to
# $1 - 2.2 \times 10^{-7}$ at $t = 80$ (top left), in the reference as in
# both methods: that motion's own, not an error.  The reference (the exact
# motion with consistent rates, DOP853 with the printed ones) is the grey
# band; both methods follow it at plotting scale, RK4 shown at its own
# maxima and minima.

# %% [markdown]
# ## Figure 2b: the energy error history
#
# $E = \tfrac12\sum_i I_i\omega_i^2$ (eq. 19).  For the printed case we also
# plot the variation of $E$ along the *reference* solution: whatever the
# method, that much "energy error" belongs to the equations.  Along the
# exact motion of the consistent case $E$ changes by rounding only: the data
# keep that curve, the figure leaves it out.

# %%
rows = []
for case in CASES:
    energy = problems.rigid_body(case).invariants["energy"]
    ref, ref_p = references[case]
    data = {"case": case, "t": runs[case]["spline"].t}
    for method, res in runs[case].items():
        e = energy(res.y, res.yp)
        data[f"energy_change_{method}"] = np.abs(e - e[0])
        data[f"solution_error_{method}"] = np.max(np.abs(res.y - ref), axis=0)
    e_ref = energy(ref, ref_p)
    data["energy_change_reference"] = np.abs(e_ref - e_ref[0])
    rows.append(pd.DataFrame(data))
errors = pd.concat(rows, ignore_index=True)
outputs.save_data(errors.iloc[::5], "rigid-body-energy-error")

# %% [markdown]
# The largest of each over the run, and what a step costs the spline:

# %%
summary = errors.groupby("case").max().drop(columns="t").reset_index()
summary["spline_evaluations_per_step"] = [runs[c]["spline"].nfev / runs[c]["spline"].nstep
                                          for c in summary.case]
outputs.save_data(summary, "rigid-body-max-errors")
for row in summary.itertuples():
    print(outputs.wrapped(
        f"{row.case:>10}: max |E - E0| spline {row.energy_change_spline:.2e}, "
        f"RK4 {row.energy_change_rk4:.2e}, reference {row.energy_change_reference:.2e}; "
        f"max |omega - reference| spline {row.solution_error_spline:.2e}, "
        f"RK4 {row.solution_error_rk4:.2e}; spline evaluations per step "
        f"{row.spline_evaluations_per_step:.2f}"))

# %% jupyter={"source_hidden": true}
fig, axes = plt.subplots(1, 2, figsize=(outputs.WIDTH, 4.2), sharey=True)
for ax, case in zip(axes, CASES):
    sel = errors[errors.case == case]
    # The exact motion's energy changes by rounding only (below 1e-12): not drawn.
    for key in ("spline", "rk4", "reference") if case == "printed" else ("spline", "rk4"):
        style = {**outputs.METHOD_STYLE[key], "linewidth": 1.2}
        if key == "reference":
            style["label"] = "reference (DOP853, rtol $10^{-13}$)"
        ax.semilogy(sel.t.to_numpy()[1:], sel[f"energy_change_{key}"].to_numpy()[1:], **style)
    ax.set_title("$\\dot\\omega(0) = 0$ (as printed)" if case == "printed"
                 else "$\\dot\\omega(0)$ from Euler's equations")
    ax.set_xlabel("time $t$")
    ax.axhline(1e-3, color="k", linewidth=1.2, linestyle="-.")
    ax.set_ylim(1e-15, 1e-2)
    ax.legend(loc="lower right")
axes[0].set_ylabel("energy change $|E(t) - E(0)|$ (eq. 19)")
axes[0].text(1, 1.5e-3, "report's bound $10^{-3}$", va="bottom", fontsize=10)
fig.suptitle("Rigid-body energy error, $\\Delta t = 0.016$")
outputs.save_figure(fig, "rigid-body-energy-error")

# %% [markdown]
# With the printed rates, the energy varies by $1.5 \times 10^{-4}$ along
# the accurate DOP853 reference: the visible "energy error" of both methods
# in that case comes from the equations, not from the method.  Measured
# against the reference, the spline's solution error there is
# $8.5 \times 10^{-6}$.  With consistent rates the energy is an invariant
# of the equations; over $t \in [0, 80]$ the spline's energy error reaches
# $5.1 \times 10^{-7}$, RK4's $1.1 \times 10^{-11}$, RK4 spending four
# evaluations per step against the spline's 3.00.

# %% [markdown]
# ## Does the energy error stay bounded?
# On the cannonball the spline's energy error is bounded (`02_cannonball`):
# the Kepler problem is $y'' = -\nabla V(y)$, where the method conserves a
# modified energy.  The rigid body in the report's second-order form,
# $\ddot\omega_i = \alpha_i(\omega)\,\omega_i$, is not of that form: its
# force is not a gradient ($\partial F_1/\partial\omega_2 = \tfrac23\omega_1\omega_2$
# while $\partial F_2/\partial\omega_1 = -2\,\omega_1\omega_2$), so nothing
# makes the error stay bounded.  We run the consistent case ten times
# longer, to $t = 800$, against the exact solution, and compare the largest
# energy error in the last eighth of the run with that in the first
# (`diagnostics.growth_ratio`: about 1 for a bounded error, about 8 for one
# that grows linearly from zero).

# %%
consistent = problems.rigid_body("consistent")
long_problem = dataclasses.replace(consistent, t_span=(0.0, 800.0))
long_runs = {m: long_problem.solve(m) for m in ("spline", "rk4")}
energy = consistent.invariants["energy"]

# %% [markdown]
# For each method: the energy error at $t = 80$ and at $t = 800$, its
# largest value in each eighth of the run, and the growth ratio.

# %%
drift = []
for method, res in long_runs.items():
    assert res.success, res.message
    e = np.abs(energy(res.y, res.yp) - energy(res.y[:, :1], res.yp[:, :1]))
    maxima = diagnostics.window_maxima(res.t, e)
    slope = np.polyfit(res.t, e, 1)[0]
    drift.append(dict(method=method, energy_error_t80=e[np.searchsorted(res.t, 80.0)],
                      energy_error_t800=e[-1], max_energy_error=e.max(),
                      growth_ratio=diagnostics.growth_ratio(res.t, e), drift_rate=slope))
    print(outputs.wrapped(
        f"{method:>6}: |E - E0| at t = 80: {drift[-1]['energy_error_t80']:.2e}, "
        f"at t = 800: {e[-1]:.2e}; largest in each eighth of the run: "
        + ", ".join(f"{m:.1e}" for m in maxima)
        + f"; growth ratio {drift[-1]['growth_ratio']:.1f}"))

# %% [markdown]
# The drift fitted over the whole run:

# %%
drift = pd.DataFrame(drift)
outputs.save_data(drift, "rigid-body-energy-drift")
spline_drift = drift.set_index("method").loc["spline"]
print(f"spline: fitted drift of |E - E0|: {spline_drift.drift_rate:.1e} per time unit")

# %% [markdown]
# The spline's energy error grows linearly: $5.1 \times 10^{-7}$ at
# $t = 80$, $4.9 \times 10^{-6}$ at $t = 800$, with a growth ratio of 7.7
# over eight equal parts of the run (a fitted drift of $6.2 \times 10^{-9}$
# per time unit).  RK4's energy error rises over the first half of the
# run and then levels off ($2.6 \times 10^{-11}$ at $t = 800$, growth ratio
# 2.9, between bounded and linear), five decades below the spline's.  So a
# single number such as the spline's error at $t = 80$
# describes the length of the run as much as the method.  The bounded
# energy error seen on the cannonball is a property of the method on
# conservative problems $y'' = -\nabla V(y)$, not on every second-order
# system.

# %% [markdown]
# ### Why the energy error drifts
# In the report's second-order form, $\omega'' = f(\omega)$ with
# $f_i = \alpha_i(\omega)\,\omega_i$.  Two things differ from the cannonball.
# First, $f$ is not a gradient (above; sympy confirms it below), so
# there is no potential, no Hamiltonian in $\omega$, and the conjugacy gives
# no modified energy.  Second, the energy $E = \tfrac12\sum I_i\omega_i^2$ is
# not an invariant of $\omega'' = f(\omega)$: it is conserved only on the
# solutions with $\omega' = G(\omega)$ (Euler's equations).  Along any
# solution, $dE/dt = \sum_i I_i\omega_i\omega'_i = \sum_i I_i \omega_i \delta_i$
# with $\delta = \omega' - G(\omega)$, because $\sum_i I_i\omega_i G_i = 0$.
# The numerical solution leaves $\delta = 0$ by the method's error, and
# nothing brings it back.

# %%
w = sp.symbols("w1:4")
moments = euler_top.MOMENTS
G = euler_top.euler_rates(sp.Matrix(w), moments)
print("sum I_i w_i G_i(w) =", sp.simplify(sum(moments[i] * w[i] * G[i] for i in range(3))))
f_sym = sp.Matrix(euler_top.rigid_body_rhs.py_func(0, w, (0, 0, 0), *moments, 0.0))
J = f_sym.jacobian(w)
print("df1/dw2 - df2/dw1 =", sp.factor(J[0, 1] - J[1, 0]))

# %% [markdown]
# Then the bookkeeping along the long run: the change of the energy
# against the integral of $\sum_i I_i\omega_i\delta_i$, the growth of
# $\delta$, and the mean of its component along $I\omega$.

# %%
long_body = long_runs["spline"]   # the consistent case over t in [0, 800], above
delta = long_body.yp - euler_top.euler_rates(long_body.y, moments)
inertia = np.asarray(moments)[:, None]
E = euler_top.energy(moments)(long_body.y, long_body.yp)
rate = np.sum(inertia * long_body.y * delta, axis=0)
predicted = np.concatenate([[0.0], np.cumsum(0.5 * (rate[1:] + rate[:-1]) * np.diff(long_body.t))])
mismatch = np.max(np.abs((E - E[0]) - predicted)) / np.max(np.abs(E - E[0]))
delta_growth = diagnostics.growth_ratio(long_body.t, np.max(np.abs(delta), axis=0))
mean_rate = np.mean(rate)
fitted_drift = np.polyfit(long_body.t, E - E[0], 1)[0]
print(f"|delta| growth ratio over eight parts of t in [0, 800]: {delta_growth:.1f}")
print(f"mean of sum I w delta: {mean_rate:.2e}; fitted drift of E: {fitted_drift:.2e} per unit time")
print(outputs.wrapped(
    f"E - E0 against the trapezoidal integral of sum I w delta: mismatch "
    f"~1e{np.log10(mismatch):.0f} of max |E - E0| (quadrature error)"))
# %% [markdown]
# Over $t \in [0, 800]$ the energy error equals the integral of
# $\sum_i I_i\omega_i\delta_i$ to the trapezoidal rule's accuracy: that is
# the identity above at work (it checks the bookkeeping, not a
# prediction).  What it explains is measured separately: the deviation
# $\delta$ itself stays bounded (growth ratio 1.0 over eight equal parts;
# about 1 is bounded, 8 linear), but its component along $I\omega$ has a
# nonzero mean, $6.2 \times 10^{-9}$ per unit time, and that is the
# energy's fitted drift ($6.2 \times 10^{-9}$).  Nothing in
# $\omega'' = f(\omega)$ pulls the solution back to the manifold
# $\omega' = G(\omega)$ or makes that mean vanish; a method that stepped
# Euler's first-order equations would keep $\delta = 0$.


# %% [markdown]
# The report's statement that the method "performs quite well" on this
# problem holds for the run it made (the solution error against the
# reference, exact with consistent rates and DOP853 with the printed ones,
# is small, and the energy error stays far below its $10^{-3}$), and
# its energy plot, if made with the printed rates, measured the equations
# rather than the method.
