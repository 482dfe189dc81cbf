# Two commands on a fresh machine: `make report` and `make test`.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed
# the real-rasterizer adapters' extras that `make` tries, each on its own (CI's bare-machine
# stage sets none: `make test ADAPTERS=`)
ADAPTERS ?= skia gl cairo vulkan freetype agg qt blend2d tiny_skia pygame
# Python's compiled modules are written and reused: with PYTHONDONTWRITEBYTECODE set (some
# shells and CI images set it) every process of a run -- each test worker, each isolated
# rasterizer, each command a test starts -- compiles every module it imports again
# (seconds each: a one-case pytest run took 6.9 s instead of 3.6 s)
unexport PYTHONDONTWRITEBYTECODE

.PHONY: report test types check bench atlas clean

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/pip install --quiet --upgrade pip
	$(BIN)/pip install --quiet -e '.[test]'
	@# each real-rasterizer adapter on its own, where this machine can build it: one that
	@# cannot (pycairo without libcairo2-dev) costs only itself, and the report says why
	@for adapter in $(ADAPTERS); do \
		$(BIN)/pip install --quiet -e ".[$$adapter]" >$(VENV)/install-$$adapter.log 2>&1 \
		|| echo "note: the $$adapter adapter could not be installed (see $(VENV)/install-$$adapter.log and README, Real rasterizers); it is skipped"; \
	done
	touch $(STAMP)

# The report is written whether checks pass or fail (exit 1); only usage errors stop make.
# every core checks rasterizers side by side (each in worker processes of its own)
report: $(STAMP)
	$(BIN)/rastercheck run --out reports --jobs $(CORES) || [ $$? -eq 1 ]

# one test worker more than the cores: many tests wait on a child process (a hang run to its
# time limit, a command, the browser), and the extra worker fills a core meanwhile (2 cores:
# the tests took 156 s on 3 workers, 178 s on 2, 165 s on 4)
CORES := $(shell $(PYTHON) -c 'import os; print(os.cpu_count() or 1)')
TEST_WORKERS ?= $(shell $(PYTHON) -c 'import os; print((os.cpu_count() or 1) + 1)')

# lint first (a second); then the two parts of compiling the numba kernels once into
# numba's cache, side by side (else every test worker compiles them again on a fresh clone),
# and beside them one collection of the tests, which writes their assertion-rewritten
# modules once (on a fresh clone each test worker rewrote every test module itself: 6 s
# each; a collection error shows in the run that follows);
# then the tests on every core and one more (a module's tests stay together, so its shared
# fixtures are built once), the longest modules first (tests/conftest.py: LONGEST_FIRST;
# xdist would otherwise hand out the modules with the most tests first, and the browser's
# module, started last, ran 10 s alone). Types are `make types`: mypy, then the tests of the static
# checks (marked `types`), which reuse its cache (CI runs both; `make check` does too):
# on a fresh clone mypy (strict, the tests included) takes one core for 30 s, the static tests 17 s more without its cache.
test: $(STAMP)
	$(BIN)/ruff check .
	$(BIN)/python -m tests.warm engine & engine=$$!; $(BIN)/python -m tests.warm rasterizers & others=$$!; \
	$(BIN)/python -m pytest --collect-only -q -m "not types" >/dev/null 2>&1 & \
	wait $$engine && wait $$others && wait
	$(BIN)/python -m pytest -n $(TEST_WORKERS) --dist loadfile --no-loadscope-reorder --durations=15 -m "not types"

types: $(STAMP)
	$(BIN)/python -m mypy
	$(BIN)/python -m pytest -q -m types

check: types test

# every installed real library in every mode, identified and judged on one page
# (reports/atlas/atlas.html, its JSON twin atlas.json, the run report beside them)
atlas: $(STAMP)
	$(BIN)/rastercheck atlas --out reports/atlas

bench: $(STAMP)
	$(BIN)/rastercheck bench --json reports/bench.json

clean:
	rm -rf $(VENV) build *.egg-info
