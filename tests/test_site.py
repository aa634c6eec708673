"""The website (`make reproduce`, `scripts/build_site.py`): built from the
notebooks and paper as they are (or the one `make reproduce` built, when it is
up to date with every file it is made of), every page opened in headless Chromium with no
network, at both widths at once.

Every page loads; every image loads and has alt text; every link within
the site leads to a file of it, and its #anchor to an element of that
page; every formula is
typeset by MathJax, with no MathJax error and no raw TeX left in the text;
no request leaves the site's folder; each notebook page shows each figure
its notebook writes, with the paper's caption.  Every page is opened at a
laptop's width (1366 x 900) and a phone's (390 x 844, as a phone: touch,
overlay scrollbars): no page is wider than the window, and nothing of its
text, printed output, code, formulas, tables or sidebars is cut off (see
:func:`test_every_page_in_a_browser`).

What the build writes into the pages (website/pages.py) is checked too:
the landing page (the findings, the notebooks by number, the claims
tables; no build instructions), the guide's examples with what each
printed, the findings page's links to the notebooks and its figures, the
paper's abstract with the numbers of data/headline-numbers.csv; a cell
folded in JupyterLab is collapsed with its outputs in view; an example
that raises fails the build.

The browser is Debian's ``chromium`` (``make browser`` installs it, and
``.ci/run`` runs that first), driven by playwright from environment.txt with
its executable path: nothing is downloaded.  Without it the browser test is
skipped with a message saying how to install it."""

import functools
import re
import shutil
import sys
from pathlib import Path
from urllib.parse import unquote, urlparse

import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "scripts"))
sys.path.insert(0, str(ROOT / "website"))
import build_site  # noqa: E402
import notebook_reader  # noqa: E402
import pages  # noqa: E402

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
# Flags for a machine with no network: no background requests, no sandbox as root.
FLAGS = ["--no-sandbox", "--disable-gpu", "--disable-background-networking",
         "--disable-component-update", "--disable-sync", "--no-first-run"]
NOTEBOOKS = sorted((ROOT / "notebooks").glob("[0-9][0-9]_*.ipynb"))

# Text a reader would see if math were not typeset: \( \) \[ \], $...$
# around a TeX command, or a TeX command alone.
RAW_MATH = re.compile(r"\\\(|\\\)|\\\[|\\\]|\$[^$\s][^$]*\$|\\(frac|times|omega|mu|sqrt|alpha)\b")
VISIBLE_TEXT = """() => {
  const root = document.querySelector('main') || document.body;
  const walk = document.createTreeWalker(root, NodeFilter.SHOW_TEXT);
  const out = []; let node;
  while ((node = walk.nextNode())) {
    if (node.parentElement.closest('pre, code, script, style, .MathJax_Preview, .MathJax, .MathJax_Display, details:not([open]), .highlight')) continue;
    out.push(node.textContent);
  }
  return out.join(' ');
}"""
MATH_STATE = """() => {
  const spans = [...document.querySelectorAll('.math.notranslate')];
  return {formulas: spans.length,
          untypeset: spans.filter(e => !e.querySelector('.MathJax, .MathJax_Display')).length,
          errors: document.querySelectorAll('.MathJax_Error, merror').length};
}"""
MATH_DONE = """() => !(window.MathJax && MathJax.Hub) ||
  (MathJax.isReady && MathJax.Hub.queue.pending == 0 && MathJax.Hub.queue.running == 0)"""
LINKS = """() => [...document.querySelectorAll('a[href]')].map(a => a.href)
  .filter(h => h.startsWith('file:'))"""
IMAGES = """() => [...document.images].map(i => ({src: i.getAttribute('src'),
  loaded: i.complete && i.naturalWidth > 0, alt: i.getAttribute('alt') || ''}))"""
# The two windows every page is read in: a laptop's, and a phone's (a
# phone's browser: touch, and scrollbars drawn over the page, not beside it).
VIEWPORTS = {"1366x900": {"viewport": {"width": 1366, "height": 900}},
             "390x844": {"viewport": {"width": 390, "height": 844},
                         "is_mobile": True, "has_touch": True}}
