# The documented commands. Each target installs what it needs first.
#   make demo   the platform with the example twins, on http://127.0.0.1:8000 (web app at /app/)
#   make cluster  the same on PostgreSQL, Kafka, two nodes and haproxy, on http://127.0.0.1:8000
#   make test   every test (unit and integration, with real servers on loopback, then the web app's)
#   make bench  the benchmarks in bench/ (API, live data, processors, gateway, web app chart), results in docs/benchmarks.md
#   make lint   ruff, mypy and the import contracts (lint-imports, [tool.importlinter] in pyproject.toml)

PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
# The demo is no part of the product: its packages (examples/demo, and the crane's services in
# examples/ilmatar) are installed beside it, as the edge SDK is, so `twinlink demo` finds them.
DEMO   := examples/ilmatar examples/demo
STAMP  := $(VENV)/.installed-$(shell cat pyproject.toml edge/pyproject.toml $(DEMO:%=%/pyproject.toml) constraints.txt | cksum | cut -d" " -f1)
HOST   ?= 127.0.0.1
PORT   ?= 8000

# The web app: ui/ (Vite + React) is built into the package, src/twinlink/web/app/, and served
# at /app/. It is rebuilt (npm install, npm run build) when its sources change. Without ui/ (or
# its package.json) the UI steps are skipped.
UI_OUT := src/twinlink/web/app
ifneq ($(wildcard ui/package.json),)
UI_BUILT := $(UI_OUT)/index.html
UI_SRC   := $(wildcard ui/package.json ui/package-lock.json ui/index.html ui/vite.config.* \
              ui/tsconfig*.json) $(shell find ui/src ui/public -type f 2>/dev/null)
endif

.PHONY: demo cluster test unit integration bench lint format clean setup constraints ui-types

setup: $(STAMP) $(UI_BUILT)

$(STAMP): pyproject.toml edge/pyproject.toml $(DEMO:%=%/pyproject.toml) constraints.txt
	@scripts/ensure-python.sh $(PYTHON)
	@scripts/ensure-packages.sh gcc g++ libc6-dev   # FMUs are built from C source; the ESP32 example's host test is C++
	@test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -c constraints.txt -e ./edge $(DEMO:%=-e ./%) -e ".[dev]"
	@rm -f $(VENV)/.installed-*
	@touch $@

# After changing dependencies in pyproject.toml: install the newest allowed versions, run
# make test, then commit the new constraints.txt with the change.
constraints:
	$(BIN)/python -m pip install --quiet --upgrade -e ./edge $(DEMO:%=-e ./%) -e ".[dev]"
	{ sed -n '1,2p' constraints.txt; $(BIN)/python -m pip freeze --exclude-editable; } > constraints.tmp
	mv constraints.tmp constraints.txt

$(UI_BUILT): $(UI_SRC)
	@scripts/ensure-node.sh
	@# npm install, not npm ci: the registry this project is built against serves rollup's
	@# native builds for Linux only, so the lock lists only those and npm ci refuses it;
	@# npm install keeps every version the lock pins.
	cd ui && npm install --no-audit --no-fund && npm run build
	@test -f $@ || { echo "npm run build wrote no $@ (see outDir in ui/vite.config.*)" >&2; exit 1; }
	@touch $@

demo: $(STAMP) $(UI_BUILT)
	$(BIN)/twinlink demo --host $(HOST) --port $(PORT)

# PostgreSQL, Kafka, two nodes and haproxy on this machine (docs/scale-out.md, "A local
# cluster"); data, logs and secrets in ./.twinlink-cluster, kept across starts.
cluster: $(STAMP) $(UI_BUILT)
	@scripts/ensure-packages.sh postgresql haproxy openjdk-17-jre-headless maven
	@scripts/ensure-kafka.sh >/dev/null
	$(BIN)/twinlink cluster up --port $(PORT)

test: $(STAMP) $(UI_BUILT)
	@# chromium: the web app's end-to-end test drives it; mosquitto: the MQTT tests' broker
	@# and clients (external mode, mosquitto_pub/sub against the embedded listener);
	@# postgresql: the PostgreSQL backend's tests start a throwaway cluster of their own;
	@# haproxy: the load balancer in front of the scale-out tests' nodes
	@scripts/ensure-packages.sh chromium mosquitto mosquitto-clients postgresql haproxy
	@# Apache Kafka's jars (Maven Central, cached in .cache/kafka): the Kafka bus tests' broker
	@scripts/ensure-packages.sh openjdk-17-jre-headless maven
	@scripts/ensure-kafka.sh >/dev/null
	@# The layering first: a broken import contract fails in a second, before 10 minutes of tests.
	$(BIN)/lint-imports --no-cache
	$(BIN)/python -m pytest tests
ifneq ($(UI_BUILT),)
	cd ui && { test -d node_modules || npm install --no-audit --no-fund; } && npm run typecheck && npm test
else
	@echo "no ui/package.json: the web app's tests are skipped"
endif

unit: $(STAMP)
	$(BIN)/python -m pytest tests/unit

integration: $(STAMP)
	$(BIN)/python -m pytest tests/integration

bench: $(STAMP) $(UI_BUILT)
	@scripts/ensure-packages.sh nginx-light wrk chromium mosquitto
	$(BIN)/python bench/api.py
	$(BIN)/python bench/live.py
	$(BIN)/python bench/processors.py
	$(BIN)/python bench/gateway.py
	$(BIN)/python bench/udp.py
	$(BIN)/python bench/mqtt.py
	@scripts/ensure-packages.sh openjdk-17-jre-headless maven
	$(BIN)/python bench/bus.py
ifneq ($(UI_BUILT),)
	$(BIN)/python bench/ui_chart.py
endif

# The web app's API types, ui/src/api/openapi.ts, generated from the server's /openapi.json
# (made without a server) by openapi-typescript: run after changing a route's models, and
# commit the file. make test fails while it is stale (test_openapi_contract.py).
ui-types: $(STAMP)
	cd ui && { test -d node_modules || npm install --no-audit --no-fund; } && \
		TWINLINK_PYTHON=$(CURDIR)/$(BIN)/python npm run api-types

lint: $(STAMP)
	$(BIN)/ruff check src edge $(DEMO) examples/plugins tests bench
	$(BIN)/ruff format --check src edge $(DEMO) examples/plugins tests bench
	$(BIN)/mypy
	$(BIN)/lint-imports --no-cache

format: $(STAMP)
	$(BIN)/ruff format src edge $(DEMO) examples/plugins tests bench
	$(BIN)/ruff check --fix src edge $(DEMO) examples/plugins tests bench

clean:
	rm -rf $(VENV) .pytest_cache .mypy_cache .ruff_cache build dist src/*.egg-info edge/src/*.egg-info $(DEMO:%=%/src/*.egg-info) $(UI_OUT) ui/node_modules
