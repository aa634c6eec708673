"""Where the analysis writes, how it writes, and how its figures look.

The notebooks in ``notebooks/`` import it (``import outputs`` with
``../scripts`` on ``sys.path``); the library in ``src/splinestep`` never
does.  Paths are found from this file's own place, so running a notebook
writes below the repository that holds it, whatever copy of ``splinestep``
is installed where.  With the environment variable
``SPLINESTEP_OUTPUT`` set, outputs go below that folder instead (the tests
regenerate everything there and compare with the committed files).

Figures are laid out for the width at which they are read: a JupyterLab
column or the README, about 900 px.  Every figure is :data:`WIDTH` inches
wide, written at :data:`DPI` (1050 px), with text of at least
:data:`MIN_FONT` points, so that it is at least as large as the notebook's own
text when the image is shown at 85 % of its size.
"""

import math
import os
import re
import textwrap
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
_OUTPUT = os.environ.get("SPLINESTEP_OUTPUT")
OUTPUT = Path(_OUTPUT) if _OUTPUT else ROOT
DATA = OUTPUT / "data"
FIGURES = OUTPUT / "figures"

WIDTH = 7.0      # inches, every figure
DPI = 150        # of the PNG: 1050 px wide
MIN_FONT = 9.5   # points, the smallest text in a figure (legends, tick labels)

# Colours per method and per gravity parameter, used in every figure.
METHOD_STYLE = {
    "spline": dict(color="C0", linestyle="-", label="cubic spline"),
    "rk4": dict(color="C3", linestyle="--", label="RK4"),
    "reference": dict(color="k", linestyle=":", label="exact"),
}
# The cannonball's orbits, from viridis (a parameter, not a method: no
# colour of METHODS).
MU_COLORS = {0.4: "#440154", 0.5: "#355f8d", 0.6: "#1e9c89", 1.0: "#7ad151"}
# One colour and one marker per method, in every figure (style_of).
METHODS = {
    "spline": ("C0", "o"), "spline, 1 sweep": ("C1", "o"), "Verlet": ("C2", "D"),
    "RK4": ("C3", "s"), "RK45": ("C4", "^"), "DOP853": ("C5", "v"),
    "spline, order 4": ("C6", "p"), "spline, order 6": ("C8", "h"), "Richardson": ("C9", "X"),
}


def style_of(method):
    """(colour, marker) of ``method`` from :data:`METHODS`, under the names the
    notebooks give it ("scipy DOP853", "RK4, same work", "spline (converged)",
    "spline (1 sweep)", "spline, order 2", "Richardson (order 2 at h, h/2)",
    "DOP853, rtol 1e-04")."""
    key = (method.split(", rtol")[0].replace("scipy ", "").replace(", same work", "").replace(" (converged)", "")
           .replace(", order 2", "").replace(" (1 sweep)", ", 1 sweep"))
    if key.startswith("Richardson"):
        key = "Richardson"
    return METHODS[key]

# With SPLINESTEP_MANIFEST set (by `make reproduce`), every file read or
# written here is noted in that file, for scripts/freshness.py.
_MANIFEST = os.environ.get("SPLINESTEP_MANIFEST")


def _note(kind, path):
    if _MANIFEST:
        with open(_MANIFEST, "a") as manifest:
            manifest.write(f"{kind} {Path(path).resolve()}\n")


def note_run():
    """Note what a run used besides the data it read: every module of this
    repository it imported (the package's in ``src/``, the scripts'), so that an edit
    of a module reruns the notebooks that import it and no other; and what
    it cost: the seconds numba spent compiling and the CPU seconds of the
    process.  ``make reproduce`` calls it after a notebook's last cell."""
    import sys
    import time
    for module in list(sys.modules.values()):
        file = getattr(module, "__file__", None)
        if file and file.endswith(".py") and any(Path(file).resolve().is_relative_to(ROOT / f)
                                                 for f in ("src", "scripts")):
            _note("read", file)
    compile_module = sys.modules.get("splinestep._compile")
    seconds = compile_module.compile_seconds() if compile_module else 0.0
    if _MANIFEST:
        with open(_MANIFEST, "a") as manifest:
            manifest.write(f"compile {seconds:.3f}\ncpu {time.process_time():.3f}\n")


