"""The report's claims against what the notebooks measured, and its errata.

Notebook 14 builds its tables here: :func:`claims_table` (written to
``data/claims.csv`` and, by ``make reproduce``, into the README),
:func:`errata_table` (``data/errata.csv``) and :func:`headline_numbers`
(``data/headline-numbers.csv``, the few numbers the paper's prose states).

Every number is read from the data the notebooks wrote (``data/*.csv``
through :class:`Measured`) or computed here with the package; none is
typed.  Each claim is one function of a :class:`Measured`, listed in
:data:`CLAIMS` in the report's order, which returns one row: where the
report makes the claim, what it says, what was measured, the verdict in
full, its kind (:data:`KINDS`) and the notebook section that measures it.

The tables are plain text (``4.1e-03``, ``omega^2``, ``sqrt(12)``) with
formulas in TeX between dollars (``$c_{i+1} = r - p\\thinspace b_{i+1}$``):
:func:`readable` shows the text as a reader reads it and leaves the formulas
to MathJax (the README, notebook 14, the website) and to the paper, which
typesets the few TeX commands they use.  Shown as tables, each reference of
the column "where" links to its heading on the report page
(:data:`REPORT_PAGE`, :func:`report_heading`) and each notebook section to
its heading (:func:`section_anchor`): :func:`with_links`.
"""

import re
from functools import cache, cached_property
from html import escape
from pathlib import Path

import numpy as np
import pandas as pd

import outputs
from splinestep import problems
from splinestep.analysis import diagnostics, tolerance
from splinestep.problems import kepler

# Editing this module makes the notebook that imports it stale (make reproduce).
outputs._note("read", Path(__file__))

# The kinds of verdict: the first three judge what the report claims, "built"
# and "proved" answer what it suggests, "beyond the report" marks a finding
# it does not make.
KINDS = ("reproduced", "partly", "not reproduced", "built", "proved", "beyond the report")

ERRORS = ["energy_error", "momentum_error", "position_error"]
LOCAL_ERROR = "local error of y, coefficient of h^4 y''''"
PERIOD_ERROR = "period error, coefficient of (omega h)^2"
STABILITY_LIMIT = "stability limit of omega h (stable below it, not at it)"
AT_LIMIT = "|y_1000| at omega h = sqrt(12) from (y, h y') = (0, 1)"


def summary(kinds):
    """One line: how many of the claims each kind of verdict has (``kinds``:
    the column "kind" of the table), in the order of :data:`KINDS`."""
    kinds = list(kinds)
    counts = ", ".join(f"{kinds.count(k)} {k}" for k in (*KINDS, *sorted(set(kinds) - set(KINDS)))
                       if kinds.count(k))
    return f"{len(kinds)} claims of the report and findings beyond it: {counts}"


def sci(value, digits=2):
    """Plain-text scientific notation for the tables (e.g. 4.1e-03)."""
    return f"{value:.{digits - 1}e}"


def row(where, claim, measured, verdict, kind, notebook, section):
    """One line of the claims table."""
    if kind not in KINDS:
        raise ValueError(f"kind must be one of {KINDS}, got {kind!r}")
    return dict(where=where, claim=claim, kind=kind, notebook=notebook, section=section,
                measured=measured, verdict=verdict)


class Measured:
    """The data the notebooks wrote, read once each, and the quantities
    several claims share, derived from them."""

    def __getattr__(self, name):
        # data/NAME.csv as an attribute: data/work-to-reach.csv is self.work_to_reach.
        if name.startswith("_"):
            raise AttributeError(name)
        frame = outputs.read_data(name.replace("_", "-"))
        setattr(self, name, frame)
        return frame

    @cached_property
    def spline(self):
        """The cannonball's largest errors at dt = 0.01, spline, by mu."""
        cannon = self.cannonball_max_errors
        return cannon[cannon.method == "spline"].set_index("mu")

    @cached_property
    def rk4(self):
        """The same for RK4."""
        cannon = self.cannonball_max_errors
        return cannon[cannon.method == "rk4"].set_index("mu")

    @cached_property
    def rigid(self):
        return self.rigid_body_max_errors.set_index("case")

    @cached_property
    def drift(self):
        return self.rigid_body_energy_drift.set_index("method")

    @cached_property
    def reach(self):
        return self.work_to_reach.set_index(["method", "target"])

    @cached_property
    def long_drift(self):
        return self.long_time_drift.set_index("method")

    @cached_property
    def phase_drift(self):
        return outputs.read_data("phase-drift").set_index("method")

    @cached_property
    def elements(self):
        """Energy, eccentricity and semi-major axis of each cannonball orbit."""
        return {mu: problems.orbit_elements(mu) for mu in problems.CANNONBALL_MU}

    @cached_property
    def per_step(self):
        """The spline's evaluations per step on the cannonball at dt = 0.01."""
        return self.spline.nfev / self.spline.nstep

    @cached_property
    def spline_slopes(self):
        slopes = self.convergence_slopes
        return slopes[slopes.method == "spline"].slope

    @cached_property
    def second_order_work(self):
        """The spline (iterated, one sweep) and Verlet rows of work-precision,
        by step (the column "setting" of a fixed-step method)."""
        work = self.work_precision
        names = {"spline (converged)": "spline", "spline (1 sweep)": "spline (1 sweep)",
                 "Verlet": "verlet"}
        return (work[work.method.isin(names)].assign(method=lambda w: w.method.map(names))
                .rename(columns={"setting": "dt"}))

    @cached_property
    def verlet_curves(self):
        """(evaluations, largest error) of the spline and of Verlet."""
        return {m: (g.nfev.to_numpy(), g.max_error.to_numpy())
                for m, g in self.second_order_work.set_index("dt").groupby("method")}

    @cached_property
    def equal_work(self):
        """Spline (iterated) over Verlet error at equal evaluations: (least, most)."""
        return diagnostics.ratio_range(self.verlet_curves["verlet"], self.verlet_curves["spline"])

    @cached_property
    def one_sweep_equal_work(self):
        """Spline (1 sweep) over Verlet error at equal evaluations: (least, most)."""
        return diagnostics.ratio_range(self.verlet_curves["verlet"],
                                       self.verlet_curves["spline (1 sweep)"])

    def adaptive_cost(self, problem, adaptive, uniform):
        """Adaptive over uniform evaluations at equal final error on one
        problem of notebook 07's study, (least, most) over the adaptive runs
        a uniform run was matched to (``adaptive``: "spline" or "spline, 1
        sweep"; ``uniform``: "iterated", "2 sweeps" or "1 sweep")."""
        cost = self.tolerance_cost
        ratio = cost[(cost.problem == problem) & (cost.adaptive == adaptive)
                     & (cost.uniform == f"uniform, {uniform}")].ratio.dropna()
        return ratio.min(), ratio.max()

    def adaptive_gain(self, sweeps):
        """How many times the evaluations of adaptive knots the uniform step
        needs for the same final error on the Kepler orbit e = 0.9, both
        runs with ``sweeps`` ("1 sweep" or "iterated"): (least, most)."""
        least, most = self.adaptive_cost(
            "Kepler e = 0.9", "spline, 1 sweep" if sweeps == "1 sweep" else "spline", sweeps)
        return 1 / most, 1 / least

    @cached_property
    def ellipse_order_4(self):
        """Order 4's largest error on the ellipse at dt = 0.01."""
        work = self.composition_work
        return work[(work.method == "spline, order 4") & (work.setting == 0.01)].max_error.iloc[0]

    def evaluations(self, method, target):
        """What work-to-reach.csv says about reaching ``target`` with ``method``."""
        at = self.reach.loc[(method, target)]
        if np.isfinite(at.nfev_interpolated):
            return f"about {outputs.round_sig(at.nfev_interpolated, 2):.0f}"
        if at.error_at_fewest < target:
            return (f"fewer than {int(at.fewest_tested)} (its fewest tested give "
                    f"{sci(at.error_at_fewest)})")
        return f"more than {int(at.most_tested)} (its most tested give {sci(at.error_at_most)})"

    def constant(self, name, digits=4):
        """A constant of the theory, derived and measured (theory-constants.csv)."""
        at = self.theory_constants.set_index("quantity").loc[name]
        return f"{at.derived:.{digits}g} derived, {at.measured:.{digits}g} measured"


