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
# The local ClickHouse cluster (`make cluster`, and the cluster tests of `make test`): ClickHouse 18.16 and
# ZooKeeper 3.8 from Debian 12.
APT_CLUSTER_PACKAGES := clickhouse-server clickhouse-client zookeeper curl
# Needed by `make test-asan` and `make fuzz` only: clang with libFuzzer and the sanitizer runtimes, and
# llvm-symbolizer for readable sanitizer stack traces (Debian 12: clang 14).
APT_FUZZ_PACKAGES := clang libclang-rt-14-dev llvm

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
	$(call apt_install,$(APT_CLUSTER_PACKAGES))

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

# ---- A local ClickHouse cluster (docker/README.md "A ClickHouse cluster") -----------------------------
# `make cluster`: 2 shards x 2 replicas of clickhouse-server and one ZooKeeper on loopback ports, every
# process ours with its pid file under $(CLUSTER_DIR); waits until each node answers and sees the topology,
# then prints the `--store clickhouse://...` URL. `make cluster-down` stops them by those pids (data kept;
# CLUSTER_FRESH=1 make cluster starts empty). The script: tests/cluster/cluster.sh.
CLUSTER_DIR ?= $(BUILD_DIR)/cluster
.PHONY: deps-cluster cluster cluster-down
deps-cluster:
	$(call apt_install,$(APT_CLUSTER_PACKAGES))
cluster: deps-cluster
	CLUSTER_DIR=$(CLUSTER_DIR) bash tests/cluster/cluster.sh up
cluster-down:
	CLUSTER_DIR=$(CLUSTER_DIR) bash tests/cluster/cluster.sh down

format:
	clang-format -i $$(git ls-files '*.cpp' '*.hpp')

clean:
	rm -rf $(BUILD_DIR) web/dist

# ---- Fuzzing and sanitizers (README "Fuzzing and sanitizers") ------------------------------------------
# One checking build, $(ASAN_BUILD_DIR): clang, every library and test with AddressSanitizer and
# UndefinedBehaviorSanitizer (undefined behaviour fatal) plus libFuzzer's coverage instrumentation, and the
# harnesses of tests/fuzz. `make test-asan` runs the C++ tests (ctest) there; `make fuzz` runs every
# harness for FUZZ_SECONDS; `make fuzz-long` runs one segment of the long run: every harness short of
# FUZZ_RUNS executions in all, for at most FUZZ_LONG_SECONDS each, FUZZ_LONG_JOBS at a time (default 1), at
# the lowest priority, resumed from its kept corpus (ASAN_BUILD_DIR/fuzz-long/<harness>/corpus), and appends
# the segment to tests/fuzz/long_run.jsonl (BENCHMARKS.md's fuzzing section adds the segments up); run it
# again until every harness reached FUZZ_RUNS. .ci/run runs test-asan and fuzz after `make test`.
ASAN_BUILD_DIR ?= build-asan
FUZZ_SECONDS ?= 60
FUZZ_RUNS ?= 10000000
FUZZ_LONG_SECONDS ?= 1200
FUZZ_LONG_JOBS ?= 1
# Wall seconds one input may take in the long run before it counts as a hang: at nice 19 beside a build the
# fuzzer waits for a core, and 10 s (make fuzz's limit) then fires on inputs that take milliseconds of CPU.
FUZZ_LONG_TIMEOUT ?= 120
FUZZ_JOBS ?= $(JOBS)
# Leak suppressions (third-party allocations only, each explained in the file); UBSan stops at the first
# report; ASan aborts so that ctest sees the failure. use_sigaltstack=0: with its own alternate signal stack
# per thread, clang 14's ASan runtime aborts in thread teardown ("unable to unmap", UnsetAlternateSignalStack)
# once a test has started and joined many threads (the bundle-stream server tests); ASan's checks are the same
# without it.
SANITIZER_ENV := ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:fast_unwind_on_malloc=0:use_sigaltstack=0 \
  LSAN_OPTIONS=suppressions=$(CURDIR)/tests/sanitizers/lsan.supp:print_suppressions=0 \
  UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1

.PHONY: deps-fuzz asan-configure test-asan fuzz-build fuzz fuzz-long

deps-fuzz: deps-test
	$(call apt_install,$(APT_FUZZ_PACKAGES))

