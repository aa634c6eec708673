"""Regenerate what changed (or, given file-name prefixes such as ``02 04``,
those notebooks): execute each notebook whose inputs or outputs changed
since it last ran here (rewriting its .ipynb outputs, data/ and figures/;
``scripts/freshness.py`` decides, on contents), one line per notebook with
its wall time, then the paper and the website if what they are built from
changed, and a one-line count of the claims' verdicts.  A failing notebook
stops the run (exit status 1).

Then every file the run rewrote is compared with the committed one (git
HEAD), by the rules ``make test`` applies (``tests/reproduction.py``), in a
few lines per kind of output: how many identical, how many within tolerance
(with the largest difference), which beyond (``scripts/rerun_report.py``).
The exit status is 3 when an output is beyond tolerance while the sources it
is made from are HEAD's (a failed reproduction), else 0; the files stay as
written either way.  A run that reran nothing says so and compares nothing.

Before any notebook runs, the package's step loops are compiled, or loaded
from numba's cache, in two processes at once (``scripts/warm_loops.py``),
so that notebooks started together do not compile the same loop twice.

The notebooks are independent, except those in ``LAST``, which read what the
others write: they run after them, whenever one of the others ran.  The
others run ``JOBS`` at a time (each in its own kernel), longest first
(``ORDER``); the lines are printed in the notebooks' order whatever order
they finish in.  A notebook in ``LAST`` starts its kernel and runs its first
code cell (imports only: it must not read data/) at once, beside the others,
and its other cells when they are done: the one step that must wait does
not also wait for a kernel to start.  Its "started" line is printed when
those other cells begin, so that the lines follow the work, and its time
counts from then."""

import asyncio
import os
import sys
import threading
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import jupytext
import nbformat
from nbclient import NotebookClient
from nbclient.exceptions import CellExecutionError

import freshness
import rerun_report

ROOT = Path(__file__).resolve().parents[1]
NOTEBOOKS = sorted((ROOT / "notebooks").glob("[0-9][0-9]_*.py"))
# Notebooks that read the data the others write: run after all the others.
# 12_step_size_check reads the long runs of 10_higher_order (data/composition-check.csv).
LAST = ("12_step_size_check", "14_claims_and_errata")
# Notebooks start longest first (times from `make bench`), so that the short
# ones fill the gaps at the end; any other notebook starts after these.
ORDER = ("07_adaptive_steps", "08_long_time", "10_higher_order", "05_theory",
         "11_hard_step_equations", "09_global_sweep_and_bvp", "13_newmark_family",
         "06_higher_degree", "04_convergence", "03_rigid_body",
         "02_cannonball", "01_method")
# Notebooks run at the same time (each kernel is one process).
JOBS = int(os.environ.get("SPLINESTEP_JOBS", "2"))
KERNELSPEC = {"name": "python3", "display_name": "Python 3 (ipykernel)", "language": "python"}
README = ROOT / "README.md"
# The hidden last cell of every run (see execute).
NOTE_RUN = ('import sys\nif "outputs" in sys.modules:\n'
            '    sys.modules["outputs"].note_run()')
# README sections written from data/ by `make reproduce`: marker name -> CSV.
README_TABLES = {"claims": "claims", "errata": "errata"}


def readme_frame(name, frame):
    """The columns of data/NAME.csv the README shows, in readable notation
    with the formulas as math (:func:`claims.readable`): the claims one line
    each (:func:`claims.glance`; the measurements stay in the CSV), the
    errata whole; each reference of "where" a link to the report page, each
    notebook section of "measured in" a link to its heading
    (:func:`claims.with_links`)."""
    import claims
    if name == "claims":
        frame = claims.glance(frame)
    text = [column for column in frame.columns if column not in ("where", "measured in")]
    frame = frame.assign(**{c: frame[c].map(lambda v: claims.readable(str(v))) for c in text})
    return claims.with_links(frame)


def markdown_table(frame):
    """A pandas DataFrame as a GitHub Markdown table (| in cells escaped)."""
    cells = [[str(v).replace("|", "\\|") for v in row] for row in frame.itertuples(index=False)]
    lines = ["| " + " | ".join(frame.columns) + " |", "|" + "---|" * len(frame.columns)]
    return "\n".join(lines + ["| " + " | ".join(row) + " |" for row in cells])


