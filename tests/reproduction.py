"""What a regenerated number must reproduce, decided once, from what it means.

Every column of every file in ``data/`` has a kind (:data:`COLUMNS`), and each
kind has one tolerance (:data:`TOLERANCES`).  :func:`compare_frames` is the only
comparison the data checks use; :func:`figures_match` the only one of figures,
:func:`notebook_difference` (nbval's rule) that of notebooks' printed text.
``make test`` applies them to a fresh run (tests/test_outputs.py, nbval), and
``make reproduce`` to what it rewrote, against git HEAD
(scripts/rerun_report.py).  The tolerances come from the meaning of the
numbers, not from the digits one machine printed:

``exact``
    Inputs (step sizes, gravity parameters, times, tolerances), labels and
    text built from measured numbers: the same values to the digits written
    (%.12g), the same strings.  Counts (steps, evaluations, points) are
    integers and compare equal.
``slope``
    Fitted orders, reported to three decimals: equal to 1e-3.
``state``
    Solution values (positions, angular velocities, radii).  Rounding in a
    run of up to 1e4 steps moves them by far less than 1e-9 of their scale;
    a change of the method moves them by the method's error (>= 1e-6 of the
    scale here), so they compare to 1e-9 of the column's largest value.
``error``
    Errors against a reference and changes of an invariant: differences of
    nearly equal numbers, whose rounding noise relative to themselves is
    about eps |solution| / |error|.  They compare to a relative 1e-4 (the
    2-3 digits quoted in the text, with margin), and below an absolute
    ROUNDING_FLOOR of 1e-12, which a double-precision run of O(1)
    quantities over 1e3-1e5 steps cannot reproduce (its own rounding).  A 1 %
    change of one coefficient of the scheme, or of the step, changes the
    spline's errors by 1-2 % and fails this (tests/test_reproduction_rule.py).
``adaptive``
    Errors and evaluation counts of scipy's adaptive baselines (RK45,
    DOP853 at a given tolerance): their step sequence is chosen from error
    estimates that are themselves rounded, so an accept/reject decision can
    flip on another CPU (measured: a relative 2.8e-3 in the error at rtol
    1e-11).  They compare to a relative 5e-2, which still separates one
    tolerance setting from the next (a factor of 10 apart).
``adaptive-long``
    The same over a long run (DOP853 over 1,000 orbits): once one decision
    has flipped, the two runs take different step sequences for the rest of
    the run, so their accumulated errors agree only in size.  Measured
    between an Intel AVX-512 and an AMD EPYC machine: invariant errors at
    late orbits 22 % apart, growth exponents 0.01 apart.  They compare to a
    factor of 2 (a drifting error grows by 1000 over the run, so a drift
    and a bounded error stay apart), exponents to 0.1.
``spectrum``
    The period error and damping ratio of a member of Newmark's family, read
    from an eigenvalue of its 3 x 3 amplification matrix (notebook 13).  The
    eigenvalue's angle is known to a few eps absolutely, so the period
    error Omega / theta - 1 to about 1e-12 at Omega = 0.01 (another CPU's
    eigenvalues moved a Fox-Goodwin value of -7.3e-11 by 1.3e-12): they
    compare to a relative 1e-6 and an absolute 1e-10, below which the
    values are that rounding.
"""

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

ROUNDING_FLOOR = 1e-12


@dataclass(frozen=True)
class Tolerance:
    rtol: float = 0.0        # relative to each value
    atol: float = 0.0        # absolute
    scale_rtol: float = 0.0  # relative to the largest |value| of the column
    factor: float = 0.0      # if set: positive values within this factor, others to atol

    def mismatch(self, old, new):
        """Boolean array: where ``new`` does not reproduce ``old``."""
        old = np.asarray(old, dtype=float)
        new = np.asarray(new, dtype=float)
        finite = np.abs(old[np.isfinite(old)])
        scale = finite.max() if finite.size else 0.0
        bound = self.rtol * np.abs(old) + self.atol + self.scale_rtol * scale
        both_nan = np.isnan(old) & np.isnan(new)
        with np.errstate(invalid="ignore"):   # inf - inf: equal infinities are compared below
            close = (np.abs(new - old) <= bound) | (old == new)
        if self.factor:
            with np.errstate(divide="ignore", invalid="ignore"):
                ratio = np.abs(np.log(new / old))
            positive = (old > 0) & (new > 0)
            close = np.where(positive, ratio <= np.log(self.factor), close)
        return ~both_nan & ~close


