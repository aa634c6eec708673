# %% [markdown]
# # Why it behaves as it does: a convergence proof, and Stormer-Verlet in other variables
#
# The report's discussion (Sec. 5) ends on "a formal proof of its
# convergence may lend some insight into its performance".  This notebook
# derives the method's properties with a computer algebra system
# (`splinestep.analysis.theory`, sympy) and measures every derived constant
# with the package.  What it proves, and measures:
#
# * **Local errors** (section 1): one step from exact values misses by
#   $h^4 y''''/24$ in $y$ and $h^3 y''''/12$ in $y'$.
# * **Convergence of order 2** (section 2): the knots obey a linear two-step
#   method, $\rho(\zeta) = (\zeta - 1)^2$,
#   $\sigma(\zeta) = (\zeta^2 + 4\zeta + 1)/6$, of order 2 with error
#   constant $-1/12$; by Henrici's theorem it converges with order 2.
# * **The oscillator** (section 3): no damping and no growth below
#   $\omega h = \sqrt{12}$, linear growth at it; a period error of
#   $+(\omega h)^2/24$, Verlet's with the opposite sign; the fixed-point
#   sweep converges below $\omega h = \sqrt 6$.
# * **Stormer-Verlet in other variables** (section 4): in
#   $Q = q - h^2 f(q)/6$ the spline stepper *is* Verlet on a modified force,
#   so it is conjugate to a symplectic method: with each step equation
#   solved to convergence its energy error stays bounded, and a modified
#   angular momentum is conserved to rounding.
#
# The last section puts each derived constant beside its measurement.
# Notebook 06 takes up the report's "higher-order polynomial splines",
# notebook 08 what the theory predicts for long runs.

# %%
import sys

import numpy as np
import pandas as pd
import sympy as sp
from IPython.display import HTML, Math, display

sys.path.insert(0, "../scripts")  # outputs.py: the repository's data/, figures/ and plot style
import outputs
import splinestep
from splinestep import check, problems
from splinestep.analysis import conjugacy, theory
from splinestep.problems import kepler

plt = outputs.setup()
x = theory.x   # the symbol omega h of section 3

# %% [markdown]
# ## 1. The local errors of one step
# One step from exact values $y_i, y'_i$ at $t_i$ sets
# $a_{i+1} = y_i + h y'_i + h^2(y''_i/3 + z/6)$,
# $b_{i+1} = y'_i + h(y''_i + z)/2$ and solves $z = F(t_{i+1}, a_{i+1}, b_{i+1})$.
# Writing the exact solution as a Taylor series ($y^{(j)}$ below is
# $y^{(j)}(t_i)$) and $F$'s change through $p = \partial F/\partial y$,
# $q = \partial F/\partial y'$, sympy solves for the errors of the step:

# %%
err_y, err_yp = theory.local_errors()
display(Math(theory.aligned([("a_{i+1} - y(t_{i+1})", err_y),
                             ("b_{i+1} - y'(t_{i+1})", err_yp)], order="rev-lex")))

# %% [markdown]
# The leading terms are $\frac{1}{24}\, h^4 y''''$ in $y$ and
# $\frac{1}{12}\, h^3 y''''$ in $y'$; $F$'s derivatives enter one order
# later.  One step of $y'' = -y$ from the exact values at $t = 0$, where
# $y'''' = 1$, measures both constants:

# %%
h = 0.01
step = splinestep.solve(lambda t, y, yp: -y, (0.0, h), 1.0, 0.0, h, tol=1e-15)
measured_y = (step.y[0, -1] - np.cos(h)) / h ** 4
measured_yp = (step.yp[0, -1] + np.sin(h)) / h ** 3
print(f"measured at h = 0.01: (a_1 - y(h)) / h^4 = {measured_y:.5f}, "
      f"(b_1 - y'(h)) / h^3 = {measured_yp:.5f}")