def readme_with_tables(text, data_dir):
    """``text`` with each block between <!-- begin NAME --> and <!-- end NAME -->
    replaced by the table of data/NAME.csv."""
    import pandas as pd
    for marker, name in README_TABLES.items():
        begin, end = f"<!-- begin {marker} -->", f"<!-- end {marker} -->"
        head, rest = text.split(begin)
        _, tail = rest.split(end)
        table = markdown_table(readme_frame(name, pd.read_csv(data_dir / f"{name}.csv")))
        text = f"{head}{begin}\n{table}\n{end}{tail}"
    return text


class _Started:
    """Prints "<notebook>: started" the first time it is called (unless
    ``quiet``), in one write: several threads print."""

    def __init__(self, script, quiet=False):
        self.script, self.done = script, quiet

    def __call__(self):
        if not self.done:
            self.done = True
            sys.stdout.write(f"{self.script.relative_to(ROOT)}: started\n")
            sys.stdout.flush()


class _HeldClient(NotebookClient):
    """A notebook client that runs the first code cell at once and waits
    for ``ready`` (a ``threading.Event``) before any later one; if
    ``abandon`` is set by then, it stops there, else it calls ``started()``
    (a :class:`_Started`) and runs them."""

    def __init__(self, notebook, ready, abandon, started=lambda: None, **kwargs):
        super().__init__(notebook, **kwargs)
        self.ready, self.abandon, self.started = ready, abandon, started
        self.first_code = next(i for i, c in enumerate(notebook.cells) if c.cell_type == "code")

    async def async_execute_cell(self, cell, cell_index, *args, **kwargs):
        if cell_index > self.first_code and not self.ready.is_set():
            await asyncio.to_thread(self.ready.wait)
        if self.abandon.is_set():
            raise _Abandoned
        if cell_index > self.first_code:
            self.started()
        return await super().async_execute_cell(cell, cell_index, *args, **kwargs)


class _Abandoned(Exception):
    """A notebook held for the others' data, given up when one failed."""


def execute(script, output_root=None, ready=None, abandon=None, started=lambda: None):
    """Execute the percent script ``script`` and return the executed notebook.
    With ``ready`` (and ``abandon``), hold every cell after the first code
    cell until ``ready`` is set, then call ``started()`` (:class:`_HeldClient`)."""
    notebook = jupytext.read(script)
    for index, cell in enumerate(notebook.cells):  # stable ids: no diff noise
        cell.id = f"cell-{index:02d}"
    # The kernel `make` installs: JupyterLab writes this same spec back on save.
    notebook.metadata["kernelspec"] = KERNELSPEC
    # A last cell, removed before the notebook is returned, notes the
    # modules the run imported and what it cost (outputs.note_run).
    notebook.cells.append(nbformat.v4.new_code_cell(NOTE_RUN, id="note-run"))
    env = dict(os.environ, MPLBACKEND="Agg")
    if output_root is not None:
        env["SPLINESTEP_OUTPUT"] = str(output_root)
    else:  # outputs into this repository
        env.pop("SPLINESTEP_OUTPUT", None)
    # What it reads and writes, noted
    manifest = manifest_path(script, output_root)
    manifest.parent.mkdir(parents=True, exist_ok=True)
    manifest.unlink(missing_ok=True)
    env["SPLINESTEP_MANIFEST"] = str(manifest)
    # The kernel's own warnings (it listens on loopback TCP) are not the
    # reader's business: only its errors are shown.
    options = dict(timeout=600, kernel_name="python3", record_timing=False,
                   extra_arguments=["--IPKernelApp.log_level=ERROR"],
                   resources={"metadata": {"path": str(script.parent)}})
    if ready is None:
        client = NotebookClient(notebook, **options)
    else:
        client = _HeldClient(notebook, ready, abandon, started, **options)
    client.execute(env=env)
    notebook.cells.pop()
    for cell in notebook.cells:
        cell_outputs = cell.get("outputs", [])
        cell_outputs[:] = _coalesced(cell_outputs)
    return notebook


def manifest_path(script, output_root=None):
    """Where a run of ``script`` notes the files it reads and writes (and
    the modules it imports, and its compile and CPU seconds)."""
    folder = ROOT / "build" if output_root is None else Path(output_root)
    return folder / "manifests" / f"{script.stem}.txt"