TOLERANCES = {
    "exact": Tolerance(rtol=1e-12),
    "slope": Tolerance(atol=1e-3),
    "state": Tolerance(scale_rtol=1e-9),
    "error": Tolerance(rtol=1e-4, atol=ROUNDING_FLOOR),
    "adaptive": Tolerance(rtol=5e-2, atol=ROUNDING_FLOOR),
    "adaptive-long": Tolerance(factor=2.0, atol=ROUNDING_FLOOR),
    "adaptive-long-exponent": Tolerance(atol=0.1),
    # Quantities a method conserves exactly, whose error is the rounding
    # accumulated over up to 4e7 steps (at most about N eps = 1e-8).
    "rounding": Tolerance(atol=1e-8),
    "spectrum": Tolerance(rtol=1e-6, atol=1e-10),
}

# file -> column -> kind.  Text columns are always compared as strings.
COLUMNS = {
    "cannonball-error-histories": dict(mu="exact", method="exact", t="exact", r="state",
                                       energy_error="error", momentum_error="error",
                                       position_error="error"),
    "cannonball-error-location": dict(quantity="exact", value="error"),
    "cannonball-max-errors": dict(mu="exact", method="exact", energy_error="error",
                                  momentum_error="error", position_error="error",
                                  nstep="exact", nfev="exact"),
    "cannonball-trajectories": dict(mu="exact", t="exact",
                                    **{f"{c}_{m}": "state" for c in "xy"
                                       for m in ("spline", "rk4", "exact")}),
    "convergence": dict(problem="exact", method="exact", dt="exact", nfev="exact",
                        max_error="error"),
    "convergence-slopes": dict(problem="exact", method="exact", slope="slope", points="exact"),
    "method-phase-error": dict(omega_h="exact", period_ratio_measured="state",
                               period_ratio_theory="state", amplitude_factor_spline="state",
                               amplitude_factor_rk4="state", amplitude_factor_rk4_theory="state",
                               estimated_local_error="error", step_flagged="exact"),
    "rigid-body-angular-velocity": dict(case="exact", t="exact",
                                        **{f"omega{i}_{m}": "state" for i in (1, 2, 3)
                                           for m in ("spline", "rk4", "reference")}),
    "rigid-body-energy-error": dict(case="exact", t="exact",
                                    **{f"{q}_{m}": "error"
                                       for q in ("energy_change", "solution_error")
                                       for m in ("spline", "rk4", "reference")}),
    "rigid-body-max-errors": dict(case="exact", spline_evaluations_per_step="exact",
                                  **{f"{q}_{m}": "error"
                                     for q in ("energy_change", "solution_error")
                                     for m in ("spline", "rk4", "reference")}),
    "work-precision": dict(method="exact", setting="exact", nfev="exact", max_error="error"),
    "work-to-reach": dict(method="exact", target="exact", nfev_interpolated="error",
                          fewest_tested="exact", error_at_fewest="error",
                          most_tested="exact", error_at_most="error"),
    "work-precision-ratios": dict(method="exact", baseline="exact", ratio_min="error",
                                  ratio_max="error"),
    "higher-degree-roots": dict(degree="exact", largest_spurious_root="exact",
                                measured_growth_per_step="slope", fitted_order_ellipse="slope"),
    "long-time-invariants": dict(orbit="exact", energy_error="error", momentum_error="error",
                                 modified_energy_error="error",
                                 modified_momentum_error="rounding"),
    "long-time-drift": dict(orbits="exact", evaluations_per_orbit="exact",
                            energy_exponent="slope",
                            energy_drift_per_orbit="error", energy_error_start="error",
                            final_energy_error="error", momentum_exponent="slope", momentum_drift_per_orbit="error",
                            final_momentum_error="error"),
    # Phase drift per orbit over 200 orbits, two ways; errors of a fixed-step run.
    "phase-drift": dict(drift_from_angle="error", drift_from_passages="error",
                        period_error="error", precession_per_orbit="error"),
    "theory-constants": dict(derived="exact", measured="error"),
    "higher-degree-constants": dict(derived="exact", measured="error"),
    "rigid-body-energy-drift": dict(method="exact", energy_error_t80="error",
                                    energy_error_t800="error", max_energy_error="error",
                                    growth_ratio="error", drift_rate="error"),
    # The paper's prose numbers, each from a file checked at its own kinds.
    "headline-numbers": dict(value="adaptive"),
    # Notebooks 07 to 09.  An adaptive run's knots come from accept/reject decisions.
    "adaptive-estimate": dict(t="adaptive", h="adaptive", r="adaptive", estimated="adaptive",
                              true="adaptive"),
    # rtol against the global error: every row an adaptive run (this
    # package's or scipy's); the scale of y is the reference solution's.
    "tolerance-proportionality": dict(method="exact", rtol="exact", nfev="adaptive",
                                      status="exact", error="adaptive", error_yp="adaptive",
                                      scale_y="state", error_ratio="adaptive",
                                      error_ratio_yp="adaptive", problem="exact"),
    "tolerance-uniform": dict(method="exact", n="exact", nfev="exact", error="error",
                              scale_y="state", problem="exact"),
    "family-members": dict(beta="exact", gamma="exact", alpha_m="exact", alpha_f="exact",
                           order="exact", limit="exact", rho_inf="exact"),
    "family-spectra": dict(Omega="exact", rho="state", period_error="spectrum",
                           damping="spectrum"),
    "family-report-problems": dict(error="error", per_step="exact"),
    "family-chain": dict(m="exact", omega_m_h="exact", nstep="exact", nfev="exact",
                         iterations="exact", error="error"),
    "pleiades-steps": dict(status="exact", nfev="exact", nstep="exact", rejected="exact",
                           failed="exact", t_end="state", error="error", flagged="exact"),
    # Uniform runs matched to adaptive ones: every column follows the adaptive run.
    "tolerance-cost": dict(rtol="exact", adaptive_nfev="adaptive", adaptive_error="adaptive",
                           n="adaptive", uniform_nfev="adaptive", uniform_error="adaptive",
                           interpolated_nfev="adaptive", ratio="adaptive"),
    "check-alarms": dict(t0="exact", tf="exact", h="exact", status="exact",
                         relative_error="error", warned="exact"),
    "newton-reuse": dict(status="exact", nfev="exact", njev="exact", nstep="exact",
                         niter="exact", error="error", flagged="exact"),
    "variable-step-energy": dict(orbit="exact", energy_error="error", nfev_per_orbit="exact"),
    "composition-orders": dict(order="exact", slope="slope", successive_slope="slope",
                               largest_error="error",
                               smallest_error="error"),
    "composition-energy": dict(orbit="exact", nfev="exact", energy_error="error",
                               position_error="error", velocity_error="error"),
    "composition-work": dict(setting="exact", nfev="exact", max_error="error"),
    "composition-check": dict(method="exact", threshold_y="error", threshold_yp="error",
                              orbit_y="error", orbit_yp="error", orbit_check_sum="error",
                              final_y="error", final_yp="error"),
    "composition-ratios": dict(ratio_min="error", ratio_max="error"),
    "global-sweep": dict(knots="exact", status="exact", newton_iterations="exact",
                         nfev="exact", njev="exact", nfev_stepwise="exact",
                         njev_stepwise="exact", max_difference="rounding"),
    "bvp-tolerance": dict(tol="exact", points="exact", estimated_error="error",
                          true_error="error"),
    "bvp-bratu": dict(points="exact", h="exact", status="exact", newton_iterations="exact",
                      error="error", scipy_status="exact", scipy_points="adaptive",
                      scipy_error="adaptive"),
}

