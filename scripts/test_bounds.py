"""The package's tests at both ends of the dependencies pyproject.toml
declares (``make test-bounds``, run by CI after ``make test``).

Each run installs the package from this checkout, as a user would (not
editable, with its ``test`` extra and pytest-xdist), into a virtual
environment of its own under ``build/``, and runs ``pytest tests`` there:
the package's tests alone, since the notebooks' tooling is not installed
(tests/conftest.py).

* ``oldest``: Python 3.11 and the oldest versions of the direct
  dependencies the bounds allow (uv's ``--resolution lowest-direct``);
* ``newest``: the newest Python this machine has (3.13 here; 3.14 first
  where there is one) and the newest versions, with numpy's, scipy's and
  numba's deprecations as errors.

    python scripts/test_bounds.py [oldest|newest ...]
"""

import glob
import os
import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
UV = Path(sys.executable).parent / "uv"
RUNS = {
    "oldest": dict(python="3.11", resolution="lowest-direct", warnings=[]),
    "newest": dict(python=("3.14", "3.13", "3.12", "3.11"), resolution="highest",
                   warnings=["-W", "error::DeprecationWarning:numpy",
                             "-W", "error::DeprecationWarning:scipy",
                             "-W", "error::DeprecationWarning:numba"]),
}
VERSIONS = ("import sys, numpy, scipy, numba, pandas, sympy, pytest; "
            "print('Python', sys.version.split()[0], '| numpy', numpy.__version__, "
            "'| scipy', scipy.__version__, '| numba', numba.__version__, '| pandas', "
            "pandas.__version__, '| sympy', sympy.__version__, '| pytest', pytest.__version__)")


def interpreter(versions):
    """A python of the first of ``versions`` ("3.11", or several, newest
    first) that this machine has and that runs: installed by pyenv, or on
    PATH (a pyenv shim of a version not selected does not run)."""
    for version in (versions,) if isinstance(versions, str) else versions:
        candidates = sorted(glob.glob(os.path.expanduser(
            f"~/.pyenv/versions/{version}*/bin/python{version}")))
        for found in filter(None, candidates + [shutil.which(f"python{version}")]):
            if subprocess.run([found, "--version"], capture_output=True).returncode == 0:
                return found
    sys.exit(f"test-bounds: no Python {versions} under ~/.pyenv/versions or on PATH")


def run(name):
    spec = RUNS[name]
    venv = ROOT / "build" / f"bounds-{name}"
    shutil.rmtree(venv, ignore_errors=True)
    subprocess.run([UV, "venv", "--quiet", "--python", interpreter(spec["python"]), venv],
                   check=True)
    python = venv / "bin" / "python"
    subprocess.run([UV, "pip", "install", "--quiet", "--python", python, "--resolution",
                    spec["resolution"], f"{ROOT}[test]", "pytest-xdist>=3.6"], check=True)
    print(f"{name}:", subprocess.run([python, "-c", VERSIONS], capture_output=True, text=True,
                                     check=True).stdout.strip(), flush=True)
    env = dict(os.environ, SPLINESTEP_CACHE_DIR=str(venv / "cache"))
    done = subprocess.run([python, "-m", "pytest", "-q", "-n", "2", "-p", "no:cacheprovider",
                           *spec["warnings"], "tests"], cwd=ROOT, env=env)
    return done.returncode


if __name__ == "__main__":
    names = sys.argv[1:] or list(RUNS)
    failed = [name for name in names if run(name) != 0]
    if failed:
        sys.exit(f"test-bounds: the package's tests failed at {', '.join(failed)}")
