"""What the website writes into its pages from the repository's files when
it is built, so that no measured number and no printed result on the site
is typed by hand.

- :func:`landing` is the landing page: ``website/landing.md`` (what the
  project found, where to go next), with the claims and errata tables
  ``make reproduce`` writes into the README and the notebooks listed by
  number.  It is shown as the site's first page (``README.html``), in place
  of the README, which tells a visitor of the repository how to build
  everything.
- :func:`headline_role` is the ``{headline}`` role: ``{headline}`position
  error, ellipse, dt = 0.01``` is that row's text in
  ``data/headline-numbers.csv``, the file the paper reads its numbers from.
- :func:`abstract` is the paper's abstract from ``paper/splinestep.typ``,
  its numbers from ``data/headline-numbers.csv``, as Markdown.
- :class:`PaperFigure` is the ``{paper-figure}`` directive: a figure of
  ``figures/`` with the paper's caption, as the notebooks' pages show it.
- :class:`Examples` runs the Python examples of ``website/guide.md`` in one
  process with the package, while Sphinx reads the other pages, and writes
  what each prints under it; an example that raises fails the build with
  its traceback.
"""

import csv
import json
import os
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from docutils import nodes
from sphinx.errors import SphinxError
from sphinx.util.docutils import SphinxDirective

import notebook_reader

ROOT = notebook_reader.ROOT
HEADLINE = Path("data") / "headline-numbers.csv"
PAPER = Path("paper") / "splinestep.typ"
BIBLIOGRAPHY = Path("paper") / "references.bib"
LANDING = Path("website") / "landing.md"
GUIDE = "website/guide"


# ---- Numbers of data/headline-numbers.csv --------------------------------

def headline_numbers(root=ROOT):
    """{name: text} of data/headline-numbers.csv."""
    with open(Path(root) / HEADLINE, newline="") as file:
        return {row["name"]: row["text"] for row in csv.DictReader(file)}


def as_unicode(text):
    """A number as the data writes it, as a reader reads it: 4.1e-03 as
    4.1 × 10⁻³, a minus sign as a minus sign."""
    def power(match):
        exponent = str(int(match.group(2))).translate(notebook_reader.outputs.SUPERSCRIPTS)
        return f"{match.group(1)}\u00a0×\u00a010{exponent}"  # not broken across lines
    text = re.sub(r"(-?\d+(?:\.\d+)?)e([-+]\d+)", power, text)
    return re.sub(r"(?<![\w-])-(?=\d)", "\u2212", text)


def headline(name, root=ROOT):
    """The text of the headline number ``name``, for a reader."""
    numbers = headline_numbers(root)
    if name not in numbers:
        raise KeyError(f"{HEADLINE} has no number named {name!r}")
    return as_unicode(numbers[name])


def headline_role(name, rawtext, text, lineno, inliner, options=None, content=None):
    """The ``{headline}`` role: the text of that row of headline-numbers.csv."""
    env = getattr(inliner.document.settings, "env", None)
    try:
        return [nodes.Text(headline(text.strip(), env.srcdir if env else ROOT))], []
    except KeyError as error:
        message = inliner.reporter.error(str(error), line=lineno)
        return [inliner.problematic(rawtext, rawtext, message)], [message]


# ---- The paper's abstract ------------------------------------------------

# Typst math names and their TeX.
_MATH_NAMES = {name: "\\" + name for name in (
    "alpha", "beta", "gamma", "delta", "Delta", "epsilon", "lambda", "mu", "omega", "Omega",
    "pi", "rho", "sigma", "tau", "theta", "zeta", "phi", "dots", "times", "approx", "in",
    "nabla")}
_MATH_NAMES.update({"dot": "\\cdot", "sqrt": "\\sqrt"})


def _typst_math_as_tex(math):
    """Typst math as TeX: ``10^(-3)`` as ``10^{-3}``, ``omega h < sqrt(12)`` as
    ``\\omega h < \\sqrt{12}``, ``"rtol"`` as ``\\text{rtol}``.  A name it does
    not know is an error."""
    pieces = re.split(r'("[^"]*")', math)
    for index, piece in enumerate(pieces):
        if index % 2:
            pieces[index] = "\\text{" + piece[1:-1] + "}"
        else:
            pieces[index] = re.sub(r"(?<![\\A-Za-z])([A-Za-z]{2,})(?![A-Za-z])",
                                   lambda m: _math_name(m.group(1)), piece)
    math = "".join(pieces)
    # ^(...), _(...), sqrt(...): braces; any other parenthesis stays
    out, stack = [], []
    for index, char in enumerate(math):
        if char == "(":
            opens_group = index > 0 and (math[index - 1] in "^_" or math[:index].endswith("\\sqrt"))
            stack.append(opens_group)
            out.append("{" if opens_group else "(")
        elif char == ")" and stack:
            out.append("}" if stack.pop() else ")")
        else:
            out.append(char)
    return "".join(out).replace("\\/", "/")


