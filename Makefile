# Thin wrapper over CMake. `make demo` and `make test` install what is missing first.
BUILD_DIR ?= build
JOBS ?= $(shell nproc 2>/dev/null || echo 2)
CMAKE_FLAGS ?=
# The interpreter Debian's numpy, pybind11 and OpenImageIO bindings belong to.
PYTHON ?= $(shell test -x /usr/bin/python3 && echo /usr/bin/python3 || echo python3)

.PHONY: all deps deps-demo deps-install configure build test test-long demo bench bench-files bench-mitsuba docs-mitsuba install docs format format-check clean test-asan \
	test-tsan fuzz figures validate docs-figures renders docs-renders test-platform
FUZZ_SECONDS ?= 60

all: build

# What each purpose needs (cmake/install-deps.sh): the demo's packages, the install's (the
# demo's and Sphinx), everything for the tests.
deps:
	@bash cmake/install-deps.sh test
deps-demo:
	@bash cmake/install-deps.sh demo
deps-install:
	@bash cmake/install-deps.sh install

configure:
	@cmake -S . -B $(BUILD_DIR) -DCMAKE_BUILD_TYPE=Release $(CMAKE_FLAGS) >/dev/null

build: configure
	@cmake --build $(BUILD_DIR) -j $(JOBS)

# Every test but those labelled "long" (suites named *Slow: a 4K map in bounded memory, the
# schema sweep through two processes per value, signals during long writes); `make test-long`
# runs those (CI runs make test and test-asan).
test: deps build
	@cd $(BUILD_DIR) && ctest --output-on-failure -j $(JOBS) -LE long; status=$$?; \
	  grep -h -o -E "(RAN|SKIPPED): the Slurm farm test.*" Testing/Temporary/LastTest.log || true; \
	  exit $$status

test-long: deps build
	@cd $(BUILD_DIR) && ctest --output-on-failure -j $(JOBS) -L long

# The suite under AddressSanitizer + UndefinedBehaviorSanitizer (build-asan/). -O1 -g1 (line
# tables only): builds in 4.6 instead of 7 min on 2 cores. Left out, besides the long ones: the
# sweeps that run one code path over many values (every setting, every compression, 10,000
# random colours, the wide-gamut tables' whole volume), and the end-to-end suites of good inputs
# on the ordinary paths (tests/CMakeLists.txt): each path is run under the sanitizers by the
# suites of bad, broken and unusual inputs, and the release build runs everything.
ASAN_SWEEPS = Spectralizer.TenThousandRandomColoursPerSpaceAndModeAt10nm|Guarantees.UpToDateMeansTheSameFileWouldBeWritten|CliImage.EveryCompressionWritesTheSameSamples|SettingsSchema.EverySettingThatShapesSpectraIsInTheCacheKeyReportAndAttributes|RtTable.EveryFeasibleColourIsExactAndBounded/(rec2020|acescg)_|RtHostile.EveryEightBitColourHasBoundedWeightsAndSamplesOnEveryModel|clang_format
test-asan: deps
	@cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1" -DSPECTRALIZE_SANITIZE=address,undefined -DSPECTRALIZE_BUILD_BENCH=OFF >/dev/null
	@cmake --build build-asan -j $(JOBS)
	@cd build-asan && ASAN_OPTIONS=detect_leaks=1 LSAN_OPTIONS=suppressions=$(CURDIR)/tests/lsan.supp UBSAN_OPTIONS=print_stacktrace=1 ctest --output-on-failure -j $(JOBS) -E "$(ASAN_SWEEPS)" -LE long

# The whole `make test` on the current VFX stack (Debian sid: OpenImageIO 3.x, OpenColorIO 2.5,
# OpenEXR 3.4, GCC 16), in a minimal sid root made with debootstrap from the Debian mirror this
# machine's apt uses and cached in $(PLATFORM_ROOT) (cmake/test-platform.sh; needs root).
# PLATFORM_TARGETS=demo runs the demo there instead.
PLATFORM_ROOT ?= $(or $(SPECTRALIZE_PLATFORM_ROOT),/var/cache/spectralize/sid)
PLATFORM_TARGETS ?= test
test-platform:
	@SPECTRALIZE_PLATFORM_ROOT=$(PLATFORM_ROOT) bash cmake/test-platform.sh $(PLATFORM_TARGETS)

