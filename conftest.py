"""Test-session setup: notebooks run under nbval write their data and
figures to a temporary folder (SPLINESTEP_OUTPUT), never over the committed
files, so tests/test_outputs.py can compare the two."""

import os
import tempfile


def pytest_configure(config):
    if "SPLINESTEP_OUTPUT" not in os.environ:
        os.environ["SPLINESTEP_OUTPUT"] = tempfile.mkdtemp(prefix="splinestep-outputs-")
    os.environ.setdefault("MPLBACKEND", "Agg")