OPEN_ALL = """() => { document.querySelectorAll('details').forEach(d => d.open = true);
  return new Promise(done => requestAnimationFrame(() => requestAnimationFrame(done))); }"""
# What of the page is wider than the window or cut off at a box's edge (the
# rules are test_every_page_in_a_browser's docstring).  A box that scrolls
# sideways shows it: its scrollbar takes room (4 px or more).
LAYOUT = r"""() => {
  const root = document.documentElement, width = root.clientWidth, problems = [];
  const article = document.querySelector('.bd-article') || document.querySelector('main')
    || document.body;
  const scrolls = e => ['auto', 'scroll'].includes(getComputedStyle(e).overflowX);
  const shown = e => e.checkVisibility() && e.offsetWidth > 0;
  const inView = e => {
    const r = e.getBoundingClientRect();
    return r.left >= -1 && r.right <= width + 1;
  };
  const scroller = e => {
    for (let a = e; a && a !== article.parentElement; a = a.parentElement)
      if (scrolls(a)) return a;
    return null;
  };
  const bar = e => {
    const s = getComputedStyle(e);
    return e.offsetHeight - e.clientHeight - parseFloat(s.borderTopWidth)
      - parseFloat(s.borderBottomWidth) >= 4;
  };
  const name = e => {
    const text = (e.innerText || e.textContent || '').trim().split('\n')
      .sort((a, b) => b.length - a.length)[0] || '';
    const classes = typeof e.className == 'string' && e.className.trim()
      ? '.' + e.className.trim().split(/\s+/).join('.') : '';
    return `${e.tagName.toLowerCase()}${classes} "${text.slice(0, 60)}"`;
  };
  const cut = e => `${e.scrollWidth} px in ${e.clientWidth}`;
  // a box that scrolls sideways: within the window, with a scrollbar
  const scrolling = (e, what) => {
    if (!inView(e)) problems.push(`${what} scrolls in a box wider than the window: ${name(e)}`);
    else if (!bar(e)) problems.push(`${what} scrolls with no scrollbar: ${name(e)}`);
  };
  // printed output and code: it fits its box, or its box scrolls; at a
  // laptop's width what a notebook prints fits
  for (const e of article.querySelectorAll('pre, .cell_output .output')) {
    if (!shown(e) || e.scrollWidth <= e.clientWidth + 1) continue;
    if (!scrolls(e)) problems.push(`cut off (${cut(e)}): ${name(e)}`);
    else if (width >= 1200 && e.matches('.cell_output pre'))
      problems.push(`printed output scrolls (${cut(e)}): ${name(e)}`);
    else scrolling(e, 'output or code');
  }
  // tables: within the window, or in a wrapper that scrolls
  for (const t of article.querySelectorAll('table')) {
    if (!shown(t) || inView(t)) continue;
    const wrapper = scroller(t.parentElement);
    if (!wrapper) problems.push(`table wider than the window: ${name(t.rows[0] || t)}`);
    else scrolling(wrapper, 'table');
  }
  // formulas: MathJax's box and the one around it cut off no more than a
  // glyph's overhang (8 px), or scroll
  for (const m of article.querySelectorAll('.math.notranslate')) {
    if (!shown(m)) continue;
    for (const box of [m.querySelector('span.math'), m]) {
      if (!box || getComputedStyle(box).display == 'inline') continue;
      if (box.scrollWidth <= box.clientWidth + 8) continue;
      if (!scrolls(box)) problems.push(`formula cut off (${cut(box)}): ${name(m)}`);
      else scrolling(box, 'formula');
      // a displayed formula that scrolls says so where it is cut: a shade
      // at its right edge (which a phone's overlaid scrollbar does not)
      if (scrolls(box) && box.matches('div.math') && box.scrollLeft == 0
          && !box.parentElement.classList.contains('ss-more'))
        problems.push(`formula scrolls with no shade at its edge: ${name(m)}`);
    }
  }
  // anything else past the window's right edge, but in a box that scrolls
  for (const e of article.querySelectorAll('*')) {
    const r = e.getBoundingClientRect();
    if (r.width > 0 && r.right > width + 1 && !scroller(e.parentElement)) {
      problems.push(`past the window's edge (${Math.round(r.right)} px): ${name(e)}`);
      break;
    }
  }
  if (root.scrollWidth > width + 1) problems.push(`page ${root.scrollWidth} px wide`);
  return {width: root.scrollWidth, problems};
}"""

