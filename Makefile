# Thin wrapper over CMake. `make demo` and `make test` install what is missing first.
BUILD_DIR ?= build
JOBS ?= $(shell nproc 2>/dev/null || echo 2)
CMAKE_FLAGS ?=

.PHONY: all deps configure build test demo bench format format-check clean

all: build

deps:
	@bash cmake/install-deps.sh

configure:
	@cmake -S . -B $(BUILD_DIR) -DCMAKE_BUILD_TYPE=Release $(CMAKE_FLAGS) >/dev/null

build: configure
	@cmake --build $(BUILD_DIR) -j $(JOBS)

test: deps build
	@cd $(BUILD_DIR) && ctest --output-on-failure -j $(JOBS)

demo: deps build
	@bash cmake/demo.sh $(BUILD_DIR)

bench: deps build
	@$(BUILD_DIR)/tests/bench/bench_spectralizer --benchmark_min_time=0.5
	@bash tests/bench/bench_cli.sh $(BUILD_DIR) 5

SOURCES = $(shell find src tests oiio_plugin -name '*.cpp' -o -name '*.h' 2>/dev/null)

format:
	@clang-format -i $(SOURCES)

format-check:
	@clang-format --dry-run --Werror $(SOURCES)

clean:
	@rm -rf $(BUILD_DIR)
