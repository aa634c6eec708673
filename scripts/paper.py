"""Build the paper: paper/splinestep.typ -> paper/splinestep.pdf with Typst
(the ``typst`` package pinned in environment.txt), from data/ and figures/.

No network (no Typst Universe packages), only the fonts Typst ships
(``ignore_system_fonts``), and no date (``set document(date: none)``): the
same sources give the same bytes on any machine.

    python scripts/paper.py [OUTPUT.pdf]
    python scripts/paper.py --pages     each figure's first reference and page
"""

import json
import platform
import re
import sys
import time
from pathlib import Path

import typst

ROOT = Path(__file__).resolve().parents[1]
SOURCE = ROOT / "paper" / "splinestep.typ"
PDF = ROOT / "paper" / "splinestep.pdf"
MACHINE = ROOT / "data" / "machine.txt"
FIGURE_SOURCES = ROOT / "paper" / "figure-sources.csv"
SAVED_FIGURE = re.compile(r"save_figure\(\s*\w+,\s*\"([^\"]+)\"")
# A figure the paper keeps the caption of but does not show: #fig("NAME", ...,
# instead: "OTHER"), OTHER showing the same.
UNSHOWN_FIGURE = re.compile(r'#fig\("([^"]+)",(?:(?!#fig\().)*?instead:', re.S)


def machine_description():
    """The machine a `make reproduce` ran on, for the paper's last section."""
    import numba
    import numpy
    import scipy
    cpu = platform.processor() or platform.machine()
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    return (f"{cpu}, {platform.system()} {platform.machine()}, Python "
            f"{platform.python_version()}, numpy {numpy.__version__}, scipy "
            f"{scipy.__version__}, numba {numba.__version__}\n")


def figure_sources(root=ROOT):
    """Which notebook writes which figure: the ``save_figure(fig, "NAME")``
    calls of each notebook, as CSV text (figure,notebook), in the order the
    paper shows the figures (that of its ``#fig("NAME", ...)`` calls, which
    Typst numbers in order); a figure the paper does not show comes last."""
    paper = (Path(root) / SOURCE.relative_to(ROOT)).read_text()
    unshown = set(UNSHOWN_FIGURE.findall(paper))
    rows = []
    for script in sorted((Path(root) / "notebooks").glob("[0-9][0-9]_*.py")):
        for name in SAVED_FIGURE.findall(script.read_text()):
            place = paper.find(f'#fig("{name}"')
            shown = place >= 0 and name not in unshown
            rows.append((place if shown else len(paper), name, script.stem))
    lines = ["figure,notebook"] + [f"{name},notebooks/{stem}.ipynb" for _, name, stem in sorted(rows)]
    return "\n".join(lines) + "\n"


def build(output=PDF, root=ROOT):
    """Compile the paper of the repository at ``root`` into ``output``;
    returns the seconds it took."""
    start = time.perf_counter()
    typst.compile(str(Path(root) / SOURCE.relative_to(ROOT)), output=str(output),
                  root=str(root), ignore_system_fonts=True)
    return time.perf_counter() - start


def query(selector):
    """Typst's query of the paper's elements (JSON text)."""
    return typst.query(str(SOURCE), selector, root=str(ROOT), ignore_system_fonts=True)


# The paper followed by a query of its own layout: for each figure, the page of
# its first reference and the page its caption is set on (a float's own
# location is where its call stands in the text, not the page it lands on;
# every figure has a caption, so figures and captions pair up in order).
FIGURE_PAGES = """#include "/paper/splinestep.typ"
#context {
  let rows = ()
  for (f, caption) in query(figure).zip(query(figure.caption)) {
    if f.kind != image or not f.has("label") { continue }
    let refs = query(ref.where(target: f.label)).map(r => r.location().page())
    rows.push((name: str(f.label).slice(4), number: f.counter.at(f.location()).first(),
               first: if refs.len() > 0 { calc.min(..refs) }, page: caption.location().page()))
  }
  [#metadata(rows) <figure-pages>]
}
"""


def figure_pages(root=ROOT):
    """Each figure of the paper: its number, name, the page of its first
    reference and the page it is set on."""
    found = typst.query(FIGURE_PAGES.encode(), "<figure-pages>", root=str(root),
                        ignore_system_fonts=True)
    return json.loads(found)[0]["value"]


if __name__ == "__main__":
    if "--pages" in sys.argv:
        for row in figure_pages():
            print(f"Figure {row['number']:2d} {row['name']:30s} first referred to on "
                  f"p. {row['first']}, set on p. {row['page']}")
        sys.exit()
    target = Path(sys.argv[1]) if len(sys.argv) > 1 else PDF
    FIGURE_SOURCES.write_text(figure_sources())
    if "--machine" in sys.argv:
        MACHINE.write_text(machine_description())
        target = PDF
    seconds = build(target)
    print(f"{target.relative_to(ROOT) if target.is_relative_to(ROOT) else target}: "
          f"built in {seconds:.2f} s")
