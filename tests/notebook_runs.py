"""Notebooks in a test session: which test item runs which notebook, and the
marker files by which workers tell each other that a notebook has finished
(see the repository's conftest.py)."""

import json
import os
import time
from pathlib import Path

import pytest

# Longest a notebook that reads the others' outputs waits for them.
WAIT_SECONDS = 900


def notebook_of(item):
    """The notebook stem of an nbval cell item, or None for other tests."""
    path = Path(str(item.path))
    if path.suffix == ".ipynb" and path.parent.name == "notebooks":
        return path.stem
    return None


def reproduced():
    """{stem: [its output files]} of the notebooks this session does not run
    again: ``make reproduce`` ran them here with the inputs they have now,
    and their outputs are as it wrote them (conftest.py, from
    ``freshness.reproduced``; empty with ``RERUN=1`` or without a record, as
    on a fresh clone)."""
    return json.loads(os.environ.get("SPLINESTEP_REPRODUCED", "{}"))


def done_marker(stem):
    return Path(os.environ["SPLINESTEP_OUTPUT"]) / ".done" / stem


def notebooks_in(session):
    return sorted({stem for stem in map(notebook_of, session.items) if stem})


def wait_for_notebooks(stems):
    """Block until every notebook in ``stems`` has finished in this session."""
    deadline = time.monotonic() + WAIT_SECONDS
    while not all(done_marker(stem).exists() for stem in stems):
        if time.monotonic() > deadline:
            missing = [s for s in stems if not done_marker(s).exists()]
            pytest.fail(f"notebooks {missing} did not finish within {WAIT_SECONDS} s")
        time.sleep(0.2)