# The threaded paths (image job, shared node cache, plugin) under ThreadSanitizer (build-tsan/).
test-tsan: deps
	@cmake -S . -B build-tsan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSPECTRALIZE_SANITIZE=thread -DSPECTRALIZE_BUILD_BENCH=OFF >/dev/null
	@cmake --build build-tsan -j $(JOBS)
	@cd build-tsan && TSAN_OPTIONS="halt_on_error=1 suppressions=$(CURDIR)/tests/tsan.supp" ctest --output-on-failure -j $(JOBS) -R "Thread|Cache|CliImage"

# libFuzzer (clang) on the recipe, channel-name, --color and --wavelengths parsers and the
# .spztab table loader, each for FUZZ_SECONDS, from the seed corpus in tests/fuzz/corpus/ (new
# inputs go to build-fuzz/corpus/; the table fuzzer writes its seed tables there).
fuzz: deps
	@CXX=clang++ cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSPECTRALIZE_FUZZ=ON >/dev/null
	@cmake --build build-fuzz -j $(JOBS)
	@for t in recipe channel_name color wavelengths table; do \
	  mkdir -p build-fuzz/corpus/$$t; \
	  echo "== fuzz_$$t ($(FUZZ_SECONDS) s)"; \
	  build-fuzz/tests/fuzz/fuzz_$$t -max_total_time=$(FUZZ_SECONDS) -print_final_stats=1 \
	    build-fuzz/corpus/$$t tests/fuzz/corpus/$$t 2>&1 | grep -E "^(stat::number_of_executed_units|stat::new_units_added|==[0-9]+==ERROR|SUMMARY|Done)" ; \
	done

# Installs into PREFIX (default /usr/local): the tool, the OIIO plugin, the OCIO config and
# data, headers and CMake package of the core library, the Python module.
PREFIX ?= /usr/local
# Builds what it installs and the guide, never the tests.
install: deps-install configure
	@cmake --build $(BUILD_DIR) -j $(JOBS) --target installable
	@cmake --build $(BUILD_DIR) --target docs
	@cmake --install $(BUILD_DIR) --prefix $(PREFIX)

# The user guide (Sphinx, warnings as errors) into $(BUILD_DIR)/docs/html; the man page is
# made by every build ($(BUILD_DIR)/docs/spectralize.1).
docs: deps-install configure
	@cmake --build $(BUILD_DIR) -j $(JOBS) --target docs

# Installs and builds only what the demo runs (the tool, the plugin, the module; Mitsuba 3 in
# the virtual environment), then runs it (cmake/demo.sh).
demo: deps-demo configure
	@cmake --build $(BUILD_DIR) -j $(JOBS) --target demo_targets
	@bash cmake/demo.sh $(BUILD_DIR)

# The paper's figures (fig1..fig6 PNGs, sphere dE2000 maps) into $(BUILD_DIR)/figures/.
figures: deps build
	@$(BUILD_DIR)/spectralize_figures figures $(BUILD_DIR)/figures

# The ColorChecker / illuminant validation into $(BUILD_DIR)/validation/ (JSON and Markdown).
validate: deps build
	@$(BUILD_DIR)/spectralize_figures validate $(BUILD_DIR)/validation

# Refreshes the guide's copies in docs/figures/ (plots as made, spheres and maps at 256 px).
docs-figures: figures
	@mkdir -p docs/figures
	@cp $(BUILD_DIR)/figures/fig1_light_spectrum.png $(BUILD_DIR)/figures/fig3_surface_spectrum.png docs/figures/
	@for f in $(BUILD_DIR)/figures/fig[2456]_*.png; do \
	  oiiotool --nosoftwareattrib $$f --resize 256x0 -o docs/figures/$$(basename $$f); done