# The claims, in the report's order, then the findings beyond it.

def orbit_types(m):
    elements = m.elements
    return row(
        "Sec. 3.1", "mu = 0.4, 0.5, 0.6, 1 give hyperbolic, parabolic, elliptic, circular orbits",
        "with launch $x(0) = (1, 0)$, $x'(0) = (0, 1)$: energies "
        + ", ".join(f"{elements[mu]['energy']:.1f}" for mu in problems.CANNONBALL_MU)
        + "; eccentricities "
        + ", ".join(f"{elements[mu]['eccentricity']:.3g}" for mu in problems.CANNONBALL_MU),
        "reproduced", "reproduced", "02_cannonball", "Figure 1a")


def solves_both(m):
    return row(
        "Sec. 4, Fig. 1", "the spline method generates an approximate solution to both problems",
        f"largest position error at dt = 0.01: {sci(m.spline.position_error.max())} (cannonball, "
        f"exact reference); largest angular-velocity error "
        f"{sci(m.rigid.loc['consistent', 'solution_error_spline'])} (rigid body, exact reference)",
        "reproduced", "reproduced", "02_cannonball", "How large are the errors?")


def cannonball_below_1e3(m):
    histories = m.cannonball_error_histories
    ellipse = histories[(histories.mu == 0.6) & (histories.method == "spline")]
    crossing = ellipse.t[ellipse.position_error > 1e-3].min()
    spline = m.spline
    return row(
        "Sec. 5, Fig. 2a", "the errors do not exceed 1e-3 (cannonball)",
        f"energy error <= {sci(spline.energy_error.max())}, angular-momentum error <= "
        f"{sci(spline.momentum_error.max())}; but the position error reaches "
        f"{sci(spline.position_error.max())} (mu = 0.6), above 1e-3 from t = {crossing:.2f} on "
        f"(errors sampled every 0.05 time units)",
        f"partly reproduced: holds for the invariants and for the other orbits' positions, not "
        f"for the ellipse's position (above 1e-3 from t = {crossing:.2f} on)",
        "partly", "02_cannonball", "How large are the errors?")


def rigid_body_below_1e3(m):
    drift, rigid = m.drift, m.rigid
    return row(
        "Sec. 5, Fig. 2b", "the errors do not exceed 1e-3; rigid body: the method does \"quite "
        "well\", within a \"nominal tolerance\"",
        f"started with the rates Euler's equations give: energy error "
        f"{sci(drift.loc['spline', 'energy_error_t80'])} at "
        f"t = 80, growing linearly ({sci(drift.loc['spline', 'energy_error_t800'])} at t = 800, "
        f"growth ratio {drift.loc['spline', 'growth_ratio']:.1f} over eight parts of the run); "
        f"angular-velocity error {sci(rigid.loc['consistent', 'solution_error_spline'])}. "
        f"Started with the report's printed rates ($\\mathrm{{d}}\\omega/\\mathrm{{d}}t = 0$): the "
        f"energy varies by "
        f"{sci(rigid.loc['printed', 'energy_change_spline'])}, "
        f"as along a DOP853 solution of the same equations "
        f"({sci(rigid.loc['printed', 'energy_change_reference'])})",
        "reproduced for the report's run; the energy error is not bounded (this second-order "
        "form is not conservative), and the printed case's energy variation belongs to the "
        "equations",
        "reproduced", "03_rigid_body", "Figure 2b")


def error_follows_orbit(m):
    location = m.cannonball_error_location.set_index("quantity").value
    a, e = m.elements[0.6]["a"], m.elements[0.6]["eccentricity"]
    return row(
        "Sec. 5", "the cannonball error follows the orbit; the spline has more difficulty where "
        "the curvature is high",
        f"mu = 0.6, largest value near periapsis (r < 1.5) over largest near apoapsis (r > 4.5): "
        f"energy-error rate {sci(location['energy_rate_ratio_arcs'])}; path curvature "
        f"{location['curvature_ratio_arcs']:.2f} (equal at both apsides; the smallest curvature, "
        f"{location['min_curvature']:.3f} per unit length, at r = {location['r_min_curvature']:.2f}; "
        f"correlation of the logarithms with the rate {location['log_correlation_rate_curvature']:.2f}); "
        f"acceleration $\\lvert x''\\rvert = \\mu/r^2$ {location['acceleration_ratio_arcs']:.0f} "
        f"({location['acceleration_ratio_apsides']:.0f} between the apsides, r = "
        f"{a * (1 - e):.0f} and {a * (1 + e):.0f}; "
        f"correlation of the logarithms {location['log_correlation_rate_acceleration']:.2f}); $\\lvert x''''\\rvert$ "
        f"{sci(location['x4_ratio_arcs'])} (correlation of the logarithms "
        f"{location['log_correlation_rate_x4']:.2f}). "
        f"{location['energy_variation_share_r_lt_1_5']:.0%} of the energy-error variation at "
        f"r < 1.5 ({location['time_share_r_lt_1_5']:.0%} of the time, both over t in [0, 50], "
        f"which holds two periapsis passages). The energy error is a plateau "
        f"({sci(location['energy_error_apoapsis'])} at apoapsis) that returns to "
        f"{sci(location['energy_error_next_periapsis'])} at the next periapsis; the position "
        f"error peaks at {sci(location['max_position_error'])} at t = "
        f"{location['t_max_position_error']:.2f} (r = {location['r_max_position_error']:.2f})",
        "partly reproduced: the error follows the orbit; if curvature means the path's, as the "
        "sentence about the orbit reads, no (the path is as curved at apoapsis, where the error "
        "does not change); if it means the solution's, as 'difficult curvatures in the function' "
        "in the report's next paragraph reads, yes (the energy error changes where the "
        "acceleration is largest, near periapsis, though far faster than it grows); the energy "
        "error stays bounded (a modified energy is conserved)",
        "partly", "02_cannonball", "Where along the orbit does the error change?")


def second_order(m):
    return row(
        "Sec. 4, Fig. 3", "second-order convergence (cannonball)",
        f"fitted slopes {m.spline_slopes.min():.3f} to {m.spline_slopes.max():.3f} for all four "
        f"orbits and the rigid body, dt = 0.08 to 0.000625, against exact solutions",
        "reproduced", "reproduced", "04_convergence", "Figure 3")


