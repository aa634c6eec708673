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
text, printed output, code, formulas or tables is cut off (see
:func:`test_every_page_in_a_browser`).

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
      the edge of its box, MathJax's or the one around it, or scrolls."""
    problems, outside, failed, widths = readings[window]
    assert not problems, problems
    assert not outside, f"requests outside the site: {outside[:5]}"
    # A file MathJax asks for on demand while the next page loads is aborted by
    # that navigation (net::ERR_ABORTED): a failure only if the file is missing.
    failed = [url for url, why in failed if "ERR_ABORTED" not in str(why)
              or not Path(unquote(urlparse(url).path)).exists()]
    assert not failed, f"requests that failed: {failed[:5]}"