# What of a sidebar is cut at its edge: at a laptop's width the sidebars as
# they stand, at a phone's each in the drawer its button opens.  A sidebar
# that scrolls sideways, or an entry past its right edge, is cut.
SIDEBARS = r"""async () => {
  const frame = () => new Promise(done => requestAnimationFrame(() => requestAnimationFrame(done)));
  const problems = [];
  const check = (box, what) => {
    const limit = box.getBoundingClientRect().left + box.clientLeft + box.clientWidth;
    if (box.scrollWidth > box.clientWidth + 1)
      problems.push(`${what} scrolls sideways (${box.scrollWidth} px in ${box.clientWidth})`);
    // the text itself (a link's box may be wider than its words)
    const walk = document.createTreeWalker(box, NodeFilter.SHOW_TEXT);
    const range = document.createRange();
    for (let node; (node = walk.nextNode());) {
      if (!node.textContent.trim() || !node.parentElement.checkVisibility()) continue;
      range.selectNodeContents(node);
      const r = range.getBoundingClientRect();
      if (r.width > 0 && r.right > limit + 1) {
        const entry = node.parentElement.closest('a, li') || node.parentElement;
        problems.push(`${what}: "${entry.textContent.trim().slice(0, 60)}" cut at its edge`);
        break;
      }
    }
  };
  for (const [side, toggle] of [['primary', '.primary-toggle'], ['secondary', '.secondary-toggle']]) {
    const sidebar = document.getElementById(`pst-${side}-sidebar`);
    if (sidebar && sidebar.checkVisibility() && sidebar.offsetWidth > 0) {
      check(sidebar, `the ${side} sidebar`);
      continue;
    }
    const button = document.querySelector(toggle);
    const dialog = document.getElementById(`pst-${side}-sidebar-modal`);
    if (!button || !dialog || !button.checkVisibility()) continue;
    button.click();
    await frame();
    if (dialog.open) check(dialog, `the ${side} sidebar's drawer`);
    dialog.close();
    await frame();
  }
  return problems;
}"""


@functools.lru_cache(maxsize=None)
def anchors(path):
    """The ids of the HTML file at ``path`` (and the names of its <a>)."""
    from html.parser import HTMLParser
    found = set()

    class Ids(HTMLParser):
        def handle_starttag(self, tag, attrs):
            found.update(value for key, value in attrs
                         if value and (key == "id" or (key == "name" and tag == "a")))
    Ids().feed(path.read_text(errors="replace"))
    return found


@pytest.fixture(scope="module")
def site(tmp_path_factory):
    """The site ``make reproduce`` built in build/site when it is up to date
    with every file it is made of (by contents: ``scripts/freshness.py``);
    else the site built here."""
    import reproduce
    if reproduce.site_is_current():
        return build_site.SITE
    output = tmp_path_factory.mktemp("site") / "site"
    seconds, pages = build_site.build(output)
    return output


def test_the_site_has_every_notebook_and_the_paper(site):
    for notebook in NOTEBOOKS:
        assert (site / "notebooks" / f"{notebook.stem}.html").exists()
    pdfs = list((site / "_downloads").rglob("splinestep.pdf"))
    assert len(pdfs) == 1 and pdfs[0].read_bytes() == (ROOT / "paper" / "splinestep.pdf").read_bytes()
    assert "splinestep.pdf" in (site / "website" / "paper.html").read_text()


