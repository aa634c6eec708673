"""How the website reads the notebooks and the paper's captions.

:func:`read` is the reader ``conf.py`` gives myst-nb for ``.ipynb`` files:
the stored notebook, its HTML outputs' links to other notebooks and pages
leading to their pages and their formulas in the site's delimiters
(:func:`site_html`), with every code cell longer than :data:`SHOWN_LINES`
lines collapsed behind a "show code" toggle, and every cell folded in
JupyterLab (:func:`folded`, the plotting code) collapsed behind "Show the
plotting code" (the outputs of both stay in view), and
each figure a notebook writes given the paper's caption for it, as caption
and as alt text.  Nothing is executed.
"""

import json
import re
import shutil
import sys
from pathlib import Path

import nbformat

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "scripts"))
import outputs  # noqa: E402  (the Unicode tables of the notebooks' tables)
from paper import SAVED_FIGURE, SOURCE as PAPER  # noqa: E402,F401

# Code cells of more lines than this are collapsed on the site.
SHOWN_LINES = 12
# A folded cell that draws: matplotlib's calls, or the figure saved.
PLOTTING = re.compile(r"\b(plt|ax|axes|fig)\b\.|\bsave_figure\(|\.plot\(")
# Typst math names: the Greek letters and a few symbols.
_SYMBOLS = {**outputs.GREEK, "dots": "…", "in": "∈", "times": "×", "approx": "≈"}


def _bracketed(text, start):
    """The text between the ``[`` at ``start`` and its matching ``]``."""
    depth = 0
    for index in range(start, len(text)):
        depth += {"[": 1, "]": -1}.get(text[index], 0)
        if depth == 0:
            return text[start + 1:index]
    raise ValueError(f"unbalanced [ at {start} of the paper")


def _plain_math(math):
    """Typst math as plain Unicode text: ``Delta t = 0.08 \\/ 2^k`` -> Δt = 0.08/2ᵏ."""
    math = re.sub(r"\^\(([-+0-9]+)\)|\^([-+0-9]+|[kyn]\b)", lambda m: (m.group(1) or m.group(2))
                  .translate(outputs.SUPERSCRIPTS), math)
    math = re.sub(r"_([0-9hiknt])\b", lambda m: m.group(1).translate(outputs.SUBSCRIPTS), math)
    math = re.sub(r"tilde\((\w)\)", "\\1\u0303", math)
    math = re.sub(r"sqrt\((\w+)\)", r"√\1", math)
    math = re.sub(r'"(\w+)"', r"\1", math)
    math = re.sub(r"(?<![A-Za-z])(" + "|".join(_SYMBOLS) + r")(?![A-Za-z])",
                  lambda m: _SYMBOLS[m.group(1)], math)
    return math.replace("\\/", "/").replace("Δ t", "Δt")


def plain(markup):
    """A caption in Typst markup as plain text (math in Unicode)."""
    text = re.sub(r"\$([^$]*)\$", lambda m: _plain_math(m.group(1)), markup)
    text = re.sub(r"`([^`]*)`", r"\1", text).replace("\\/", "/")
    return re.sub(r"\s+", " ", text).strip()


def captions(paper=PAPER):
    """{figure name: its caption in the paper, as plain text}."""
    text = Path(paper).read_text()
    found = {}
    for match in re.finditer(r'#fig\("([^"]+)",\s*\[', text):
        found[match.group(1)] = plain(_bracketed(text, match.end() - 1))
    return found


def site_html(html):
    """An HTML output as the site shows it: its links to notebooks and
    Markdown pages (``02_cannonball.ipynb#figure-3``,
    ``../website/report.md#eq-9``) lead to their pages, and its formulas
    between dollars, which JupyterLab's MathJax typesets, are written
    between \\( and \\), which the site's MathJax 2 reads."""
    html = re.sub(r'href="([^":#]+)\.(?:ipynb|md)(#[^"]*)?"',
                  lambda m: f'href="{m[1]}.html{m[2] or ""}"', html)
    return re.sub(r"\$([^$<>]+)\$", r"\\(\1\\)", html)