def against_rk4(m):
    slopes = m.convergence_slopes
    rk4_slopes = slopes[slopes.method == "rk4"].slope
    ratios = (m.spline[ERRORS] / m.rk4[ERRORS]).stack()
    return row(
        "(none)", "the spline against RK4 at the same step (the report draws both, without a "
        "verdict)",
        f"at dt = 0.01 RK4's errors are {ratios.min():.0f} to {sci(ratios.max(), 1)} times "
        f"smaller (energy, angular momentum, position; all four orbits); RK4 spends "
        f"{(m.rk4.nfev / m.rk4.nstep).max():.2f} evaluations per step, the spline "
        f"{m.per_step.min():.2f} to {m.per_step.max():.2f}, so the same step is not the same "
        f"work; RK4 slopes {rk4_slopes.min():.2f} to {rk4_slopes.max():.2f}",
        "a finding beyond the report (it states the comparison, not its result): RK4 is more "
        "accurate on every measure",
        "beyond the report", "02_cannonball", "How large are the errors?")


def stable(m):
    phase = m.method_phase_error
    spline_rho = np.max(np.abs(phase.amplitude_factor_spline - 1))
    rk4_stable = phase[phase.omega_h < 2 * np.sqrt(2)].amplitude_factor_rk4
    rk4_unstable = phase[phase.omega_h > 2 * np.sqrt(2)].amplitude_factor_rk4
    spline_factor = "to within 1e-12" if spline_rho < 1e-12 else f"to {sci(spline_rho)}"
    return row(
        "Sec. 5", "the method is stable (inferred from its convergence)",
        f"convergent at order 2 (slopes above), i.e. zero-stable as $h \\to 0$. Linear stability "
        f"is conditional: on $y'' = -\\omega^2 y$ the spline's amplification factor is 1 (no "
        f"damping) {spline_factor} for $\\omega h$ up to {phase.omega_h.max():.2f}, below its limit "
        f"$\\sqrt{{12}} = {np.sqrt(12):.2f}$. RK4's factor is below 1 for every $\\omega h$ below "
        f"its limit $2\\sqrt{{2}} = {2 * np.sqrt(2):.2f}$ (it damps, "
        f"$\\lvert R\\rvert = (1 - x^6/72 + x^8/576)^{{1/2}}$ with "
        f"$x = \\omega h$, least at $x = \\sqrt{{6}}$ where $\\lvert R\\rvert = 0.5$; measured "
        f"{rk4_stable.min():.3f} at the nearest sampled $\\omega h$, "
        f"{phase.omega_h[rk4_stable.idxmin()]:.2f}; 1 - {sci(1 - rk4_stable.max())} at "
        f"$\\omega h = {phase.omega_h.min():.2f}$) and above 1 beyond it "
        f"($\\lvert R\\rvert$ up to {rk4_unstable.max():.2f}, "
        f"at $\\omega h = {phase.omega_h.max():.2f}$). The "
        f"fixed-point sweep needs $\\omega h < \\sqrt{{6}} = {np.sqrt(6):.2f}$",
        "reproduced in the report's sense (convergence); linear stability is conditional, "
        "as for RK4, and without RK4's damping",
        "reproduced", "01_method", "Stability and period error")


def reaches_tolerance(m):
    ev = m.evaluations
    return row(
        "Sec. 6", "reaches desired tolerance levels; needs improvement to be a viable solver",
        f"evaluations for a max error of 1e-3 on the ellipse (interpolated on the "
        f"work-precision curves): spline {ev('spline (1 sweep)', 1e-3)} with one sweep, "
        f"{ev('spline (converged)', 1e-3)} iterated; RK4 {ev('RK4', 1e-3)}; "
        f"scipy DOP853 {ev('scipy DOP853', 1e-3)}. For 1e-6: spline with one sweep "
        f"{ev('spline (1 sweep)', 1e-6)}; RK4 {ev('RK4', 1e-6)}; DOP853 "
        f"{ev('scipy DOP853', 1e-6)}",
        "reproduced: it converges, but is not competitive",
        "reproduced", "04_convergence", "The same work elsewhere")


def proof(m):
    c = m.constant
    return row(
        "Sec. 5", "a formal proof of convergence may lend insight",
        "the $y_n$ obey the two-step method $\\rho(\\zeta) = (\\zeta - 1)^2$, "
        "$\\sigma(\\zeta) = (\\zeta^2 + 4\\zeta + 1)/6$ (sympy), order 2, error constant "
        "$-1/12$, zero-stable; with starting errors $O(h^3)$ "
        "($y_0$ exact, $y_1$ from one step) Henrici's theorem gives order 2. Constants against "
        "measurements: local error of y "
        f"{c(LOCAL_ERROR)}; period error {c(PERIOD_ERROR)}; stability limit "
        f"$\\sqrt{{12}}$ {c(STABILITY_LIMIT, 10)} (stable for $\\omega h < \\sqrt{{12}}$ only: "
        f"at the limit a Jordan block, $\\lvert y_{{1000}}\\rvert$ {c(AT_LIMIT)} from "
        f"$(y, h y') = (0, 1)$)",
        "proved (notebooks/05_theory)",
        "proved", "05_theory", "The two-step recurrence, its order, and the convergence theorem")


def higher_degree(m):
    degrees = m.higher_degree_roots.set_index("degree")
    return row(
        "Sec. 5", "higher-order polynomial splines with more continuity may do better",
        f"degree 4 ($C^3$): extra root -1, order {degrees.loc[4, 'fitted_order_ellipse']:.2f} on the "
        f"ellipse but weakly stable (a parasitic mode that damping makes grow); degree 5 and 6: "
        f"spurious roots of modulus {degrees.loc[5, 'largest_spurious_root']:.3f} and "
        f"{degrees.loc[6, 'largest_spurious_root']:.3f} (errors grow by "
        f"{degrees.loc[5, 'measured_growth_per_step']:.3f} and "
        f"{degrees.loc[6, 'measured_growth_per_step']:.3f} per step)",
        "built: degree 4 raises the order (to 4 on the ellipse, when started with the exact "
        "$y'''(0)$; from $y'''(0) = 0$ its error is about the cubic's) but is only weakly stable (a "
        "parasitic mode that damping makes grow); degrees 5 and 6 diverge for every h (as "
        "Loscalzo and Talbot 1967 found for $y' = f$)",
        "built", "06_higher_degree", "Degree k, k - 1 continuous derivatives")