def test_every_figure_has_the_papers_caption(site):
    """Each figure a notebook writes is shown on its page with the paper's
    caption for that figure, as caption and as alt text (read from the
    figure element that carries the figure's name)."""
    import html
    captions = notebook_reader.captions()
    for notebook in NOTEBOOKS:
        script = notebook.with_suffix(".py").read_text()
        page = (site / "notebooks" / f"{notebook.stem}.html").read_text()
        for name in notebook_reader.SAVED_FIGURE.findall(script):
            caption = captions[name]
            # no Typst markup left: $, \, #, ^, or a one-letter name with an index
            assert not re.search(r"[$\\#^]|(?<![A-Za-z])[A-Za-zα-ω]_\w", caption), caption
            figure = re.search(r'<figure[^>]*id="fig-%s">\s*<img alt="([^"]*)"' % re.escape(name), page)
            assert figure, f"{notebook.stem}: no figure {name}"
            assert html.unescape(figure.group(1)) == caption, name


def test_long_code_cells_are_collapsed_and_short_ones_shown(site):
    """Long cells behind "Show code cell source", cells folded in JupyterLab
    behind their own summary (test_a_folded_cell_is_collapsed_with_its_outputs_shown)."""
    page = (site / "notebooks" / "02_cannonball.html").read_text()
    assert "Show code cell source" in page
    import nbformat
    cells = nbformat.read(NOTEBOOKS[1], as_version=4).cells
    long_cells = [c for c in cells if c.cell_type == "code" and not notebook_reader.folded(c)
                  and len(c.source.splitlines()) > notebook_reader.SHOWN_LINES]
    assert page.count("Show code cell source") == len(long_cells) > 0


def tiny_notebook():
    """A notebook of a plotting cell folded in JupyterLab, with printed text
    and an image as outputs, and a short cell that is not folded."""
    import nbformat
    from nbformat.v4 import new_code_cell, new_markdown_cell, new_notebook, new_output
    png = ("iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAYAAAAfFcSJAAAADUlEQVR42mNk+M9QDwADhgGAWjR9awAAAABJRU5ErkJggg==")
    folded = new_code_cell("fig, ax = plt.subplots()\nax.plot([0, 1])\nprint('drawn', 'and', 'folded')",
                           metadata={"jupyter": {"source_hidden": True}},
                           outputs=[new_output("stream", name="stdout", text="drawn and folded\n"),
                                    new_output("display_data", data={"image/png": png,
                                                                     "text/plain": "<Figure>"})])
    shown = new_code_cell("answer = 6 * 7\nprint(answer)",
                          outputs=[new_output("stream", name="stdout", text="42\n")])
    notebook = new_notebook(cells=[new_markdown_cell("# A tiny notebook"), folded, shown],
                            metadata={"kernelspec": {"name": "python3", "display_name": "Python 3",
                                                     "language": "python"},
                                      "language_info": {"name": "python"}})
    return nbformat.writes(notebook)


def test_a_folded_cell_is_collapsed_with_its_outputs_shown(tmp_path):
    """A cell JupyterLab shows folded (``{"jupyter": {"source_hidden":
    true}}``, a percent script's ``# %% jupyter={"source_hidden": true}``)
    is read by the site's reader and built by myst-nb as the site builds
    notebooks: its code inside a closed <details> under "Show the plotting
    code", its printed text and figure after it, in view; a cell that is not
    folded shows its code."""
    import jupytext
    from sphinx.cmd.build import build_main
    script = jupytext.reads('# %% jupyter={"source_hidden": true}\nax.plot([0, 1])\n\n'
                            '# %%\nprint(1)\n', fmt="py:percent")
    assert [notebook_reader.folded(c) for c in script.cells] == [True, False]

    source = tmp_path / "source"
    source.mkdir()
    (source / "tiny.ipynb").write_text(tiny_notebook())
    (source / "conf.py").write_text(
        f"import sys\nsys.path.insert(0, {str(ROOT / 'website')!r})\n"
        "import notebook_reader\n"
        "extensions = ['myst_nb']\nroot_doc = 'tiny'\nnb_execution_mode = 'off'\n"
        "nb_custom_formats = {'.ipynb': ['notebook_reader.read', {}, False]}\n"
        "nb_merge_streams = True\n")
    import contextlib
    import io
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()) as err:
        code = build_main(["-q", "-W", "-E", "-b", "html", str(source), str(tmp_path / "html")])
    assert code == 0, err.getvalue()
    html = (tmp_path / "html" / "tiny.html").read_text()
    folded = re.search(r"<details[^>]*>(.*?)</details>", html, flags=re.S)
    assert folded and "Show the plotting code" in folded.group(1)
    assert "subplots" in folded.group(1) and "drawn and folded" not in folded.group(1)
    after = html[folded.end():]
    assert "drawn and folded" in after and "<img" in after      # the outputs, in view
    assert html.count("<details") == 1 and "6</span>" in after and "42" in after


