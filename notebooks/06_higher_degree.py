# %% [markdown]
# # Higher-degree splines: the report's suggestion, and where it fails
#
# The report suggests "higher-order polynomial splines" with more
# continuity.  This notebook builds them as the report writes them and
# derives their stability with sympy (`splinestep.analysis.theory`): the
# extra roots of their recurrences decide which degrees converge.  What it
# finds:
#
# * **Degrees 5 and 6 diverge for every step**: their recurrences have
#   roots outside the unit circle, $2 + \sqrt 3$ and $5 + 2\sqrt 6$ in
#   modulus, and any perturbation, rounding included, grows like them.
# * **Degree 4 converges with order 4, but only weakly**: its extra root
#   $-1$ sits on the unit circle and leaves it as soon as the equation is
#   damped, and it needs the exact $y'''(0)$ to start.
# * **The usable fourth-order method is built another way**, by symmetric
#   composition of the cubic step (notebook 10).

# %%
import sys

import numpy as np
import pandas as pd
import sympy as sp
from IPython.display import HTML, Math, display

sys.path.insert(0, "../scripts")  # outputs.py: the repository's data/, figures/ and plot style
import outputs
import splinestep
from splinestep import problems
from splinestep.analysis import theory
from splinestep.analysis.higher_degree import solve_degree

plt = outputs.setup()
ellipse = problems.cannonball(0.6)   # the report's ellipse, at its step h = 0.01
mu, h = 0.6, ellipse.h               # mu: the gravity parameter
period_T = problems.orbit_elements(mu)["period"]

# %% [markdown]
# ## Degree $k$, $k - 1$ continuous derivatives
# The report's suggestion as it is written: a spline of degree $k$ with
# $k - 1$ continuous derivatives, collocating the ODE at every knot, one
# knot per step (`splinestep.analysis.higher_degree.solve_degree`; $k = 3$ is the
# report's method).  The state at a knot is now $p, p', \dots, p^{(k-1)}$,
# and for $k \ge 4$ the derivatives beyond $p''$ are extra state.  On
# $y'' = \lambda y - c\, y'$ (damping $c$) one step is a linear map; sympy
# gives its characteristic polynomial as $h \to 0$ (zero-stability), and
# the same for the first-order analogue ($y' = f$, degree $k - 1$,
# collocating $p'$), which Loscalzo and Talbot (1967) studied.

# %%
rows, lines = [], []
for k in (3, 4, 5, 6):
    poly = theory.characteristic_at_zero(k)
    first = theory.characteristic_at_zero(k - 1, first_order=True)
    roots = [complex(r) for r in sp.Poly(poly, theory.zeta).nroots()]
    spurious = [abs(r) for r in roots if abs(r - 1) > 1e-9 and abs(r) > 1e-12]
    rows.append(dict(degree=k, polynomial=str(poly), first_order_polynomial=str(first),
                     largest_spurious_root=max(spurious, default=0.0)))
    lines.append(f"{k} & {theory.latex(poly)} & {k - 1} & {theory.latex(first)}")
roots_table = pd.DataFrame(rows)
display(Math(r"\begin{array}{rl|rl} k & y'' = F & k - 1 & y' = f \\ \hline "
             + r" \\ ".join(lines) + r"\end{array}"))

# %% [markdown]
# Beyond the double root 1 of $\rho$ and the root 0 (the slaved $p''$),
# degree 4 adds the root $-1$, degree 5 the roots of $\zeta^2 + 4\zeta + 1$,
# $-2 \pm \sqrt 3$, and degree 6 the root $-1$ again and those of
# $\zeta^2 + 10\zeta + 1$, $-5 \pm 2\sqrt 6$.  A root outside the unit circle makes the method
# divergent: any perturbation, a rounding error included, grows like that
# root to the power of the step count, however small $h$ is.  The
# first-order polynomials have the same spurious factors one degree lower:
# degree 2 (the trapezoidal rule) and 3 are usable, degree 4 and above
# diverge, as Loscalzo and Talbot (1967) found for first-order equations
# $y' = f$.
#
# Degree 4 for second-order equations has a simple root $-1$ on the
# circle: zero-stable, but only weakly, so we look at what perturbs it.
# Sympy follows that root for small $h$ on the damped $y'' = \lambda y - c\, y'$:

# %%
c, e1 = sp.Symbol("c"), sp.Symbol("e1")
poly4 = sp.numer(sp.together(theory.spline_step_matrix(4).charpoly(theory.zeta).as_expr()))
# The root near -1 as zeta = -(1 - e1 h): the lowest power of h fixes e1.
near = sp.Poly(sp.expand(poly4.subs(theory.zeta, -(1 - e1 * theory.h))), theory.h)
lowest = min(monomial[0] for monomial in near.monoms())
e1_value = sp.solve(near.coeff_monomial(theory.h ** lowest), e1)[0]
display(Math(r"\zeta_{\rm parasitic} = -\left(1 + " + theory.latex(-e1_value * theory.h)
             + r"\right) + O(h^2), \qquad |\zeta_{\rm parasitic}|^{t/h} \to "
             + theory.latex(sp.exp(-e1_value * sp.Symbol("t")))))
damping = 0.5   # the c of the damped oscillator below
parasitic_rate = float(-e1_value.subs(c, damping))

# %% [markdown]
# Undamped ($c = 0$), the root stays on the circle to this order; damped
# ($c > 0$), it leaves it, and the parasitic mode grows like $e^{ct/3}$
# while the solution decays.
#
# Now the measurements.  First degrees 3 to 6 on $y'' = -y$ at $h = 0.05$,
# from the exact starting values (the extra derivatives included): the
# errors of degrees 5 and 6 should grow per step by their largest spurious
# root.

# %%
def harmonic_error(k, h, t_end):
    start = [[0.0], [1.0], [0.0]][:k - 3]   # y''' = 0, y'''' = 1, y''''' = 0 at t = 0
    res = solve_degree(lambda t, y, yp: -y, (0.0, t_end), 1.0, 0.0, h, k,
                       derivatives=start or None)
    return res.t, np.abs(res.y[0] - np.cos(res.t))


# degrees 5 and 6 leave double precision within 1.5 time units
degree_runs = {k: harmonic_error(k, 0.05, 1.5 if k > 4 else 30.0) for k in (3, 4, 5, 6)}
growth = []
for k in (5, 6):
    e = degree_runs[k][1]
    use = (e > 1e-13) & (e < 1e100)
    growth.append(np.exp(np.polyfit(np.arange(e.size)[use], np.log(e[use]), 1)[0]))
    print(f"degree {k}: error grows by {growth[-1]:.4f} per step (largest spurious root "
          f"{roots_table.set_index('degree').largest_spurious_root[k]:.4f})")
roots_table["measured_growth_per_step"] = [np.nan, np.nan] + growth

# %% [markdown]
# They do: 3.737 and 9.906 per step against
# $2 + \sqrt 3 = 3.732$ and $5 + 2\sqrt 6 = 9.899$.  Degree 4 does not
# diverge; on one orbit of the ellipse (from its exact $y'''(0)$) its
# order, and its error when started with $y'''(0) = 0$ instead:

# %%
a0, a1, a2 = problems.acceleration_derivatives(ellipse.y0[:, None], ellipse.yp0[:, None], mu)
orbit_errors = []
for step in (0.04, 0.02, 0.01):
    res = solve_degree(ellipse.fun, (0.0, period_T), ellipse.y0, ellipse.yp0, step, 4,
                       derivatives=a1.T, args=ellipse.args)
    orbit_errors.append(np.max(np.abs(res.y - ellipse.reference(res.t)[0])))
quartic_slope = np.polyfit(np.log([0.04, 0.02, 0.01]), np.log(orbit_errors), 1)[0]
for step, error in zip((0.04, 0.02, 0.01), orbit_errors):
    print(f"degree 4, one orbit of the ellipse, dt = {step}: max position error {error:.2e}")
