"""The committed notebooks, data, figures and README tables are what the
code produces: paired files agree, and a fresh run reproduces data/ and
figures/ to the rule of tests/reproduction.py, on this machine's CPU or
another's."""

import json
import os
import sys
from pathlib import Path

import jupytext
import pandas as pd
import pytest

import notebook_runs
import reproduction

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "scripts"))
import reproduce  # noqa: E402

SCRIPTS = reproduce.NOTEBOOKS
COMMITTED_DATA = sorted((ROOT / "data").glob("*.csv"))
COMMITTED_PNG = sorted((ROOT / "figures").glob("*.png"))


def test_every_notebook_is_a_committed_pair():
    assert len(SCRIPTS) >= 5
    for script in SCRIPTS:
        assert script.with_suffix(".ipynb").exists(), f"{script.name} has no .ipynb"


@pytest.mark.parametrize("script", SCRIPTS, ids=lambda p: p.stem)
def test_pair_has_the_same_cells(script):
    """Compare the cells themselves, not file dates (arbitrary in a clone)."""
    text = jupytext.read(script)
    executed = jupytext.read(script.with_suffix(".ipynb"))
    assert [(c.cell_type, c.source.strip()) for c in text.cells] == \
           [(c.cell_type, c.source.strip()) for c in executed.cells]
    code_cells = [c for c in executed.cells if c.cell_type == "code"]
    assert all(c.execution_count is not None for c in code_cells), "stored notebook not executed"


@pytest.mark.parametrize("script", SCRIPTS, ids=lambda p: p.stem)
def test_notebook_names_the_installed_kernel(script):
    """The kernelspec stored in each notebook is the one `make` installs,
    so JupyterLab has nothing to rewrite when it saves."""
    from jupyter_client.kernelspec import KernelSpecManager
    stored = json.loads(script.with_suffix(".ipynb").read_text())["metadata"]["kernelspec"]
    installed = KernelSpecManager().get_kernel_spec(stored["name"])
    assert stored["display_name"] == installed.display_name
    assert stored == reproduce.KERNELSPEC


@pytest.fixture(scope="session")
def fresh(request):
    """The outputs of a fresh run: those nbval writes in this session (once
    every notebook has finished, on whichever worker), or a new run."""
    out = Path(os.environ["SPLINESTEP_OUTPUT"])
    running = notebook_runs.notebooks_in(request.session)
    if running:
        notebook_runs.wait_for_notebooks(running)
    missing = [s for s in SCRIPTS if s.stem not in running]
    for script, _, error, _ in reproduce.execute_all(missing, output_root=out):
        assert error is None, f"{script.name} failed: {error}"
    return out


def test_outputs_exist():
    assert len(COMMITTED_DATA) >= 10 and len(COMMITTED_PNG) >= 7
    names = {p.stem for p in COMMITTED_PNG}
    for figure in ("cannonball-trajectories", "cannonball-error-histories",
                   "rigid-body-angular-velocity", "rigid-body-energy-error", "convergence"):
        assert figure in names
        assert (ROOT / "figures" / f"{figure}.pdf").exists()


def test_every_data_column_has_a_declared_kind():
    for path in COMMITTED_DATA:
        frame = pd.read_csv(path)
        for column in frame.columns:
            if pd.api.types.is_numeric_dtype(frame[column]):
                reproduction.kind_of(path.stem, column)  # KeyError if undeclared


@pytest.mark.parametrize("committed", COMMITTED_DATA, ids=lambda p: p.stem)
def test_data_reproduces(fresh, committed):
    old = pd.read_csv(committed)
    new = pd.read_csv(fresh / "data" / committed.name)
    problems = reproduction.compare_frames(committed.stem, old, new)
    assert not problems, "\n".join(problems)


@pytest.mark.parametrize("committed", COMMITTED_PNG, ids=lambda p: p.stem)
def test_figures_reproduce(fresh, committed):
    assert reproduction.figures_match(committed, fresh / "figures" / committed.name)


def test_readme_tables_are_the_data():
    text = (ROOT / "README.md").read_text()
    assert reproduce.readme_with_tables(text, ROOT / "data") == text