def test_an_example_that_raises_fails_the_build(tmp_path):
    """The guide's examples run in one process, in order, in one namespace;
    what each prints is written under it; the first that raises stops the
    build with the example, its line and its traceback."""
    page = tmp_path / "page.md"
    page.write_text("# A page\n\n```python\nx = 6 * 7\nprint('x is', x)\n```\n\nText.\n\n"
                    "```python\nimport warnings\nwarnings.warn('careful')\nprint(x + 1)\n```\n")
    examples = pages.Examples(page, root=tmp_path).start()
    assert examples.printed() == ["x is 42\n", "UserWarning: careful\n43\n"]
    shown = pages.Examples(page, root=tmp_path).start().with_outputs()
    assert shown.count(":class: ss-example-output") == 2 and "x is 42\n```" in shown
    assert shown.index("x is 42") < shown.index("Text.")

    page.write_text(page.read_text() + "\n```python\nprint('before')\n1 / (x - 42)\n```\n")
    with pytest.raises(pages.ExampleFailed, match=r"example 3 \(the Python block at line 16\)"
                       r"(.|\n)*before(.|\n)*ZeroDivisionError"):
        pages.Examples(page, root=tmp_path).start().printed()


def test_the_guide_shows_what_each_example_prints(site):
    """Each example of the guide that prints has its output under it, on
    the built page."""
    blocks = pages.Examples(ROOT / "website" / "guide.md").blocks()
    page = (site / "website" / "guide.html").read_text()
    printing = [b for b in blocks if "print(" in b]
    assert page.count('class="ss-example-output') == len(printing) > 0
    assert "observed order 2.00" in page


def test_the_landing_page_is_for_its_reader(site):
    """The landing page says what the project found and where to go next;
    it does not ask its reader to build the site; the claims and errata
    tables are the README's; the numbers its prose gives are inputs or
    computed (tests/test_prose_numbers.py's rule), those of the findings
    read from data/headline-numbers.csv when the site is built."""
    import test_prose_numbers as prose
    page = (site / "README.html").read_text()
    assert "make site" not in page and "build/site" not in page
    assert "{headline}" not in page and "{notebooks}" not in page
    text = (ROOT / "website" / "landing.md").read_text()
    for name in re.findall(r"\{headline\}`([^`]+)`", re.sub(r"<!--.*?-->", "", text, flags=re.S)):
        assert pages.headline(name) in page.replace("&nbsp;", "\u00a0"), name
    for table in ("claims", "errata"):
        rows = [line for line in pages.readme_table(table).splitlines()[2:] if line.startswith("|")]
        assert page.count("<tr") >= len(rows) > 0
    words = re.sub(r"\{headline\}`[^`]*`|<!--.*?-->", " ", text, flags=re.S)
    words = re.sub(r"```.*?```", " ", words, flags=re.S)
    words = re.sub(r"\]\([^)]*\)", "]", words)
    candidates = prose.np.array([v for script in prose.NOTEBOOKS
                                 for v in prose.output_numbers(script.with_suffix(".ipynb"))]
                                + prose.data_numbers())
    assert prose.unexplained(words, candidates) == []


def test_the_sidebar_lists_the_notebooks_by_number(site):
    """The sidebar (and the landing page) list the notebooks by number,
    each under its number, the claims notebook last."""
    page = (site / "README.html").read_text()
    sidebar = page[page.index('class="bd-sidebar-primary'):]
    listed = re.findall(r'href="notebooks/(\d\d)_\w+\.html">\s*(\d\d) \u00b7 ', sidebar)
    numbers = [n for n, _ in listed]
    assert numbers == sorted(p.stem[:2] for p in NOTEBOOKS)
    assert all(a == b for a, b in listed) and numbers[-1] == "14"
    article = page[page.index('<article'):page.index('</article>')]
    assert re.findall(r'href="notebooks/(\d\d)_\w+\.html">', article[article.index("Where to go next"):]
                      )[:len(numbers)] == numbers


