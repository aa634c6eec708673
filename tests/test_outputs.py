"""The committed notebooks, data, figures and README tables are what the
code produces: paired files agree, and a fresh run reproduces data/ and
figures/ to the rule of tests/reproduction.py, on this machine's CPU or
another's.  A notebook that ``make reproduce`` ran here with the inputs it
has now is not run again: its files are compared with git HEAD's."""

import json
import os
import re
import subprocess
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
    every notebook has finished, on whichever worker), or a new run; not of
    the notebooks this session does not run again
    (:func:`notebook_runs.reproduced`)."""
    out = Path(os.environ["SPLINESTEP_OUTPUT"])
    running = notebook_runs.notebooks_in(request.session)
    if running:
        notebook_runs.wait_for_notebooks(running)
    missing = [s for s in SCRIPTS if s.stem not in running and s.stem not in REPRODUCED]
    for script, _, error, _ in reproduce.execute_all(missing, output_root=out):
        assert error is None, f"{script.name} failed: {error}"
    return out


# Outputs written by `make reproduce` here, from the inputs they have now.
REPRODUCED = notebook_runs.reproduced()
REPRODUCED_OUTPUTS = {path for paths in REPRODUCED.values() for path in paths}


def _compared(fresh, committed, tmp_path):
    """(old, new): the file as stored and the one a fresh run wrote; for an
    output of a notebook not run again, git HEAD's file and the one
    ``make reproduce`` wrote here, which is what a fresh run would write."""
    name = committed.relative_to(ROOT).as_posix()
    if name not in REPRODUCED_OUTPUTS:
        return committed, fresh / name
    shown = subprocess.run(["git", "-C", str(ROOT), "show", f"HEAD:{name}"], capture_output=True)
    if shown.returncode != 0:
        pytest.skip(f"{name} is not in git HEAD: nothing to compare make reproduce's file with")
    head = tmp_path / committed.name
    head.write_bytes(shown.stdout)
    return head, committed


@pytest.mark.parametrize("committed", COMMITTED_DATA, ids=lambda p: p.stem)
def test_data_reproduces(fresh, committed, tmp_path):
    old, new = _compared(fresh, committed, tmp_path)
    problems = reproduction.compare_frames(committed.stem, pd.read_csv(old), pd.read_csv(new))
    assert not problems, "\n".join(problems)


@pytest.mark.parametrize("committed", COMMITTED_PNG, ids=lambda p: p.stem)
def test_figures_reproduce(fresh, committed, tmp_path):
    assert reproduction.figures_match(*_compared(fresh, committed, tmp_path))


@pytest.mark.parametrize("stem", sorted(REPRODUCED) or [pytest.param(None, marks=pytest.mark.skip(
    reason="every notebook ran under nbval in this session"))], ids=str)
def test_a_notebook_not_run_again_prints_what_git_head_stores(stem):
    """What nbval checks of a notebook this session does not run: the run
    ``make reproduce`` made of it here prints, cell by cell, what the
    committed notebook stores (nbval's comparison and sanitizing rules)."""
    name = f"notebooks/{stem}.ipynb"
    shown = subprocess.run(["git", "-C", str(ROOT), "show", f"HEAD:{name}"], capture_output=True)
    if shown.returncode != 0:
        pytest.skip(f"{name} is not in git HEAD")
    difference = reproduction.notebook_difference(shown.stdout.decode(),
                                                  (ROOT / name).read_text())
    assert difference is None, difference


def test_readme_tables_are_the_data():
    text = (ROOT / "README.md").read_text()
    assert reproduce.readme_with_tables(text, ROOT / "data") == text



def test_the_readme_opens_on_the_verdict_and_stays_short():
    """A landing page: at most 150 lines, and what became of the report's
    claims (the reproduced order, the bound of 1e-3, the built
    improvements) before any section, "Run it" included."""
    text = (ROOT / "README.md").read_text()
    assert len(text.splitlines()) <= 150
    opening = text.split("\n## ")[0]
    for finding in ("Second order is reproduced", "10^{-3}", "are built and measured"):
        assert finding in opening, finding
    # every notebook named in the reading order, in the files' order
    named = re.findall(r"`(\d\d_\w+)`", text.split("## Reading order")[1])
    assert named == sorted(p.stem for p in (ROOT / "notebooks").glob("[0-9][0-9]_*.py"))
