"""The report in brief (website/report.md) and the links the claims and errata
tables make to it and to the notebooks' sections (scripts/claims.py): every
"where" of data/claims.csv and data/errata.csv names a heading of the page,
every "measured in" a heading of its notebook, and the links written into
the README and notebook 14 lead there.  The anchors are computed here as
MyST computes them (markdown-it with dollar math, myst_parser's GitHub slug
of a heading's text and code), independently of the tables' generator."""

import json
import re
import sys
from pathlib import Path

import jupytext
import pandas as pd
import pytest
from markdown_it import MarkdownIt
from mdit_py_plugins.dollarmath import dollarmath_plugin
from myst_parser.slugs import github_slugify, unique_slug

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "scripts"))
import claims  # noqa: E402

REPORT = ROOT / claims.REPORT_PAGE
CLAIMS = pd.read_csv(ROOT / "data" / "claims.csv")
ERRATA = pd.read_csv(ROOT / "data" / "errata.csv")
WHERE = sorted({ref for table in (CLAIMS, ERRATA) for where in table["where"]
                for ref in where.split(", ")})
PARSER = MarkdownIt("commonmark").use(dollarmath_plugin)


def heading_slugs(markdown_texts):
    """{anchor: heading} of the level 1-3 headings of a page made of
    ``markdown_texts`` (a page's text, or a notebook's Markdown cells), as
    MyST names them with myst_heading_anchors = 3."""
    found = {}
    for text in markdown_texts:
        tokens = PARSER.parse(text)
        for opening, inline in zip(tokens, tokens[1:]):
            if opening.type == "heading_open" and int(opening.tag[1]) <= 3:
                title = "".join(child.content for child in inline.children
                                if child.type in ("text", "code_inline"))
                slug = github_slugify(title)
                if slug:
                    found[unique_slug(slug, found)] = inline.content
    return found


def report_slugs():
    return heading_slugs([REPORT.read_text()])


def notebook_slugs(notebook, suffix=".ipynb"):
    """The anchors of notebooks/NOTEBOOK as the site shows it (its .ipynb),
    or (``suffix=".py"``) as its source says."""
    cells = jupytext.read(ROOT / "notebooks" / f"{notebook}{suffix}").cells
    return heading_slugs([c.source for c in cells if c.cell_type == "markdown"])


@pytest.mark.parametrize("reference", WHERE)
def test_every_where_names_a_heading_of_the_report_page(reference):
    assert claims.anchor(claims.report_heading(reference)) in report_slugs(), reference


@pytest.mark.parametrize("notebook, section", sorted(set(zip(CLAIMS.notebook, CLAIMS.section))))
def test_every_measured_in_names_a_heading_of_its_notebook(notebook, section):
    slugs = notebook_slugs(notebook)
    found = claims.section_anchor(notebook, section)
    assert found in slugs, (notebook, section, found)
    assert re.sub(r"^\d+\. ", "", slugs[found]).replace("$", "").startswith(section)


def test_the_generator_names_anchors_as_myst_does():
    """claims.anchors (the tables' links) against MyST's slugs, on the report
    page and on every notebook, whose headings have math, quotes, numbers
    and repeats."""
    page = [line.lstrip("#").strip() for line in REPORT.read_text().splitlines()
            if re.match(r"#{1,3} ", line)]
    assert claims.anchors(page) == list(report_slugs())
    for script in sorted((ROOT / "notebooks").glob("[0-9][0-9]_*.py")):
        ours = [found for _, found in claims.notebook_headings(script.stem)]
        assert ours == list(notebook_slugs(script.stem, ".py")), script.stem


def test_the_report_page_has_every_section_equation_and_figure():
    """A heading for each section the report numbers, each of its 19
    equations and 3 figures, and the findings it does not make; no math in
    a heading, so that GitHub, which slugs the math's text too, gives the
    same anchors as MyST."""
    slugs = report_slugs()
    references = ([f"Sec. {n}" for n in claims.REPORT_SECTIONS] + [f"eq. {n}" for n in range(1, 20)]
                  + [f"Fig. {n}" for n in (1, 2, 3)] + ["(none)"])
    missing = [r for r in references if claims.anchor(claims.report_heading(r)) not in slugs]
    assert missing == []
    assert not [h for h in slugs.values() if "$" in h]


def test_a_wrong_reference_fails():
    """The checks can fail: a reference the page has no heading for, a
    section no notebook heading starts with, links to neither."""
    assert claims.anchor(claims.report_heading("eq. 20")) not in report_slugs()
    with pytest.raises(ValueError, match="Sec. 7"):
        claims.report_heading("Sec. 7")
    with pytest.raises(ValueError, match="no heading"):
        claims.section_anchor("02_cannonball", "Figure 4")
    assert claims.anchor("How large? ($10^{-3}$)") == "how-large-"
    planted = ["website/report.md#eq-20", "notebooks/02_cannonball.ipynb#figure-4",
               "website/report.md#eq-9", "notebooks/04_convergence.ipynb#figure-3"]
    assert link_problems(planted, ROOT) == planted[:2]


def link_problems(targets, base):
    """The links among ``targets`` (href or Markdown targets, relative to the
    folder ``base``) to the report page or a notebook whose #fragment is not
    one of its headings' anchors."""
    problems = []
    for target in targets:
        path, _, fragment = target.partition("#")
        file = (base / path).resolve()
        if file == REPORT.resolve():
            known = report_slugs()
        elif file.parent == ROOT / "notebooks" and file.suffix == ".ipynb":
            known = notebook_slugs(file.stem)
        else:
            continue
        if fragment not in known:
            problems.append(target)
    return problems


def test_the_readme_tables_link_to_headings_that_exist():
    text = (ROOT / "README.md").read_text()
    tables = "".join(m[2] for m in re.finditer(r"<!-- begin (\w+) -->(.*?)<!-- end \1 -->",
                                               text, flags=re.S))
    targets = re.findall(r"\]\(([^)]+#[^)]*)\)", tables)
    # one per reference of "where" in both tables, one per claim's "measured in"
    assert len(targets) == len(CLAIMS) + sum(len(w.split(", ")) for t in (CLAIMS, ERRATA)
                                             for w in t["where"])
    assert link_problems(targets, ROOT) == []


def test_the_claims_notebook_links_to_headings_that_exist():
    cells = json.loads((ROOT / "notebooks" / "14_claims_and_errata.ipynb").read_text())["cells"]
    html = "".join("".join(o.get("data", {}).get("text/html", "")) for c in cells
                   for o in c.get("outputs", []))
    targets = re.findall(r'href="([^"]+#[^"]*)"', html)
    assert len(targets) > len(CLAIMS)
    assert link_problems(targets, ROOT / "notebooks") == []