def test_the_findings_link_the_notebooks_and_show_the_figures(site):
    """Every notebook the findings page names is a link to its page, and
    each figure it shows is the paper's, with the paper's caption as alt
    text, linked to the figure on its notebook's page."""
    import html
    text = (ROOT / "website" / "findings.md").read_text()
    linked = re.sub(r"\[[^\]]*\]\(\.\./notebooks/\d\d_\w+\.ipynb(#[^)]*)?\)", " ", text)
    assert not re.findall(r"\b\d\d_[a-z_]+|notebook \d\d|notebooks/", linked)
    assert "../figures/" not in text
    page = (site / "website" / "findings.html").read_text()
    names = re.findall(r"```\{paper-figure\} ([\w-]+)", text)
    assert len(names) >= 8
    captions = notebook_reader.captions()
    where = pages.figure_notebooks()
    for name in names:
        image = re.search(r'<img alt="([^"]*)" src="\.\./_images/%s\.png"' % re.escape(name), page)
        assert image and html.unescape(image.group(1)) == captions[name], name
        assert f'href="../{where[name]}.html#fig-{name}"' in page, name


def test_the_paper_page_has_the_abstract_and_the_pdf(site):
    """The paper's page gives the title, the abstract with the numbers the
    paper reads from data/headline-numbers.csv, its sections and a link
    to the PDF."""
    page = (site / "website" / "paper.html").read_text().replace("&nbsp;", "\u00a0")
    source = (ROOT / "paper" / "splinestep.typ").read_text()
    block = source[source.index("*Abstract.*"):]
    block = block[:block.index("])")]
    names = re.findall(r'#n\("([^"]+)"\)', block)
    assert names
    for name in names:
        assert pages.headline(name) in page, name
    assert "#n(" not in page and "{abstract}" not in page
    assert "Newmark's linear-acceleration method" in page
    assert re.search(r'href="[^"]*_downloads/[^"]*/splinestep\.pdf"', page)
    for section in pages.paper_sections():
        assert section.replace("'", "&#x27;") in page or section in page, section


def test_typst_prose_as_markdown():
    """The abstract's Typst: a number of the data, math, a citation; what
    the site does not know is an error, not text."""
    name = next(iter(pages.headline_numbers()))
    text = pages.typst_markup_as_markdown(f'*Strong* at #n("{name}"), $10^(-3)$, '
                                          '$omega h < sqrt(12)$ @report.')
    assert text.startswith("**Strong** at " + pages.headline(name))
    assert "$10^{-3}$" in text and "$\\omega h < \\sqrt{12}$" in text and "report.md" in text
    assert pages.as_unicode("4.1e-03") == "4.1\u00a0\u00d7\u00a010\u207b\u00b3"
    for bad in ('#claim("x")', '$arrow.r$', '#n("no such number")', "@nobody"):
        with pytest.raises((ValueError, KeyError)):
            pages.typst_markup_as_markdown(bad)


def test_the_speed_page_counts_the_fixed_costs_from_its_table():
    """The speed page's prose on the step-size check's share of a whole
    solve (fixed costs as large as the steps' own time at m = 10 and 100)
    agrees with the check's table on the same page."""
    text = (ROOT / "website" / "speed.md").read_text()
    rows = dict((m, (float(c), float(w))) for m, c, w in re.findall(
        r"^\| (10|100) \| ([\d.e+-]+) s \| ([\d.e+-]+) s \| [\d.]+% \|$", text, flags=re.M))
    prose = text[text.index('The last table\'s "whole run"'):text.index("<!-- begin scaling -->")]
    prose = " ".join(prose.split())
    steps_shown = re.search(r"the whole run less the check: ([\d.]+) s and ([\d.]+) s", prose)
    for (m, (check, whole)), shown_steps in zip(sorted(rows.items(), key=lambda r: int(r[0])),
                                                steps_shown.groups()):
        steps = whole - check
        table_share, whole_share = check / whole, check / (whole + steps)
        assert abs(float(shown_steps) - steps) < 1e-9 + 1e-3 * steps, (m, steps)
        shown = re.search(rf"from (\d+) % to about (\d+) % at m = {m}\b", prose)
        assert shown, m
        assert int(shown.group(1)) == round(100 * table_share)
        assert abs(int(shown.group(2)) - 100 * whole_share) <= 2.5, (m, whole_share)
    assert set(rows) == {"10", "100"}