# %% [markdown]
# Measured: 0.04167 and 0.08333, against $1/24 = 0.04167$ and
# $1/12 = 0.08333$ (the next terms are $O(h)$ smaller).  These are the
# constants of the run's own error estimate (`splinestep.check`).
#
# ## 2. The two-step recurrence, its order, and the convergence theorem
# For $y'' = f(t, y)$, two consecutive steps eliminate $y'$: sympy checks
# that the steps satisfy
# $\sum_j \alpha_j y_{n+j} = h^2 \sum_j \beta_j f_{n+j}$ with the
# characteristic polynomials $\rho$ and $\sigma$ below (the residual of the
# relation on the step equations is shown).  Henrici's order conditions
# give the constants $C_k$ of
# $L[y] = \sum_j \alpha_j y(t + jh) - h^2 \sum_j \beta_j y''(t + jh) = \sum_k C_k h^k y^{(k)}(t)$,
# here beside those of Stormer-Verlet ($\sigma = \zeta$):

# %%
rho, sigma, residual = theory.two_step()
zeta = theory.zeta
C = theory.error_constants([rho.coeff(zeta, j) for j in range(3)],
                           [sigma.coeff(zeta, j) for j in range(3)])
verlet_C = theory.error_constants((1, -2, 1), (0, 1, 0))
display(Math(theory.aligned([
    (r"\rho(\zeta)", theory.latex(rho) + " = " + theory.latex(sp.factor(rho))),
    (r"\sigma(\zeta)", sigma),
    (r"\text{residual on two spline steps}", residual),
    (r"\rho''(1) - 2\sigma(1)", (sp.diff(rho, zeta, 2) - 2 * sigma).subs(zeta, 1)),
    (r"(C_0, \dots, C_6)", sp.Tuple(*C)),
    (r"(C_0, \dots, C_6)_{\rm Verlet}", sp.Tuple(*verlet_C))])))

# %% [markdown]
# So the $y_n$ of the spline stepper obey a linear two-step method for
# second-order equations with $\rho(\zeta) = (\zeta - 1)^2$ and
# $\sigma(\zeta) = (\zeta^2 + 4\zeta + 1)/6$.  It is of order 2:
# $C_0 = \dots = C_3 = 0$, and its error constant is $C_4 = -\frac{1}{12}$,
# the same size as Stormer-Verlet's ($C_4 = \frac{1}{12}$) with the
# opposite sign.
#
# The package's knots satisfy the relation, with $f_n = F(t_n, y_n)$
# evaluated afresh at each knot (the stored $y''$ would make it an
# identity).  Converged step equations leave rounding error; one sweep per
# step leaves the unconverged part of each step equation:

# %%
ellipse = problems.cannonball(0.6)
converged = ellipse.solve(h=0.01, tol=1e-15, t_eval=None)
one_sweep = ellipse.solve(h=0.01, iterations=1, t_eval=None)
converged_residual = theory.relation_residual(ellipse, converged)
one_sweep_residual = theory.relation_residual(ellipse, one_sweep)
print(f"largest residual of the relation on the ellipse's {converged.nstep} steps")
assert converged_residual < 1e-14
print(f"  converged steps: {outputs.rounding(converged_residual)}")
print(f"  one sweep per step: ~1e{np.log10(one_sweep_residual):.0f}")

# %% [markdown]
# **Convergence.** Henrici's theorem (Discrete Variable Methods, 1962,
# Ch. 6; Hairer, Norsett & Wanner I, Sec. III.10): a linear multistep
# method for $y'' = f(t, y)$, $f$ Lipschitz in $y$, converges with order $p$
# if (i) it is consistent of order $p$, (ii) the roots of $\rho$ lie in the
# closed unit disc, those on the unit circle at most double, and (iii) the
# starting errors are $O(h^{p+1})$.  Each holds: (i) by the $C_k$ above;
# (ii) as $\rho = (\zeta - 1)^2$; (iii) as $y_0$ is exact and $y_1$ is one
# spline step, with local error $O(h^4)$.  So the spline stepper converges
# with order 2 in $y$, and in $y'$, the trapezoidal sums of the $f_n$.
#
# Why (iii) asks for $p + 1$: with the double root 1 the error recursion
# carries $e_1 - e_0$ forward like a velocity, $e_n \approx e_0 + n(e_1 - e_0)$
# with $n \sim 1/h$.  `theory.two_step_order` runs the two-step method on
# $y'' = -y$ from chosen starting values and fits the order.  It should
# give order 2 when started as the package starts, order 1 with $y_0$ off
# by $h^2$, and order 2 again with $y_0$ off by $h^3$.