# The spectral path tracer's measurements (JSON) and figures into $(BUILD_DIR)/renders/:
# spectralize::rt against the dense reference and, under illuminant A, against the measured
# ColorChecker and the Jakob & Hanika baseline (docs/RENDERERS.md). About a minute on 2 cores.
renders: deps build
	@bash cmake/renders.sh $(BUILD_DIR) $(BUILD_DIR)/renders

# Refreshes the documents' copies in docs/figures/ (render_*.png) and the numbers in
# docs/RENDERERS.md from make renders.
docs-renders: renders
	@mkdir -p docs/figures
	@cp $(BUILD_DIR)/renders/render_*.png docs/figures/
	@$(PYTHON) cmake/render_tables.py $(BUILD_DIR)/renders docs/RENDERERS.md

bench: deps build
	@cmake --build $(BUILD_DIR) --target benchmarks -j $(JOBS)
	@$(BUILD_DIR)/tests/bench/bench_spectralizer --benchmark_min_time=0.5
	@$(BUILD_DIR)/tests/bench/model_study 10000
	@$(BUILD_DIR)/tests/bench/sigmoid_study 64 20000 2
	@bash tests/bench/bench_cli.sh $(BUILD_DIR) 5
	@bash tests/bench/bench_ingest.sh $(BUILD_DIR) 200
	@bash tests/bench/bench_tiny_files.sh $(BUILD_DIR) 5 $(BENCH_BASELINE)
	@bash tests/bench/bench_usd_stage.sh $(BUILD_DIR) 5 $(BENCH_BASELINE)
	@$(PYTHON) tests/bench/bench_python.py $(BUILD_DIR) 5
	@bash tests/bench/bench_bigmap.sh $(BUILD_DIR)
	@$(MAKE) --no-print-directory bench-mitsuba

# Mitsuba 3: one scene rendered with its bitmap and with spectralize_rgb, same spp, same run
# (tests/bench/bench_mitsuba.py, in the virtual environment of cmake/install-deps.sh).
VENV ?= $(or $(SPECTRALIZE_VENV),$(HOME)/.cache/spectralize/venv)
# The guide's Mitsuba picture (docs/figures/mitsuba_example.png) from docs/examples/mitsuba_scene.py.
docs-mitsuba: deps build
	@PYTHONPATH=$(BUILD_DIR)/python DRJIT_LIBLLVM_PATH=$$(ls /usr/lib/*/libLLVM.so.19* | head -1) \
	  SPECTRALIZE_CACHE=$(BUILD_DIR)/mitsuba_cache SPECTRALIZE_EXE=$(BUILD_DIR)/spectralize \
	  $(VENV)/bin/python docs/examples/mitsuba_scene.py $(BUILD_DIR)/mitsuba_example.png 256
	@cp $(BUILD_DIR)/mitsuba_example.png docs/figures/

bench-mitsuba: deps build
	@PYTHONPATH=$(BUILD_DIR)/python DRJIT_LIBLLVM_PATH=$$(ls /usr/lib/*/libLLVM.so.19* | head -1) \
	  SPECTRALIZE_CACHE=$(BUILD_DIR)/mitsuba_cache \
	  $(VENV)/bin/python tests/bench/bench_mitsuba.py 5 $(CURDIR)/testimages/colorchecker_srgb8.png

# The cost of a file beyond its pixels: ingest of 300 and 3,000 tiny PNGs, CPU and wall per file
# (tests/bench/bench_tiny_files.sh); BENCH_BASELINE=path/to/an/older/spectralize runs it beside.
# On Debian sid's stack: make test-platform PLATFORM_TARGETS=bench-files.
bench-files: deps build
	@bash tests/bench/bench_tiny_files.sh $(BUILD_DIR) 5 $(BENCH_BASELINE)

SOURCES = $(shell find src include tests oiio_plugin python -name '*.cpp' -o -name '*.h' -o -name '*.hpp' -o -name '*.c' 2>/dev/null) \
	$(shell find docs/snippets -name '*.cpp' -o -name '*.c' 2>/dev/null)

format:
	@clang-format -i $(SOURCES)

format-check:
	@cmake -DSOURCE_DIR=$(CURDIR) -DCLANG_FORMAT=clang-format -P cmake/FormatCheck.cmake

clean:
	@rm -rf $(BUILD_DIR)