def test_captions_as_plain_text():
    """Typst math in a caption becomes Unicode text."""
    assert notebook_reader.plain("steps $Delta t = 0.08 \\/ 2^k$, rtol $10^(-13)$, "
                                 "$mu = 0.4$, $sqrt(6)$, $omega_1$, $tilde(H)$, $T_h$") == \
        "steps Δt = 0.08 / 2ᵏ, rtol 10⁻¹³, μ = 0.4, √6, ω₁, H̃, Tₕ"


def read_in_own_browser(site, window):
    """:func:`read_pages` in a headless Chromium of its own, its scrollbars
    shown (playwright hides them by default), started by this thread's own
    playwright (playwright's objects belong to the thread that made them)."""
    from playwright.sync_api import sync_playwright
    with sync_playwright() as playwright:
        browser = playwright.chromium.launch(executable_path=CHROMIUM, args=FLAGS,
                                             ignore_default_args=["--hide-scrollbars"])
        try:
            return read_pages(browser, site, window)
        finally:
            browser.close()


@pytest.fixture(scope="module")
def readings(site):
    """{window: what :func:`read_pages` found}, every window read at once,
    each in its own thread and browser."""
    from concurrent.futures import ThreadPoolExecutor
    with ThreadPoolExecutor(len(VIEWPORTS)) as pool:
        futures = {window: pool.submit(read_in_own_browser, site, window)
                   for window in VIEWPORTS}
        return {window: future.result() for window, future in futures.items()}


def read_pages(browser, site, window):
    """Open every page of ``site`` in ``window`` (a key of VIEWPORTS).
    Returns (problems, requests outside the site, failed requests, {page:
    its width in pixels})."""
    pages = [p for p in sorted(site.rglob("*.html"))
             if "_static" not in p.parts and p.name != "index.html"]
    outside, failed, problems, widths = [], [], [], {}
    context = browser.new_context(**VIEWPORTS[window])
    page = context.new_page()
    page.on("request", lambda r: outside.append(r.url) if not (
        r.url.startswith(site.as_uri() + "/") or r.url.startswith(("data:", "about:"))) else None)
    page.on("requestfailed", lambda r: None if r.url.startswith("about:")
            else failed.append((r.url, r.failure)))
    page.on("pageerror", lambda error: problems.append(f"{page.url}: script error {error}"))
    page.goto((site / "index.html").as_uri())
    page.wait_for_url("**/README.html")
    for path in pages:
        response = page.goto(path.as_uri(), wait_until="load")
        name = f"{path.relative_to(site)} at {window}"
        if response is None or not response.ok:
            problems.append(f"{name}: did not load")
            continue
        page.wait_for_function(MATH_DONE, timeout=30_000)
        math = page.evaluate(MATH_STATE)
        if math["untypeset"] or math["errors"]:
            problems.append(f"{name}: {math}")
        raw = [m.group(0) for m in RAW_MATH.finditer(page.evaluate(VISIBLE_TEXT))]
        if raw:
            problems.append(f"{name}: raw math {raw[:5]}")
        for image in page.evaluate(IMAGES):
            # docutils writes the file's path where alt text is missing
            if (not image["loaded"] or not image["alt"].strip()
                    or re.search(r"\.(png|svg|jpe?g)$", image["alt"])):
                problems.append(f"{name}: image {image}")
        for target in sorted(set(page.evaluate(LINKS))):
            url = urlparse(target)
            file = Path(unquote(url.path))
            if not file.exists():
                problems.append(f"{name}: broken link {target}")
            elif (url.fragment and file.suffix == ".html"
                  and unquote(url.fragment) not in anchors(file)):
                problems.append(f"{name}: link to a missing anchor "
                                f"{file.relative_to(site)}#{url.fragment}")
        if path.parent.name == "notebooks" and math["formulas"] == 0:
            problems.append(f"{name}: no formula")
        # what a reader can open (collapsed code cells, details) opened
        page.evaluate(OPEN_ALL)
        layout = page.evaluate(LAYOUT)
        widths[str(path.relative_to(site))] = layout["width"]
        problems += [f"{name}: {problem}" for problem in layout["problems"]]
        problems += [f"{name}: {problem}" for problem in page.evaluate(SIDEBARS)]
    context.close()
    return problems, outside, failed, widths