print(f"fitted order {quartic_slope:.2f}")
roots_table["fitted_order_ellipse"] = [np.nan, quartic_slope, np.nan, np.nan]
outputs.save_data(roots_table, "higher-degree-roots")

# %%
wrong_start = solve_degree(ellipse.fun, (0.0, period_T), ellipse.y0, ellipse.yp0, 0.01, 4,
                           derivatives=np.zeros((1, 2)), args=ellipse.args)
wrong_start_error = np.max(np.abs(wrong_start.y - ellipse.reference(wrong_start.t)[0]))
print(f"degree 4 started with y'''(0) = 0 instead of its value: error {wrong_start_error:.2e}")
cubic = splinestep.solve(ellipse.fun, (0.0, period_T), ellipse.y0, ellipse.yp0, 0.01,
                         args=ellipse.args)
cubic_orbit_error = np.max(np.abs(cubic.y - ellipse.reference(cubic.t)[0]))
print(f"the cubic on one orbit at dt = 0.01: max position error {cubic_orbit_error:.1e}")
# The same wrong start with y'(0) raised by h^2 y'''(0) / 12, the offset the first steps
# give the velocity when y'''(0) is taken as 0:
offset_start = solve_degree(ellipse.fun, (0.0, period_T), ellipse.y0,
                            ellipse.yp0 + 0.01 ** 2 * a1.ravel() / 12, 0.01, 4,
                            derivatives=np.zeros((1, 2)), args=ellipse.args)
offset_error = np.max(np.abs(offset_start.y - ellipse.reference(offset_start.t)[0]))
print(f"the same, y'(0) raised by h^2 y'''(0) / 12: error {offset_error:.1e}")

# %% [markdown]
# Degree 4 converges with fitted order 4.00 (one orbit, steps 0.04 to
# 0.01; $5.5 \times 10^{-10}$ at the report's step, where the cubic's is
# $4.1 \times 10^{-3}$), but started with $y'''(0) = 0$ its error is
# $3.2 \times 10^{-3}$, about the cubic's.  The wrong start does two
# things.  It excites the parasitic mode, which never decays but costs
# almost nothing in position here; and it shifts the velocity of the
# principal solution by $-h^2 y'''(0)/12$ (to leading order, from the
# analysis of the two modes), from which the orbit drifts smoothly, an
# error of order 2.  Started with $y'(0)$ raised by $h^2 y'''(0)/12$ (and the same
# wrong $y'''(0)$), the error falls to $9.6 \times 10^{-9}$: the shift, not
# the parasitic mode, is the error.  Last, degree 4 on the damped
# oscillator $y'' = -y - c\, y'$ with $c = 0.5$, from its exact
# $y'''(0) = c$ (at $t = 0$, $y''' = -y' - c\, y'' = c$):

# %%
damped = solve_degree(lambda t, y, yp: -y - damping * yp, (0.0, 120.0), 1.0, 0.0, 0.05, 4,
                      derivatives=[[damping]])  # y''' = -y' - c y'' = c at t = 0
w_d = np.sqrt(1 - damping ** 2 / 4)
exact_damped = np.exp(-damping * damped.t / 2) * (np.cos(w_d * damped.t)
                                                  + damping / (2 * w_d) * np.sin(w_d * damped.t))
damped_error = np.abs(damped.y[0] - exact_damped)
late = damped.t > 60  # once the parasitic mode dominates the error
damped_rate = np.polyfit(damped.t[late], np.log(damped_error[late]), 1)[0]
print(f"degree 4 on y'' = -y - c y', c = 0.5: error grows like exp({damped_rate:.4f} t)")
print(f"  parasitic root: exp({parasitic_rate:.4f} t)")

# %% [markdown]
# Started right, the error is small at first, and then grows like
# $e^{0.1667 t}$, the parasitic root's $e^{ct/3}$: the root that sits on the
# unit circle without damping leaves it with damping.  The figure shows the four degrees on
# the undamped oscillator and degree 4 on the damped one:

# %% jupyter={"source_hidden": true}
fig, (ax, bx) = plt.subplots(2, 1, figsize=(outputs.WIDTH, 5.6))
for k, style in ((3, "C0-"), (4, "C1-"), (5, "C3-"), (6, "C4-")):
    e = degree_runs[k][1]
    keep = (e > 0) & (e < 1e6)
    # steps on a log axis: degrees 5 and 6 leave the plot within 30 steps, 3 and 4 run 600
    ax.loglog(np.arange(e.size)[keep], e[keep], style, marker="o", markersize=2.5,
              label=f"degree {k}")
n = np.arange(1, 30)
ax.semilogy(n, 1e-16 * (2 + np.sqrt(3)) ** n, "k:", linewidth=1,
            label="spurious roots: $3.73^n$, $9.90^n$")
ax.semilogy(n, 1e-16 * (5 + 2 * np.sqrt(6)) ** n, "k:", linewidth=1)
ax.set_xlim(1, 600)
ax.set_ylim(1e-17, 1e6)
ax.set_xlabel("step number $n$ ($h = 0.05$)")
ax.set_ylabel("$|y_n - \\cos t_n|$")
ax.set_title("Degree-$k$ splines ($k - 1$ continuous derivatives) on $y'' = -y$", loc="left")
ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.3), ncol=5, fontsize=outputs.MIN_FONT,
          columnspacing=1.0, frameon=False)   # below the axis, off the curves
bx.semilogy(damped.t, damped_error, "C1-", label="degree 4, error")
bx.semilogy(damped.t, np.abs(exact_damped), "k-", linewidth=1, label="the solution $|y|$")
start = damped.t[late][0]
bx.semilogy(damped.t, damped_error[late][0] * np.exp(parasitic_rate * (damped.t - start)),
            "k:", label=f"parasitic root, $e^{{ct/3}} = e^{{{parasitic_rate:.3f} t}}$")
bx.set_xlabel("$t$")
bx.set_ylabel("error $|y_n - y(t_n)|$, and $|y|$")
bx.set_title("Degree 4 on the damped $y'' = -y - c\\,y'$, $c = 0.5$ ($h = 0.05$)")
bx.legend(loc="upper center", bbox_to_anchor=(0.5, -0.3), ncol=3, fontsize=outputs.MIN_FONT,
          frameon=False)   # below the axis, off the curves
outputs.save_figure(fig, "higher-degree-splines")

# %% [markdown]
# Degree 4 is the surprise: its extra root $-1$ sits on the unit circle, the
# method is zero-stable, and it converges with order 4.  But only weakly:
# the root's perturbation $-(1 + c h/3)$ leaves the circle as soon as the
# equation is damped ($c > 0$), and the parasitic mode then grows like
# $e^{c t/3}$ while the solution decays; and a wrong $y'''(0)$ shifts the
# velocity and so costs order 2.  Usable, in the strict sense of the theory,
# are degree 3 (the report's method) and degree 4 for undamped problems with
# exact starting derivatives; degrees 5 and 6 diverge for every $h$.  The
# fourth-order method that keeps the cubic's good behaviour is built in
# another way, by symmetric composition of the cubic step (notebook 10).
#
# ## The derived constants against the measurements
# Written to `data/higher-degree-constants.csv`:

# %%
constants = pd.DataFrame([
    ("degree 5: spurious root modulus 2 + sqrt(3)", 2 + sp.sqrt(3), growth[0], 4),
    ("degree 6: spurious root modulus 5 + 2 sqrt(6)", 5 + 2 * sp.sqrt(6), growth[1], 4),
    ("degree 4, damping 0.5: parasitic growth rate per unit time",
     -e1_value.subs(c, sp.nsimplify(damping)), damped_rate, 4),
], columns=["quantity", "exact", "measured", "digits"])
outputs.save_data(constants.assign(derived=constants.exact.astype(float))
                  [["quantity", "derived", "measured"]], "higher-degree-constants")
display(HTML(outputs.html_table(theory.constants_table(constants), text=outputs.readable)))