# %%
HENRICI_STEPS = [0.1, 0.05, 0.025, 0.0125]


def package_start(step):
    one = splinestep.solve(lambda t, y, yp: -y, (0.0, step), 1.0, 0.0, step, tol=1e-15)
    return 1.0, one.y[0, -1]


starts = {"y_0 exact, y_1 from one spline step": package_start,
          "y_0 off by h^2, y_1 exact": lambda step: (1.0 + step ** 2, np.cos(step)),
          "y_0 off by h^3, y_1 exact": lambda step: (1.0 + step ** 3, np.cos(step))}
for name, start in starts.items():
    fitted = theory.two_step_order(start, HENRICI_STEPS, 10.0)
    print(f"{name:<36} fitted order {fitted:.2f}")

# %% [markdown]
# They do.  And the two-step method started as the package starts is the
# package's run, step for step:

# %%
package_run = splinestep.solve(lambda t, y, yp: -y, (0.0, 10.0), 1.0, 0.0, 0.05, tol=1e-15)
recurrence = theory.two_step_oscillator(1.0, package_run.y[0, 1], 0.05, package_run.nstep)
recurrence_miss = np.max(np.abs(recurrence - package_run.y[0]))
assert recurrence_miss < 1e-12
print(f"two-step method against the package's run (h = 0.05), largest |difference|: "
      f"{outputs.rounding(recurrence_miss)}")

# %% [markdown]
# For the general $F(t, y, y')$ the one-step argument applies (Hairer,
# Norsett & Wanner I, Thm. II.3.6): the step is a one-step map of
# $u = (y, y')$.  For $h$ with $h^2 L_y/6 + h L_{y'}/2 < 1$ ($L$: Lipschitz
# constants of $F$) its equation has a unique solution, by the contraction
# of the fixed-point sweep, and the increment function is Lipschitz in $u$
# with a constant bounded as $h \to 0$.  Its local error is $O(h^3)$ in the
# max norm of $u$ (section 1).  So the global error is $O(h^2)$.  The fitted
# slopes of `04_convergence` (all four orbits and the rigid body) measure
# what this proves.
#
# ## 3. The oscillator $y'' = -\omega^2 y$: stability, period, and the sweep
# One step maps $(y_n, h y'_n)$ by a matrix $M(x)$, $x = \omega h$.  Sympy
# gives it, its determinant and half trace, where the half trace reaches
# $-1$, the period error (for the spline, and for Verlet's
# $\cos\theta = 1 - x^2/2$), and where the sweep's factor $x^2/6$ reaches 1:

# %%
M = theory.amplification()
cos_theta = sp.simplify(M.trace() / 2)
limit = [s for s in sp.solve(sp.Eq(cos_theta, -1), x) if s.is_positive][0]
period = theory.period_error(cos_theta)
period_verlet = theory.period_error(1 - x ** 2 / 2)
sweep_limit = sp.solve(sp.Eq(x ** 2 / 6, 1), x)[1]  # |dz_new/dz| of one sweep: x^2/6
display(Math(theory.aligned([
    ("M(x)", M.applyfunc(sp.factor)), (r"\det M", sp.simplify(M.det())),
    (r"\cos\theta = \tfrac{1}{2}\operatorname{tr} M", cos_theta),
    (r"\cos\theta = -1 \text{ at } x", limit),
    (r"T_h/T - 1 \text{ (spline)}", theory.latex(period, "rev-lex")),
    (r"T_h/T - 1 \text{ (Verlet)}", theory.latex(period_verlet, "rev-lex")),
    (r"x^2/6 = 1 \text{ (sweep) at } x", sweep_limit)])))