def bounded_energy(m):
    long_drift, phase_drift = m.long_drift, m.phase_drift
    converged = phase_drift.loc[["spline", "Verlet"]]
    rk4 = long_drift.loc["RK4, same work"]
    one_sweep = long_drift.loc["spline, 1 sweep"]
    agreement = np.max(np.abs(converged.drift_from_passages / converged.drift_from_angle - 1))
    return row(
        "(none)", "the energy error stays bounded (cannonball)",
        f"10,000 orbits of the ellipse at dt = 0.01: energy-error growth exponent "
        f"{outputs.signed(long_drift.loc['spline', 'energy_exponent'])} (Verlet "
        f"{outputs.signed(long_drift.loc['Verlet', 'energy_exponent'])}, each method measured at "
        f"its own steps); RK4 at the same work drifts linearly from the first orbit, "
        f"{sci(rk4.energy_error_start, 3)} + {sci(rk4.energy_drift_per_orbit, 3)} per orbit "
        f"(exponent {rk4.energy_exponent:.2f} from orbit 100 on); "
        f"final energy error {sci(long_drift.loc['spline', 'final_energy_error'])} against RK4's "
        f"{sci(rk4.final_energy_error)}. With one fixed-point "
        f"sweep per step the energy error drifts: "
        f"{sci(one_sweep.final_energy_error)} after 10,000 orbits "
        f"(exponent {one_sweep.energy_exponent:.2f}) downwards, and the "
        f"period shortens with it (mean $T_h/T - 1$ over 200 orbits "
        f"{sci(phase_drift.loc['spline, 1 sweep', 'period_error'])}). The "
        f"position is not bounded: the polar angle, averaged over each orbit, lags by "
        f"{sci(-phase_drift.loc['spline', 'drift_from_angle'])} rad per orbit (Verlet "
        f"{sci(-phase_drift.loc['Verlet', 'drift_from_angle'])}), measured against the exact "
        f"solution and, to a relative {sci(agreement, 1)}, from the periapsis passages alone",
        "a finding beyond the report: the method is Verlet in the variables $q - h^2 f(q)/6$, "
        "so a modified energy is conserved and the energy error does not drift over 10,000 "
        "orbits; the phase drifts; this holds for the step equation solved to convergence, not "
        "for one sweep per step",
        "beyond the report", "08_long_time", "10,000 orbits of the ellipse")


def against_verlet(m):
    by_method = {k: g.set_index("dt") for k, g in m.second_order_work.groupby("method")}
    same_step = by_method["spline"].max_error / by_method["verlet"].max_error
    cost = by_method["spline"].nfev / by_method["verlet"].nfev
    return row(
        "(none)", "the spline stepper against Stormer-Verlet",
        f"ellipse (mu = 0.6 only), t in [0, 50], dt = 0.08 to 0.000625: at the same step the "
        f"spline's error is "
        f"{outputs.span((same_step.min(), same_step.max()), decimals=2)} times Verlet's at "
        f"{outputs.span((cost.min(), cost.max()), decimals=2)} times its evaluations (iterated "
        f"to convergence); at equal evaluations {outputs.span(m.equal_work)} times; with one "
        f"sweep per step, one evaluation per step as Verlet, "
        f"{outputs.span(m.one_sweep_equal_work)} "
        f"times over t in [0, 50] (over 10,000 orbits one sweep's energy error drifts, "
        f"Verlet's does not)",
        "on this orbit Verlet wins at equal work against the spline iterated to convergence "
        "(the same method in other variables); the other orbits were not measured",
        "beyond the report", "04_convergence", "Where Verlet's advantage comes from")


def adaptability(m):
    """The improvements the report suggests (notebooks 07 and 11)."""
    gain_one, gain_iter = m.adaptive_gain("1 sweep"), m.adaptive_gain("iterated")
    others = ("harmonic oscillator", "forced Duffing", "pendulum, 3 rad", "rational, backwards")

    def cost(problem, adaptive="spline", uniform="iterated"):
        return " to ".join(tolerance.ratio_text(v)
                           for v in m.adaptive_cost(problem, adaptive, uniform))
    one_sweep = [m.adaptive_cost(p, "spline", "1 sweep") for p in others]
    uniform_cheaper = min(lo for lo, _ in one_sweep) > 1
    cost_table = m.tolerance_cost
    matched_rtols = cost_table[(cost_table.problem == "Kepler e = 0.9")
                               & cost_table.ratio.notna()].rtol
    rtol_span = " to ".join(f"1e{round(np.log10(r))}"
                            for r in (matched_rtols.max(), matched_rtols.min()))
    estimate = m.adaptive_estimate
    # Steps whose true local error is below rounding (notebook 07) are left out.
    estimate = estimate[estimate.true > 1e-12]
    pleiades = m.pleiades_steps
    # The uniform runs this claim states: h >= 1e-3 (notebook 11 also runs smaller steps).
    uniform_h = pleiades.run.str.extract(r"^uniform h = (.*)$")[0].astype(float)
    pleiades = pleiades[~(uniform_h < 1e-3)]
    adaptive = pleiades[pleiades.run.str.startswith("adaptive")]
    failing = pleiades[pleiades.status != 0]
    reached = pleiades[pleiades.run.str.startswith("uniform") & (pleiades.status == 0)]
    steps_tried = ", ".join(f"{v:g}" for v in sorted(
        {float(run.split("= ")[1]) for run in pleiades.run if run.startswith("uniform")}))
    over_rtol = adaptive.error / adaptive.run.str.split("= ").str[1].astype(float)
    variable = m.variable_step_energy
    controlled = variable[variable.method.str.startswith("adaptive")]
    wandering = controlled.energy_error
    # The reversible run whose work per orbit is nearest the error-controlled run's.
    runs_ = variable[variable.method.str.startswith("reversible")]
    nearest = runs_.method[(runs_.nfev_per_orbit - controlled.nfev_per_orbit.iloc[0]).abs().idxmin()]
    reversible = runs_[runs_.method == nearest].energy_error
    newton = m.newton_reuse
    uniform_fine = newton[(newton.run == "uniform h = 0.0001")
                          & (newton.method == "fixed-point sweep")]
    adaptive_coarse = adaptive[adaptive.run == "adaptive rtol = 0.0001"]
    per_step = newton.assign(per_step=newton.nfev / newton.nstep).pivot(
        index="run", columns="method", values="per_step")
    kept_over_sweep = per_step["kept matrix"] / per_step["fixed-point sweep"]
    runs = m.tolerance_proportionality
    spline = runs[runs.method == "spline"]
    slopes = [tolerance.slope(g.rtol, g.error) for _, g in spline.groupby("problem")]
    problems_measured = spline.problem.nunique()
    one_sweep = runs[runs.method == "spline, 1 sweep"]
    worst_one_sweep = one_sweep.loc[one_sweep.error_ratio.idxmax()]
    return row(
        "Sec. 5", "improved accuracy through adaptability",
        f"adaptive knots from the jump of the spline's third derivative (estimate / true local "
        f"error: median {np.median(estimate.estimated / estimate.true):.2f} along "
        f"a Kepler orbit e = 0.9); rtol bounds the final error (error per unit step): on "
        f"{problems_measured} problems over rtol = 1e-3 to 1e-8 the final error "
        f"of y is at most {spline.error_ratio.max():.2f} times rtol times the "
        f"solution's scale (of y' {spline.error_ratio_yp.max():.1f} times), falling "
        f"with rtol at slopes {min(slopes):.2f} to {max(slopes):.2f}; on that "
        f"orbit the uniform step needs {outputs.span(gain_one)} times the "
        f"evaluations for the same final error with one sweep per step, {outputs.span(gain_iter)} "
        f"times iterated to convergence (uniform runs matched to each adaptive run's final "
        f"error, rtol {rtol_span}). "
        f"Pleiades (seven stars in the plane, Hairer, Norsett and Wanner's PLEI, to t = 3): "
        f"uniform steps fail at h = "
        f"{', '.join(sorted(set(failing.run.str.split('= ').str[1])))}; the others reach "
        f"t = 3 with errors {reached.error.min():.2f} to "
        f"{reached.error.max():.1f}, all flagged as too large a step; adaptive "
        f"runs reach t = 3 (errors {sci(adaptive.error.min())} to "
        f"{sci(adaptive.error.max())}); a step equation that fails is retried smaller "
        f"(shown on $y'' = -y$ from a first step of 3; no adaptive Pleiades run needed it). Over "
        f"300 orbits the adaptive energy error (rtol 0.1) goes from {sci(wandering.iloc[0], 1)} to "
        f"{sci(wandering.iloc[-30:].max(), 2)}; time-reversible steps (Hairer and Soderlind) at the "
        f"same work per orbit keep it at {sci(reversible.mean())}. Newton keeping its Jacobian and LU factors across "
        f"iterations and steps, on accurate Pleiades runs "
        f"(uniform h = 1e-4, adaptive rtol = 1e-6): "
        f"{per_step['full Newton'].min():.1f}-{per_step['full Newton'].max():.1f} -> "
        f"{per_step['kept matrix'].min():.2f}-{per_step['kept matrix'].max():.2f} "
        f"evaluations per step, {kept_over_sweep.min():.2f} to {kept_over_sweep.max():.2f} times "
        f"the default fixed-point sweep's",
        f"built: rtol bounds the final error of y (below rtol times the solution's scale on "
        f"{problems_measured} problems, as measured in notebook 07, with each step iterated to "
        f"convergence; with one sweep per step up to {worst_one_sweep.error_ratio:.2f} times on "
        f"the {worst_one_sweep.problem}; "
        f"not on Pleiades, whose close encounters amplify errors: "
        f"{outputs.span((over_rtol.min(), over_rtol.max()))} times rtol); "
        f"{outputs.span(gain_one)} times fewer evaluations on an "
        f"eccentric orbit with one "
        f"sweep per step ({outputs.span(gain_iter)} iterated), over one period of e = 0.9; of the "
        f"uniform Pleiades runs tried (h = {steps_tried}) none is usable, while uniform "
        f"h = 1e-4 reaches t = 3 with error {sci(uniform_fine.error.min())}, unflagged, at "
        f"{uniform_fine.nfev.min() / adaptive_coarse.nfev.min():.1f} times the evaluations of "
        f"adaptive rtol 1e-4 (error {sci(adaptive_coarse.error.min())}); where the solution's "
        f"scale varies less the gain is small or negative (notebook 07, both runs iterated to "
        f"convergence: adaptive knots cost {cost(others[0])} times the uniform evaluations on "
        f"the oscillator, {cost(others[1])} on the forced Duffing oscillator, {cost(others[2])} "
        f"on the pendulum and {cost(others[3])} on the rational problem; against a uniform "
        f"run with one sweep per step, {cost(others[0], uniform='1 sweep')} on the oscillator, "
        f"the uniform step is {'cheaper on all four' if uniform_cheaper else 'not always cheaper'}"
        f"); on the Kepler "
        f"orbit e = 0.9 over 300 orbits reversible steps keep the energy error bounded where "
        f"error-controlled knots do not; keeping "
        f"Newton's matrix saves only against full Newton, not against the sweep",
        "built", "07_adaptive_steps", "Adaptive knots")


