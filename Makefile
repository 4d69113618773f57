# microbrdf: the two commands a newcomer needs are `make demo` and `make test`.
# Every target installs the Debian dependencies first (fast when already there).

JOBS ?= $(shell nproc)
FUZZ_SECONDS ?= 60
DEMO_OUT ?= demo-out
BIN := build/bin/microbrdf

.PHONY: deps build build-installed install package test test-slow test-hostile test-package test-docs demo bench asan fuzz fuzz-build format clean

deps:
	@scripts/install-deps.sh

build: deps
	@cmake --preset release >/dev/null
	@cmake --build --preset release -j $(JOBS)

# What others build on (docs/architecture.md, "Using microbrdf from C++"): the CLI, the shared
# library and its headers, the CMake package (find_package(microbrdf CONFIG)), microbrdf.pc and the
# Python module (lib/python3.X/dist-packages) under $(PREFIX); DESTDIR for staging, as usual.
# Builds only what is installed.
PREFIX ?= /usr/local
INSTALLED_TARGETS := microbrdf_cli microbrdf_shared microbrdf_python
build-installed: deps
	@cmake --preset release >/dev/null
	@cmake --build --preset release -j $(JOBS) --target $(INSTALLED_TARGETS)

install: build-installed
	cmake --install build --prefix $(PREFIX)

# A Debian package of the same (build/microbrdf_<version>_<arch>.deb, under /usr; the Python
# module in /usr/lib/python3/dist-packages); Depends from dpkg-shlibdeps.
package: build-installed
	cd build && cpack -G DEB

test: build
	ctest --preset release -j $(JOBS)

# Long-running physics checks (larger surfaces, more seeds).
test-slow: build
	ctest --test-dir build -L slow --output-on-failure -j $(JOBS)

# The hostile suite: several hundred hostile variants, a tally per class (tests/cli_slow).
test-hostile: build
	ctest --test-dir build -L hostile --output-on-failure

# Every command block of README.md and docs/*.md, run as a reader would (tests/docs/).
test-docs: build
	ctest --test-dir build -L docs --output-on-failure -j $(JOBS)

# The Debian package built, installed with dpkg -i, run and removed with dpkg -r (root).
test-package: build-installed
	ctest --test-dir build -L package --output-on-failure

# predict on a real scan and a synthetic brushed surface -> HTML reports, screenshot in Chromium
# (install-deps --report adds chromium; `make test` and CI do not need it).
# Builds only the command-line tool the demo runs (about 4 minutes on 2 cores from scratch);
# the tests, benchmarks and Python module are built by `make test` / `make build`.
demo: deps
	@scripts/install-deps.sh --report
	@cmake --preset release >/dev/null
	@cmake --build --preset release -j $(JOBS) --target microbrdf_cli
	@scripts/demo.sh $(BIN) $(DEMO_OUT)
	@echo "make demo: built only the CLI; 'make test' builds the rest (library tests, benchmarks,"
	@echo "  Python module: about 10 more minutes on 2 cores) and runs the suite."

bench: build
	build/bin/microbrdf_bench --benchmark_counters_tabular=true

asan: deps
	@cmake --preset asan >/dev/null
	@cmake --build --preset asan -j $(JOBS)
	ctest --preset asan -j $(JOBS)

# libFuzzer: every binary reader for FUZZ_SECONDS seconds each (clang, ASan + UBSan).
fuzz-build: deps
	@cmake --preset fuzz >/dev/null
	@cmake --build --preset fuzz -j $(JOBS)

fuzz: fuzz-build
	@cmake -S . -B build-fuzz -DFUZZ_SECONDS=$(FUZZ_SECONDS) >/dev/null
	ctest --test-dir build-fuzz -L fuzz --output-on-failure

format:
	clang-format -i $$(git ls-files '*.cpp' '*.hpp')

clean:
	rm -rf build build-debug build-asan build-fuzz $(DEMO_OUT)
