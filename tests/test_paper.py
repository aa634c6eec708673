"""The paper (`make paper`): built from the committed data/ and figures/, it
holds every figure and every row of the claims and errata tables, and the
build is deterministic and is the committed PDF."""

import json
import shutil
import sys
from pathlib import Path

import pandas as pd
import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "scripts"))
import paper  # noqa: E402


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    folder = tmp_path_factory.mktemp("paper")
    first, second = folder / "first.pdf", folder / "second.pdf"
    paper.build(first)
    paper.build(second)
    return first, second


def unshown():
    """{figure the paper does not show: the figure it shows instead}
    (``#fig(NAME, ..., instead: OTHER)``: the two show the same)."""
    return {m["value"]["name"]: m["value"]["instead"]
            for m in json.loads(paper.query("<unshown-figure>"))}


def test_every_figure_is_in_the_paper():
    """Each figure is shown, but one that repeats a figure the paper shows."""
    sources = {Path(image["source"]).stem for image in json.loads(paper.query("image"))}
    figures = {path.stem for path in (ROOT / "figures").glob("*.pdf")}
    left_out = unshown()
    assert figures - set(left_out) <= sources, (
        f"figures not in the paper: {sorted(figures - set(left_out) - sources)}")
    assert not set(left_out) & sources
    assert set(left_out.values()) <= sources


def test_every_figure_is_set_near_its_first_reference():
    """Each figure is set on the page of its first reference or the next."""
    far = [f"Figure {row['number']} ({row['name']}): first referred to on p. {row['first']}, "
           f"set on p. {row['page']}" for row in paper.figure_pages()
           if row["first"] is None or row["page"] - row["first"] not in (0, 1)]
    assert not far, far


@pytest.mark.parametrize("label, name, column", [("claim-row", "claims", "claim"),
                                                  ("erratum-row", "errata", "erratum")])
def test_every_table_row_is_in_the_paper(label, name, column):
    rows = [element["value"] for element in json.loads(paper.query(f"<{label}>"))]
    assert rows == pd.read_csv(ROOT / "data" / f"{name}.csv")[column].tolist()


def test_two_builds_give_the_same_bytes_and_the_committed_pdf(built):
    first, second = built
    assert first.read_bytes() == second.read_bytes()
    assert first.read_bytes() == paper.PDF.read_bytes(), (
        "paper/splinestep.pdf is not the build of the committed data: run make paper")


def test_the_paper_reads_its_numbers_from_data(tmp_path, built):
    """The same paper from a copy of the repository whose data/ says another
    headline number is a different PDF: the number is read, not typed."""
    for part in ("paper", "data", "figures"):
        shutil.copytree(ROOT / part, tmp_path / part)
    shutil.copy(ROOT / "CITATION.cff", tmp_path)
    headline = pd.read_csv(tmp_path / "data" / "headline-numbers.csv")
    headline.loc[headline.name == "position error, ellipse, dt = 0.01", "text"] = "7.7e-07"
    headline.to_csv(tmp_path / "data" / "headline-numbers.csv", index=False)
    paper.build(tmp_path / "changed.pdf", root=tmp_path)
    assert (tmp_path / "changed.pdf").read_bytes() != built[0].read_bytes()


def test_every_figure_is_cited_in_the_text():
    """Each figure is referred to (@fig-NAME) where the text discusses it; the
    table of figure sources names figures by number, not by reference."""
    cited = {ref["target"] for ref in json.loads(paper.query("ref"))}
    figures = {f"<fig-{path.stem}>" for path in (ROOT / "figures").glob("*.pdf")
               if path.stem not in unshown()}
    assert figures <= cited, f"figures never cited: {sorted(figures - cited)}"


def test_the_figure_sources_are_the_notebooks_that_write_them():
    """paper/figure-sources.csv (the paper's reproduction table) is what the
    notebooks' save_figure calls say, and names every figure once."""
    committed = (ROOT / "paper" / "figure-sources.csv").read_text()
    assert committed == paper.figure_sources(), "run make paper"
    names = pd.read_csv(ROOT / "paper" / "figure-sources.csv").figure
    assert sorted(names) == sorted(path.stem for path in (ROOT / "figures").glob("*.pdf"))
    assert names.is_unique
