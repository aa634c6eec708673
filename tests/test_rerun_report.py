"""The comparison that ends `make reproduce` (scripts/rerun_report.py) sorts
constructed outputs as the rules of tests/reproduction.py do, in a temporary
git repository: identical, within tolerance, beyond tolerance (named); and
the run's log says that a notebook held for the others' data started when
its held cells begin, not when its kernel does."""

import asyncio
import subprocess
import threading
import time

from pathlib import Path

import nbformat
import numpy as np
import pandas as pd
import pytest
from matplotlib.image import imsave

import reproduce
import reproduction
import rerun_report

TABLE = ("tol,points,estimated_error,true_error\n"
         "0.001,12,{:.12g},{:.12g}\n0.0001,40,2e-06,{:.12g}\n")
VALUES = (1.23456789012e-4, 9.87654321098e-5, 3.45678901234e-6)


def table(first=VALUES[0], second=VALUES[1], third=VALUES[2]):
    return TABLE.format(first, second, third)


def picture(offset=0, size=(60, 90)):
    """A white image with a black diagonal line, moved right by ``offset`` px."""
    image = np.ones((*size, 3))
    for row in range(size[0]):
        image[row, 10 + row // 2 + offset:13 + row // 2 + offset] = 0.0
    return image


def notebook(text, count=1, address="0x7f3a2b"):
    cell = nbformat.v4.new_code_cell("print(x)", execution_count=count)
    cell.outputs = [nbformat.v4.new_output("stream", name="stdout",
                                           text=f"{text}\n<object at {address}>\n")]
    return nbformat.writes(nbformat.v4.new_notebook(cells=[cell]))


def git(root, *args):
    subprocess.run(["git", "-C", str(root), *args], check=True, capture_output=True)


@pytest.fixture
def repository(tmp_path):
    """A committed copy of constructed outputs: three tables, four figures,
    two notebooks, a paper and the machine they were made on."""
    files = {f"data/{name}.csv": table() for name in ("bvp-tolerance", "convergence-like",
                                                      "theory-like")}
    for path, text in files.items():
        (tmp_path / path).parent.mkdir(exist_ok=True)
        (tmp_path / path).write_text(text)
    (tmp_path / "data" / "machine.txt").write_text("AMD EPYC, Linux x86_64, Python 3.11.7\n")
    (tmp_path / "figures").mkdir()
    for name in ("same", "shifted", "moved", "long-time-invariants"):
        imsave(tmp_path / "figures" / f"{name}.png", picture())
    (tmp_path / "notebooks").mkdir()
    for name in ("01_same_text", "02_other_text"):
        (tmp_path / "notebooks" / f"{name}.ipynb").write_text(notebook("x = 0.25"))
    (tmp_path / "paper").mkdir()
    (tmp_path / "paper" / "splinestep.pdf").write_bytes(b"%PDF-1.7 committed")
    (tmp_path / "scripts").mkdir()
    (tmp_path / "scripts" / "analysis.py").write_text("STEP = 0.01\n")
    git(tmp_path, "init", "-q")
    git(tmp_path, "add", ".")
    git(tmp_path, "-c", "user.name=t", "-c", "user.email=t@t", "commit", "-q", "-m", "outputs")
    return tmp_path


def rerun(root):
    """Rewrite the outputs of ``repository`` as another run would; the files written."""
    # The tables bear the kinds of data/bvp-tolerance.csv.
    (root / "data" / "bvp-tolerance.csv").write_text(table())
    (root / "data" / "convergence-like.csv").write_text(table())
    (root / "data" / "theory-like.csv").write_text(table())
    imsave(root / "figures" / "same.png", picture())
    imsave(root / "figures" / "shifted.png", picture(offset=1))
    imsave(root / "figures" / "moved.png", picture(offset=3))
    imsave(root / "figures" / "long-time-invariants.png", picture(offset=3))
    (root / "data" / "machine.txt").write_text("Intel Xeon, Linux x86_64, Python 3.11.7\n")
    (root / "paper" / "splinestep.pdf").write_bytes(b"%PDF-1.7 rebuilt")
    (root / "notebooks" / "01_same_text.ipynb").write_text(
        notebook("x = 0.25", count=7, address="0x55d0c1"))
    (root / "notebooks" / "02_other_text.ipynb").write_text(notebook("x = 0.26"))
    return sorted(p for p in root.rglob("*") if p.is_file() and ".git" not in p.parts)


@pytest.fixture
def kinds(monkeypatch):
    """The constructed tables declared with bvp-tolerance's kinds."""
    for name in ("convergence-like", "theory-like"):
        monkeypatch.setitem(reproduction.COLUMNS, name, reproduction.COLUMNS["bvp-tolerance"])


def by_name(found):
    return {v.name: v for v in found}


def test_tables_identical_last_digit_and_third_digit(repository, kinds):
    rerun(repository)
    (repository / "data" / "convergence-like.csv").write_text(
        table(first=1.23456789013e-4))                        # 12th digit
    (repository / "data" / "theory-like.csv").write_text(
        table(third=3.46678901234e-6))                        # 3rd digit
    found = by_name(rerun_report.verdicts(rerun_report.committed_versions(
        sorted((repository / "data").glob("*.csv")), repository), repository))
    assert found["bvp-tolerance.csv"].status == "identical"
    within = found["convergence-like.csv"]
    assert within.status == "within"
    assert within.size == pytest.approx(1e-15 / 1.23456789013e-4, rel=1e-3)
    assert "estimated_error[0] (error)" in within.detail
    beyond = found["theory-like.csv"]
    assert beyond.status == "beyond"
    assert beyond.detail == ("theory-like.csv true_error[1] (error): "
                             "3.45678901234e-06 -> 3.46678901234e-06")


def test_a_changed_text_is_shown_where_it_changes():
    """A long text cell is cut to a window around its first change, and
    the count of the other values beyond tolerance follows."""
    old = "with launch x(0) = (1, 0), x'(0) = (0, 1): energies 0.1, 0.0, -0.1, -0.5"
    assert rerun_report.excerpt(old, old.replace("x(0)", "$x(0)$")) == \
        "'...aunch x(0) = (1, 0...' -> '...aunch $x(0)$ = (1,...'"
    frame = pd.DataFrame({"quantity": [old, "b", "c"], "value": [1.0, 2.0, 3.0]})
    moved = frame.assign(quantity=[old.replace("0.1", "0.2"), "b", "d"], value=[1.0, 2.1, 3.0])
    assert rerun_report.first_cell(Path("cannonball-error-location.csv"), frame, moved) == (
        "cannonball-error-location.csv quantity[0] (text): "
        "'...ies 0.1, 0.0, -0.1...' -> '...ies 0.2, 0.0, -0.2...' (2 more)")


def test_figures_identical_within_the_shift_allowed_and_moved(repository):
    rerun(repository)
    found = by_name(rerun_report.verdicts(rerun_report.committed_versions(
        sorted((repository / "figures").glob("*.png")), repository), repository))
    assert found["same.png"].status == "identical"
    assert found["shifted.png"].status == "within"   # 1 px, the rule's allowance
    assert "within 1 px (shifted.png)" in found["shifted.png"].detail
    assert found["moved.png"].status == "beyond"     # 3 px
    assert "moved.png" in found["moved.png"].detail
    # 3 px is within this figure's own allowance (reproduction.FIGURE_SHIFTS).
    assert found["long-time-invariants.png"].status == "within"


def test_notebooks_compared_as_nbval_does():
    same = notebook("x = 0.25", count=7, address="0x55d0c1")
    assert reproduction.notebook_difference(notebook("x = 0.25"), same) is None
    assert reproduction.notebook_difference(notebook("x = 0.25"), notebook("x = 0.26")) == \
        ("Cell 0", "x = 0.25", "x = 0.26")
    edited = notebook("x = 0.25").replace('"print(x)"', '"print(y)"')
    assert reproduction.notebook_difference(notebook("x = 0.25"), edited) == \
        ("Cell 0 (source)", "print(x)", "print(y)")
    # Without the sanitize rules, the object's address would differ.
    assert reproduction.notebook_difference(notebook("x = 0.25"), same, patterns={}) == \
        ("Cell 0", "<object at 0x7f3a2b>", "<object at 0x55d0c1>")


def test_the_sanitize_rules_are_those_make_test_gives_nbval():
    patterns = reproduction.nbval_sanitize_patterns()
    assert patterns["0x[0-9a-fA-F]+"] == "0xADDRESS"


def test_report_names_what_is_beyond_and_fails(repository, kinds):
    written = rerun(repository)
    (repository / "data" / "theory-like.csv").write_text(table(third=3.46678901234e-6))
    lines = []
    status = rerun_report.report(written, repository, out=lines.append)
    text = "\n".join(lines)
    assert status == rerun_report.NOT_REPRODUCED
    assert "data tables: 3 written, 2 identical, 0 within tolerance, 1 beyond" in text
    assert "beyond: theory-like.csv true_error[1] (error): 3.45678901234e-06 -> 3.4667" in text
    assert "figures: 4 written, 1 identical, 2 within tolerance, 1 beyond" in text
    assert "notebooks: 2 written, 0 identical, 1 within tolerance, 1 beyond" in text
    assert "02_other_text.ipynb Cell 0: 'x = 0.25' -> 'x = 0.26'" in text
    assert "paper/splinestep.pdf: rebuilt from the data above" in text
    assert "made on AMD EPYC; this run on Intel Xeon" in text
    assert lines[-1].startswith("NOT REPRODUCED: 3 outputs")
    assert all(len(line) <= 100 for line in lines), lines


def test_report_within_tolerance_passes(repository, kinds):
    written = rerun(repository)
    (repository / "data" / "convergence-like.csv").write_text(table(first=1.23456789013e-4))
    (repository / "notebooks" / "02_other_text.ipynb").write_text(notebook("x = 0.25"))
    imsave(repository / "figures" / "moved.png", picture())
    lines = []
    assert rerun_report.report(written, repository, out=lines.append) == 0
    assert any("within tolerance: the last digits differ, largest relative difference 8.1e-12"
               " in convergence-like.csv estimated_error[0]" in line for line in lines), lines
    assert lines[-1].startswith("reproduced:")


def test_outputs_of_edited_sources_are_changes_not_failures(repository, kinds):
    written = rerun(repository)
    (repository / "scripts" / "analysis.py").write_text("STEP = 0.02\n")
    lines = []
    assert rerun_report.report(written, repository, out=lines.append) == 0
    assert lines[-2] == "  sources edited since HEAD: scripts/analysis.py"
    assert lines[-1].startswith("changed: 2 outputs beyond tolerance of HEAD's")


def test_readme_tables_compared_not_its_prose(repository):
    readme = "Prose.\n<!-- begin claims -->\n| a |\n|---|\n| 1 |\n<!-- end claims -->\nMore.\n"
    (repository / "README.md").write_text(readme)
    git(repository, "add", "README.md")
    git(repository, "-c", "user.name=t", "-c", "user.email=t@t", "commit", "-q", "-m", "readme")
    written = rerun(repository)
    lines = []
    (repository / "README.md").write_text(readme.replace("Prose.", "Other prose."))
    rerun_report.report(written, repository, out=lines.append)
    assert "README.md tables: identical" in lines
    (repository / "README.md").write_text(readme.replace("| 1 |", "| 2 |"))
    rerun_report.report(written, repository, out=lines.append)
    assert "README.md tables: rewritten from data/ above" in lines


def test_no_checkout_and_nothing_written(tmp_path, monkeypatch):
    monkeypatch.setenv("GIT_CEILING_DIRECTORIES", str(tmp_path.parent))
    (tmp_path / "data").mkdir()
    (tmp_path / "data" / "a.csv").write_text("x\n1\n")
    lines = []
    assert rerun_report.report([tmp_path / "data" / "a.csv"], tmp_path, out=lines.append) == 0
    assert len(lines) == 1 and lines[0].startswith("not compared with the committed files:")
    assert rerun_report.report([], tmp_path, out=lines.append) == 0
    assert lines[-1].startswith("nothing ran")


def test_held_notebook_says_started_when_its_held_cells_begin(monkeypatch, capsys):
    """Its first cell runs at once, silently; "started" comes once, when the
    next cell is let through, before it runs."""
    events = []

    async def run_cell(self, cell, index, *args, **kwargs):
        events.append(f"cell {index}")

    monkeypatch.setattr(reproduce.NotebookClient, "async_execute_cell", run_cell)
    script = reproduce.NOTEBOOKS[-1]
    cells = [nbformat.v4.new_markdown_cell("# t")] + [nbformat.v4.new_code_cell(str(i))
                                                       for i in range(3)]
    ready, abandon = threading.Event(), threading.Event()
    client = reproduce._HeldClient(nbformat.v4.new_notebook(cells=cells), ready, abandon,
                                   reproduce._Started(script))

    async def scenario():
        await client.async_execute_cell(cells[1], 1)
        held = asyncio.ensure_future(client.async_execute_cell(cells[2], 2))
        await asyncio.sleep(0.05)
        assert events == ["cell 1"] and capsys.readouterr().out == ""
        ready.set()
        await held
        await client.async_execute_cell(cells[3], 3)

    asyncio.run(scenario())
    assert events == ["cell 1", "cell 2", "cell 3"]
    assert capsys.readouterr().out == f"notebooks/{script.name}: started\n"


def test_log_follows_the_work(monkeypatch, capsys):
    """With execute_all, a notebook of LAST says "started" after the others'
    lines, though its kernel starts with theirs."""
    def fake_execute(script, output_root, ready, abandon, started):
        if ready is None:
            time.sleep(0.05)
        else:
            ready.wait()
            started()
        return script.stem

    monkeypatch.setattr(reproduce, "execute", fake_execute)
    first, last = reproduce.NOTEBOOKS[0], next(s for s in reproduce.NOTEBOOKS
                                               if s.stem in reproduce.LAST)
    for script, notebook, error, seconds in reproduce.execute_all([first, last]):
        print(f"{script.stem}: done")
    assert capsys.readouterr().out.splitlines() == [
        f"notebooks/{first.name}: started", f"{first.stem}: done",
        f"notebooks/{last.name}: started", f"{last.stem}: done"]


@pytest.mark.parametrize("stem", reproduce.LAST)
def test_a_last_notebook_reads_no_data_in_its_first_cell(stem):
    """A notebook of LAST runs its first code cell beside the others, before
    they have written data/: that cell may only import.  Every statement of
    it is an import or a sys.path entry (a data read there would see the
    data of the run before)."""
    import ast
    import jupytext
    cell = next(c for c in jupytext.read(reproduce.ROOT / "notebooks" / f"{stem}.py").cells
                if c.cell_type == "code")
    for node in ast.parse(cell.source).body:
        assert isinstance(node, (ast.Import, ast.ImportFrom)) or (
            "sys.path" in ast.unparse(node)), (stem, ast.unparse(node))
