# Two commands on a fresh machine: `make report` and `make test`.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed

.PHONY: report test bench clean

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/pip install --quiet --upgrade pip
	$(BIN)/pip install --quiet -e '.[test]'
	@# the real-rasterizer adapters where this machine can build them (cairo needs libcairo2-dev)
	$(BIN)/pip install --quiet -e '.[test,real]' || echo "note: real-rasterizer adapters not installed; see README (Real rasterizers)"
	touch $(STAMP)

# The report is written whether checks pass or fail (exit 1); only usage errors stop make.
report: $(STAMP)
	$(BIN)/rastercheck run --out reports || [ $$? -eq 1 ]

# lint and types first (seconds), then the tests on every core (a module's tests stay
# together, so its shared fixtures are built once)
test: $(STAMP)
	$(BIN)/ruff check .
	$(BIN)/python -m mypy
	$(BIN)/python -m pytest -n auto --dist loadfile

bench: $(STAMP)
	$(BIN)/rastercheck bench --json reports/bench.json

clean:
	rm -rf $(VENV) build *.egg-info
