# %% [markdown]
# # All knots at once: the single Newton-LU sweep and boundary value problems
#
# The first of the report's directions (Sec. 5): "the coefficients at all
# points in a single sweep or set of iterations through the use of
# Newton's method and LU-decomposition".  We read it as the same step
# equations solved for every knot together; with $y$ given at both ends
# they become boundary value problems.  What we find:
#
# * **All knots at once give the stepwise solution** (to
#   $7 \times 10^{-13}$, in 2 to 3 Newton iterations) but spend 1.33 to 7.40
#   times its evaluations of $F$ and factorise the whole trajectory's
#   matrix at each iteration: it costs more than stepping.
# * **Its natural use is boundary value problems**: `splinestep.solve_bvp`
#   finds both solutions of the Bratu problem and converges at second
#   order; scipy's fourth-order `solve_bvp` is far more accurate per node.
# * **Its tolerance holds where the solutions converge with the mesh** (the
#   estimated error is the true error to the three digits shown); where
#   they do not, the run fails with status -1 and says why.

# %%
import sys
import textwrap

import numpy as np
import pandas as pd
from IPython.display import HTML, display
from scipy.integrate import solve_bvp as scipy_solve_bvp

sys.path.insert(0, "../scripts")  # outputs.py: the repository's data/, figures/ and plot style
import outputs
import splinestep
from splinestep import problems
from splinestep.analysis import diagnostics

plt = outputs.setup()
cases = {f"cannonball mu={mu:g}": problems.cannonball(mu) for mu in problems.CANNONBALL_MU}
cases["rigid body"] = problems.rigid_body("consistent")
ellipse = cases["cannonball mu=0.6"]

# %% [markdown]
# ## The single Newton-LU sweep
# `iteration="global"` solves the equations of all knots together: the step
# relations of each interval and the collocation at each knot, $3m$ unknowns
# per knot, by Newton's method with a sparse LU (SuperLU in its natural
# order keeps the band of the block-bidiagonal Jacobian).  It starts from one
# fixed-point sweep per step.
#
# We solve three problems both ways, globally and step by step with
# Newton's method, and count every call each solve makes
# (`tests/test_improvements.py` counts them from outside).  The counts
# include the checks the solvers make: the global solve's starting sweep
# has its step-size check ($2m+1$ evaluations of $F$ at each of three
# states); the stepwise Newton checks $F$ and the Jacobian at $t_0$, and its
# step-size check evaluates three Jacobians.

# %%
global_rows = []
global_cases = {"cannonball mu=0.6": ellipse,
                "oscillator omega=3": problems.harmonic(3.0, (0.0, 20.0), 0.05),
                "rigid body": cases["rigid body"]}
for name, problem in global_cases.items():
    stepwise = problem.solve(iteration="newton", tol=1e-14)
    whole = problem.solve(iteration="global", tol=1e-13)
    global_rows.append(dict(problem=name, jacobian="analytic" if problem.jac else
                            "finite differences", knots=whole.t.size, status=whole.status,
                            newton_iterations=whole.niter, nfev=whole.nfev, njev=whole.njev,
                            nfev_stepwise=stepwise.nfev, njev_stepwise=stepwise.njev,
                            max_difference=np.max(np.abs(whole.y - stepwise.y))))
global_table = pd.DataFrame(global_rows)
outputs.save_data(global_table, "global-sweep")

# %% [markdown]
# Side by side: Newton's iterations on the whole run, and the evaluations
# and Jacobians it spends against the stepwise run's:

# %%
shown = pd.DataFrame({
    "problem": global_table.problem, "knots": global_table.knots,
    "Jacobian": global_table.jacobian,
    "Newton iterations": global_table.newton_iterations,
    "F, global / stepwise": [f"{a} / {b} = {a / b:.2f}" for a, b in
                             zip(global_table.nfev, global_table.nfev_stepwise)],
    "Jacobians, global / stepwise": [f"{a} / {b}" for a, b in
                                     zip(global_table.njev, global_table.njev_stepwise)],
    "largest difference": global_table.max_difference.map(lambda v: outputs.plain(v, 1))})
display(HTML(outputs.html_table(shown)))