@pytest.mark.skipif(CHROMIUM is None, reason="no chromium: `make browser` (or "
                    "`apt-get install chromium` as root) installs Debian's, which the test drives")
@pytest.mark.parametrize("window", VIEWPORTS)
def test_every_page_in_a_browser(readings, window):
    """Every page, in a laptop's window and in a phone's: it loads with no
    script error, its formulas are typeset, its images load and have alt text, its links
    within the site and their #anchors resolve (the id is read from the
    target's HTML file), no request leaves the site; and it is readable at
    that width, with every collapsed code cell and other details opened:

    - the page is no wider than the window (the root's scrollWidth at most
      its clientWidth + 1 px), and no element of the text reaches past the
      window's right edge unless it is inside a box that scrolls sideways
      (overflow-x auto or scroll);
    - printed output and code (every ``pre`` and notebook output) fits its
      box (scrollWidth <= clientWidth + 1 px) or scrolls in it: overflow-x
      auto or scroll, the box within the window and its scrollbar shown
      (taking 4 px or more): nothing is cut off at a box's edge.  At the
      laptop's width what a notebook prints fits, with no scrolling;
    - a table wider than the window is in a wrapper that scrolls in the
      same way;
    - a formula is not cut off by more than a glyph's overhang (8 px) at
      the edge of its box, MathJax's or the one around it, or scrolls; a
      displayed one that scrolls has a shade at its right edge;
    - nothing of the sidebars (the notebooks and pages, a page's
      contents) reaches past their right edge or makes them scroll
      sideways: at the laptop's width as they stand, at the phone's in the
      drawer each one's button opens."""
    problems, outside, failed, widths = readings[window]
    assert not problems, problems
    assert not outside, f"requests outside the site: {outside[:5]}"
    # A file MathJax asks for on demand while the next page loads is aborted by
    # that navigation (net::ERR_ABORTED): a failure only if the file is missing.
    failed = [url for url, why in failed if "ERR_ABORTED" not in str(why)
              or not Path(unquote(urlparse(url).path)).exists()]
    assert not failed, f"requests that failed: {failed[:5]}"


@pytest.mark.skipif(CHROMIUM is None, reason="no chromium: `make browser` installs Debian's")
def test_on_a_phone_the_visible_sidebar_buttons_open_their_drawers(site):
    """The menu and the page's contents: a tap on the button a phone shows
    opens the drawer (the theme binds only the first button of each kind,
    which its header hides; readable.js passes the others' clicks on)."""
    from playwright.sync_api import sync_playwright
    with sync_playwright() as playwright:
        browser = playwright.chromium.launch(executable_path=CHROMIUM, args=FLAGS)
        try:
            page = browser.new_page(**VIEWPORTS[min(VIEWPORTS, key=lambda w: VIEWPORTS[w]
                                                    ["viewport"]["width"])])
            page.goto((site / "website" / "guide.html").as_uri(), wait_until="load")
            for kind in ("primary", "secondary"):
                shown = [b for b in page.query_selector_all(f".{kind}-toggle") if b.is_visible()]
                assert shown, kind
                shown[0].click()
                page.wait_for_timeout(300)
                assert page.evaluate(f"() => document.querySelector('#pst-{kind}-sidebar-modal')"
                                     "?.open === true"), kind
                page.keyboard.press("Escape")
                page.wait_for_timeout(200)
        finally:
            browser.close()
