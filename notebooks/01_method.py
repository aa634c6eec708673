# %% [markdown]
# # The method: one spline step, the fixed-point sweep, and why it behaves as it does
#
# On $[t_i, t_{i+1}]$, $h = t_{i+1} - t_i$, the solution of $y'' = F(t, y, y')$
# is the cubic $s_i(t) = a_i + b_i (t - t_i) + c_i (t - t_i)^2 + d_i (t - t_i)^3$
# (report eqs. 1-3), continuous with $s'$ and $s''$ at the knots and satisfying
# the ODE at every knot.  Since $s''(t_i) = 2c_i$, the knot condition reads
# $2c_{i+1} = F(t_{i+1}, a_{i+1}, b_{i+1})$: the report's eq. 9 prints it
# without the factor 2 (inconsistent with its own eq. 5).  With
# $z = 2c_{i+1} = y''_{i+1}$ as the unknown, eqs. 6-8 give
#
# $$a_{i+1} = y_i + h y'_i + h^2\left(\tfrac13 y''_i + \tfrac16 z\right), \qquad
#   b_{i+1} = y'_i + \tfrac h2\left(y''_i + z\right), \qquad
#   d_i = \frac{z - y''_i}{6h},$$
#
# which is **Newmark's method with $\beta = 1/6$, $\gamma = 1/2$** (the
# "linear acceleration method" of structural dynamics, 1959): the spline
# time stepper is a known method.  The test suite checks the equality to
# $10^{-12}$ against an independent Newmark code.
#
# ## One step by hand, on $y'' = -y$
# The report starts the iteration from $d_i = 0$ ($z = y''_i$, a quadratic
# through the knot) and repeats "a few times".  Each sweep evaluates
# eqs. 6-7, then eq. 9 and eq. 8.  `iterations=k` does exactly $k$ sweeps:

# %%
import numpy as np
import pandas as pd

import splinestep
from splinestep import figures, problems

plt = figures.setup()
h = 0.5
exact_step = splinestep.solve(lambda t, y, yp: -y, (0, h), 1.0, 0.0, h, tol=1e-15)
for k in range(1, 6):
    res = splinestep.solve(lambda t, y, yp: -y, (0, h), 1.0, 0.0, h, iterations=k)
    d = (res.ypp[0, 1] - res.ypp[0, 0]) / (6 * h)
    print(f"{k} sweep(s): d_0 = {d:+.12f}, a_1 = {res.y[0, 1]:.12f}, "
          f"change from converged {abs(res.y[0, 1] - exact_step.y[0, 1]):.1e}")
print(f"converged  : a_1 = {exact_step.y[0, 1]:.12f}; exact cos(0.5) = {np.cos(h):.12f}")

# %% [markdown]
# Each sweep shrinks the error of $z$ by the factor
# $\partial z_{\rm new}/\partial z = \tfrac{h^2}{6}\,\partial F/\partial y + \tfrac h2\,\partial F/\partial y'$,
# here $-(h\omega)^2/6 = -0.0417$: the printed changes fall by about 24 per
# sweep.  So the sweep converges only while $(h\omega)^2/6 < 1$, i.e.
# $h\omega < \sqrt 6 \approx 2.45$, although the method itself is stable up
# to $h\omega < \sqrt{12} \approx 3.46$ (below).  Newton's method (the
# report's own suggestion, `iteration="newton"`) removes that limit and is
# exact in one iteration on linear problems.
#
# ## Stability and phase error on $y'' = -\omega^2 y$
# For the oscillator, the step maps $(y_i, y'_i)$ linearly; its eigenvalues
# $e^{\pm i\Omega h}$ satisfy
#
# $$\cos\Omega h = 1 - \frac{x^2}{2 + x^2/3}, \qquad x = \omega h,$$
#
# so $|e^{\pm i \Omega h}| = 1$ (no numerical damping, the amplitude is
# kept) for $x \le \sqrt{12}$ and one eigenvalue exceeds 1 beyond.  The
# numerical period is longer than the true one:
# $T_h / T - 1 = x^2/24 + O(x^4)$.  We measure the period of the spline
# solution and compare.

# %%
rows = []
for x in np.linspace(0.05, 3.4, 40):
    problem = problems.harmonic(omega=1.0, t_span=(0.0, 400 * x), h=x)
    res = problem.solve(iteration="newton")
    # Rotation per step from two successive steps: y_{n+1} + y_{n-1} = 2 cos(Omega h) y_n.
    y = res.y[0]
    cos_measured = np.sum((y[2:] + y[:-2]) * y[1:-1]) / (2 * np.sum(y[1:-1] ** 2))
    cos_theory = 1 - x * x / (2 + x * x / 3)
    rows.append(dict(omega_h=x, period_ratio_measured=x / np.arccos(cos_measured),
                     period_ratio_theory=x / np.arccos(cos_theory),
                     amplitude_growth=np.max(np.abs(y)) / np.max(np.abs(y[: y.size // 10]))))
phase = pd.DataFrame(rows)
figures.save_data(phase, "method-phase-error")
print(f"largest |measured - theory| of the period ratio: "
      f"{np.max(np.abs(phase.period_ratio_measured - phase.period_ratio_theory)):.1e}")
print(f"largest amplitude growth over 400 steps for omega h <= 3.4: {phase.amplitude_growth.max():.6f}")

fig, ax = plt.subplots(figsize=(6.5, 4.2))
ax.loglog(phase.omega_h, phase.period_ratio_measured - 1, "o", markersize=4,
          label="measured, cubic-spline stepper")
ax.loglog(phase.omega_h, phase.period_ratio_theory - 1, "-", label="closed form (Newmark $\\beta$=1/6)")
ax.loglog(phase.omega_h, phase.omega_h ** 2 / 24, "--", label="leading term $(\\omega h)^2/24$")
ax.axvline(np.sqrt(6), color="grey", linestyle=":", label="fixed-point limit $\\sqrt{6}$")
ax.axvline(np.sqrt(12), color="k", linestyle=":", label="stability limit $\\sqrt{12}$")
ax.set_xlabel("$\\omega h$ (step times angular frequency)")
ax.set_ylabel("relative period error $T_h / T - 1$")
ax.set_title("Phase error of the spline stepper on $y'' = -\\omega^2 y$")
ax.legend(fontsize=7)
figures.save_figure(fig, "method-phase-error")

# %% [markdown]
# The measured periods follow the closed form to rounding error, and the
# amplitude does not grow or decay below the stability limit.  This
# explains the report's results:
#
# * **second order** (Fig. 3): the local error of the linear-acceleration
#   method is $O(h^4)$ in $y$, $O(h^3)$ in $y'$, so the global error is $O(h^2)$;
# * **an error that follows the orbit** (Sec. 5): the method does not
#   damp, and it is symplectic for a modified symplectic form (Kane,
#   Marsden, Ortiz & West, Int. J. Numer. Meth. Eng. 49, 2000): energy errors
#   oscillate with the orbit instead of drifting, while the phase error
#   $x^2/24$ per unit time grows linearly, so the position error grows;
# * **one sweep is enough for the order**: after one sweep the remaining
#   error of $z$ is $O(h^2)\cdot O(h)$, which changes $a_{i+1}$ by $O(h^5)$ and
#   $b_{i+1}$ by $O(h^4)$; "a few times" only changes the constant.