# Rows produced by scipy's adaptive solvers, and which of their columns are
# then of kind "adaptive" instead of the column's own kind.
ADAPTIVE_ROWS = {
    "newton-reuse": (lambda frame: frame["run"].str.startswith("adaptive"),
                     ("nfev", "nstep", "niter", "error")),
    "pleiades-steps": (lambda frame: frame["run"].str.startswith("adaptive"),
                       ("nfev", "nstep", "rejected", "failed", "t_end", "error")),
    "composition-work": (lambda frame: frame["method"].str.startswith("scipy"),
                         ("nfev", "max_error")),
    "composition-ratios": (lambda frame: frame["baseline"].str.startswith("scipy"),
                           ("ratio_min", "ratio_max")),
    "work-precision": (lambda frame: frame["method"].str.startswith("scipy"),
                       ("nfev", "max_error")),
    "work-to-reach": (lambda frame: frame["method"].str.startswith("scipy"),
                      ("nfev_interpolated", "fewest_tested", "error_at_fewest",
                       "most_tested", "error_at_most")),
    "work-precision-ratios": (lambda frame: frame["baseline"].str.startswith("scipy"),
                              ("ratio_min", "ratio_max")),
}
# Rows of long adaptive runs, and their columns' kinds there.
ADAPTIVE_LONG_ROWS = {
    "variable-step-energy": (lambda frame: frame["method"].str.startswith("adaptive"),
                             dict(energy_error="adaptive-long", nfev_per_orbit="adaptive")),
    "long-time-invariants": (lambda frame: frame["method"].str.startswith("DOP853"),
                             dict(energy_error="adaptive-long", momentum_error="adaptive-long")),
    "long-time-drift": (lambda frame: frame["method"].str.startswith("DOP853"),
                        dict(energy_exponent="adaptive-long-exponent",
                             evaluations_per_orbit="adaptive",
                             energy_drift_per_orbit="adaptive-long",
                             energy_error_start="adaptive-long",
                             final_energy_error="adaptive-long",
                             momentum_exponent="adaptive-long-exponent",
                             momentum_drift_per_orbit="adaptive-long",
                             final_momentum_error="adaptive-long")),
    # Adaptive knots with one sweep per step: their final error of y' is far
    # below the tolerance (0.03 of it on the forced Duffing oscillator), so
    # it is not what the controller holds; after one decision flips
    # (measured: 11 evaluations in 37,399 with generic CPU code) it moved by
    # 5.2 %.
    "tolerance-proportionality": (lambda frame: frame["method"] == "spline, 1 sweep",
                                  dict(error_yp="adaptive-long",
                                       error_ratio_yp="adaptive-long")),
}
# Rows whose columns measure only accumulated rounding (kind "rounding").
ROUNDING_ROWS = {
    "long-time-invariants": (lambda frame: frame["method"] == "Verlet", ("momentum_error",)),
    "long-time-drift": (lambda frame: frame["method"] == "Verlet", ("final_momentum_error",)),
    # The conjugacy gap and the rigid body's energy balance are rounding
    # (a change of rounding in the step moved the latter by 4 %).
    "theory-constants": (lambda frame: frame["quantity"].str.startswith(("conjugacy",
                                                                          "rigid body: E")),
                         ("measured",)),
}


