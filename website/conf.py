"""Sphinx configuration of the website: a landing page for its reader
(website/landing.md, shown in the README's place), the notebooks with the
outputs stored in their .ipynb (nothing is executed), the manual (the
guide's examples run as the site is built, their printed output shown) and
the paper's abstract and PDF, readable with no network (MathJax from the
environment).

Built by ``scripts/build_site.py`` (``make reproduce`` or ``make site``) into
``build/site``; the source folder is the repository root, of which only the
files in ``include_patterns`` are read.
"""

import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import docstrings  # noqa: E402  (the source folder is the repository root)
import notebook_reader  # noqa: E402
import pages  # noqa: E402

project = "splinestep"
author = "the splinestep authors"
copyright = "the splinestep authors"
root_doc = "README"
include_patterns = ["README.md", "notebooks/[0-9][0-9]_*.ipynb", "website/*.md"]
# The landing page's text, read into the README's page (pages.landing).
exclude_patterns = ["website/landing.md"]
# The API reference (website/api.md) is written from the docstrings, which
# are numpydoc: what help() shows is what the site shows.
extensions = ["myst_nb", "sphinx.ext.autodoc", "sphinx.ext.napoleon"]
sys.path.insert(0, str(HERE.parent / "src"))
autodoc_member_order = "bysource"
autodoc_typehints = "none"
napoleon_google_docstring = False
napoleon_numpy_docstring = True
napoleon_use_rtype = False
myst_enable_extensions = ["dollarmath", "amsmath"]
myst_heading_anchors = 3
# MathJax 2 typesets the page (its tex2jax reads the \\( \\) that myst writes);
# myst's own settings are for MathJax 3.
myst_update_mathjax = False
# The stored outputs are what the site shows: no notebook is run.
nb_execution_mode = "off"
# Each notebook is read with its long code cells collapsed (notebook_reader).
nb_custom_formats = {".ipynb": ["notebook_reader.read", {}, False]}
nb_merge_streams = True
# y'' stays two primes (smart quotes would make it a closing quote).
smartquotes = False
# A docstring's References list need not be cited in its text.
suppress_warnings = ["myst.header", "misc.highlighting_failure", "ref.citation"]

html_theme = "sphinx_book_theme"
html_title = "splinestep"
html_theme_options = {"show_toc_level": 2, "use_download_button": False,
                      "use_fullscreen_button": False, "home_page_in_toc": True}
html_show_sourcelink = False
html_copy_source = False
html_last_updated_fmt = None
# MathJax 2 from the environment (jupyter-server-mathjax), copied into the
# site's _static by notebook_reader.copy_mathjax (a relative path is read
# below _static): no request leaves the site's folder.
mathjax_path = "mathjax/MathJax.js?config=TeX-AMS-MML_HTMLorMML-full"
# The package bundles the STIX-Web fonts only (as the classic notebook used them).
# An undefined macro is an error (tests/test_site.py finds those), not red text.
mathjax2_config = {"tex2jax": {"processEscapes": True}, "messageStyle": "none",
                   "TeX": {"noUndefined": {"disabled": True}},
                   "HTML-CSS": {"availableFonts": [], "webFont": "STIX-Web", "scale": 90,
                                "imageFont": None, "preferredFont": None}}


def setup(app):
    # The landing page in the README's place first, then its table of contents.
    app.connect("source-read", pages.page_contents, priority=400)
    app.connect("source-read", notebook_reader.site_contents)
    # The guide's examples run while the other pages are read.
    app.connect("builder-inited", pages.run_examples)
    app.connect("build-finished", pages.stop_examples)
    app.add_role("headline", pages.headline_role)
    app.add_directive("paper-figure", pages.PaperFigure)
    # Before napoleon turns the numpydoc sections into reStructuredText.
    app.connect("autodoc-process-docstring", docstrings.as_rst, priority=100)
    app.connect("build-finished", notebook_reader.copy_mathjax)
    app.connect("build-finished", notebook_reader.landing_redirect)


# Readable at a phone's width and a laptop's (website/_static/readable.*):
# the content column fits the ~100-character printed lines at 1366 px;
# printed output and code wrap, or scroll inside their own box, tables
# inside their wrapper; a figure opens at full size on a click.
html_static_path = ["_static"]
html_css_files = ["readable.css"]
html_js_files = ["readable.js"]
