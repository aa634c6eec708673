"""Shared helpers of the tests, and which tests need the repository's
tooling.

The package's tests need numpy, scipy, numba, pytest, pandas and sympy
(``pip install 'splinestep[test]'``).  The repository's checks of its
notebooks, data, paper and website (REPOSITORY_CHECKS) need the notebooks'
tooling of environment.txt (jupytext, nbformat, nbclient, matplotlib,
Sphinx, ...); where it is not installed they are not collected, and the
package's tests run alone.
"""

import importlib.util

import numpy as np


def fitted_order(hs, errors):
    """Least-squares slope of log(error) against log(h)."""
    return np.polyfit(np.log(hs), np.log(errors), 1)[0]


REPOSITORY_CHECKS = [
    "test_claims_table.py", "test_freshness.py", "test_lab.py", "test_outputs.py",
    "test_paper.py", "test_printed_lines.py", "test_prose_numbers.py", "test_report_page.py",
    "test_reproduction_rule.py", "test_rerun_report.py", "test_site.py"]
TOOLING = ["jupytext", "nbformat", "nbclient", "jupyter_client", "matplotlib", "sphinx",
           "myst_parser", "markdown_it"]
collect_ignore = ([] if all(importlib.util.find_spec(name) for name in TOOLING)
                  else REPOSITORY_CHECKS)