def _key(column):
    return column.replace(".", "_")


def kind_of(name, column):
    """The kind of ``column`` in ``data/<name>.csv``; KeyError if undeclared."""
    try:
        return COLUMNS[name][_key(column)]
    except KeyError:
        raise KeyError(f"data/{name}.csv: column {column!r} has no declared kind in "
                       "tests/reproduction.py") from None


def row_kinds(name, frame, column):
    """The kind of each row of ``column`` in ``frame`` (the committed
    ``data/<name>.csv``): "text" for a text column, else the column's kind
    with the rows of :data:`ADAPTIVE_ROWS`, :data:`ADAPTIVE_LONG_ROWS` and
    :data:`ROUNDING_ROWS` in theirs.  KeyError if the column is undeclared."""
    if not pd.api.types.is_numeric_dtype(frame[column]):
        return np.full(len(frame), "text", dtype=object)
    kinds = np.full(len(frame), kind_of(name, column), dtype=object)
    select, adaptive_columns = ADAPTIVE_ROWS.get(name, (None, ()))
    if column in adaptive_columns:
        kinds[np.asarray(select(frame), dtype=bool)] = "adaptive"
    pick, long_columns = ADAPTIVE_LONG_ROWS.get(name, (None, {}))
    if column in long_columns:
        kinds[np.asarray(pick(frame), dtype=bool)] = long_columns[column]
    pick, rounding_columns = ROUNDING_ROWS.get(name, (None, ()))
    if column in rounding_columns:
        kinds[np.asarray(pick(frame), dtype=bool)] = "rounding"
    return kinds