# %% [markdown]
# $\det M = 1$ for every $x$, so the eigenvalues are $e^{\pm i\theta}$ with
# $\cos\theta = \operatorname{tr} M/2$ as long as $|\operatorname{tr} M| < 2$:
# no damping and no growth below the stability limit $x = \sqrt{12}$.  The
# limit itself is unstable: there $\operatorname{tr} M = -2$, the two
# eigenvalues meet at $-1$, and $M = -I + N$ with $N \ne 0$, $N^2 = 0$ (a
# Jordan block), so that $M^n = (-1)^n(I - nN)$ and the solution grows
# linearly: from $(y, hy') = (0, 1)$, $|y_n| = n\,|N_{12}| = n/3$.  Beyond
# the limit one eigenvalue is real and below $-1$.  The period error comes
# from $\theta = \arccos(\operatorname{tr} M/2)$; the spline's is Verlet's
# with the opposite sign at leading order.
#
# The figure puts the derivation against runs over the whole range of
# $\omega h$.  On the left, how far the measured period error lies from the
# leading term $x^2/24$, from the two-term series, and from the closed form
# $x/\theta - 1$: each truncation should miss by its first omitted term, and
# sympy gives the third, for the lines.  On the right, the amplitude factor
# per step, the largest eigenvalue modulus of the measured step matrix,
# against its closed form $|\cos\theta| + \sqrt{\cos^2\theta - 1}$ beyond
# the limit (1 below it).

# %%
series3 = theory.period_error(cos_theta, terms=3)
leading = float(period.coeff(x, 2))
half_trace = sp.lambdify(x, cos_theta)
x_period = np.geomspace(0.05, 3.4, 24)
period_measured = np.array([theory.oscillator_period_error(v) for v in x_period])
misses = {"measured $-$ $x^2/24$": leading * x_period ** 2,   # by their legend labels
          "measured $-$ two terms": sp.lambdify(x, period)(x_period),
          "measured $-$ closed form": x_period / np.arccos(half_trace(x_period)) - 1}
misses = {name: np.abs(period_measured - derived) for name, derived in misses.items()}
x_matrix = np.geomspace(0.1, 20.0, 40)  # Newton's tol: see theory.oscillator_run
radius = [np.max(np.abs(np.linalg.eigvals(theory.oscillator_step_matrix(v, tol=1e-10))))
          for v in x_matrix]
closed_miss = misses["measured $-$ closed form"]
assert closed_miss.max() < 1e-12
print(f"closed form against the {x_period.size} runs, largest |difference|: "
      f"{outputs.rounding(closed_miss.max())}")

# %% jupyter={"source_hidden": true}
fig, (ax, bx) = plt.subplots(1, 2, figsize=(outputs.WIDTH, 3.9))
ROUNDING = 1e-12  # differences below it are rounding, which differs from CPU to CPU
for (name, miss), marker, colour in zip(misses.items(), "os^", ("C0", "C1", "C2")):
    ax.loglog(x_period, np.maximum(miss, ROUNDING), marker, color=colour, markersize=4,
              label=name)
ax.axhline(ROUNDING, color="0.5", linewidth=0.8, label="rounding level")
fine = np.geomspace(0.05, 3.4, 200)
for power, colour in ((4, "C0"), (6, "C1")):
    term = abs(series3.coeff(x, power)) * x ** power
    ax.loglog(fine, sp.lambdify(x, term)(fine), ":", color=colour, linewidth=1.2,
              label=f"${sp.latex(term, fold_short_frac=True)}$ (next term)")
ax.set_ylim(3e-13, 10)
ax.set_ylabel("|measured $-$ derived| of $T_h/T - 1$")
ax.set_title("Period error: measured $-$ derived", loc="left")
fine = np.geomspace(0.1, 20.0, 400)
c = half_trace(fine)  # below -1 past the limit: eigenvalues c -+ sqrt(c^2 - 1)
bx.semilogx(fine, np.where(c >= -1, 1.0, -c + np.sqrt(np.abs(c * c - 1))), "k-", linewidth=1,
            label="closed form")
bx.semilogx(x_matrix, radius, "o", color="C0", markersize=4, label="measured step matrix")
bx.axhline(2 + np.sqrt(3), color="0.5", linestyle="--", linewidth=1,
           label="$2 + \\sqrt{3}$ ($\\omega h \\to \\infty$)")
bx.set_ylim(0.8, 4)
bx.set_ylabel("amplitude factor per step")
bx.set_title("Stability: largest $|$eigenvalue$|$ of $M$", loc="left")
for axis, ticks in ((ax, [0.05, 0.1, 0.2, 0.5, 1, 2, 3]),
                    (bx, [0.1, 0.2, 0.5, 1, 2, 5, 10, 20])):
    axis.axvline(np.sqrt(12), color="C3", linestyle=":", linewidth=1.5, label="$\\sqrt{12}$")
    axis.set_xlabel("$\\omega h$ (step $\\times$ angular frequency)")
    axis.set_xticks(ticks, [f"{t:g}" for t in ticks])
    axis.xaxis.set_minor_formatter(plt.NullFormatter())
