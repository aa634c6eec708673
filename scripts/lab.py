"""Start JupyterLab as `make lab` does.

The server is rooted at the repository, where jupytext finds
``jupytext.toml`` and pairs every notebook (a server rooted at ``notebooks/``
would not see it), and opens ``notebooks/``.  ``jupyter/overrides.json`` makes
a ``.py`` open as a notebook with the outputs of its ``.ipynb``; it is
installed into the environment's JupyterLab settings before the start.

    python scripts/lab.py [--root DIR] [extra jupyter lab options]
"""

import os
import shutil
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
OVERRIDES = ROOT / "jupyter" / "overrides.json"


def install_settings(prefix=sys.prefix):
    """Copy the settings overrides into ``<prefix>/share/jupyter/lab/settings``."""
    target = Path(prefix) / "share" / "jupyter" / "lab" / "settings" / "overrides.json"
    target.parent.mkdir(parents=True, exist_ok=True)
    shutil.copyfile(OVERRIDES, target)
    return target


def command(root=ROOT, *extra):
    """The command line of the server, rooted at ``root``."""
    return [sys.executable, "-m", "jupyter", "lab", f"--ServerApp.root_dir={root}",
            "--LabApp.default_url=/lab/tree/notebooks", *extra]


def main(argv):
    root = ROOT
    if argv[:1] == ["--root"]:
        root, argv = Path(argv[1]).resolve(), argv[2:]
    install_settings()
    args = command(root, *argv)
    os.execv(args[0], args)


if __name__ == "__main__":
    main(sys.argv[1:])