def differing_rows(name, old, new, column):
    """(kinds, differ): each row's kind (:func:`row_kinds`) and whether the
    regenerated ``new`` value of ``column`` fails to reproduce the committed
    ``old`` one at that kind's tolerance (text: as strings)."""
    kinds = row_kinds(name, old, column)
    if not pd.api.types.is_numeric_dtype(old[column]):
        return kinds, (old[column].astype(str) != new[column].astype(str)).to_numpy()
    differ = np.zeros(len(old), bool)
    for k in set(kinds):
        rows = kinds == k
        differ[rows] = TOLERANCES[k].mismatch(old[column][rows], new[column][rows])
    return kinds, differ


def compare_frames(name, old, new):
    """Differences between the committed ``old`` and a regenerated ``new``
    version of ``data/<name>.csv``, as a list of readable strings (empty
    when ``new`` reproduces ``old``)."""
    problems = []
    if list(old.columns) != list(new.columns):
        return [f"{name}: columns {list(new.columns)} instead of {list(old.columns)}"]
    if old.shape != new.shape:
        return [f"{name}: shape {new.shape} instead of {old.shape}"]
    for column in old.columns:
        kinds, differ = differing_rows(name, old, new, column)
        for row in np.flatnonzero(differ)[:3]:
            was, now = (getattr(v, "item", lambda v=v: v)() for v in
                        (old[column].iloc[row], new[column].iloc[row]))  # 0.1, not np.float64(0.1)
            problems.append(f"{name}: {column}[{row}] ({kinds[row]}) {was!r} -> {now!r}")
        if differ.sum() > 3:
            problems.append(f"{name}: {column}: {differ.sum() - 3} more rows differ")
    return problems


# Figures: a pixel of the new image matches when some pixel within
# FIGURE_SHIFT pixels of it in the committed image has the same colour to
# within FIGURE_COLOUR (on a 0-1 scale).  Rounding moves a curve by a small
# fraction of a pixel, which changes anti-aliased edge pixels but never
# leaves a pixel without a match nearby; a curve that moves by a few pixels
# leaves hundreds.  At most FIGURE_PIXELS unmatched pixels are allowed.
FIGURE_SHIFT = 1
FIGURE_COLOUR = 0.2
FIGURE_PIXELS = 20
# Figures that plot "adaptive-long" data: DOP853's curve there moves with
# the CPU (22 % measured, 0.09 decade), which is 3.5 pixels on that figure's
# log axes (38 pixels per decade); 5 pixels allow 0.13 decade.
# The adaptive-knots figure plots each step's true local error, a difference
# of nearly equal numbers that dips to 1e-13 where it changes sign: there its
# rounding (eps |y| / error, up to tens of per cent) moves a dot by up to 0.1
# decade, 3 pixels at that axis's 31 pixels per decade.
FIGURE_SHIFTS = {"long-time-invariants": 5, "adaptive-knots": 5}


def unmatched_pixels(old_png, new_png, shift=FIGURE_SHIFT):
    """Number of pixels of ``new_png`` with no match within ``shift`` pixels in
    ``old_png`` (see above), or None when the sizes differ."""
    from matplotlib.image import imread
    old, new = imread(old_png)[..., :3], imread(new_png)[..., :3]
    if old.shape != new.shape:
        return None
    # A pixel equal to the one at the same place is matched: search only
    # around the others.
    rows, cols = np.nonzero(np.any(new != old, axis=2))
    k = shift
    padded = np.pad(old, ((k, k), (k, k), (0, 0)), mode="edge")
    best = np.full(rows.size, np.inf)
    for dy in range(2 * k + 1):
        for dx in range(2 * k + 1):
            shifted = padded[rows + dy, cols + dx]
            best = np.minimum(best, np.max(np.abs(new[rows, cols] - shifted), axis=1))
    return int(np.sum(best > FIGURE_COLOUR))


def unmatched_both_ways(old_png, new_png):
    """The larger of the numbers of unmatched pixels of ``new_png`` in
    ``old_png`` and back, within the shift allowed for this figure (named
    by ``old_png``'s file name), or None when the sizes differ."""
    shift = FIGURE_SHIFTS.get(Path(old_png).stem, FIGURE_SHIFT)
    there = unmatched_pixels(old_png, new_png, shift)
    if there is None:
        return None
    return max(there, unmatched_pixels(new_png, old_png, shift))