_PDF_METADATA = {"Creator": None, "Producer": None, "CreationDate": None}
_PNG_METADATA = {"Software": None}


_SUPERSCRIPTS = str.maketrans("0123456789-\u2212+kny", "\u2070\u00b9\u00b2\u00b3\u2074\u2075\u2076\u2077\u2078\u2079\u207b\u207b\u207a\u1d4f\u207f\u02b8")
SUBSCRIPTS = str.maketrans("0123456789hiknt", "\u2080\u2081\u2082\u2083\u2084\u2085\u2086\u2087\u2088\u2089\u2095\u1d62\u2096\u2099\u209c")
SUPERSCRIPTS = _SUPERSCRIPTS


def plain_power_label(label):
    """A label of matplotlib's log-axis formatter, ``$\\mathdefault{10^{-3}}$``
    or ``$\\mathdefault{2\\times10^{-3}}$``, as plain text with Unicode
    superscripts (10\u207b\u00b3, 2\u00d710\u207b\u00b3); other labels unchanged.

    Tick labels are most of a figure's text, and matplotlib lays out each
    mathtext label with a parser that costs about 6 ms per label and
    resolution: about 5 s of the notebooks' run time, for text that
    plain Unicode sets the same way."""
    match = re.fullmatch(r"\$\\mathdefault\{(.*)\}\$", label)
    if not match:
        return label
    body = match.group(1).replace("\\times", "\u00d7")
    body = re.sub(r"\^\{(-?\d+)\}|\^(-?\d+)",
                  lambda m: (m.group(1) or m.group(2)).translate(_SUPERSCRIPTS), body)
    if not re.fullmatch(r"-?[\d.]*(\u00d7)?(10|2|e)?[\u2070-\u209f\u00b9\u00b2\u00b3]*", body):
        return label   # anything but an integer power stays mathtext
    return body.replace("-", "\u2212")


def _plain_log_formatter():
    from matplotlib.ticker import LogFormatterSciNotation

    class PlainLogFormatter(LogFormatterSciNotation):
        """matplotlib's log-axis labels, as plain text (:func:`plain_power_label`)."""

        def __call__(self, x, pos=None):
            return plain_power_label(super().__call__(x, pos))

    return PlainLogFormatter


