"""Test-session setup.

Notebooks run under nbval write their data and figures to a temporary
folder (SPLINESTEP_OUTPUT), never over the committed files, so that
tests/test_outputs.py can compare the two.

With pytest-xdist (``make test`` runs two workers, ``--dist loadfile``),
each notebook's cells stay together on one worker (one kernel), in order.  The notebooks are
independent except those in ``reproduce.LAST``, which read what the others
write: their first cell waits until every other notebook of the session has
finished, as ``make reproduce`` runs them last.  A finished notebook leaves a
marker file in SPLINESTEP_OUTPUT, which the workers share.
"""

import json
import os
import shutil
import sys
import tempfile
from pathlib import Path


ROOT = Path(__file__).resolve().parent
sys.path[:0] = [str(ROOT / "scripts"), str(ROOT / "tests")]
try:   # the notebooks' tooling (environment.txt): without it, the package's tests alone
    import freshness  # noqa: E402
    import reproduce  # noqa: E402
    from jupyter_client.channels import HBChannel  # noqa: E402
    from notebook_runs import (done_marker, notebook_of, notebooks_in, reproduced,  # noqa: E402
                               wait_for_notebooks)
except ImportError:
    reproduce = None


def pytest_configure(config):
    os.environ.setdefault("MPLBACKEND", "Agg")
    if reproduce is None:
        return
    if "SPLINESTEP_OUTPUT" not in os.environ:  # set once, inherited by the workers
        os.environ["SPLINESTEP_OUTPUT"] = tempfile.mkdtemp(prefix="splinestep-outputs-")
    if not hasattr(config, "workerinput"):  # the controller: no markers of an earlier session
        shutil.rmtree(done_marker("any").parent, ignore_errors=True)
    if not hasattr(config, "workerinput"):  # the controller decides, the workers inherit
        skipped = _not_run_again()
        os.environ["SPLINESTEP_REPRODUCED"] = json.dumps(skipped)
        _outputs_of(skipped, Path(os.environ["SPLINESTEP_OUTPUT"]))


def _not_run_again():
    """{stem: outputs} of the notebooks this session does not run under
    nbval: those ``make reproduce`` ran here with the inputs they have now
    and whose outputs are unchanged since (``freshness.reproduced``), and
    whose notebook git HEAD holds (a new one runs); none with RERUN=1."""
    if os.environ.get("SPLINESTEP_RERUN", "") not in ("", "0"):
        return {}
    import subprocess
    listed = subprocess.run(["git", "-C", str(ROOT), "ls-tree", "--name-only", "HEAD",
                             "notebooks/"], capture_output=True, text=True)
    committed = set(listed.stdout.split()) if listed.returncode == 0 else set()
    return {stem: outputs for stem, outputs in freshness.reproduced(reproduce.NOTEBOOKS).items()
            if f"notebooks/{stem}.ipynb" in committed}


def _outputs_of(skipped, folder):
    """The data and figures of the notebooks not run again, copied where
    the session's notebooks write theirs: a notebook that runs and reads
    them (the claims notebook) finds them there."""
    for outputs in skipped.values():
        for name in outputs:
            if name.startswith(("data/", "figures/")) and (ROOT / name).is_file():
                (folder / name).parent.mkdir(parents=True, exist_ok=True)
                shutil.copy2(ROOT / name, folder / name)


_STARTED = set()


def _stop_heartbeat(channel, seconds=10.0):
    """jupyter_client's HBChannel.stop, with the join bounded: when nbval
    stops a notebook's kernel, the heartbeat thread (a daemon) can wait on its
    socket for ever and hang the worker, and with it the whole test run."""
    channel._running = False
    channel._exit.set()
    channel.join(seconds)
    if not channel.is_alive():
        channel.close()


if reproduce is not None:
    HBChannel.stop = _stop_heartbeat


def pytest_runtest_setup(item):
    if reproduce is None:
        return
    stem = notebook_of(item)
    if stem in reproduce.LAST and stem not in _STARTED:
        _STARTED.add(stem)
        wait_for_notebooks([s for s in notebooks_in(item.session) if s not in reproduce.LAST])


def pytest_runtest_teardown(item, nextitem):
    if reproduce is None:
        return
    stem = notebook_of(item)
    if stem and (nextitem is None or notebook_of(nextitem) != stem):
        done_marker(stem).parent.mkdir(exist_ok=True)
        done_marker(stem).touch()


# Tests that compare what the notebooks wrote with the committed files: they
# wait for every notebook, so they come last of all.
COMPARISONS = "test_outputs.py"


def pytest_report_header(config):
    if reproduce is None:
        return ("the package's tests alone: the notebooks' tooling (environment.txt) is not "
                "installed, so the repository's checks of its notebooks, data, paper and site "
                "are not collected (tests/conftest.py)")
    if reproduced():
        return ("notebooks not run again (make reproduce ran them here with the inputs they have "
                "now; their outputs are compared with git HEAD's; RERUN=1 runs them): "
                + " ".join(sorted(reproduced())))


def pytest_collection_modifyitems(config, items):
    """Notebooks that ``make reproduce`` ran with the inputs they have now,
    and whose outputs are as it wrote them, are not run again: nbval would
    execute the same code on the same inputs to compare its printed lines
    with those that run stored, and tests/test_outputs.py compares the files
    that run wrote with git HEAD's instead.  Notebooks in ``reproduce.LAST``
    after every other test, and the comparisons of their outputs after
    those: a worker then never waits for a notebook that it would itself
    run later, and waits for the others only when it has nothing else left
    to run.  Before them, the long ones first, so that no worker is left with
    a long file when the other has run out of work: the notebooks in
    ``reproduce.ORDER`` (longest first), the website's browser test after the
    two longest, then the rest in their order."""
    if reproduce is None:
        return
    kept = [item for item in items if notebook_of(item) not in reproduced()]
    if len(kept) < len(items):
        config.hook.pytest_deselected(items=[i for i in items if i not in kept])
        items[:] = kept

    def rank(item):
        if Path(str(item.path)).name == COMPARISONS:
            return 2
        return 1 if notebook_of(item) in reproduce.LAST else 0

    def start(item):
        if notebook_of(item) in reproduce.ORDER:
            return reproduce.ORDER.index(notebook_of(item))
        return 1.5 if Path(str(item.path)).name == "test_site.py" else len(reproduce.ORDER)
    items.sort(key=lambda item: (rank(item), start(item)))