def _math_name(name):
    if name in _MATH_NAMES:
        return _MATH_NAMES[name]
    raise ValueError(f"the site cannot write the Typst math name {name!r} of the "
                     f"paper's abstract in TeX (website/pages.py: _MATH_NAMES)")


def _citations(root):
    """{key: how the site cites it}: Author year, the report by its page."""
    text = (Path(root) / BIBLIOGRAPHY).read_text()
    found = {}
    for match in re.finditer(r"@\w+\{([^,]+),(.*?)\n\}", text, flags=re.S):
        key, body = match.group(1).strip(), match.group(2)
        author = re.search(r"author\s*=\s*\{([^,}]+)", body)
        year = re.search(r"year\s*=\s*\{(\d+)\}", body)
        if author and year:
            found[key] = f"({author.group(1).strip()} {year.group(1)})"
    found["report"] = "([the report in brief](report.md))"
    return found


def typst_markup_as_markdown(markup, root=ROOT):
    """Prose of the paper in Typst markup as MyST Markdown: ``#n("name")`` the
    headline number, math in TeX, ``@key`` a citation, strong and emphasis.
    Anything else of Typst's (a function call, a label) is an error: the
    site does not guess."""
    numbers = headline_numbers(root)
    cites = _citations(root)

    def number(match):
        if match.group(1) not in numbers:
            raise ValueError(f"{HEADLINE} has no number named {match.group(1)!r}")
        return as_unicode(numbers[match.group(1)])

    def cite(match):
        if match.group(1) not in cites:
            raise ValueError(f"no citation @{match.group(1)} in {BIBLIOGRAPHY}")
        return cites[match.group(1)]

    paragraphs = []
    for paragraph in re.split(r"\n[ \t]*\n", markup.strip()):
        # math and raw text (`...`) are not markup
        parts = re.split(r"(\$[^$]*\$|`[^`]*`)", paragraph)
        for index, part in enumerate(parts):
            if index % 2:
                if part.startswith("$"):
                    parts[index] = "$" + _typst_math_as_tex(part[1:-1].strip()) + "$"
                continue
            part = re.sub(r'#n\("([^"]+)"\)', number, part)
            part = re.sub(r"(?<![\w.])@([A-Za-z][\w-]*)", cite, part)
            part = re.sub(r"\*([^*\n]+)\*", r"**\1**", part)
            part = re.sub(r"(?<!\w)_([^_\n]+)_(?!\w)", r"*\1*", part)
            part = part.replace("---", "\u2014").replace("--", "\u2013").replace("\\/", "/")
            if re.search(r"#\w|<[\w-]+>", part):
                raise ValueError(f"Typst the site does not write as Markdown: {part.strip()[:80]!r}")
            parts[index] = part
        paragraphs.append(re.sub(r"\s*\n\s*", " ", "".join(parts)).strip())
    return "\n\n".join(p for p in paragraphs if p)


def paper_title(root=ROOT):
    match = re.search(r'#set document\(title: "([^"]+)"', (Path(root) / PAPER).read_text())
    if not match:
        raise ValueError(f"{PAPER}: no #set document(title: ...)")
    return match.group(1)


def paper_sections(root=ROOT):
    """The paper's sections (its level-1 headings), in order."""
    text = (Path(root) / PAPER).read_text()
    return [m.group(1).strip() for m in re.finditer(r"^= (.+?)(?:\s*<[\w.:-]+>)?\s*$", text,
                                                     flags=re.M)]


def abstract(root=ROOT):
    """The paper's abstract (the block that starts with ``*Abstract.*``) as
    Markdown, without that word."""
    text = (Path(root) / PAPER).read_text()
    start = text.find("*Abstract.*")
    if start < 0:
        raise ValueError(f"{PAPER}: no *Abstract.*")
    opening = text.rfind("[", 0, start)
    block = notebook_reader._bracketed(text, opening)
    block = block[block.find("*Abstract.*") + len("*Abstract.*"):]
    return typst_markup_as_markdown(block, root)


# ---- Figures with the paper's captions ------------------------------------