def higher_order(m):
    orders = m.composition_orders
    curves = {k: (g.nfev.to_numpy(), g.max_error.to_numpy())
              for k, g in m.composition_work.groupby("method")}
    long_runs = {k: g.set_index("orbit") for k, g in m.composition_energy.groupby("method")}
    order4_energy = long_runs["spline, order 4"].energy_error
    rk4_long = long_runs["RK4, same work"]
    first_above = np.flatnonzero(rk4_long.energy_error.to_numpy() > order4_energy.max())[0]
    rk4_crossing = diagnostics.loglog_interp(
        rk4_long.energy_error.iloc[first_above - 1:first_above + 1],
        rk4_long.index[first_above - 1:first_above + 1], [order4_energy.max()])[0]
    rich = diagnostics.work_ratio_range(curves["Richardson (order 2 at h, h/2)"],
                                        curves["spline, order 4"])
    rk4_4 = diagnostics.work_ratio_range(curves["RK4"], curves["spline, order 4"])
    rk4_6 = diagnostics.work_ratio_range(curves["RK4"], curves["spline, order 6"])
    dop_6 = diagnostics.work_ratio_range(curves["scipy DOP853"], curves["spline, order 6"])

    def slopes(order, column):
        return outputs.span(orders[orders.order == order][column].agg(["min", "max"]), decimals=2)

    return row(
        "(none)", "higher order by symmetric composition of the step",
        f"symmetric compositions of the spline step (Yoshida): fitted slopes "
        f"{slopes(4, 'slope')} (order 4) and {slopes(6, 'slope')} "
        f"(order 6) on the four cannonball orbits and the rigid body (successive differences of "
        f"the runs: {slopes(4, 'successive_slope')} and {slopes(6, 'successive_slope')}); "
        f"ellipse at dt = 0.01: {sci(m.ellipse_order_4)} (order 4; order 6 is at a floor there). "
        f"10,000 orbits at dt = 0.08: order-4 energy error "
        f"{outputs.span((order4_energy.min(), order4_energy.max()), digits=3)} "
        f"in every sampled orbit, without growth (order 6 not run that long); RK4 at the same "
        f"work starts at "
        f"{sci(rk4_long.energy_error.iloc[0])}, grows, and passes it from orbit "
        f"{outputs.round_sig(rk4_crossing, 3):,.0f} on; RK4's position error is "
        f"{sci(long_runs['spline, order 4'].position_error.iloc[0] / rk4_long.position_error.iloc[0])} "
        f"times smaller in the first orbit, until both lose the phase. Over t in [0, 50] "
        f"Richardson extrapolation needs {outputs.span(rich)} times the evaluations of order 4, "
        f"RK4 {outputs.span(rk4_4)} times those of order 4 and {outputs.span(rk4_6)} times those "
        f"of order 6, DOP853 {outputs.span(dop_6)} times those of order 6",
        "a finding beyond the report (what it suggests for higher order is higher-degree "
        "splines), "
        "built: order 4 and 6; order 4 keeps a bounded energy error over 10,000 orbits (order 6 "
        "was not run that long); over t in [0, 50] order 4 costs more "
        "than RK4, order 6 as much at low accuracy and less at high (ellipse), and DOP853 is "
        "cheaper than both; over "
        "10,000 orbits at equal work RK4 is more accurate in position than order 4 until both "
        "have lost the phase, and in energy "
        "for the first thousands of orbits",
        "beyond the report", "10_higher_order", "Order 4 and 6 by symmetric composition")


