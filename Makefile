# Two commands: `make demo` and `make test`. Both create .venv on first use.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed

.PHONY: demo test every-model bench clean

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e '.[test]'
	touch $(STAMP)

demo: $(STAMP)
	@# Validates every model into the report validation/report/, then exits non-zero if any missed its tolerance.
	$(BIN)/linkgen validate models/ -o validation/report || { echo "some models missed their tolerance: see validation/report/README.md" >&2; exit 1; }
	$(MAKE) --no-print-directory every-model

# Two workers: the suite is CPU-bound and its tests independent (this machine has two cores);
# worksteal: a worker that runs out of tests takes some of the other's, so the long ones do not end alone.
# linkgen byte-compiled first (0.3 s): where PYTHONDONTWRITEBYTECODE is set, Python never caches it, and
# each of the suite's command-line runs (a new process each) would compile it again (~0.1 s a run).
test: $(STAMP)
	$(BIN)/python -m compileall -q linkgen
	$(BIN)/python -m pytest -q -n 2 --dist worksteal

# The every-model checks (marked every_model) on every bundled model; `make test` runs them on one model
# per family and feature (tests/conftest.py, REPRESENTATIVE).
every-model: $(STAMP)
	LINKGEN_EVERY_MODEL=1 $(BIN)/python -m pytest -q -n 2 --dist worksteal -m every_model

bench: $(STAMP)
	$(BIN)/python -m pip install --quiet -e '.[bench]'
	$(BIN)/python validation/bench_kinematics.py

clean:
	rm -rf $(VENV) validation/report