# %% [markdown]
# The global solve gives the stepwise solution, to $7 \times 10^{-13}$, in 2
# to 3 Newton iterations.  Each iteration evaluates $F$ and its Jacobian at
# every knot, and that is its cost.
#
# With an analytic Jacobian it spends 1.33 to 1.51 times the stepwise
# evaluations of $F$, and one Jacobian per knot and iteration (15,004 and
# 803 with the check at $t_0$), where the stepwise Newton's kept matrix is
# built once per run (its count, 5, includes the check at $t_0$ and the three
# of the step-size check).  With a finite-difference Jacobian, whose columns
# are evaluations of $F$, it spends 7.40 times the stepwise evaluations.  And
# it factorises the sparse matrix of the whole trajectory at every
# iteration.
#
# So it costs more than stepping (the Speed page of the website,
# `website/speed.md`, also times it against the stepwise Newton).  To pay
# on several processors it would need
# the structure of parallel-in-time methods: the knots' evaluations and the
# factorisation split over processors, as in parareal and
# multigrid-reduction-in-time, with a cheap coarse propagator for the
# guess.  Its natural use is elsewhere: problems that stepping cannot solve
# at all.

# %% [markdown]
# ## Boundary value problems
# The same equations with $y$ given at both ends instead of $y$ and $y'$ at
# the start: `splinestep.solve_bvp(fun, x, ya, yb)`.
#
# The Bratu problem $y'' + \lambda e^y = 0$, $y(0) = y(1) = 0$,
# $\lambda = 1$, has two solutions,
# $y = -2\ln\left(\cosh((x - \tfrac12)\theta/2)/\cosh(\theta/4)\right)$
# for the two roots of $\theta = \sqrt{2\lambda}\cosh(\theta/4)$; the
# guesses $0.1\sin\pi x$ and $4\sin\pi x$ find one each.  We solve it on
# meshes of 11 to 1281 equally spaced points.
#
# Beside it, scipy's `solve_bvp` (fourth-order collocation with mesh
# refinement, tol $10^{-8}$) from the same meshes and guesses, allowed up to
# 100,000 nodes.  Both errors are measured on the same 2001 equally spaced
# points (between the knots: the spline's and scipy's own interpolants).

# %%
SCIPY_MAX_NODES = 100_000


def scipy_bratu(x, guess, amplitude):
    """scipy's solve_bvp on Bratu's problem as the first-order system (y, y')."""
    return scipy_solve_bvp(lambda s, u: np.vstack([u[1], -np.exp(u[0])]),
                           lambda a, b: np.array([a[0], b[0]]), x,
                           np.vstack([guess, np.pi * amplitude * np.cos(np.pi * x)]),
                           tol=1e-8, max_nodes=SCIPY_MAX_NODES)


# %%
x_check = np.linspace(0.0, 1.0, 2001)
bvp_rows = []
for branch, amplitude in (("lower", 0.1), ("upper", 4.0)):
    fun, jac, args, exact = problems.bratu(1.0, branch)
    for n in (11, 21, 41, 81, 161, 321, 641, 1281):
        x = np.linspace(0.0, 1.0, n)
        guess = amplitude * np.sin(np.pi * x)[None]
        ours = splinestep.solve_bvp(fun, x, 0.0, 0.0, y_guess=guess, args=args,
                                    tol=np.inf)   # on this mesh: the order is measured
        theirs = scipy_bratu(x, guess, amplitude)
        bvp_rows.append(dict(branch=branch, points=n, h=x[1], status=ours.status,
                             newton_iterations=ours.niter,
                             error=np.max(np.abs(ours.sol(x_check)[0] - exact(x_check)[0])),
                             scipy_status=theirs.status, scipy_points=theirs.x.size,
                             scipy_error=np.max(np.abs(theirs.sol(x_check)[0]
                                                       - exact(x_check)[0]))))
bvp_table = pd.DataFrame(bvp_rows)
outputs.save_data(bvp_table, "bvp-bratu")

# %% [markdown]
# The order of the spline collocation, fitted over all meshes and from each
# pair of successive errors (the step halves), and what scipy's runs used
# and reached:

# %%
bvp_orders = {b: np.polyfit(np.log(g.h), np.log(g.error), 1)[0]
              for b, g in bvp_table.groupby("branch")}
# Second way: the order from the ratio of successive errors (the step halves).
bvp_successive = {b: np.log2(g.error.to_numpy()[:-1] / g.error.to_numpy()[1:])
                  for b, g in bvp_table.groupby("branch")}
for b, g in bvp_table.groupby("branch"):
    iterations = sorted(set(g.newton_iterations))
    print(outputs.wrapped(
        f"{b} branch: fitted order {bvp_orders[b]:.2f} (successive errors "
        f"{bvp_successive[b].min():.2f} to {bvp_successive[b].max():.2f}); Newton iterations "
        f"{' to '.join(str(v) for v in iterations[::max(len(iterations) - 1, 1)])}; error at "
        f"{g.points.max()} points {outputs.plain(g.error.iloc[-1])}; scipy: status "
        f"{', '.join(str(v) for v in sorted(set(g.scipy_status)))}, {g.scipy_points.min()} to "
        f"{g.scipy_points.max()} nodes, errors {outputs.plain(g.scipy_error.min(), 1)} to "
        f"{outputs.plain(g.scipy_error.max(), 1)}"))