fig.legend(*ax.get_legend_handles_labels(), loc="outside lower center", ncol=3,
           fontsize=outputs.MIN_FONT, frameon=False, columnspacing=1.2)   # the left panel's
bx.legend(loc="upper left", fontsize=outputs.MIN_FONT)  # above the points, left of the curve
outputs.save_figure(fig, "theory-oscillator")

# %% [markdown]
# Left: the leading term and the two-term series each miss the measured
# period error by about the first term they leave out (dotted), closely
# at small $x$ and more loosely towards the stability limit; the closed form
# agrees with the measurement to rounding at every $x$ (its triangles sit on
# the grey line, below which differences are rounding).  Right: the measured amplitude factor is 1
# up to $\sqrt{12}$ and follows the closed form beyond it, where one
# eigenvalue is real and below $-1$; as $x$ grows, $\cos\theta \to -2$ and
# the factor tends to $2 + \sqrt 3$.

# %% [markdown]
# ## 4. The spline stepper is Stormer-Verlet in other variables
# For $y'' = f(y) = -\nabla V(y)$ put $Q = \phi(q) = q - h^2 f(q)/6$.  The
# two-step relation of section 2 becomes
# $Q_{n+1} - 2Q_n + Q_{n-1} = h^2 f(q_n)$, $q_n = \phi^{-1}(Q_n)$: Verlet for
# the modified force $\tilde f(Q) = f(\phi^{-1}(Q))$.  With velocities it is
# exact too: the spline step maps $(q_n, v_n)$ to $(q_{n+1}, v_{n+1})$ if and
# only if velocity Verlet on $\tilde f$ maps $(Q_n, v_n)$ to
# $(Q_{n+1}, v_{n+1})$ (the velocity is unchanged by the map).
#
# And $\tilde f$ is a gradient: $\phi = \nabla(|q|^2/2 + h^2 V/6)$, so
# $\phi^{-1}$ is the gradient of that function's Legendre transform $G^*$
# and $\tilde f(Q) = -\nabla \tilde V(Q)$ with
# $\tilde V(Q) = \tfrac{6}{h^2}\left(|Q|^2/2 - G^*(Q)\right)$.  Sympy checks
# the identity and expands $\tilde V$ for a sample potential:

# %%
Qsym = sp.Symbol("Q")
V_sample = Qsym ** 2 / 2 + Qsym ** 4 / 4
correction = sp.expand((theory.modified_potential(V_sample, Qsym) - V_sample).coeff(theory.h, 2))
display(Math(theory.aligned([
    (r"\text{Verlet relation in } Q - \text{spline relation in } q",
     theory.verlet_in_other_variables()),
    (r"\tilde V - V \text{ for } V = \tfrac{Q^2}{2} + \tfrac{Q^4}{4}",
     theory.latex(theory.h ** 2 * sp.factor(correction)) + " + O(h^4)"),
    (r"-\tfrac{1}{12} |V'|^2", sp.factor(-sp.diff(V_sample, Qsym) ** 2 / 12))])))

# %% [markdown]
# So $\tilde V = V - \tfrac{h^2}{12}|\nabla V|^2 + O(h^4)$.  Now the
# measurement: a Verlet run (`splinestep.verlet`) on the modified force
# (`conjugacy.modified_force`, $q$ recovered from $Q$ by Newton's method)
# started from $\phi(q_0), v_0$, against the spline's run mapped by $\phi$,
# on the ellipse ($\mu = 0.6$) at the report's step over 100 orbits, with
# plain Verlet on $f$ for comparison.

# %%
mu, h = 0.6, ellipse.h
n_conj = int(round(100 * problems.orbit_elements(mu)["period"] / h))
compared = conjugacy.compare(ellipse, n_conj, every=211)
spline_run, conj_gap, plain_gap = (compared[k] for k in ("spline", "conjugate_gap", "plain_gap"))
print(f"{n_conj} steps: |Verlet on f~ - phi(spline)| <= {conj_gap:.1e}")
print(f"  |Verlet on f - spline| up to {plain_gap:.2f}")