asan-configure: deps-fuzz
	cmake -S . -B $(ASAN_BUILD_DIR) -G Ninja -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
	  -DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -gline-tables-only" \
	  -DTRAILSCOPE_FUZZ=ON -DTRAILSCOPE_BUILD_BENCH=OFF \
	  $(shell command -v ccache >/dev/null && echo -DCMAKE_CXX_COMPILER_LAUNCHER=ccache)

# The C++ tests under ASan + UBSan (gtest discovery runs the test binaries at build time: same options).
# Left out there, each run by `make test` in the release build: tests whose point is a figure over a long
# computation (accuracy over 1,000 synthetic frames, every separation event of the Europe day, a sort of
# every column both ways) or a wait on other processes (the cluster's faults, the chaos test's kills), each
# 0.5-7 minutes under the sanitizers, while a shorter sibling runs the same code there. Measured on
# 2026-12-08 (2 cores): ctest under the sanitizers took 2,150 s of wall time, 4,250 s of test time, of which
# these took 1,820 s:
# - the demo day's comparison of the two stores (17M points through the ClickHouse cluster): the Europe
#   day's comparison runs the same code;
# - TrackerAccuracy.StandardScenario... and .CupsAttached... (421 s, 342 s): Tracker.IsDeterministic,
#   RunTracker.* and TrackerAccuracy's other tests run the tracker and the synthetic camera;
# - SeparationEurope.SameEventsAsDenseGeodesicSampling (412 s): the Separation.* cases and the other
#   SeparationEurope tests;
# - CongestionEurope.InterpolatedMatchesSlabClipping and .GridAndSeparationEqualToTheLibrary... (133 s,
#   57 s): the five other CongestionEurope tests;
# - FlightsSort.EveryColumnBothOrdersPagedAgainstAPlainSort (101 s): FlightsSort.InWindowAndWholeFlight...;
# - RealDepth.PsnrRisesWithTheNumberOfLayers (65 s): RealDepth.FrameZeroMatchesTheRecordedFacts;
# - StreamBundle.DriftPerUpdateIsSmallAndReportedExactly (51 s): the six other StreamBundle tests;
# - ClickHouseStoreFaults.* (55 s, 34 s: replicas killed and restarted): ClickHouseStore.*, the ingest
#   killed midway included;
# - server_chaos (147 s: kill -9 at every write path, then a restart): the stores' reopen and recovery
#   tests (EmbeddedStore.InterruptedWriteLeavesNoDataset, GazeStoreTest.DeleteRestartAndLeftovers,
#   VideosTest.SurvivesReopen, ...).
ASAN_CTEST_EXCLUDE := ClickHouseStore.DemoDayAnswersTheSameOnBothBackends|TrackerAccuracy.StandardScenarioMeetsTheTargets|TrackerAccuracy.CupsAttachedIsLostWhileCoveredAndReacquiredAfter|SeparationEurope.SameEventsAsDenseGeodesicSampling|CongestionEurope.InterpolatedMatchesSlabClipping|CongestionEurope.GridAndSeparationEqualToTheLibraryWithProgressEvents|FlightsSort.EveryColumnBothOrdersPagedAgainstAPlainSort|RealDepth.PsnrRisesWithTheNumberOfLayers|StreamBundle.DriftPerUpdateIsSmallAndReportedExactly|ClickHouseStoreFaults\.|^server_chaos$$
test-asan: asan-configure
	$(SANITIZER_ENV) cmake --build $(ASAN_BUILD_DIR) -j $(JOBS)
	cd $(ASAN_BUILD_DIR) && $(SANITIZER_ENV) ctest --output-on-failure -j $(JOBS) -E '$(ASAN_CTEST_EXCLUDE)'

fuzz-build: asan-configure
	cmake --build $(ASAN_BUILD_DIR) -j $(JOBS) --target fuzzers
	bash tests/fuzz/seeds.sh $(ASAN_BUILD_DIR)

fuzz: fuzz-build
	bash tests/fuzz/run.sh $(ASAN_BUILD_DIR) --seconds $(FUZZ_SECONDS) --jobs $(FUZZ_JOBS)

fuzz-long: fuzz-build
	nice -n 19 bash tests/fuzz/run.sh $(ASAN_BUILD_DIR) --long --goal $(FUZZ_RUNS) --max-seconds $(FUZZ_LONG_SECONDS) \
	  --timeout $(FUZZ_LONG_TIMEOUT) --jobs $(FUZZ_LONG_JOBS) --out tests/fuzz/long_run.jsonl