class PaperFigure(SphinxDirective):
    """``{paper-figure} NAME``: figures/NAME.png with the paper's caption for
    it, as caption and as alt text, as the notebooks' pages show it, and a
    link to the figure on the page of the notebook that draws it."""
    required_arguments = 1
    has_content = False

    def run(self):
        name = self.arguments[0]
        known = notebook_reader.captions()
        if name not in known:
            raise self.error(f"the paper has no figure {name!r} (#fig in {PAPER})")
        if not (Path(self.env.srcdir) / "figures" / f"{name}.png").exists():
            raise self.error(f"no figures/{name}.png")
        caption = known[name]
        figure = nodes.figure(classes=["ss-paper-figure"])
        figure += nodes.image(uri=f"/figures/{name}.png", alt=caption)
        text = nodes.caption(caption, caption)
        notebook = figure_notebooks(self.env.srcdir).get(name)
        if notebook:
            where = self.env.app.builder.get_relative_uri(self.env.docname, notebook)
            text += nodes.Text(" ")
            text += nodes.reference("", f"In notebook {Path(notebook).name[:2]}.",
                                    refuri=f"{where}#fig-{name}", internal=True)
        figure += text
        self.set_source_info(figure)
        return [figure]


def figure_notebooks(root=ROOT):
    """{figure name: docname of the notebook that draws it}, read from the
    notebooks' code (``save_figure(fig, "name")``)."""
    found = {}
    for path in sorted((Path(root) / "notebooks").glob("[0-9][0-9]_*.ipynb")):
        for cell in json.loads(path.read_text())["cells"]:
            if cell["cell_type"] == "code":
                for name in notebook_reader.SAVED_FIGURE.findall("".join(cell["source"])):
                    found.setdefault(name, f"notebooks/{path.stem}")
    return found


# ---- The landing page ----------------------------------------------------

def readme_table(name, root=ROOT):
    """The table ``make reproduce`` writes into the README between
    ``<!-- begin NAME -->`` and ``<!-- end NAME -->``."""
    text = (Path(root) / "README.md").read_text()
    match = re.search(rf"<!-- begin {name} -->\n(.*?)<!-- end {name} -->", text, flags=re.S)
    if not match:
        raise ValueError(f"README.md has no {name} table")
    return match.group(1).strip()


def landing(root=ROOT):
    """The landing page: website/landing.md with its {notebooks}, {claims}
    and {errata} filled in."""
    text = (Path(root) / LANDING).read_text()
    text = re.sub(r"<!--.*?-->\n?", "", text, count=1, flags=re.S)  # the note on the file
    listed = "\n".join(f"  - **{stem[:2]}** [{title}](notebooks/{stem}.ipynb)"
                       for stem, title in notebook_reader.notebook_pages(root))
    for key, value in (("{notebooks}", listed), ("{claims}", readme_table("claims", root)),
                       ("{errata}", readme_table("errata", root))):
        if key not in text:
            raise ValueError(f"{LANDING} has no {key}")
        text = text.replace(key, value)
    return text


# ---- The guide's examples, run --------------------------------------------

# Run in a process of its own: each example in turn in one namespace, what
# it prints (stdout, stderr and warnings, in order) kept apart, written as
# JSON to the file named by argv[1]; the first that raises stops the run.
_RUNNER = r'''
import contextlib, io, json, sys, traceback, warnings
blocks = json.load(sys.stdin)
results = []
namespace = {"__name__": "__main__"}
def show(message, category, filename, lineno, file=None, line=None):
    print(f"{category.__name__}: {message}", file=sys.stderr)
warnings.showwarning = show
warnings.simplefilter("default")
for index, source in enumerate(blocks):
    printed = io.StringIO()
    error = None
    with contextlib.redirect_stdout(printed), contextlib.redirect_stderr(printed):
        try:
            exec(compile(source, f"<example {index + 1}>", "exec"), namespace)
        except BaseException as raised:  # the example's frames, not this loop's
            error = "".join(traceback.format_exception(type(raised), raised,
                                                       raised.__traceback__.tb_next))
    results.append({"printed": printed.getvalue(), "error": error})
    if error:
        break
with open(sys.argv[1], "w") as file:
    json.dump(results, file)
'''

_PYTHON_BLOCK = re.compile(r"^```python[ \t]*\n(.*?)^```[ \t]*$", flags=re.M | re.S)


class ExampleFailed(SphinxError):
    """An example of the guide raised (or its process did not finish)."""
    category = "An example of the guide failed"