# %% [markdown]
# The two runs agree to $1.5 \times 10^{-9}$ over 421489 steps, while
# plain Verlet on $f$ ends far from the spline.  The difference is not
# zero because each step leaves its rounding and the tolerances of its
# equations (the spline's step equation, the Newton solve that recovers
# $q$), and on the Kepler problem such small errors per step grow along
# the run into a phase error proportional to time.
#
# What the conjugacy implies (Hairer, Lubich & Wanner, Chs. VI, IX):
#
# * the spline stepper is **conjugate to a symplectic method**: it preserves
#   the symplectic form pulled back by $\phi$, and it is symmetric;
# * backward error analysis of Verlet gives its **modified energy**: for
#   velocity Verlet on $H = p^2/2 + U(q)$,
#   $\tilde H = H + h^2\left(U_{qq}(p, p)/12 - |U_q|^2/24\right) + O(h^4)$
#   is conserved up to $O(h^4)$ without drift.  With $U = \tilde V$ and back
#   in the spline's variables,
#   $\tilde H_{\rm spline}(q, v) = H + h^2\left(|\nabla V|^2/24 + V_{qq}(v, v)/12\right) + O(h^4)$:
#   the spline's energy error stays $O(h^2)$ without drift, for times
#   exponentially long in $1/h$ where the theorem's hypotheses hold (an
#   analytic Hamiltonian on a bounded region: for Kepler, away from $r = 0$);
#   notebook 08 measures no drift over $10^4$ orbits;
# * **phase**: on the oscillator the period error is Verlet's with the
#   opposite sign at leading order (section 3: $\pm x^2/24$).
#
# And **angular momentum**: Verlet conserves $Q \times P$ exactly for a
# central force, and $Q = (1 + h^2\mu/(6r^3))\, q$ is parallel to $q$, so
# the spline should conserve $\tilde L = (1 + h^2\mu/(6 r^3))\, q \times v$
# to rounding error, while its $q \times v$ oscillates by $O(h^2)$ without
# drift.  On the same run:

# %%
r_spline = np.hypot(*spline_run.y)
L_spline = kepler.angular_momentum(spline_run.y, spline_run.yp)
L_tilde = (1 + h * h * mu / (6 * r_spline ** 3)) * L_spline
print(f"q x v varies by {np.ptp(L_spline):.1e}; (1 + h^2 mu / (6 r^3)) q x v "
      f"by {np.ptp(L_tilde):.1e}")

# %% [markdown]
# $q \times v$ varies by $9.9 \times 10^{-6}$ along the run, the modified
# $\tilde L$ only by rounding error.  Kane, Marsden, Ortiz and West (2000) proved that Newmark's method with
# $\gamma = 1/2$ is symplectic for a non-standard symplectic form and
# conserves a nearby energy; the map $\phi$ makes that concrete for
# $\beta = 1/6$ and identifies the form.

# %% [markdown]
# ## How section 3 was measured
#
# Each property of section 3, measured with the package.  First the
# period, from the computed
# samples of 400 Newton-solved steps (`diagnostics.recurrence_fit`, in
# `theory.oscillator_period_error`), at three small $x$, and the
# coefficient of $x^2$ fitted to them:

# %%
xs = np.array([0.05, 0.1, 0.2])
measured = np.array([theory.oscillator_period_error(v) for v in xs])
two_terms = np.array([float(period.subs(x, v)) for v in xs])
fitted_leading = np.polyfit(xs ** 2, measured / xs ** 2, 1)[1]
for v, m, s2 in zip(xs, measured, two_terms):
    print(f"x = {v:.2f}: measured T_h/T - 1 = {m:.6e}, two-term series {s2:.6e}")
print(f"fitted coefficient of x^2: {fitted_leading:.6f} (derived {leading:.6f})")

# %% [markdown]
# The measured period error and the two-term series agree to the 7 digits
# printed at $x = 0.05$ and to 5 at $x = 0.2$, where the next term begins to
# show; the fitted coefficient of $x^2$ is $1/24$ to the 6 decimals printed.
#
# Next the stability limit, by bisection on the half trace of the step
# matrix $M$ measured from one Newton-solved step of two starting vectors
# (`theory.oscillator_step_matrix`).  The half trace crosses $-1$ at the
# limit with slope $-\sqrt{12}/9$, so the bisected limit is as accurate as
# the rounding of one step.  Then the growth at the limit over 1,000 steps,
# and where the package's step-too-large check (`splinestep.check`) fires:
# where the linearised step's spectral radius exceeds
# $1 + {}$`GROWTH_MARGIN`.

