# splinestep: one command regenerates everything, one runs every test.
#   make reproduce   build .venv from environment.txt, run the notebooks whose inputs or outputs
#                    changed (all of them on a fresh clone), write data/ and figures/, build the
#                    paper (paper/splinestep.pdf) and the website (build/site/index.html) if what
#                    they are built from changed; NB=03 (or NB="02 04") runs those notebooks;
#                    then compares what it wrote with the committed files (git HEAD) by the
#                    rules of make test (tests/reproduction.py) and says how many are
#                    identical, within tolerance, beyond; exit status 3 (make fails) when
#                    one is beyond tolerance while the sources are HEAD's, 1 when a notebook fails
#   make paper       build the paper alone from data/ and figures/
#   make site        build the website alone from the notebooks and the paper
#   make browser     install Debian's chromium (root), which tests/test_site.py drives
#   make test        build .venv, run pytest: the package's tests, and nbval on every
#                    notebook but those make reproduce ran here with the inputs they have
#                    now and whose outputs are unchanged since (their printed lines, data
#                    and figures are compared with git HEAD's instead: after a commit of
#                    them, a file with itself); RERUN=1 runs every notebook; JUNIT=1 writes each
#                    test's seconds to build/junit.xml
#   make bench       speed benchmark (compiled, plain Python, scipy, C) and cost against
#                    the number of equations (benchmarks/scaling.py), the error
#                    controller on a stiff system (benchmarks/controller.py), solve's
#                    defaults against scipy's (benchmarks/defaults.py)
#   make lab         JupyterLab at the repository root, .py <-> .ipynb pairs active
#   make test-emulated   the tests with numpy's newer CPU kernels switched off, as on another CPU
#   make test-bounds     the package's tests alone, installed from this checkout into fresh
#                    venvs: the oldest declared dependencies (Python 3.11) and the newest (3.13)
#   make opensees-reference   run OpenSees (openseespy, in a venv of its own under build/) on the
#                    problems of scripts/opensees_reference.py and rewrite tests/data/opensees/,
#                    which tests/test_opensees.py compares every member of the family with

PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed
FAST_IMPORT := $(VENV)/.fast-import

export MPLBACKEND := Agg
# The line a first compilation prints on stderr is for a user's own runs:
# here it would become part of a notebook's outputs.
export SPLINESTEP_QUIET := 1
export PYTHONHASHSEED := 0
export SOURCE_DATE_EPOCH := 0
# Python writes its bytecode caches (__pycache__, ignored by git) even where
# the environment asks it not to: the package's modules and pytest's
# rewritten test modules are then compiled once, not again in every process.
export PYTHONDONTWRITEBYTECODE :=

# numpy's runtime-dispatched kernels beyond the baseline, switched off to see
# what another CPU's rounding does (names not present on a CPU are ignored).
EMULATED_CPU := NPY_DISABLE_CPU_FEATURES="AVX512_ICL AVX512_SPR X86_V4 X86_V3" NUMBA_CPU_NAME=generic

.PHONY: reproduce paper site browser test test-emulated test-bounds bench lab env clean opensees-reference

env: $(STAMP) $(FAST_IMPORT)

# Rebuilt when missing or older than environment.txt or pyproject.toml.  pip
# installs uv (its version pinned in environment.txt), and uv the rest from
# PyPI, several times faster than pip, their bytecode compiled once here (as
# pip does), not by every process that imports them.
UV := $(BIN)/uv pip install --quiet --compile-bytecode --python $(BIN)/python
$(STAMP): environment.txt pyproject.toml
	rm -rf $(VENV)
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet "$$(grep '^uv==' environment.txt)"
	$(UV) -r environment.txt
	$(UV) --no-deps -e .
	$(BIN)/python -m ipykernel install --sys-prefix --name python3 > /dev/null
	touch $(STAMP)

# jsonschema, which nbformat loads to validate notebooks, imports the optional
# rfc3987-syntax, which compiles an IRI grammar when imported: 0.9 s in every
# process that reads a notebook (make reproduce, pytest and each of its
# workers).  Notebooks hold no IRIs; a .pth file in the environment marks the
# module absent, and jsonschema then leaves that one format unchecked.
$(FAST_IMPORT): $(STAMP)
	echo 'import sys; sys.modules.setdefault("rfc3987_syntax", None)' > \
		"$$($(BIN)/python -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')/splinestep-skip-iri-grammar.pth"
	touch $(FAST_IMPORT)

reproduce: $(STAMP) $(FAST_IMPORT)
	SPLINESTEP_JOBS=$(JOBS) $(BIN)/python scripts/reproduce.py $(NB)

# The paper from the data and figures as they are (no notebook runs).
paper: $(STAMP) $(FAST_IMPORT)
	$(BIN)/python scripts/paper.py

# The website alone, from the notebooks' stored outputs and the paper.
site: $(STAMP) $(FAST_IMPORT)
	$(BIN)/python scripts/build_site.py

# The browser the website's test drives (Debian's; playwright downloads none).
browser:
	command -v chromium > /dev/null || { apt-get update -qq && apt-get install -y -qq chromium > /dev/null; }

# Notebooks run at once by make reproduce, and pytest-xdist workers of make
# test (each notebook's cells stay on one worker).
JOBS ?= 2
PYTEST := $(BIN)/python -m pytest -n $(JOBS) --dist loadfile --no-loadscope-reorder \
	--nbval --nbval-current-env --nbval-sanitize-with tests/nbval-sanitize.cfg notebooks tests

test: $(STAMP) $(FAST_IMPORT)
	SPLINESTEP_RERUN=$(RERUN) $(PYTEST) $(if $(JUNIT),--junitxml=build/junit.xml)

test-emulated: $(STAMP) $(FAST_IMPORT)
	SPLINESTEP_RERUN=$(RERUN) $(EMULATED_CPU) $(PYTEST)

# The package's tests, installed as a user installs it, at both ends of the
# bounds pyproject.toml declares: the oldest direct dependencies on Python
# 3.11, the newest on Python 3.13 (scripts/test_bounds.py; venvs in build/).
test-bounds: $(STAMP)
	$(BIN)/python scripts/test_bounds.py

bench: $(STAMP) $(FAST_IMPORT)
	$(BIN)/python benchmarks/speed.py
	$(BIN)/python benchmarks/scaling.py
	$(BIN)/python benchmarks/controller.py
	$(BIN)/python benchmarks/defaults.py

# The reference trajectories from OpenSees (not a dependency of the package:
# its own venv, its wheel pinned so that the data regenerate byte for byte;
# its Linux wheel loads Debian's BLAS and LAPACK).
OSVENV ?= build/opensees-venv
opensees-reference:
	dpkg -s libblas3 liblapack3 > /dev/null 2>&1 || apt-get install -y -qq libblas3 liblapack3 > /dev/null
	test -x $(OSVENV)/bin/python || { $(PYTHON) -m venv $(OSVENV) && \
		$(OSVENV)/bin/pip install --quiet openseespy==3.7.1.2 "$$(grep '^numpy==' environment.txt)"; }
	$(OSVENV)/bin/python scripts/opensees_reference.py

lab: $(STAMP) $(FAST_IMPORT)
	$(BIN)/python scripts/lab.py

clean:
	rm -rf $(VENV) .pytest_cache build
