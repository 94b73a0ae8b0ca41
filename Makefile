# The two commands of the README: `make demo` and `make test`.
# Both install missing Debian packages, configure and build first.
PRESET ?= release
BUILD  := build
JOBS   ?= $(shell nproc)
FUZZ_SECONDS ?= 60

.PHONY: all deps deps-test configure build demo test test-asan fuzz bench clean

all: build

deps:
	@scripts/install-deps.sh

# The whole build also makes the man pages and the Python module (and `make test` runs its tests).
deps-test:
	@scripts/install-deps.sh test

# The compiled runs of the built-in kernels (NESSHI_COMPILED_RUNS) are a fifth of a first build of
# the command line (about 145 CPU-s with their generator) and save the demo half a second: a first
# `make demo` configures without them, `make` and CI's `make test` turn them on, and a developer's
# `make test` keeps what the build has (so `make demo` then `make test` tests the threaded engine
# on the presets' kernels, and CI the compiled runs too).
FULL := -DNESSHI_COMPILED_RUNS=ON

configure: deps
	@cmake --preset $(PRESET) $(FULL) >/dev/null

build: deps-test configure
	@cmake --build $(BUILD) -j $(JOBS)

# The demo needs the command line only; `make test` builds the rest.
demo: deps
	@test -f $(BUILD)/CMakeCache.txt || cmake --preset $(PRESET) -DNESSHI_COMPILED_RUNS=OFF >/dev/null
	@cmake --build $(BUILD) -j $(JOBS) --target nesshi
	@$(BUILD)/nesshi demo

# In CI (CI=true) warnings are errors and the unit tests also run under ASan+UBSan.
test: deps-test
ifeq ($(CI),true)
	@cmake --preset ci $(FULL) >/dev/null
else
	@cmake --preset $(PRESET) >/dev/null
endif
	@cmake --build $(BUILD) -j $(JOBS)
	@ctest --test-dir $(BUILD) --output-on-failure -j $(JOBS)
ifeq ($(CI),true)
	@$(MAKE) --no-print-directory test-asan
endif

# Under the sanitizers (preset asan: the libraries at -O1, the tests' code at -O0, no compiled
# runs) the unit tests but these: two property tests that schedule kernels for many machines
# (345 s and 151 s of 899 at -O0); kernels.regenerate, which needs the command line; and three
# renders whose time is the IC's kernel scheduled for ic-real and variants, instrumented (52, 38
# and 27 s of 442 at stop 43; the sched suite, fuzz.pipeline and the ic-real twins test still run
# the pipeliner under the sanitizers). All of them run in the release suite.
ASAN_SKIP := never busier than its preset|scheduled from its .pk source, the preset|kernels.regenerate|Variants render what the native renderer renders|The -real presets run the whole machine|The IC kernel is chosen on the scene
test-asan: deps-test
	@cmake --preset asan >/dev/null
	@cmake --build build-asan -j $(JOBS) --target unit_tests
	@ctest --test-dir build-asan --output-on-failure -j $(JOBS) -L unit -E "$(ASAN_SKIP)"

# libFuzzer harnesses (tests/fuzz/), each for FUZZ_SECONDS (default 60); needs clang, unlike `make test`.
fuzz:
	@scripts/install-deps.sh fuzz
	@cmake --preset fuzz >/dev/null
	@nice cmake --build --preset fuzz -j $(JOBS)
	@FUZZ_SECONDS=$(FUZZ_SECONDS) scripts/fuzz.sh

# Benchmarks print figures measured in one run; long (minutes), never part of `make test`.
bench: build
	@$(BUILD)/bench_iss
	@$(BUILD)/bench_native_render
	@$(BUILD)/bench_machine_render
	@$(BUILD)/bench_sched

clean:
	rm -rf build build-asan build-fuzz