# %% [markdown]
# Why scipy was given more room than its default node limit (1000): with
# it, most upper-branch runs stop before they meet the tolerance (status
# 1).  And, since scipy chooses its own meshes, the two solvers are compared
# per node: our error, interpolated at the number of nodes scipy used,
# against scipy's error there.

# %%
default_limit = [scipy_solve_bvp(lambda s, u: np.vstack([u[1], -np.exp(u[0])]),
                                 lambda a, b: np.array([a[0], b[0]]), x,
                                 np.vstack([4.0 * np.sin(np.pi * x), 4.0 * np.pi * np.cos(np.pi * x)]),
                                 tol=1e-8).status
                 for x in (np.linspace(0.0, 1.0, n) for n in (11, 21, 41, 81, 161, 321))]
print(outputs.wrapped(
    f"scipy with its default max_nodes = 1000, upper branch from 11 to 321 points: status 1 "
    f"(node limit) in {sum(v == 1 for v in default_limit)} of {len(default_limit)} runs"))
# Accuracy per node: our error interpolated at the nodes scipy used, over scipy's error.
per_node = np.concatenate([
    diagnostics.loglog_interp(g.points, g.error, g.scipy_points) / g.scipy_error
    for _, g in bvp_table.groupby("branch")])
per_node_range = [float(f"{v:.0e}") for v in (np.nanmin(per_node), np.nanmax(per_node))]
print(f"at the nodes scipy used, our error is {outputs.plain(per_node_range[0], 1)} to "
      f"{outputs.plain(per_node_range[1], 1)} times scipy's")

# %% [markdown]
# The two solutions, and the errors of both solvers against the number of
# nodes each used:

# %% jupyter={"source_hidden": true}
fig, (ax, bx) = plt.subplots(1, 2, figsize=(outputs.WIDTH, 3.6))
x_fine = np.linspace(0.0, 1.0, 201)
for branch, amplitude, color in (("lower", 0.1, "C0"), ("upper", 4.0, "C3")):
    fun, jac, args, exact = problems.bratu(1.0, branch)
    x = np.linspace(0.0, 1.0, 21)
    res = splinestep.solve_bvp(fun, x, 0.0, 0.0, y_guess=amplitude * np.sin(np.pi * x)[None],
                               args=args, tol=np.inf)
    ax.plot(x_fine, exact(x_fine)[0], "k-", linewidth=1,
            label="exact" if branch == "lower" else None)
    ax.plot(x, res.y[0], "o", color=color, markersize=4, label=f"{branch} branch, 21 points")
    g = bvp_table[bvp_table.branch == branch]
    bx.loglog(g.points, g.error, "o-", color=color, markersize=4, label=f"spline, {branch}")
    bx.loglog(g.scipy_points, g.scipy_error, "x", color=color, markersize=6,
              label=f"scipy, {branch}")
ax.set_xlabel("$x$")
ax.set_ylabel("$y$")
ax.set_title("Bratu, $\\lambda = 1$")
ax.set_ylim(-0.2, 5.8)
ax.legend(loc="upper left", fontsize=outputs.MIN_FONT)
bx.set_xlabel("nodes used")
bx.set_ylabel("max error")
bx.set_title("Error against the exact solutions")
bx.set_ylim(1e-12, 1.0)
fig.legend(*bx.get_legend_handles_labels(), loc="outside lower right", ncol=4,
           fontsize=outputs.MIN_FONT, frameon=False, columnspacing=1.2)
outputs.save_figure(fig, "bvp-bratu")

# %% [markdown]
# Both branches are found from their guesses, in 4 (lower) and 5 (upper)
# Newton iterations on every mesh, at order 2.00 and 1.99 in the mesh width;
# the ratios of successive errors give 1.96 to 2.00.
#
# scipy's `solve_bvp` is of fourth order and refines its mesh until its
# residual meets the tolerance.  Given room (all runs end with status 0),
# it uses 121 to 1281 nodes and reaches errors of $7 \times 10^{-12}$ to
# $7 \times 10^{-11}$; at the same number of nodes our error is 800 to
# $1 \times 10^{5}$ times larger.  scipy is the better solver for this
# problem, per node and overall; the spline collocation is the simpler
# method and converges at second order.
#
# Two more checks of the solver: a linear problem with a known solution,
# $y'' = y$, $y(0) = 0$, $y(1) = 1$ (exact $\sinh x/\sinh 1$), and Bratu at
# $\lambda = 4$, above the largest $\lambda$ for which a solution exists:

# %%
linear = splinestep.solve_bvp(lambda t, y, yp: y, np.linspace(0.0, 1.0, 101), 0.0, 1.0,
                              tol=np.inf)