def _coalesced(cell_outputs):
    """Consecutive prints to one stream as one output, as nbval compares them:
    where the kernel splits them depends on timing (a compilation in the
    middle of a cell), and the stored notebook should not."""
    merged = []
    for output in cell_outputs:
        if (merged and output.get("output_type") == "stream"
                and merged[-1].get("output_type") == "stream"
                and merged[-1].get("name") == output.get("name")):
            merged[-1]["text"] = merged[-1]["text"] + output["text"]
        else:
            merged.append(output)
    return merged


def _timed(script, output_root, ready=None, abandon=None):
    """(notebook, error, seconds), with a "started" line when it starts its
    work if it writes here (``output_root`` None); a held notebook's work
    starts at its second code cell, and its seconds count from ``ready``,
    when it could first read the others' data."""
    start = time.perf_counter()
    started = _Started(script, quiet=output_root is not None)
    if ready is None:
        started()
    try:
        notebook = execute(script, output_root, ready, abandon, started)
    except CellExecutionError as error:
        return None, error, time.perf_counter() - start
    except _Abandoned:
        return None, None, 0.0
    started()  # a held notebook with a single code cell: said at its end
    if ready is not None:
        start = max(start, ready.time)
    return notebook, None, time.perf_counter() - start


def _start_rank(script):
    return ORDER.index(script.stem) if script.stem in ORDER else len(ORDER)


def execute_all(scripts, output_root=None, jobs=JOBS):
    """Execute ``scripts``, ``jobs`` at a time, those in ``LAST`` after the
    others (with their kernels started at once).  Yields (script, notebook,
    error, seconds) in the order of ``scripts``; after an error nothing
    more is yielded (and nothing more started)."""
    first = [s for s in scripts if s.stem not in LAST]
    last = [s for s in scripts if s.stem in LAST]
    ready, abandon = threading.Event(), threading.Event()
    ready.time = 0.0
    with ThreadPoolExecutor(max_workers=max(1, jobs)) as pool, \
            ThreadPoolExecutor(max_workers=max(1, len(last))) as held:
        waiting = {s: held.submit(_timed, s, output_root, ready, abandon) for s in last}
        try:
            started = {s: pool.submit(_timed, s, output_root)
                       for s in sorted(first, key=_start_rank)}
            for script in first:
                notebook, error, seconds = started[script].result()
                yield script, notebook, error, seconds
                if error is not None:
                    for other in started.values():
                        other.cancel()
                    return
            ready.time = time.perf_counter()
            ready.set()
            for script in last:
                notebook, error, seconds = waiting[script].result()
                yield script, notebook, error, seconds
                if error is not None:
                    return
        finally:
            abandon.set()   # after a failure (or a consumer that stopped early)
            ready.set()


def to_run(state, names=()):
    """The notebooks to run, each with why: those named (by file-name
    prefix), or else those not up to date; and those in ``LAST`` whenever
    another runs.  Prints a line for each notebook left as it is."""
    chosen = []
    if names:
        named = [s for s in NOTEBOOKS if s.name.startswith(tuple(names))]
        chosen = [(s, "asked for") for s in named if s.stem not in LAST]
        last = [s for s in NOTEBOOKS if s.stem in LAST and (chosen or s in named)]
        return chosen + [(s, "asked for" if s in named else "the others' data may have changed")
                         for s in last]
    # Those in LAST are judged after the others, whatever their file names.
    for script in sorted(NOTEBOOKS, key=lambda s: s.stem in LAST):
        why = state.why_stale(script.stem, [script])
        if why is None and script.stem in LAST and chosen:
            why = "the others' data may have changed"
        if why is None:
            print(f"{script.relative_to(ROOT)}: up to date", flush=True)
        else:
            chosen.append((script, why))
    return sorted(chosen, key=lambda pair: NOTEBOOKS.index(pair[0]))


def _paper_sources():
    """What the paper reads (its csv(), read(), yaml() and image() calls) and how it is built."""
    return freshness.files(("paper/*.typ", "paper/*.bib", "paper/*.csv", "CITATION.cff",
                            "data/*.csv", "data/machine.txt", "figures/*.pdf",
                            "scripts/paper.py", "environment.txt"))


def _site_sources():
    # The package's modules too: the API page is made from their docstrings
    # (this process does not import the package before the site is built).
    return freshness.files(("README.md", "notebooks/*.ipynb", "paper/splinestep.pdf",
                            "paper/splinestep.typ", "figures/*.png", "data/*.csv", "website/*",
                            "website/_static/*", "scripts/build_site.py", "environment.txt",
                            "src/splinestep/*.py", "src/splinestep/*/*.py",
                            # what website/notebook_reader.py imports from scripts/
                            "scripts/outputs.py", "scripts/paper.py", "scripts/reproduce.py"))


