# aniso: every target installs what it needs first (scripts/install-deps.sh is idempotent).
PRESET ?= release
JOBS   ?= $(shell nproc)
BIN    := build/$(PRESET)/bin

.PHONY: all deps configure build test bench bench-python bench-fit-db clean format render sanitize-build test-sanitize fuzz-build fuzz fuzz-ci install package format-check

all: build

deps:
	@bash scripts/install-deps.sh

configure: deps
	@cmake --preset $(PRESET) -DANISO_RENDER_ONLY=OFF >/dev/null

build: configure
	@cmake --build --preset $(PRESET) -j $(JOBS)
	@echo "built $(BIN)/aniso"

# The main job: the built-in gallery -> aniso-gallery.png in the current directory. Only what the
# picture needs: the packages of the `aniso` executable, then that target alone (no tests,
# benchmarks, fuzz targets or Python module; `make test` adds them in the same build directory).
# A build directory configured already keeps its configuration.
render:
	@bash scripts/install-deps.sh --render
	@test -f build/$(PRESET)/CMakeCache.txt || cmake --preset $(PRESET) -DANISO_RENDER_ONLY=ON >/dev/null
	@cmake --build --preset $(PRESET) -j $(JOBS) --target aniso
	@$(BIN)/aniso render

# The suite, then its wall and CPU time and its ten slowest entries (scripts/ctest_timed.sh; the
# exit status is ctest's).
test: build
	@bash scripts/ctest_timed.sh $(PRESET) -j $(JOBS)

# The headers, libraries, CMake package, pkg-config files, CLI, Python package and docs under
# PREFIX (docs/cpp.md, "Install"; cmake/install.cmake). Without PREFIX: the configured prefix
# (/usr/local).
install: build
	@cmake --install build/$(PRESET) $(if $(PREFIX),--prefix $(PREFIX))

# The Debian package build/$(PRESET)/aniso_<version>_amd64.deb (CPack; cmake/install.cmake):
# `apt-get install ./build/release/aniso_*.deb` on Debian 12.
package: build
	@cd build/$(PRESET) && cpack -G DEB >/dev/null && ls $$(pwd)/aniso_*.deb

# The sanitizer build (build/sanitize, preset `sanitize`): ASan + UBSan, asserts on, no benchmarks.
# clang when installed (then the fuzz targets link libFuzzer), g++ otherwise (they replay the
# corpus). docs/testing.md.
SANITIZE_CXX ?= $(shell command -v clang++ >/dev/null 2>&1 && echo clang++ || echo g++)
FUZZ_SECONDS ?= 120

sanitize-build: deps
	@cmake --preset sanitize -DCMAKE_CXX_COMPILER=$(SANITIZE_CXX) >/dev/null
	@cmake --build --preset sanitize -j $(JOBS)

# The whole suite under the sanitizers (statistical tests and the slowest fits at ANISO_TEST_SCALE,
# see the preset), then its times and ten slowest entries as for `make test`.
test-sanitize: sanitize-build
	@bash scripts/ctest_timed.sh sanitize -j $(JOBS)

# The fuzz targets alone in the sanitizer build (the readers and their libraries, not the suite).
fuzz-build: deps
	@cmake --preset sanitize -DCMAKE_CXX_COMPILER=$(SANITIZE_CXX) >/dev/null
	@cmake --build --preset sanitize -j $(JOBS) --target fuzz_targets

# Every fuzz target for FUZZ_SECONDS each (libFuzzer, random seeds), or a replay of the corpus
# without clang.
fuzz: fuzz-build
	@bash scripts/fuzz.sh build/sanitize $(FUZZ_SECONDS)

# CI's fuzz run: each target for the inputs and from the seed fuzz/ci.txt gives it (about a minute
# in all), the same inputs on every run of the same sources.
fuzz-ci: fuzz-build
	@bash scripts/fuzz.sh --ci build/sanitize

# The kernels (Google Benchmark), then the renderer (a command: gallery, ray ceiling, noise; ~1 min).
bench: build
	@$(BIN)/aniso_bench --benchmark_min_time=0.2 $(BENCH_ARGS)
	@$(BIN)/aniso_bench_render $(BENCH_RENDER_ARGS)

# Python bindings vs the C++ batch path on a million pairs (python/bench/bench_eval.py, docs/python.md).
bench-python: build
	@PYTHONPATH=build/$(PRESET)/python ANISO_BATCH_EVAL_CPP=$(BIN)/aniso_batch_eval_cpp /usr/bin/python3 python/bench/bench_eval.py $(BENCH_ARGS)

# aniso.fit_many / aniso fit-db on a generated database of 20 materials x 4 models: the thread pool
# and Dask LocalClusters of 1, 2 and max(4, nproc) workers (python/bench/bench_fit_db.py, docs/fit-db.md).
bench-fit-db: build
	@PYTHONPATH=build/$(PRESET)/python MPLBACKEND=Agg /usr/bin/python3 python/bench/bench_fit_db.py $(BENCH_ARGS)

# The C++ sources through .clang-format (clang-format 14, Debian 12's: another version may format
# differently). format-check changes nothing and fails naming each file that differs (.ci/run).
FORMAT_FILES = $$(git ls-files '*.h' '*.cpp' '*.cu')
format: deps
	@clang-format -i $(FORMAT_FILES)

format-check: deps
	@clang-format --dry-run --Werror $(FORMAT_FILES) 2>&1 | grep 'error: code should be clang-formatted' | cut -d: -f1 | sort -u | sed 's/^/not formatted (make format): /'; \
	  clang-format --dry-run --Werror $(FORMAT_FILES) >/dev/null 2>&1

clean:
	@rm -rf build
