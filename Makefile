# The documented commands. Each target installs what it needs first.
#   make demo   the platform with the example twins, on http://127.0.0.1:8000
#   make test   every test (unit and integration, with real servers on loopback)
#   make bench  the benchmarks in bench/ (API, live data, processors, then the gateway), results in docs/benchmarks.md
#   make lint   ruff and mypy

PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed-$(shell cat pyproject.toml edge/pyproject.toml | cksum | cut -d" " -f1)
HOST   ?= 127.0.0.1
PORT   ?= 8000

.PHONY: demo test unit integration bench lint format clean setup

setup: $(STAMP)

$(STAMP): pyproject.toml edge/pyproject.toml
	@scripts/ensure-python.sh $(PYTHON)
	@scripts/ensure-packages.sh gcc libc6-dev   # FMUs are built from C source
	@test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e ./edge -e ".[dev]"
	@rm -f $(VENV)/.installed-*
	@touch $@

demo: $(STAMP)
	$(BIN)/twinlink demo --host $(HOST) --port $(PORT)

test: $(STAMP)
	$(BIN)/python -m pytest tests

unit: $(STAMP)
	$(BIN)/python -m pytest tests/unit

integration: $(STAMP)
	$(BIN)/python -m pytest tests/integration

bench: $(STAMP)
	@scripts/ensure-packages.sh nginx-light wrk
	$(BIN)/python bench/api.py
	$(BIN)/python bench/live.py
	$(BIN)/python bench/processors.py
	$(BIN)/python bench/gateway.py

lint: $(STAMP)
	$(BIN)/ruff check src edge tests bench
	$(BIN)/ruff format --check src edge tests bench
	$(BIN)/mypy

format: $(STAMP)
	$(BIN)/ruff format src edge tests bench
	$(BIN)/ruff check --fix src edge tests bench

clean:
	rm -rf $(VENV) .pytest_cache .mypy_cache .ruff_cache build dist src/*.egg-info