class Examples:
    """The Python examples of a page, run in one process with the package
    (from ``src/`` of the repository being built) while the build goes on:
    :meth:`start` starts the process, :meth:`printed` waits for it."""

    def __init__(self, page, root=ROOT, timeout=900):
        self.page = Path(page)
        self.root = Path(root)
        self.timeout = timeout
        self.process = None

    def blocks(self, text=None):
        text = self.page.read_text() if text is None else text
        return [m.group(1) for m in _PYTHON_BLOCK.finditer(text)]

    def start(self, text=None):
        self.source = self.page.read_text() if text is None else text
        self.folder = tempfile.TemporaryDirectory(prefix="site-examples-")
        self.result = Path(self.folder.name) / "printed.json"
        self.log = open(Path(self.folder.name) / "output.txt", "w+")
        env = dict(os.environ, MPLBACKEND="Agg", PYTHONHASHSEED="0",
                   PYTHONPATH=os.pathsep.join(filter(None, [str(self.root / "src"),
                                                            os.environ.get("PYTHONPATH")])))
        self.started = time.perf_counter()
        self.process = subprocess.Popen([sys.executable, "-c", _RUNNER, str(self.result)],
                                        stdin=subprocess.PIPE, stdout=self.log,
                                        stderr=subprocess.STDOUT, cwd=self.folder.name,
                                        env=env, text=True)
        self.process.stdin.write(json.dumps(self.blocks(self.source)))
        self.process.stdin.close()
        return self

    def printed(self):
        """[what each example printed], once the process has ended; raises
        ExampleFailed, with the example and its traceback, if one raised
        or the process did not finish."""
        if self.process is None:
            self.start()
        try:
            code = self.process.wait(timeout=self.timeout)
        except subprocess.TimeoutExpired:
            self.process.kill()
            self.process.wait()
            raise ExampleFailed(f"{self.page}: the examples did not finish in {self.timeout} s")
        self.seconds = time.perf_counter() - self.started
        self.log.seek(0)
        log = self.log.read()
        self.log.close()
        try:
            results = json.loads(self.result.read_text()) if code == 0 else None
        finally:
            self.folder.cleanup()
        if results is None:
            raise ExampleFailed(f"{self.page}: the process running the examples ended with "
                                f"status {code}:\n{log}")
        blocks = list(_PYTHON_BLOCK.finditer(self.source))
        for index, result in enumerate(results):
            if result["error"]:
                line = self.source.count("\n", 0, blocks[index].start()) + 1
                raise ExampleFailed(
                    f"{self.page}: example {index + 1} (the Python block at line {line}) "
                    f"failed:\n{result['printed']}{result['error']}")
        return [result["printed"] for result in results]

    def stop(self):
        """End the process if it still runs, and remove its folder."""
        if self.process is not None and self.process.poll() is None:
            self.process.kill()
            self.process.wait()
        if self.process is not None:
            self.log.close()
            self.folder.cleanup()

    def with_outputs(self):
        """The page's text with what each example printed under it."""
        printed = self.printed()
        pieces, last = [], 0
        for match, text in zip(_PYTHON_BLOCK.finditer(self.source), printed):
            pieces.append(self.source[last:match.end()])
            last = match.end()
            if text.strip():
                fence = "````" if "```" in text else "```"
                pieces.append(f"\n\n{fence}{{code-block}} text\n:class: ss-example-output\n\n"
                              f"{text.rstrip()}\n{fence}")
        pieces.append(self.source[last:])
        return "".join(pieces)


# {id(app): the Examples started for that build}
_running = {}


def run_examples(app):
    """Sphinx's builder-inited: the guide's examples start running."""
    _running[id(app)] = Examples(Path(app.srcdir) / f"{GUIDE}.md", root=app.srcdir).start()


def stop_examples(app, exception):
    """Sphinx's build-finished: examples the build did not wait for (it
    failed before it read the guide) are stopped."""
    examples = _running.pop(id(app), None)
    if examples is not None:
        examples.stop()


def page_contents(app, docname, source):
    """Sphinx's source-read: the landing page in place of the README's
    text, the guide with its examples' printed output, the paper's page
    with the paper's title, abstract and sections ({title}, {abstract},
    {sections})."""
    if docname == "README":
        source[0] = landing(app.srcdir)
    elif docname == GUIDE:
        examples = _running.pop(id(app), None)
        if examples is None or examples.source != source[0]:
            if examples is not None:
                examples.stop()
            examples = Examples(Path(app.srcdir) / f"{GUIDE}.md", root=app.srcdir).start(source[0])
        source[0] = examples.with_outputs()
    elif docname == "website/paper":
        for key, value in (("{title}", paper_title(app.srcdir)),
                           ("{abstract}", abstract(app.srcdir)),
                           ("{sections}", "; ".join(paper_sections(app.srcdir)))):
            if key not in source[0]:
                raise ValueError(f"website/paper.md has no {key}")
            source[0] = source[0].replace(key, value)
