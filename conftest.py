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

import os
import shutil
import sys
import tempfile
from pathlib import Path


ROOT = Path(__file__).resolve().parent
sys.path[:0] = [str(ROOT / "scripts"), str(ROOT / "tests")]
import reproduce  # noqa: E402
from notebook_runs import done_marker, notebook_of, notebooks_in, wait_for_notebooks  # noqa: E402


def pytest_configure(config):
    if "SPLINESTEP_OUTPUT" not in os.environ:  # set once, inherited by the workers
        os.environ["SPLINESTEP_OUTPUT"] = tempfile.mkdtemp(prefix="splinestep-outputs-")
    if not hasattr(config, "workerinput"):  # the controller: no markers of an earlier session
        shutil.rmtree(done_marker("any").parent, ignore_errors=True)
    os.environ.setdefault("MPLBACKEND", "Agg")


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


def _bounded_heartbeat_stop():
    from jupyter_client.channels import HBChannel
    HBChannel.stop = _stop_heartbeat


_bounded_heartbeat_stop()


def pytest_runtest_setup(item):
    stem = notebook_of(item)
    if stem in reproduce.LAST and stem not in _STARTED:
        _STARTED.add(stem)
        wait_for_notebooks([s for s in notebooks_in(item.session) if s not in reproduce.LAST])


def pytest_runtest_teardown(item, nextitem):
    stem = notebook_of(item)
    if stem and (nextitem is None or notebook_of(nextitem) != stem):
        done_marker(stem).parent.mkdir(exist_ok=True)
        done_marker(stem).touch()


# Tests that compare what the notebooks wrote with the committed files: they
# wait for every notebook, so they come last of all.
COMPARISONS = "test_outputs.py"


def pytest_collection_modifyitems(config, items):
    """Notebooks in ``reproduce.LAST`` after every other test, and the
    comparisons of their outputs after those: a worker then never waits for a
    notebook that it would itself run later, and waits for the others only
    when it has nothing else left to run."""
    def rank(item):
        if Path(str(item.path)).name == COMPARISONS:
            return 2
        return 1 if notebook_of(item) in reproduce.LAST else 0
    items.sort(key=rank)
