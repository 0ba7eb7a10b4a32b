# TrailScope: `make run` and `make test` do all set-up on a fresh Debian 12 machine.
SHELL := /bin/bash
BUILD_DIR ?= build
DATA_DIR ?= data
PORT ?= 8080
JOBS ?= $(shell nproc)
SUDO := $(shell [ "$$(id -u)" = 0 ] || echo sudo)

# Debian packages (Debian 12 names; Boost 1.81 brings Beast, Asio, JSON and URL). Only the missing ones are
# installed.
APT_PACKAGES := build-essential cmake ninja-build pkg-config \
  libeigen3-dev libopencv-dev libgeographiclib-dev libopenimageio-dev openimageio-tools \
  pocl-opencl-icd ocl-icd-opencl-dev opencl-headers opencl-clhpp-headers clinfo \
  libboost1.81-dev libboost-json1.81-dev libboost-url1.81-dev nlohmann-json3-dev \
  libprotobuf-dev protobuf-compiler libsqlite3-dev libgtest-dev libgmock-dev libbenchmark-dev \
  libspdlog-dev libcli11-dev libzstd-dev libtbb-dev zlib1g-dev libpugixml-dev curl \
  libsodium-dev
# Needed by `make test` (browser test, loopback test: python3 reads its JSON) and `make bench` only.
APT_TEST_PACKAGES := chromium wrk python3
APT_BENCH_PACKAGES := clickhouse-server clickhouse-client

.PHONY: run test deps deps-test deps-bench web-deps web build demo clean format bench check-web

define apt_install
	@missing=$$(for p in $(1); do dpkg-query -W -f='$${Status}\n' $$p 2>/dev/null | grep -q 'install ok installed' || echo $$p; done); \
	if [ -n "$$missing" ]; then \
	  echo "installing Debian packages:" $$missing; \
	  $(SUDO) apt-get update -qq && DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get install -y -qq --no-install-recommends $$missing; \
	fi
endef

deps:
	$(call apt_install,$(APT_PACKAGES))
	@# Node.js may come from Debian (nodejs + npm) or from a distribution that bundles npm in its nodejs
	@# package (which then conflicts with Debian's npm): install Debian's only when the commands are missing.
	@command -v node >/dev/null || { $(SUDO) apt-get update -qq && DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get install -y -qq --no-install-recommends nodejs; }
	@command -v npm >/dev/null || { DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get install -y -qq --no-install-recommends npm; }

deps-test: deps
	$(call apt_install,$(APT_TEST_PACKAGES))

deps-bench: deps-test
	$(call apt_install,$(APT_BENCH_PACKAGES))

# npm packages for web/ (and vega-datasets for the demo generator), from the lock file.
web-deps: web/node_modules/.package-lock.json
web/node_modules/.package-lock.json: web/package.json web/package-lock.json
	cd web && npm ci --no-audit --no-fund
	@touch $@

web: web-deps
	cd web && npm run build

build: deps
	cmake -S . -B $(BUILD_DIR) -G Ninja -DCMAKE_BUILD_TYPE=Release
	cmake --build $(BUILD_DIR) -j $(JOBS)

# Builds everything, generates the demo dataset when absent, and serves http://127.0.0.1:$(PORT)/.
run: build web
	$(BUILD_DIR)/server/trailscope serve --data-dir $(DATA_DIR) --port $(PORT) --web-root web/dist --demo

# Every test: C++ unit and API tests (ctest), the web unit tests, and the browser end-to-end test.
test: deps-test build web
	cd $(BUILD_DIR) && ctest --output-on-failure -j $(JOBS)
	cd web && npm test
	TRAILSCOPE_BIN=$(BUILD_DIR)/server/trailscope bash tests/e2e/run.sh

bench: deps-bench build web
	BUILD_DIR=$(BUILD_DIR) bash tests/bench/run_benchmarks.sh

# Bounded load test: 100 connections of mixed requests, uploads and 10 WebSockets for 60 s against a server
# with the demo dataset on loopback; records in tests/bench/load_results.jsonl, the Load section of
# BENCHMARKS.md rewritten (tests/bench/load_test.sh).
.PHONY: load
load: deps-test build web-deps
	BUILD_DIR=$(BUILD_DIR) LOAD_DEMO_SOURCE=$(CURDIR)/web/node_modules/vega-datasets/data bash tests/bench/load_test.sh

format:
	clang-format -i $$(git ls-files '*.cpp' '*.hpp')

clean:
	rm -rf $(BUILD_DIR) web/dist