def read(text, path=None):
    """The notebook in ``text`` (ipynb JSON) as the site shows it."""
    notebook = nbformat.reads(text, as_version=4)
    known = captions()
    for cell in notebook.cells:
        if cell.cell_type != "code":
            continue
        for output in cell.get("outputs", []):
            html = output.get("data", {}).get("text/html")
            if html:
                output["data"]["text/html"] = site_html("".join(html) if isinstance(html, list) else html)
        tags = cell.metadata.setdefault("tags", [])
        mystnb = cell.metadata.setdefault("mystnb", {})
        if folded(cell):
            # folded in JupyterLab: collapsed here too, under what it is
            kind = "the plotting code" if PLOTTING.search(cell.source) else "the code"
            mystnb["code_prompt_show"] = f"Show {kind}"
            mystnb["code_prompt_hide"] = f"Hide {kind}"
            if "hide-input" not in tags:
                tags.append("hide-input")
        elif len(cell.source.splitlines()) > SHOWN_LINES and "hide-input" not in tags:
            tags.append("hide-input")
        names = SAVED_FIGURE.findall(cell.source)
        if len(names) == 1 and names[0] in known:
            caption = known[names[0]]
            mystnb.update({"image": {"alt": caption},
                           "figure": {"caption": caption, "name": f"fig-{names[0]}"}})
    return notebook


def folded(cell):
    """True for a code cell whose source JupyterLab shows folded: the
    metadata ``{"jupyter": {"source_hidden": true}}`` (in a percent script,
    ``# %% jupyter={"source_hidden": true}``)."""
    return bool(cell.get("metadata", {}).get("jupyter", {}).get("source_hidden"))


def copy_mathjax(app, exception):
    """After a build: MathJax (from the jupyter-server-mathjax package) into
    the site's ``_static/mathjax/`` folder, so that math is typeset offline."""
    if exception is not None or app.builder.format != "html":
        return
    import jupyter_server_mathjax
    source = Path(jupyter_server_mathjax.__file__).parent / "static"
    shutil.copytree(source, Path(app.outdir) / "_static" / "mathjax", dirs_exist_ok=True)


# The manual's pages (website/NAME.md), in the order the sidebar lists them.
MANUAL = ("guide", "api", "scipy", "step-size-check", "fast-path", "speed", "findings",
          "report", "layout")


def notebook_pages(root=ROOT):
    """[(stem, title)] of the notebooks in reading order, which is their
    numbers' (the claims notebook, which collects the others' verdicts, is
    numbered last); the title is the notebook's first heading."""
    stems = sorted(p.stem for p in (Path(root) / "notebooks").glob("[0-9][0-9]_*.ipynb"))
    found = []
    for stem in stems:
        cells = json.loads((Path(root) / "notebooks" / f"{stem}.ipynb").read_text())["cells"]
        sources = ("".join(c["source"]) for c in cells if c["cell_type"] == "markdown")
        headings = (re.search(r"^# (.+)$", s, flags=re.M) for s in sources)
        title = next((h.group(1).strip() for h in headings if h), stem)
        found.append((stem, title.replace("`", "")))
    return found


def site_contents(app, docname, source):
    """Sphinx's source-read: the landing page (the README's page) ends with
    the site's table of contents, the notebooks in reading order, each
    under its number, the manual's pages and the paper (hidden: the sidebar
    shows it; the landing page lists them in its own words)."""
    if docname != "README":
        return
    lines = ["", "```{toctree}", ":hidden:", ":caption: Notebooks", ""]
    lines += [f"{stem[:2]} · {title} <notebooks/{stem}>"
              for stem, title in notebook_pages(app.srcdir)]
    lines += ["```", "", "```{toctree}", ":hidden:", ":caption: Manual", ""]
    lines += [f"website/{page}" for page in MANUAL]
    lines += ["```", "", "```{toctree}", ":hidden:", ":caption: Paper", "", "website/paper", "```"]
    source[0] += "\n".join(lines) + "\n"


def landing_redirect(app, exception):
    """After a build: ``index.html`` leading to the landing page (the README)."""
    if exception is None and app.builder.format == "html":
        (Path(app.outdir) / "index.html").write_text(
            '<!DOCTYPE html><meta charset="utf-8"><title>splinestep</title>'
            '<meta http-equiv="refresh" content="0; url=README.html">'
            '<a href="README.html">splinestep</a>\n')
