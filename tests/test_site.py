"""The website (`make reproduce`, `scripts/build_site.py`): built from the committed
notebooks and paper, every page opened in headless Chromium with no network.

Every page loads; every image loads and has alt text; every link within
the site leads to a file of it; every formula is
typeset by MathJax, with no MathJax error and no raw TeX left in the text;
no request leaves the site's folder; each notebook page shows each figure
its notebook writes, with the paper's caption.

The browser is Debian's ``chromium`` (``make browser`` installs it, and
``.ci/run`` runs that first), driven by playwright from environment.txt with
its executable path: nothing is downloaded.  Without it the browser test is
skipped with a message saying how to install it."""

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
  .filter(h => h.startsWith('file:')).map(h => h.split('#')[0])"""
IMAGES = """() => [...document.images].map(i => ({src: i.getAttribute('src'),
  loaded: i.complete && i.naturalWidth > 0, alt: i.getAttribute('alt') || ''}))"""


@pytest.fixture(scope="module")
def site(tmp_path_factory):
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
    page = (site / "notebooks" / "02_cannonball.html").read_text()
    assert "Show code cell source" in page
    import nbformat
    cells = nbformat.read(NOTEBOOKS[1], as_version=4).cells
    long_cells = [c for c in cells if c.cell_type == "code"
                  and len(c.source.splitlines()) > notebook_reader.SHOWN_LINES]
    assert page.count("Show code cell source") == len(long_cells) > 0


def test_captions_as_plain_text():
    """Typst math in a caption becomes Unicode text."""
    assert notebook_reader.plain("steps $Delta t = 0.08 \\/ 2^k$, rtol $10^(-13)$, "
                                 "$mu = 0.4$, $sqrt(6)$, $omega_1$, $tilde(H)$, $T_h$") == \
        "steps Δt = 0.08 / 2ᵏ, rtol 10⁻¹³, μ = 0.4, √6, ω₁, H̃, Tₕ"


@pytest.mark.skipif(CHROMIUM is None, reason="no chromium: `make browser` (or "
                    "`apt-get install chromium` as root) installs Debian's, which the test drives")
def test_every_page_in_a_browser(site):
    from playwright.sync_api import sync_playwright
    pages = [p for p in sorted(site.rglob("*.html"))
             if "_static" not in p.parts and p.name != "index.html"]
    outside, failed, problems = [], [], []
    with sync_playwright() as playwright:
        browser = playwright.chromium.launch(executable_path=CHROMIUM, args=FLAGS)
        page = browser.new_page(viewport={"width": 1366, "height": 900})
        page.on("request", lambda r: outside.append(r.url) if not (
            r.url.startswith(site.as_uri() + "/") or r.url.startswith(("data:", "about:"))) else None)
        page.on("requestfailed", lambda r: None if r.url.startswith("about:")
                else failed.append((r.url, r.failure)))
        response = page.goto((site / "index.html").as_uri())
        page.wait_for_url("**/README.html")
        for path in pages:
            response = page.goto(path.as_uri(), wait_until="load")
            name = str(path.relative_to(site))
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
            for target in page.evaluate(LINKS):
                if not Path(unquote(urlparse(target).path)).exists():
                    problems.append(f"{name}: broken link {target}")
            if path.parent.name == "notebooks" and math["formulas"] == 0:
                problems.append(f"{name}: no formula")
        browser.close()
    assert not problems, problems
    assert not outside, f"requests outside the site: {outside[:5]}"
    # A file MathJax asks for on demand while the next page loads is aborted by
    # that navigation (net::ERR_ABORTED): a failure only if the file is missing.
    failed = [url for url, why in failed if "ERR_ABORTED" not in str(why)
              or not Path(unquote(urlparse(url).path)).exists()]
    assert not failed, f"requests that failed: {failed[:5]}"