def figures_match(old_png, new_png):
    """True when ``new_png`` reproduces ``old_png`` under the rule above
    (checked both ways, so nothing may appear or vanish)."""
    unmatched = unmatched_both_ways(old_png, new_png)
    return unmatched is not None and unmatched <= FIGURE_PIXELS


# Notebooks: `make test` runs each notebook under nbval, which compares the
# outputs of every code cell with the stored ones after the substitutions of
# the sanitize file the Makefile names (tests/nbval-sanitize.cfg):
# printed text, results and HTML must be identical; images, metadata and
# execution counts are not compared.  notebook_difference applies that rule,
# with nbval's own functions, to a regenerated notebook and the committed one.
# nbval's keys left out of the comparison (nbval.plugin.IPyNbFile, without --nbdime).
NBVAL_SKIP = ("metadata", "traceback", "prompt_number", "output_type", "name",
              "execution_count", "application/vnd.jupyter.widget-view+json",
              "image/png", "image/jpeg")


def nbval_sanitize_patterns(root=Path(__file__).resolve().parents[1]):
    """{regex: replacement} of the sanitize file that ``make test`` (the
    Makefile in ``root``) gives nbval, in its order."""
    import re
    from nbval.plugin import get_sanitize_patterns
    given = re.search(r"--nbval-sanitize-with\s+(\S+)", (Path(root) / "Makefile").read_text())
    cfg = Path(root) / given.group(1)
    return dict(get_sanitize_patterns(cfg.read_text()))


class _NbvalCell:
    """What nbval's cell item (nbval.plugin.IPyNbCell) needs to compare
    outputs, without a pytest session; keeps the first mismatch it reports."""

    def __init__(self, patterns):
        from nbval.plugin import IPyNbCell, nocolors
        self.parent = type("File", (), dict(skip_compare=NBVAL_SKIP,
                                            sanitize_patterns=patterns))()
        self.colors, self.mismatch = nocolors, None
        self._compare, self._sanitize = IPyNbCell.compare_outputs, IPyNbCell.sanitize

    def sanitize(self, text):
        return self._sanitize(self, text)

    def format_output_compare(self, key, left, right):
        self.mismatch = (key, left, right)

    def compare(self, test, ref):
        return self._compare(self, test, ref)


def notebook_difference(old_json, new_json, patterns=None):
    """None when the notebook ``new_json`` (its text) prints what ``old_json``
    prints, as nbval compares them; else (where, old, new): the first code
    cell that differs ("Cell N", nbval's name for it) and its first
    differing line in each (sanitized), or what else differs (the number of
    code cells, a cell's source, its outputs' kinds)."""
    import nbformat
    from nbval.plugin import coalesce_streams, find_comment_markers, find_metadata_tags
    patterns = nbval_sanitize_patterns() if patterns is None else patterns
    old_cells, new_cells = [[c for c in nbformat.reads(text, as_version=4).cells
                             if c.cell_type == "code"] for text in (old_json, new_json)]
    if len(old_cells) != len(new_cells):
        return "cells", f"{len(old_cells)} code cells", f"{len(new_cells)} code cells"
    for number, (old, new) in enumerate(zip(old_cells, new_cells)):
        if old.source != new.source:
            return (f"Cell {number} (source)", *_first_difference(old.source, new.source))
        options = dict(find_metadata_tags(old.metadata))
        options.update(find_comment_markers(old.source))
        if options.get("skip") or not options.get("check", True) or old.execution_count is None:
            continue
        cell = _NbvalCell(patterns)
        if cell.compare(coalesce_streams(new.outputs), coalesce_streams(old.outputs)):
            continue
        if cell.mismatch is None:  # another number or kind of outputs
            kinds = [", ".join(o.get("name", o.output_type) for o in c.outputs) or "none"
                     for c in (old, new)]
            return f"Cell {number}", f"outputs: {kinds[0]}", f"outputs: {kinds[1]}"
        _, left, right = cell.mismatch
        return (f"Cell {number}", *_first_difference(str(left), str(right)))
    return None


def _first_difference(old, new):
    """The first line where the texts ``old`` and ``new`` differ, in each."""
    old, new = old.splitlines() or [""], new.splitlines() or [""]
    line = next((i for i, (a, b) in enumerate(zip(old, new)) if a != b),
                min(len(old), len(new)))
    return tuple(lines[line] if line < len(lines) else "(no more lines)" for lines in (old, new))