def site_is_current():
    """True when build/site is what :func:`build_site.build` would make now:
    built by make reproduce from the files it is made of as they are."""
    return freshness.State().why_stale("site", _site_sources(), common=False) is None


def build_if_stale(state, name, sources, build, output):
    """Run ``build()`` (which returns a line to print) if ``name`` is not up
    to date, and record it with its ``output`` file; else say so.  Returns
    whether it ran."""
    why = state.why_stale(name, sources, common=False)
    if why is None:
        print(f"{output.relative_to(ROOT)}: up to date", flush=True)
        return False
    before = state.before(sources, common=False)
    print(build(), f"({why})", flush=True)
    state.record(name, sources, outputs=[output], common=False, before=before)
    return True


def main(names=()):
    """Run the notebooks :func:`to_run` chooses, then the paper and the site
    if what they are built from changed; compare what was written with the
    committed files (:func:`rerun_report.report`, which gives the exit status)."""
    import paper
    import build_site
    import warm_loops
    total = time.perf_counter()
    state = freshness.State()
    if names and not any(s.name.startswith(tuple(names)) for s in NOTEBOOKS):
        print(f"no notebook's file name starts with {' or '.join(names)}; the notebooks: "
              f"{', '.join(s.stem for s in NOTEBOOKS)}", file=sys.stderr)
        return 2
    chosen = to_run(state, names)
    if chosen:  # the machine the data are made on: an output of every run below
        paper.MACHINE.write_text(paper.machine_description())
    before, written = {}, []
    for script, why in chosen:
        print(f"{script.relative_to(ROOT)}: runs ({why})", flush=True)
        before[script] = state.before([script])
    snapshot = state.snapshot()
    if chosen:
        print(f"step loops compiled or loaded from numba's cache: {warm_loops.warm():.1f} s",
              flush=True)
    for script, notebook, error, seconds in execute_all([s for s, _ in chosen]):
        if error is not None:
            state.forget(script.stem)
            print(f"FAILED {script.relative_to(ROOT)}:\n{error}", file=sys.stderr)
            return 1
        target = script.with_suffix(".ipynb")
        jupytext.write(notebook, target)
        reads, writes = freshness.read_manifest(manifest_path(script))
        if not state.record(script.stem, [script], reads, [*writes, target, paper.MACHINE],
                            before=before[script], snapshot=snapshot):
            print(f"{script.relative_to(ROOT)}: a module it imported changed while it ran: "
                  "left stale, to run again", flush=True)
        written += [*writes, target, paper.MACHINE]
        costs = freshness.run_costs(manifest_path(script))
        spent = (f" (CPU {costs['cpu']:.1f} s, of which compiling {costs['compile']:.1f} s)"
                 if costs else "")
        print(f"{script.relative_to(ROOT)}: {seconds:5.1f} s{spent}", flush=True)
    if chosen:
        print(f"{len(chosen)} notebooks run: {time.perf_counter() - total:5.1f} s "
              f"({JOBS} at a time)")
    # The README's tables are data/'s, whatever edited them.
    README.write_text(readme_with_tables(README.read_text(), ROOT / "data"))
    paper.FIGURE_SOURCES.write_text(paper.figure_sources())
    if build_if_stale(state, "paper", _paper_sources(),
                      lambda: f"paper/splinestep.pdf: built in {paper.build():.1f} s", paper.PDF):
        written.append(paper.PDF)
    build_if_stale(state, "site", _site_sources(), lambda: "build/site/index.html: "
                   "{1} pages built in {0:.1f} s".format(*build_site.build()),
                   build_site.SITE)
    claims_csv = ROOT / "data" / "claims.csv"
    print()
    if claims_csv.exists():
        import claims
        import pandas as pd
        print(claims.summary(pd.read_csv(claims_csv).kind))
    print("data: data/*.csv; figures: figures/*.png and .pdf; notebooks with outputs: "
          "notebooks/*.ipynb; the claims table: README.md and data/claims.csv; the paper: "
          "paper/splinestep.pdf; the website: build/site/index.html "
          f"({time.perf_counter() - total:.1f} s in all)")
    print()
    return rerun_report.report(written)


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
