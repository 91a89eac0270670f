# Thin wrapper over CMake presets. `make demo` and `make test` work on a fresh Debian machine:
# scripts/setup installs whatever Debian package is missing first.
JOBS ?= $(shell nproc)
BUILD := build
SVETLO := $(BUILD)/svetlo
DEMO_SCENES := $(wildcard scenes/*.json)

.PHONY: all build test demo bench setup clean format

all: build

setup:
	@scripts/setup

$(BUILD)/CMakeCache.txt: | setup
	cmake --preset release

build: setup $(BUILD)/CMakeCache.txt
	cmake --build $(BUILD) -j $(JOBS)

test: build
	ctest --test-dir $(BUILD) --output-on-failure -j $(JOBS)

demo: build
	@mkdir -p out
	@for s in $(DEMO_SCENES); do \
	    name=$$(basename $$s .json); \
	    if grep -q 'shared/data' $$s && [ ! -d ../shared/data ]; then \
	        echo "skipping $$s: it reads the models in ../shared/data, absent here"; continue; \
	    fi; \
	    echo "svetlo render $$s -o out/$$name.png"; \
	    $(SVETLO) render $$s -o out/$$name.png || exit 1; \
	done

bench: build
	$(BUILD)/bench/svetlo_bench
	$(BUILD)/bench/svetlo_raster_bench 1
	$(BUILD)/bench/svetlo_raster_bench $(JOBS)
	$(SVETLO) bench scenes/bunny.json --accel none,bvh --rays primary --threads 1 -W 64 -H 40
	$(SVETLO) bench scenes/bunny.json --rays primary --threads 1
	$(SVETLO) bench scenes/bunny.json --rays primary --threads $(JOBS)
	$(SVETLO) bench scenes/bunny.json --rays diffuse --threads 1
	$(SVETLO) bench scenes/bunny.json --rays diffuse --threads $(JOBS)

format:
	clang-format -i $$(git ls-files '*.cpp' '*.h')

clean:
	rm -rf $(BUILD) out
