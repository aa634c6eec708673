"""Paths of ``data/`` and ``figures/``, the shared figure style, and writers
with deterministic bytes.  Used by the notebooks only: the solver modules
never import it.

Outputs go to the repository's ``data/`` and ``figures/``, or below the
folder named by the environment variable ``SPLINESTEP_OUTPUT`` (the tests
use it to regenerate everything elsewhere and compare with the committed
files).
"""

import os
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
_OUTPUT = os.environ.get("SPLINESTEP_OUTPUT")
OUTPUT = Path(_OUTPUT) if _OUTPUT else ROOT
DATA = OUTPUT / "data"
FIGURES = OUTPUT / "figures"

# Colours per method and per gravity parameter, used in every figure.
METHOD_STYLE = {
    "spline": dict(color="C0", linestyle="-", label="cubic spline"),
    "rk4": dict(color="C3", linestyle="--", label="RK4"),
    "reference": dict(color="k", linestyle=":", label="exact"),
}
MU_COLORS = {0.4: "C0", 0.5: "C1", 0.6: "C2", 1.0: "C4"}

_PDF_METADATA = {"Creator": None, "Producer": None, "CreationDate": None}
_PNG_METADATA = {"Software": None}


def setup():
    """Agg backend and the shared style; returns ``matplotlib.pyplot``."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    plt.rcParams.update({
        "figure.dpi": 100, "savefig.dpi": 150, "font.size": 10,
        "axes.grid": True, "grid.alpha": 0.3, "legend.fontsize": 8,
        "svg.hashsalt": "splinestep", "figure.constrained_layout.use": True,
    })
    return plt


def save_figure(fig, name):
    """Write ``figures/<name>.pdf`` and ``.png`` with no dates or version
    stamps, so the same environment regenerates identical bytes; close the
    figure and return the PNG for display (an IPython ``Image``, whose text
    form has no address, so nbval compares it stably)."""
    import matplotlib.pyplot as plt
    FIGURES.mkdir(parents=True, exist_ok=True)
    fig.savefig(FIGURES / f"{name}.pdf", metadata=_PDF_METADATA)
    fig.savefig(FIGURES / f"{name}.png", metadata=_PNG_METADATA)
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


def read_data(name):
    """Read ``data/<name>.csv`` as written by :func:`save_data`."""
    import pandas as pd
    return pd.read_csv(DATA / f"{name}.csv")