# %%
def unstable(v):  # the half trace of the measured step matrix at or below -1
    return 0.5 * np.trace(theory.oscillator_step_matrix(v)) <= -1.0


stability = theory.bisect(unstable, 3.0, 4.0, steps=60)
print(f"stability limit (tr M / 2 = -1), measured {stability:.10f}, derived sqrt(12) = "
      f"{float(limit):.10f}")
at_limit = theory.oscillator_run(np.sqrt(12.0), 0.0, 1.0, 1000)
growth_at_limit = np.abs(at_limit.y[0, [10, 100, 1000]])
print("at omega h = sqrt(12), from (y, h y') = (0, 1):\n  |y_10|, |y_100|, |y_1000| = "
      + ", ".join(f"{g:.4g}" for g in growth_at_limit) + " (derived n/3)")
check_fires = theory.bisect(lambda v: check.growth(np.array([[-1.0]]), np.array([[0.0]]),
                                                   v)[0] > 1 + check.GROWTH_MARGIN,
                            3.0, 4.0, steps=60)
print(f"the step-too-large check fires above omega h = {check_fires:.7f}")

# %% [markdown]
# The measured limit is $\sqrt{12}$ to the 10 digits printed, the growth at
# the limit is $n/3$, and the check fires just past the limit.  Last, the
# fixed-point sweep's limit, by bisection on whether it converges within
# 100,000 sweeps (`theory.sweep_converges`):

# %%
sweep = theory.bisect(lambda v: not theory.sweep_converges(v), 2.0, 3.0, steps=24)
print(f"sweep limit, measured {sweep:.6f}, derived sqrt(6) = {float(sweep_limit):.6f}")

# %% [markdown]
# Near $\sqrt 6$ the sweep's factor $x^2/6$ is close to 1, so the sweep
# needs ever more iterations: with a budget of 100,000 the measured limit
# lies just below $\sqrt 6$, and it approaches it as the budget grows.

# %% [markdown]
# ## The derived constants against the measurements
# Every constant of this notebook, derived by sympy and measured with the
# package (written to `data/theory-constants.csv`):

# %%
constants = pd.DataFrame([
    ("local error of y, coefficient of h^4 y''''",
     err_y.coeff(theory.h, 4).coeff(theory.Y[4]), measured_y, 6),
    ("local error of y', coefficient of h^3 y''''",
     err_yp.coeff(theory.h, 3).coeff(theory.Y[4]), measured_yp, 6),
    ("period error, coefficient of (omega h)^2", period.coeff(x, 2), fitted_leading, 6),
    ("stability limit of omega h (stable below it, not at it)", limit, stability, 10),
    ("|y_1000| at omega h = sqrt(12) from (y, h y') = (0, 1)", sp.Rational(1000, 3),
     growth_at_limit[-1], 6),
    ("fixed-point sweep limit of omega h", sweep_limit, sweep, 6),
    ("conjugacy: max |Verlet on f~ - phi(spline)| over 100 orbits", sp.Integer(0), conj_gap, 2),
], columns=["quantity", "exact", "measured", "digits"])
outputs.save_data(constants.assign(derived=constants.exact.astype(float))
                  [["quantity", "derived", "measured"]], "theory-constants")
display(HTML(outputs.html_table(theory.constants_table(constants), text=outputs.readable)))

# %% [markdown]
# Every derived constant is matched by its measurement, to the accuracy
# each allows: the local errors' next terms are $O(h)$ at $h = 0.01$, and
# the sweep's limit is bisected with a budget of 100,000 sweeps.  The conjugacy,
# exact in exact arithmetic, leaves the two runs, made by two different
# codes, $1.5 \times 10^{-9}$ apart after 421489 steps.  The
# method is of order 2 and converges, is stable below $\omega h = \sqrt{12}$,
# and is Stormer-Verlet in other variables: notebook 08 follows what that
# means for runs of 10,000 orbits.
