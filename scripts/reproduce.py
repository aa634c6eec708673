"""Regenerate everything (or, given file-name prefixes such as ``02 04``, those
notebooks): execute every notebook (rewriting its .ipynb outputs, data/ and
figures/), one line per notebook with its wall time, then print the claims
table.  A failing notebook stops the run.

The notebooks are independent, except those in ``LAST``, which read what the
others write and run after them.  The others run ``JOBS`` at a time (each in
its own kernel); the lines are printed in the notebooks' order whatever
order they finish in."""

import os
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import jupytext
from nbclient import NotebookClient
from nbclient.exceptions import CellExecutionError

ROOT = Path(__file__).resolve().parents[1]
NOTEBOOKS = sorted((ROOT / "notebooks").glob("[0-9][0-9]_*.py"))
# Notebooks that read the data the others write: run after all the others.
LAST = ("05_claims_and_errata",)
# The longest notebooks start first, so that the others run beside them.
LONGEST = ("06_theory", "07_improvements")
# Notebooks run at the same time (each kernel is one process).
JOBS = int(os.environ.get("SPLINESTEP_JOBS", "2"))
KERNELSPEC = {"name": "python3", "display_name": "Python 3 (ipykernel)", "language": "python"}
README = ROOT / "README.md"
# README sections written from data/ by `make reproduce`: marker name -> CSV.
README_TABLES = {"claims": "claims", "errata": "errata"}


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
        table = markdown_table(pd.read_csv(data_dir / f"{name}.csv"))
        text = f"{head}{begin}\n{table}\n{end}{tail}"
    return text


def execute(script, output_root=None):
    """Execute the percent script ``script`` and write its paired .ipynb."""
    notebook = jupytext.read(script)
    for index, cell in enumerate(notebook.cells):  # stable ids: no diff noise
        cell.id = f"cell-{index:02d}"
    # The kernel `make` installs: JupyterLab writes this same spec back on save.
    notebook.metadata["kernelspec"] = KERNELSPEC
    env = dict(os.environ, MPLBACKEND="Agg")
    if output_root is not None:
        env["SPLINESTEP_OUTPUT"] = str(output_root)
    client = NotebookClient(notebook, timeout=600, kernel_name="python3", record_timing=False,
                            resources={"metadata": {"path": str(script.parent)}})
    client.execute(env=env)
    for cell in notebook.cells:
        cell_outputs = cell.get("outputs", [])
        cell_outputs[:] = _coalesced(cell_outputs)
    return notebook


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


def _timed(script, output_root):
    start = time.perf_counter()
    try:
        return execute(script, output_root), None, time.perf_counter() - start
    except CellExecutionError as error:
        return None, error, time.perf_counter() - start


def execute_all(scripts, output_root=None, jobs=JOBS):
    """Execute ``scripts``, ``jobs`` at a time, those in ``LAST`` after the
    others.  Yields (script, notebook, error, seconds) in the order of
    ``scripts``; after an error nothing more is yielded (and nothing more
    started)."""
    first = [s for s in scripts if s.stem not in LAST]
    last = [s for s in scripts if s.stem in LAST]
    with ThreadPoolExecutor(max_workers=max(1, jobs)) as pool:
        for group in (first, last):
            started = {s: pool.submit(_timed, s, output_root)
                       for s in sorted(group, key=lambda s: s.stem not in LONGEST)}
            futures = [started[s] for s in group]
            for script, future in zip(group, futures):
                notebook, error, seconds = future.result()
                yield script, notebook, error, seconds
                if error is not None:
                    for other in futures:
                        other.cancel()
                    return


def main(names=()):
    """Run every notebook, or those whose file names start with one of ``names``."""
    total = time.perf_counter()
    scripts = [s for s in NOTEBOOKS if not names or s.name.startswith(tuple(names))]
    for script, notebook, error, seconds in execute_all(scripts):
        if error is not None:
            print(f"FAILED {script.relative_to(ROOT)}:\n{error}", file=sys.stderr)
            return 1
        jupytext.write(notebook, script.with_suffix(".ipynb"))
        print(f"{script.relative_to(ROOT)}: {seconds:5.1f} s", flush=True)
    print(f"all notebooks: {time.perf_counter() - total:5.1f} s ({JOBS} at a time)\n")
    README.write_text(readme_with_tables(README.read_text(), ROOT / "data"))
    claims = ROOT / "data" / "claims.csv"
    if claims.exists():
        import pandas as pd
        print("The report's claims (data/claims.csv):")
        for row in pd.read_csv(claims).itertuples():
            print(f"- [{row.where}] {row.claim}\n    measured: {row.measured}\n"
                  f"    verdict:  {row.verdict}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