def global_sweep(m):
    runs = m.global_sweep
    analytic = runs[runs.jacobian == "analytic"]
    fd = runs[runs.jacobian != "analytic"]

    def ratio(frame):
        return outputs.span((frame.nfev / frame.nfev_stepwise).agg(["min", "max"]), decimals=1)

    return row(
        "Sec. 5", "all knots' coefficients at once, by Newton's method with an LU "
        "factorisation",
        f"all knots solved at once (sparse banded LU of the whole trajectory): the stepwise "
        f"solution "
        f"to {sci(runs.max_difference.max(), 1)} in "
        f"{runs.newton_iterations.min()} to {runs.newton_iterations.max()} "
        f"Newton iterations; analytic Jacobian: {ratio(analytic)} "
        f"times the stepwise F evaluations and "
        f"{' and '.join(f'{j:,} ({p})' for j, p in zip(analytic.njev, analytic.problem))} "
        f"Jacobian evaluations against {analytic.njev_stepwise.max() - 4} for the stepwise "
        f"kept matrix ({analytic.njev_stepwise.max()} with the checks at t0 and of the "
        f"step size); finite-difference Jacobian: {ratio(fd)} times the stepwise F evaluations",
        "built; it gives the same solution and does not pay on one processor (a "
        "parallel-in-time structure); its use is boundary value problems",
        "built", "09_global_sweep_and_bvp", "The single Newton-LU sweep")


def boundary_value_problems(m):
    bratu = m.bvp_bratu
    orders = {b: np.polyfit(np.log(g.h), np.log(g.error), 1)[0] for b, g in bratu.groupby("branch")}
    per_node = np.concatenate([
        diagnostics.loglog_interp(g.points, g.error, g.scipy_points) / g.scipy_error
        for _, g in bratu.groupby("branch")])
    runs = m.bvp_tolerance
    estimate_over_true = runs.estimated_error / runs.true_error
    return row(
        "(none)", "boundary value problems",
        f"solve_bvp: Bratu ($\\lambda = 1$) both branches from the guesses $0.1 \\sin(\\pi x)$ and "
        f"$4 \\sin(\\pi x)$, fitted orders {orders['lower']:.2f} and {orders['upper']:.2f} "
        f"against the exact solutions; scipy's solve_bvp (4th order, mesh refinement, tol 1e-8, "
        f"up to 100,000 nodes: {'converged' if set(bratu.scipy_status) == {0} else 'not converged'} "
        f"in every run) uses {bratu.scipy_points.min()} to {bratu.scipy_points.max()} nodes for "
        f"errors {sci(bratu.scipy_error.min(), 1)} to {sci(bratu.scipy_error.max(), 1)}; at the "
        f"same number of nodes the spline's error is {sci(np.nanmin(per_node), 1)} to "
        f"{sci(np.nanmax(per_node), 1)} times larger. With tol, the mesh is refined where "
        f"the error is largest until the error estimated by mesh halving is within it: lower branch from 11 points, tol "
        f"{', '.join(f'{v:g}' for v in runs.tol)} end on "
        f"{', '.join(str(v) for v in runs.points)} points, the estimate "
        f"{estimate_over_true.min():.3f} to {estimate_over_true.max():.3f} times the true error",
        "a finding beyond the report: the global sweep, built, solves them by second-order "
        "spline collocation, far less accurate per node than scipy's, with "
        "a tolerance on the solution (estimated by mesh halving); a run without solution ends as failed, "
        "with a message, and so does a problem whose solution does not converge with the mesh "
        "($y'' = -y$, $y(0) = 0$, $y(\\pi) = 1$, which has none)",
        "beyond the report", "09_global_sweep_and_bvp", "Boundary value problems")


def _leading(series):
    """The lowest-order term of a series written by sympy (data/family-members.csv), as LaTeX."""
    import sympy as sp
    omega = sp.Symbol("Omega")
    terms = sp.sympify(series).as_ordered_terms()
    coefficient, power = min(terms, key=lambda t: sp.degree(t, omega)).as_coeff_exponent(omega)
    coefficient = sp.Rational(coefficient)
    sign = "-" if coefficient < 0 else ""
    top = "" if abs(coefficient.p) == 1 else str(abs(coefficient.p))
    return f"{sign}{top}(\\omega h)^{{{power}}}/{coefficient.q}"


def newmark_family(m):
    members = m.family_members.set_index("member")
    errors = m.family_report_problems.pivot(index="member", columns="problem", values="error")
    cannon = errors[[c for c in errors.columns if c.startswith("cannonball")]]
    spread = (cannon.max() / cannon.min()).max()
    rigid = errors["rigid body"]
    chain = m.family_chain.set_index(["m", "member"]).nstep
    sizes = sorted({size for size, _ in chain.index})
    ratios = [chain[(size, "spline")] / chain[(size, "average-acceleration")] for size in sizes]
    return row(
        "(none)", "the report's member of Newmark's family (linear acceleration) against its "
        "neighbours",
        f"period error on $y'' = -\\omega^2 y$ to leading order "
        f"${_leading(members.period_error['spline'])}$ for the report's member, "
        f"${_leading(members.period_error['average-acceleration'])}$ for average "
        f"acceleration (sympy); stability limit $\\omega h$ < "
        f"{members.limit['spline']:.3f} (Fox-Goodwin {members.limit['fox-goodwin']:.3f}; "
        f"average acceleration, HHT and generalized-$\\alpha$ none). At the report's steps the "
        f"six members' largest errors on each cannonball orbit lie within a factor of "
        f"{spread:.1f} of each other; on the rigid body Fox-Goodwin's is "
        f"about {outputs.round_sig(rigid['spline'] / rigid['fox-goodwin'], 1):.0f} times below "
        f"the report's member's, "
        f"average acceleration's {rigid['average-acceleration'] / rigid['spline']:.1f} times "
        f"above. On the chain of m masses, the slowest mode to a phase error of 1e-3, the "
        f"report's member takes {' and '.join(f'{r:.1f}' for r in ratios)} times average "
        f"acceleration's steps at m = {' and '.join(f'{size:,}' for size in sizes)}, a ratio "
        f"that grows like m",
        "a finding beyond the report: its member is not the best of its family on its own "
        "problems (none is best on all; where the period error decides, Fox-Goodwin is, at "
        "the same cost); what it has of its own is the spline, a C2 cubic through its knots, "
        "and the largest stability limit of the named conditionally stable members with half "
        "average acceleration's period error. For a discretised structure, whose fast modes "
        "need no resolution, an unconditionally stable member is the better choice at the "
        "accuracy structural analysis asks of the slow modes (here a phase error of 1e-3); "
        "where more is wanted than the report's member reaches at its stability limit, its "
        "half period error should make it cheaper than average acceleration (inferred, not "
        "run), and Fox-Goodwin, with 1.4 times its steps, is far more accurate still",
        "beyond the report", "13_newmark_family", "Verdict")


# The claims in the order of the table: the report's, then the findings beyond it.
CLAIMS = (orbit_types, solves_both, cannonball_below_1e3, rigid_body_below_1e3,
          error_follows_orbit, second_order, against_rk4, stable, reaches_tolerance, proof,
          higher_degree, bounded_energy, against_verlet, adaptability, higher_order,
          global_sweep, boundary_value_problems, newmark_family)


def claims_table(measured=None):
    """The claims table: one row per function of :data:`CLAIMS`."""
    measured = Measured() if measured is None else measured
    return pd.DataFrame([claim(measured) for claim in CLAIMS])


