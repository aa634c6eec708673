"""Build the website: a landing page (website/landing.md, with the
README's claims tables), the notebooks with their stored outputs (no
notebook is executed), the manual, whose guide's examples are run in one
process as the site is built and their printed output shown (an example
that raises fails the build), and the paper's abstract and PDF, into
``build/site`` (not committed), readable offline: open
``build/site/index.html`` in a browser.  The configuration is in
``website/conf.py``; ``tests/test_site.py`` opens every page in headless
Chromium.

    python scripts/build_site.py [OUTPUT_DIR]
"""

import re
import sys
import time
import warnings
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SITE = ROOT / "build" / "site"


def build(output=SITE, root=ROOT):
    """Build the site of the repository at ``root`` into ``output`` (emptied
    first); returns (seconds, number of HTML pages).  Raises RuntimeError
    with Sphinx's messages when a warning or error occurs."""
    import io
    import shutil
    from contextlib import redirect_stderr, redirect_stdout

    from sphinx.cmd.build import build_main
    start = time.perf_counter()
    output = Path(output)
    shutil.rmtree(output, ignore_errors=True)
    messages = io.StringIO()
    # The theme's use of a Sphinx API that Sphinx 11 drops is the theme's affair.
    with redirect_stdout(io.StringIO()), redirect_stderr(messages), warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        warnings.simplefilter("ignore", PendingDeprecationWarning)
        # -W: a warning (a broken link, a missing image) fails the build;
        # -E -a: read every source again (no stale pickled state).
        code = build_main(["-q", "-W", "-E", "-a", "-b", "html", "-d", str(output / ".doctrees"),
                           "-c", str(Path(root) / "website"), str(root), str(output)])
    if code:
        # Sphinx's closing request to report the error to its developers is
        # not for a failure of this site's own pages (a guide example that raises).
        told = re.split(r"\n(?=To report this error to the developers)", messages.getvalue())[0]
        raise RuntimeError(f"the site did not build:\n{told.rstrip()}")
    shutil.rmtree(output / ".doctrees", ignore_errors=True)
    pages = len([p for p in output.rglob("*.html") if "_static" not in p.parts])
    return time.perf_counter() - start, pages


if __name__ == "__main__":
    target = Path(sys.argv[1]) if len(sys.argv) > 1 else SITE
    seconds, pages = build(target)
    shown = target.relative_to(ROOT) if target.resolve().is_relative_to(ROOT) else target
    print(f"{shown}/index.html: {pages} pages built in {seconds:.1f} s")
