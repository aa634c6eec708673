# splinestep: one command regenerates everything, one runs every test.
#   make reproduce   build .venv from environment.txt, run all notebooks, write data/ and figures/
#   make test        build .venv, run pytest (package tests and nbval on every notebook)
#   make bench       speed benchmark (compiled, plain Python, scipy, C)
#   make lab         JupyterLab with the .py <-> .ipynb pairing active

PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed

export MPLBACKEND := Agg
export PYTHONHASHSEED := 0
export SOURCE_DATE_EPOCH := 0

.PHONY: reproduce test bench lab env clean

env: $(STAMP)

# Rebuilt when missing or older than environment.txt or pyproject.toml.
$(STAMP): environment.txt pyproject.toml
	rm -rf $(VENV)
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet -r environment.txt
	$(BIN)/python -m pip install --quiet --no-deps -e .
	$(BIN)/python -m ipykernel install --sys-prefix --name python3 > /dev/null
	touch $(STAMP)

reproduce: $(STAMP)
	$(BIN)/python scripts/reproduce.py

test: $(STAMP)
	$(BIN)/python -m pytest

bench: $(STAMP)
	$(BIN)/python benchmarks/speed.py

lab: $(STAMP)
	$(BIN)/jupyter lab notebooks/

clean:
	rm -rf $(VENV) .pytest_cache