def eq9_first_zero(h=0.01):
    """Where the first zero of y'' = -y, y(0) = 1, y'(0) = 0 (pi/2) lands when
    the spline step solves y'' = 2F, as eq. 9 as printed computes: the zero
    interpolated linearly between the knots either side of it (to O(h^2))."""
    import splinestep
    oscillator = problems.harmonic(1.0, t_span=(0.0, 20.0), h=h)
    printed = splinestep.solve(lambda t, y, yp: 2 * oscillator.fun.py_func(t, y, yp, 1.0),
                               oscillator.t_span, oscillator.y0, oscillator.yp0, h)
    below = np.argmax(printed.y[0] < 0)  # the first knot past the first zero
    (t_a, t_b), (y_a, y_b) = printed.t[below - 1:below + 1], printed.y[0, below - 1:below + 1]
    return t_a - y_a * (t_b - t_a) / (y_b - y_a)


def errata_table(measured=None, crossing=None):
    """The errata: where, the erratum, and the evidence.  ``crossing`` is
    :func:`eq9_first_zero` (computed if None)."""
    m = Measured() if measured is None else measured
    crossing = eq9_first_zero() if crossing is None else crossing
    t = np.linspace(0, 50, 2001)
    spread = {mu: np.ptp(kepler.energy_as_printed(*problems.kepler_exact(t, mu)))
              for mu in problems.CANNONBALL_MU}
    work = m.work_precision
    at_001 = np.isclose(work.setting, 0.01)
    one_sweep = work[(work.method == "spline (1 sweep)") & at_001].max_error.item()
    converged = work[(work.method == "spline (converged)") & at_001].max_error.item()
    body = problems.rigid_body("consistent")
    rigid, long_drift = m.rigid, m.long_drift
    return pd.DataFrame([
        ("eq. 9", "$c_{i+1} = r - p\\thinspace b_{i+1} - q\\thinspace a_{i+1}$ lacks the factor "
         "$1/2$ of eq. 5 ($c$ is half the second derivative)",
         f"taken literally it solves $y'' = 2F$: solved as that equation, $y'' = -y$ has its first zero moved from "
         f"$\\pi/2 = {np.pi / 2:.3f}$ to {crossing:.3f} "
         f"($\\pi/(2\\sqrt{{2}}) = {np.pi / (2 * np.sqrt(2)):.3f}$)"),
        ("eq. 13", "the energy omits $\\mu$: $H = v^2/2 - \\mu/r$",
         "along the exact orbits, eq. 13 as printed varies by "
         + ", ".join(f"{spread[mu]:.2f} ($\\mu = {mu:g}$)" for mu in problems.CANNONBALL_MU)),
        ("eq. 15", "$\\beta$ is never defined", "differentiating Euler's equations gives eq. 15 "
         "with $\\beta = 0$; the exact Jacobi-elliptic motion satisfies eqs. 15-18 with "
         "$\\beta = 0$ (tests)"),
        ("Sec. 3.1", "the cannonball's initial values are not printed",
         "$x(0) = (1, 0)$, $x'(0) = (0, 1)$ reproduces the four named orbit types (energy "
         "$1/2 - \\mu$)"),
        ("Sec. 3.2", "$\\mathrm{d}\\omega/\\mathrm{d}t\\thinspace(0) = 0$ contradicts Euler's "
         "equations",
         f"they give $\\mathrm{{d}}\\omega/\\mathrm{{d}}t\\thinspace(0)$ = "
         f"({', '.join(f'{v:.2e}' for v in body.yp0)}); with the "
         f"printed rates the energy "
         f"of eq. 19 varies by {sci(rigid.loc['printed', 'energy_change_reference'])} along a "
         "DOP853 solution (rtol 1e-13) of the printed equations"),
        ("Sec. 2", "the number of fixed-point sweeps ('a few times') is unspecified",
         f"iterating to 1e-12 takes {m.per_step.min():.2f} to {m.per_step.max():.2f} evaluations "
         f"per step (one per sweep) on the cannonball at dt = 0.01 and "
         f"{rigid.loc['consistent', 'spline_evaluations_per_step']:.2f} on the rigid body at "
         f"dt = 0.016; one sweep keeps order 2 (max error {sci(one_sweep, 3)} against "
         f"{sci(converged, 3)} converged, $\\mu = 0.6$, $\\Delta t = 0.01$, $t \\in [0, 50]$) but is "
         f"another "
         f"method over long runs: its energy error drifts to "
         f"{sci(long_drift.loc['spline, 1 sweep', 'final_energy_error'])} over 10,000 orbits, "
         f"where the converged step's stays at "
         f"{sci(long_drift.loc['spline', 'final_energy_error'])}"),
        ("Sec. 2", "the scheme is derived for the linear eq. 4 but applied to nonlinear problems",
         "the same steps hold for $y'' = F(t, y, y')$; the implicit equation is then nonlinear"),
        ("Sec. 3.1", "$\\omega^2$ 'describes the gravitational constant'",
         "$\\omega^2 = \\mu/r^3$ varies along the orbit; $\\mu$ is the gravitational parameter"),
    ], columns=["where", "erratum", "evidence"])


def headline_numbers(measured=None):
    """The numbers the paper states in its prose: name, value and the text it
    prints (data/headline-numbers.csv)."""
    m = Measured() if measured is None else measured
    errors = m.cannonball_max_errors
    ellipse = errors[(errors.mu == 0.6) & (errors.method == "spline")].iloc[0]
    long_drift, phase_drift = m.long_drift, m.phase_drift
    spline, rk4 = long_drift.loc["spline"], long_drift.loc["RK4, same work"]
    one_sweep = long_drift.loc["spline, 1 sweep"]
    # RK4's energy error on its fitted line a + c (k - 1) reaches the spline's at orbit k:
    rk4_reaches_spline = 1 + ((spline.final_energy_error - rk4.energy_error_start)
                              / rk4.energy_drift_per_orbit)
    gain_one, gain_iter = m.adaptive_gain("1 sweep"), m.adaptive_gain("iterated")
    slopes = m.spline_slopes
    headline = [
        ("position error, ellipse, dt = 0.01", ellipse.position_error,
         sci(ellipse.position_error)),
        ("smallest spline slope", slopes.min(), f"{slopes.min():.3f}"),
        ("largest spline slope", slopes.max(), f"{slopes.max():.3f}"),
        ("energy growth exponent, spline", spline.energy_exponent,
         outputs.signed(spline.energy_exponent)),
        ("energy drift per orbit, RK4 same work", rk4.energy_drift_per_orbit,
         sci(rk4.energy_drift_per_orbit)),
        ("energy error in the first orbit, RK4 same work", rk4.energy_error_start,
         sci(rk4.energy_error_start)),
        ("energy error after 10,000 orbits, one sweep", one_sweep.final_energy_error,
         sci(one_sweep.final_energy_error)),
        ("orbit where RK4 would reach the spline's energy error", rk4_reaches_spline,
         f"{outputs.round_sig(rk4_reaches_spline, 2):,.0f}"),
        ("energy error after 10,000 orbits, spline", spline.final_energy_error,
         sci(spline.final_energy_error)),
        ("adaptive gain, one sweep", gain_one[0], outputs.span(gain_one)),
        ("adaptive gain, iterated", gain_iter[0], outputs.span(gain_iter)),
        ("order 4 error, ellipse, dt = 0.01", m.ellipse_order_4, sci(m.ellipse_order_4)),
        ("phase drift per orbit, spline", -phase_drift.loc["spline", "drift_from_angle"],
         sci(-phase_drift.loc["spline", "drift_from_angle"])),
        ("phase drift per orbit, Verlet", -phase_drift.loc["Verlet", "drift_from_angle"],
         sci(-phase_drift.loc["Verlet", "drift_from_angle"])),
        ("one sweep against Verlet at equal work", m.one_sweep_equal_work[0],
         outputs.span(m.one_sweep_equal_work, 2)),
        ("Verlet at equal work, smallest factor", m.equal_work[0], f"{m.equal_work[0]:.1f}"),
        ("Verlet at equal work, largest factor", m.equal_work[1], f"{m.equal_work[1]:.1f}"),
    ]
    return pd.DataFrame(headline, columns=["name", "value", "text"])