def setup():
    """Agg backend and the shared style; returns ``matplotlib.pyplot``.

    Log axes label their ticks with :func:`plain_power_label`'s plain
    text (set as the default formatters of matplotlib's log scale)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib import scale, ticker
    formatter = _plain_log_formatter()

    def log_defaults(self, axis):
        axis.set_major_locator(ticker.LogLocator(self.base))
        axis.set_major_formatter(formatter(self.base))
        axis.set_minor_locator(ticker.LogLocator(self.base, self.subs))
        axis.set_minor_formatter(formatter(self.base, labelOnlyBase=self.subs is not None))

    scale.LogScale.set_default_locators_and_formatters = log_defaults
    plt.rcParams.update({
        "figure.dpi": 100, "savefig.dpi": DPI, "font.size": 11,
        "axes.titlesize": 11, "axes.labelsize": 11, "figure.titlesize": 12,
        "legend.fontsize": MIN_FONT, "xtick.labelsize": 10, "ytick.labelsize": 10,
        "axes.grid": True, "grid.alpha": 0.3, "legend.framealpha": 0.9,
        "axes.formatter.useoffset": False, "lines.linewidth": 1.4,
        "svg.hashsalt": "splinestep", "figure.constrained_layout.use": True,
    })
    return plt


def save_figure(fig, name):
    """Write ``figures/<name>.pdf`` and ``.png`` with no dates or version
    stamps, so the same environment regenerates identical bytes; close the
    figure and return the PNG for display (an IPython ``Image``, whose text
    form has no address, so nbval compares it stably)."""
    import matplotlib.pyplot as plt
    width = fig.get_size_inches()[0]
    if abs(width - WIDTH) > 1e-9:
        raise ValueError(f"figure {name!r} is {width} in wide; lay it out for {WIDTH} in")
    FIGURES.mkdir(parents=True, exist_ok=True)
    fig.savefig(FIGURES / f"{name}.pdf", metadata=_PDF_METADATA)
    fig.savefig(FIGURES / f"{name}.png", metadata=_PNG_METADATA)
    _note("wrote", FIGURES / f"{name}.pdf")
    _note("wrote", FIGURES / f"{name}.png")
    plt.close(fig)
    try:
        from IPython.display import Image
    except ImportError:  # pragma: no cover - outside Jupyter
        return FIGURES / f"{name}.png"
    return Image(filename=str(FIGURES / f"{name}.png"))


def save_data(frame, name):
    """Write ``data/<name>.csv`` (a pandas DataFrame) with 12 significant
    digits.  Returns None, so a notebook cell ending with it shows nothing."""
    DATA.mkdir(parents=True, exist_ok=True)
    frame.to_csv(DATA / f"{name}.csv", index=False, float_format="%.12g",
                 lineterminator="\n")
    _note("wrote", DATA / f"{name}.csv")


def read_data(name):
    """Read ``data/<name>.csv`` as written by :func:`save_data`."""
    import pandas as pd
    _note("read", DATA / f"{name}.csv")
    return pd.read_csv(DATA / f"{name}.csv")


def sci(value, digits=2):
    """``value`` to ``digits`` significant digits in Markdown math,
    e.g. ``$4.1 \\times 10^{-3}$``; plain decimals between 0.01 and 1000."""
    if value == 0 or not math.isfinite(value):
        return f"${value:g}$"
    exponent = math.floor(math.log10(abs(value)))
    if -2 <= exponent < 3:
        return f"${value:.{max(digits - 1 - exponent, 0)}f}$"
    mantissa = f"{value / 10 ** exponent:.{digits - 1}f}"
    if float(mantissa) >= 10:  # rounding carried into the next decade
        exponent += 1
        mantissa = f"{value / 10 ** exponent:.{digits - 1}f}"
    return f"${mantissa} \\times 10^{{{exponent}}}$"


def plain(value, digits=2):
    """:func:`sci` as plain text, for printed lines (no Markdown there):
    ``7.2 × 10⁻⁶``; plain decimals between 0.01 and 1000."""
    text = sci(value, digits).strip("$")
    match = re.fullmatch(r"(.*) \\times 10\^\{(-?\d+)\}", text)
    if match is None:
        return text
    return f"{match.group(1)} \u00d7 10{match.group(2).translate(_SUPERSCRIPTS)}"


# Greek letters by name, for the tables (readable) and the site's captions.
GREEK = {"alpha": "\u03b1", "beta": "\u03b2", "gamma": "\u03b3", "Delta": "\u0394",
         "delta": "\u03b4", "zeta": "\u03b6", "theta": "\u03b8", "kappa": "\u03ba",
         "lambda": "\u03bb", "mu": "\u03bc", "nu": "\u03bd", "pi": "\u03c0", "rho": "\u03c1",
         "sigma": "\u03c3", "omega": "\u03c9", "Omega": "\u03a9", "epsilon": "\u03b5",
         "xi": "\u03be"}


def readable(text):
    """Plain text of the tables (``data/claims.csv``) as a reader reads it:
    Greek names as letters, ``4.1e-03`` and ``1e-3`` as 4.1 \u00d7 10\u207b\u00b3 and
    10\u207b\u00b3, powers ``h^2`` and ``(omega h)^2`` as superscripts, ``sqrt(12)`` as
    \u221a12, ``<=`` as \u2264, ``dt`` (the step) as \u0394t; other text unchanged."""
    def power(match):
        mantissa, exponent = match.group(1), int(match.group(2))
        ten = "10" + str(exponent).translate(_SUPERSCRIPTS)
        return ten if mantissa in ("1", None) else f"{mantissa} \u00d7 {ten}"
    text = re.sub(r"\b(\d+(?:\.\d+)?)e([-+]?\d+)\b", power, text)
    text = re.sub(r"\b(" + "|".join(GREEK) + r")\b", lambda m: GREEK[m.group(1)], text)
    text = re.sub(r"\^(?:\((-?\d+)\)|(-?\d+))",
                  lambda m: (m.group(1) or m.group(2)).translate(_SUPERSCRIPTS), text)
    text = re.sub(r"sqrt\((\w+)\)", "\u221a\\1", text)
    text = re.sub(r"(^|[^/\w])dt\b", "\\1\u0394t", text)
    return text.replace("<=", "\u2264").replace(">=", "\u2265").replace(" -> ", " \u2192 ")


def html_table(frame, raw=(), widths=None, text=str):
    """``frame`` as an HTML table that reads the same in JupyterLab and on
    the site: left-aligned text that wraps at word breaks, a line between
    rows, no index (inline styles: JupyterLab drops the style sheets of
    untrusted outputs).  Formulas between dollars are left for MathJax.

    Parameters
    ----------
    frame : pandas.DataFrame
        The table; its index is not shown.
    raw : collection of str
        Columns that are HTML already; the others are escaped.
    widths : dict, optional
        {column: least width}, e.g. "9em", for columns that must not wrap
        to a sliver.
    text : callable
        Applied to each escaped cell's ``str`` (e.g. :func:`readable`).
    """
    from html import escape
    style = "text-align: left; vertical-align: top"
    widths = widths or {}
    head = "".join(f'<th style="{style}; padding: 0.25em 0.75em 0.25em 0; '
                   f'min-width: {widths.get(c, "0")}">{escape(str(c))}</th>' for c in frame.columns)

    def cell(column, value):
        return str(value) if column in raw else escape(text(str(value)))

    rows = "".join("<tr>" + "".join(
        f'<td style="{style}; padding: 0.25em 0.75em 0.25em 0; border-top: 1px solid #ccc">'
        f"{cell(c, v)}</td>"
        for c, v in zip(frame.columns, values)) + "</tr>"
        for values in frame.itertuples(index=False))
    return f"<table><thead><tr>{head}</tr></thead><tbody>{rows}</tbody></table>"


def round_sig(value, digits=2):
    """``value`` rounded to ``digits`` significant digits."""
    return float(f"{value:.{digits - 1}e}")


def wrapped(text, width=100):
    """``text`` as printed lines of at most ``width`` characters: a longer
    line is broken first at its "; " (one clause a line), then at spaces,
    continuation lines indented by two spaces.  JupyterLab would otherwise
    break it wherever the pane ends."""
    lines = []
    for line in text.split("\n"):
        clauses = line.split("; ") if len(line) > width else [line]
        for k, clause in enumerate(clauses):
            clause += ";" if k < len(clauses) - 1 else ""
            lines += textwrap.wrap(clause, width, initial_indent="  " if k else "",
                                   subsequent_indent="  ", break_long_words=False,
                                   break_on_hyphens=False, drop_whitespace=True) or [""]
    return "\n".join(lines)


def span(pair, digits=2, decimals=None):
    """A measured range for prose: "a to b", or "about a" when both print
    alike (to ``digits`` significant digits, or to ``decimals`` places)."""
    if decimals is None:
        lo, hi = (f"{round_sig(v, digits):g}" for v in pair)
    else:
        lo, hi = (f"{v:.{decimals}f}" for v in pair)
    return f"about {lo}" if lo == hi else f"{lo} to {hi}"


def signed(value, decimals=2):
    """``value`` with an explicit sign and ``decimals`` decimals, never "-0.00":
    a value that rounds to zero prints as "+0.00"."""
    text = f"{value:+.{decimals}f}"
    return text.replace("-", "+") if float(text) == 0 else text


def rounding(value):
    """A difference at the level of rounding errors, printed as a number
    with one digit and marked "(rounding)": its digits differ between CPUs,
    so the check of printed outputs (tests/nbval-sanitize.cfg) compares
    the marker, not the digits."""
    return f"{value:.0e} (rounding)"