linear_error = np.max(np.abs(linear.y[0] - np.sinh(linear.t) / np.sinh(1.0)))
print(outputs.wrapped(
    f"y'' = y, y(0) = 0, y(1) = 1 on 101 points: {linear.niter} Newton iterations, error "
    f"{outputs.plain(linear_error)} (exact sinh x / sinh 1)"))
bratu_fun = problems.bratu(1.0, "lower")[0]
no_solution = splinestep.solve_bvp(bratu_fun, np.linspace(0.0, 1.0, 41), 0.0, 0.0,
                                   args=(4.0,))
print(f"Bratu with lambda = 4 > {problems.boundary.LAMBDA_CRITICAL:.4f} (no solution): "
      f"status {no_solution.status}")

# %% [markdown]
# The linear problem is solved to the method's error on 101 points; the
# problem without solution ends with status -1 and a message, not an
# exception.

# %% [markdown]
# ### A tolerance on the solution
# Newton's method converging says only that the equations of one mesh are
# solved.  `solve_bvp(..., tol=)` also estimates the error of $y$: it solves
# again on the mesh with every interval halved, and, the method being of
# order 2, takes $\tfrac43 (y_h - y_{h/2})$ as the error of $y_h$.  While that
# exceeds tol (relative to $\max(1, \max|y|)$) it refines the mesh where
# the spline's truncation error is largest (each such interval split into
# up to four), up to `max_nodes`.
#
# The lower Bratu branch, from 11 points, at three tolerances:

# %%
fun, jac, args, exact = problems.bratu(1.0, "lower")
tolerance_rows = []
for tol in (1e-3, 1e-6, 1e-9):
    res = splinestep.solve_bvp(fun, np.linspace(0.0, 1.0, 11), 0.0, 0.0, args=args, tol=tol,
                               max_nodes=100_000)
    tolerance_rows.append(dict(tol=tol, points=res.t.size, estimated_error=res.error_estimate,
                               true_error=np.max(np.abs(res.y[0] - exact(res.t)))))
bvp_tolerance = pd.DataFrame(tolerance_rows)
outputs.save_data(bvp_tolerance, "bvp-tolerance")
display(HTML(outputs.html_table(pd.DataFrame({
    "tol": bvp_tolerance.tol.map("{:.0e}".format), "mesh points": bvp_tolerance.points,
    "estimated error": bvp_tolerance.estimated_error.map("{:.2e}".format),
    "true error": bvp_tolerance.true_error.map("{:.2e}".format)}), text=outputs.readable)))

# %% [markdown]
# The estimate is the true error to the three digits shown, and each run
# stops on the first mesh whose error is below its tolerance: 11 points are
# already enough for $10^{-3}$, 161 and 5424 are needed for $10^{-6}$ and
# $10^{-9}$ (the lower branch's $|y|$ stays below 1, so tol is absolute
# here).  The mesh is refined where the truncation error is largest: on
# this smooth solution that saves nothing over halving every interval;
# where the solution has a layer it saves most of the points (scipy's
# shock problem, `tests/test_bvp.py` and the docstring of `solve_bvp`).
#
# ### When the mesh does not converge
# The resonant problem $y'' = -y$, $y(0) = 0$, $y(\pi) = 1$ has no solution
# ($\sin$ vanishes at both ends).  Yet every mesh has a discrete solution,
# and Newton converges on each: only the refinement can tell.

# %%
resonant = splinestep.solve_bvp(lambda x, y, yp: -y, np.linspace(0.0, np.pi, 11), 0.0, 1.0)
print(f"status {resonant.status} on {resonant.t.size} mesh points, "
      f"max |y| = {outputs.plain(np.max(np.abs(resonant.y)), 1)}; the solver's message:")
print(textwrap.indent(textwrap.fill(resonant.message, 90), "    "))

# %% [markdown]
# The discrete solutions grow as the mesh is refined, to
# $\max|y| = 3 \times 10^{5}$ on 641 points, and so do the estimates of
# their error: $7.9 \times 10^{4}$, then $1.3 \times 10^{6}$, where a
# converging solution's would fall fourfold per halving.  The solver stops
# at the node limit with status -1 and says why: the problem may have no
# solution near the guess.  It returns a failure with its reason, not a
# large number that looks like an answer.
#
# **What to take away.**  Solving all knots at once gives the stepwise
# solution but costs more than stepping on one processor; its use is where
# stepping cannot go, boundary value problems.  There the spline
# collocation finds both Bratu solutions and converges at second order, but
# scipy's fourth-order `solve_bvp` is far more accurate per node.  The
# tolerance on the solution holds where the solutions converge with the
# mesh, and where they do not, the run says so.