def glance(claims):
    """The claims one line each, as the notebook and the README show them:
    where, the claim, the kind of verdict, and the notebook section that
    measures it as (notebook, section) pairs in the column "measured in"."""
    return (claims[["where", "claim", "kind"]].rename(columns={"kind": "verdict"})
            .assign(**{"measured in": list(zip(claims.notebook, claims.section))}))


def readable(text):
    """``text`` as a reader reads it (:func:`outputs.readable`: 4.1 \u00d7 10\u207b\u00b3, \u03c9,
    \u221a12, \u0394t), its formulas between dollars left for MathJax."""
    return "".join(part if part.startswith("$") and part.endswith("$") and len(part) > 1
                   else outputs.readable(part) for part in re.split(r"(\$[^$]+\$)", text))


# The report in brief, the website's page of the report's equations, figures
# and claims by its own numbers: a heading for each of its sections (the
# report's numbers and titles), equations ("Eq. 9") and figures ("Fig. 2"),
# and one for the findings it does not make, whose anchors the tables link to.
REPORT_PAGE = "website/report.md"
REPORT_SECTIONS = {"1": "Introduction", "2": "Cubic spline time-stepping algorithm",
                   "3": "Test cases", "3.1": "Newton's cannonball",
                   "3.2": "Euler equations for rigid body rotation", "4": "Results",
                   "5": "Discussion", "6": "Conclusion"}
BEYOND_THE_REPORT = "Not in the report"


def anchor(heading):
    """The anchor GitHub and MyST (``myst_heading_anchors``) give a Markdown
    heading: its text without inline math (which MyST leaves out), code
    marks or emphasis marks, in lower case, spaces as hyphens, every
    character but letters, digits, ``_`` and ``-`` dropped ("Sec. 3.1
    Newton's cannonball": sec-31-newtons-cannonball).  A heading whose anchor
    an earlier heading of the page has takes "-1" (:func:`anchors`)."""
    text = re.sub(r"\$[^$]*\$", "", heading).replace("`", "").replace("*", "")
    return re.sub(r"[^\w\- ]", "", text.lower()).replace(" ", "-")


def anchors(headings):
    """The anchors of a page's headings (levels 1 to 3, in order), made unique
    as GitHub and MyST make them: a second "x" is "x-1", a third "x-2"."""
    found = []
    for heading in headings:
        base = unique = anchor(heading)
        count = 0
        while unique in found:
            count += 1
            unique = f"{base}-{count}"
        found.append(unique)
    return found


def report_heading(reference):
    """The heading of the report page that a reference of the column "where"
    leads to: "Sec. 3.1" to its section ("Sec. 3.1 Newton's cannonball"),
    "eq. 9" to "Eq. 9", "Fig. 2a" to "Fig. 2", "(none)" to
    :data:`BEYOND_THE_REPORT`."""
    if reference == "(none)":
        return BEYOND_THE_REPORT
    if (match := re.fullmatch(r"Sec\. (\d(?:\.\d)?)", reference)) and match[1] in REPORT_SECTIONS:
        return f"Sec. {match[1]} {REPORT_SECTIONS[match[1]]}"
    if match := re.fullmatch(r"[Ee]q\. (\d+)", reference):
        return f"Eq. {match[1]}"
    if match := re.fullmatch(r"Fig\. (\d)[ab]?", reference):
        return f"Fig. {match[1]}"
    raise ValueError(f"not a reference to the report's sections, equations or figures: "
                     f"{reference!r}")


@cache
def notebook_headings(notebook):
    """The headings of notebooks/NOTEBOOK.py that have anchors (levels 1 to
    3, as ``myst_heading_anchors = 3``), in order: (heading, anchor)."""
    import jupytext
    cells = jupytext.read(outputs.ROOT / "notebooks" / f"{notebook}.py").cells
    headings = [match[1] for cell in cells if cell.cell_type == "markdown"
                for match in re.finditer(r"^ {0,3}#{1,3}[ \t]+(.+?)[ \t]*$", cell.source, re.M)]
    return list(zip(headings, anchors(headings)))


def section_anchor(notebook, section):
    """The anchor of the heading of notebooks/NOTEBOOK that the column
    "section" names: the one whose text, without a leading number ("2. ")
    or the dollars of its math, is ``section``, or else the first that
    starts with it."""
    headings = [(re.sub(r"^\d+\. ", "", heading).replace("$", ""), found)
                for heading, found in notebook_headings(notebook)]
    for text, found in sorted(headings, key=lambda pair: pair[0] != section):
        if text.startswith(section):
            return found
    raise ValueError(f"no heading of notebooks/{notebook} starts with {section!r}")


def link(text, target, html=False):
    """A Markdown link, or (``html``) an HTML one."""
    if html:
        return f'<a href="{escape(target)}">{escape(text)}</a>'
    return f"[{text}]({target})"


def with_links(frame, root="", html=False):
    """``frame`` (the claims, :func:`glance` or the errata) with each
    reference of its column "where" ("Sec. 5, Fig. 2a": two) a link to its
    heading on the report page, and each (notebook, section) of its column
    "measured in" a link to that section, as Markdown or (``html``) HTML;
    ``root`` is the way from the table's document to the repository's root
    ("" for the README, "../" for a notebook)."""
    frame = frame.copy()
    frame["where"] = [", ".join(link(reference, f"{root}{REPORT_PAGE}#"
                                     f"{anchor(report_heading(reference))}", html)
                                for reference in where.split(", ")) for where in frame["where"]]
    if "measured in" in frame:
        frame["measured in"] = [
            link(f"{notebook[:2]}: {section}", f"{root}notebooks/{notebook}.ipynb#"
                 f"{section_anchor(notebook, section)}", html)
            for notebook, section in frame["measured in"]]
    return frame


def folded(html, summary):
    """``html`` inside a closed ``<details>`` element whose ``<summary>``
    reads ``summary``: one click opens it, in JupyterLab and on the site."""
    return (f'<details><summary style="cursor: pointer; font-weight: bold">{escape(summary)}'
            f"</summary>{html}</details>")


def table_html(frame, raw=()):
    """A table as JupyterLab shows it (:func:`outputs.html_table`), its
    notation readable (:func:`readable`: JupyterLab's MathJax typesets the
    formulas); the columns in ``raw`` are HTML already."""
    # the short columns keep a readable width; the long ones share the rest
    widths = {"where": "6em", "claim": "12em", "verdict": "8em", "measured in": "9em",
              "erratum": "16em", "measured": "18em", "why this verdict": "14em"}
    return outputs.html_table(frame, raw=raw, widths=widths, text=readable)
