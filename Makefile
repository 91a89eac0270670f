# Thin wrapper over CMake presets. `make demo` and `make test` work on a fresh Debian machine:
# scripts/setup installs whatever Debian package is missing first.
JOBS ?= $(shell nproc)
BUILD := build
SVETLO := $(BUILD)/svetlo
DEMO_SCENES := $(wildcard scenes/*.json)

WEB_BUILD := build-web-cmake
WEB := $(BUILD)/web

.PHONY: web test-web all build test test-asan test-asan-input asan-configure test-scalar scalar-images scalar-configure test-arm64 demo bench setup clean format fuzz fuzz-scenes figures

all: build

setup:
	@scripts/setup

$(BUILD)/CMakeCache.txt: | setup
	cmake --preset release

build: setup $(BUILD)/CMakeCache.txt
	cmake --build $(BUILD) -j $(JOBS)

# Every test stops after CTEST_TIMEOUT seconds, so that a hang names its test rather than
# running into CI's limit.
CTEST_TIMEOUT ?= 900
test: build
	ctest --test-dir $(BUILD) --output-on-failure -j $(JOBS) --timeout $(CTEST_TIMEOUT)

# The suite built with AddressSanitizer and UndefinedBehaviorSanitizer (the asan preset;
# docs/robustness.md). test-asan runs all of it (by hand: longer than CI's time,
# so each test may take 3000 s);
# test-asan-input, which .ci/run runs, the code that reads what a user gives: the core and
# scene units (images, scene files, meshes) and every file of the fuzz corpus.
ASAN := build-asan
asan-configure: setup
	cmake --preset asan > /dev/null
test-asan: asan-configure
	cmake --build $(ASAN) -j $(JOBS)
	ctest --test-dir $(ASAN) --output-on-failure -j $(JOBS) --timeout 3000
test-asan-input: asan-configure
	cmake --build $(ASAN) -j $(JOBS) --target core_test scene_test fuzz_replay_test
	ctest --test-dir $(ASAN) --output-on-failure -j $(JOBS) --timeout $(CTEST_TIMEOUT) \
	    -L '^(unit|fuzz)$$' --no-tests=error

# The suite built from the scalar twins alone (SVETLO_SIMD=OFF: no SSE or AVX2 anywhere) and
# the parallel loops on std::threads (SVETLO_TBB=OFF): the browser's build, natively. Every
# engine's images are held against the SIMD build's (tests/app/twins_test.sh; docs/kernels.md).
# scalar-images, which .ci/run runs, builds the program and the core's tests (the thread pool,
# the checksums) and runs them, then compares the images; test-scalar does that first.
SCALAR := build-scalar
scalar-configure: build
	cmake -S . -B $(SCALAR) -DCMAKE_BUILD_TYPE=Release -DSVETLO_SIMD=OFF -DSVETLO_TBB=OFF \
	    -DSVETLO_BENCH=OFF -DSVETLO_PYTHON=OFF > /dev/null
scalar-images: scalar-configure
	cmake --build $(SCALAR) -j $(JOBS) --target svetlo core_test
	$(SCALAR)/tests/core_test --gtest_brief=1
	bash tests/app/twins_test.sh $(SVETLO) $(SCALAR)/svetlo scenes
test-scalar: scalar-images
	cmake --build $(SCALAR) -j $(JOBS)
	ctest --test-dir $(SCALAR) --output-on-failure -j $(JOBS) --timeout $(CTEST_TIMEOUT)

# The suite on ARM64: cross-built with Debian's g++-aarch64-linux-gnu and arm64 libraries
# (multiarch; scripts/setup arm64 installs them), run under qemu-user (docs/kernels.md).
ARM64 := build-arm64
test-arm64:
	@scripts/setup arm64
	cmake -S . -B $(ARM64) --toolchain cmake/aarch64-linux-gnu.cmake -DCMAKE_BUILD_TYPE=Release \
	    -DSVETLO_BENCH=OFF -DSVETLO_PYTHON=OFF
	cmake --build $(ARM64) -j $(JOBS)
	ctest --test-dir $(ARM64) --output-on-failure -j $(JOBS) --timeout 6000

# The page (docs/web.md): every engine compiled to WebAssembly by Debian's emscripten
# (scripts/setup web installs it; its tools find Debian's JavaScript packages through
# NODE_PATH), in build/web/ with the page's files (the viewer of svetlo serve, apps/svetlo/viewer/,
# with the backend that hands its requests to the module) and the demo scenes: two modules, one with
# threads for cross-origin isolated pages, one without for the others. test-web, which .ci/run
# runs after make test, builds it and drives the page in headless chromium.
EMENV := NODE_PATH=/usr/share/nodejs
web:
	@scripts/setup web
	$(EMENV) emcmake cmake -S . -B $(WEB_BUILD) -DCMAKE_BUILD_TYPE=Release \
	    -DSVETLO_WEB_OUT=$(CURDIR)/$(WEB) > /dev/null
	$(EMENV) cmake --build $(WEB_BUILD) -j $(JOBS)
	$(EMENV) emcmake cmake -S . -B $(WEB_BUILD)-st -DCMAKE_BUILD_TYPE=Release \
	    -DSVETLO_WEB_THREADS=OFF -DSVETLO_WEB_OUT=$(CURDIR)/$(WEB) > /dev/null
	$(EMENV) cmake --build $(WEB_BUILD)-st -j $(JOBS)
	cp apps/svetlo/viewer/index.html apps/svetlo/viewer/viewer.js web/page/backend.js \
	    web/page/render_worker.js $(WEB)/
	@du -sh $(WEB) | sed 's/^/make web: /'
test-web: build web
	/usr/bin/python3 tests/web/web_test.py $(SVETLO) $(WEB) scenes

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
	$(BUILD)/bench/svetlo_image_bench
	$(BUILD)/bench/svetlo_guiding_bench
	$(BUILD)/bench/svetlo_raster_bench 1
	$(BUILD)/bench/svetlo_raster_bench $(JOBS)
	$(SVETLO) bench scenes/bunny.json --accel none,bvh --rays primary --threads 1 -W 64 -H 40
	$(SVETLO) bench scenes/bunny.json --rays primary --threads 1
	$(SVETLO) bench scenes/bunny.json --rays primary --threads $(JOBS)
	$(SVETLO) bench scenes/bunny.json --rays diffuse --threads 1
	$(SVETLO) bench scenes/bunny.json --rays diffuse --threads $(JOBS)
	$(SVETLO) render scenes/cornell.json --engine path --set render.max_depth=64 \
	    --set render.light_samples=1 -W 512 -H 512 --spp 16 --threads 1 -o $(BUILD)/bench_path.pfm
	$(SVETLO) render scenes/cornell.json --engine path --set render.max_depth=64 \
	    --set render.light_samples=1 -W 512 -H 512 --spp 16 --threads $(JOBS) -o $(BUILD)/bench_path.pfm
	$(SVETLO) render scenes/door_ajar.json -W 160 -H 120 --spp 128 --threads $(JOBS) \
	    -o $(BUILD)/bench_door.pfm
	$(SVETLO) render scenes/door_ajar.json --set render.guiding=true -W 160 -H 120 --spp 128 \
	    --threads $(JOBS) -o $(BUILD)/bench_door_guided.pfm
	/usr/bin/python3 bench/radiosity/scaling.py $(SVETLO) $(JOBS)
	/usr/bin/python3 bench/radiosity/equal_error.py $(SVETLO) 512 2048 $(JOBS)
	PYTHONPATH=$(BUILD)/python /usr/bin/python3 bench/python_overhead.py
	/usr/bin/python3 bench/serve_latency.py $(SVETLO) scenes
	@echo "The path tracer against Cycles needs Blender: bench/cycles/convergence.py (docs/performance.md)."

# Every picture of docs/ again, from fixed seeds (scripts/figures.sh; docs/techniques.md).
figures: build
	scripts/figures.sh $(SVETLO)

format:
	clang-format -i $$(git ls-files '*.cpp' '*.h' '*.inc')

# Fuzz each loader for FUZZ_SECONDS (clang's libFuzzer, with ASan and UBSan). New inputs go to
# build-fuzz/found/TARGET; copy the ones that broke svetlo into tests/fuzz/corpus/TARGET with
# the fix, and the test suite replays them.
FUZZ_SECONDS ?= 60
FUZZ_TARGETS := scene obj ply gltf image environment
fuzz:
	@scripts/setup fuzz
	cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
	    -DSVETLO_FUZZ=ON -DSVETLO_TESTS=OFF -DSVETLO_BENCH=OFF
	cmake --build build-fuzz -j $(JOBS) --target $(addprefix fuzz_,$(FUZZ_TARGETS))
	@for t in $(FUZZ_TARGETS); do \
	    mkdir -p build-fuzz/found/$$t; \
	    echo "fuzz $$t for $(FUZZ_SECONDS) s"; \
	    build-fuzz/tests/fuzz/fuzz_$$t build-fuzz/found/$$t tests/fuzz/corpus/$$t \
	        -max_total_time=$(FUZZ_SECONDS) -max_len=65536 -timeout=10 -rss_limit_mb=4096 \
	        -artifact_prefix=build-fuzz/found/$$t- || exit 1; \
	done

# Mutate the bundled scenes and render them with every engine under ASan and UBSan, checking
# the contract's two outcomes (tests/fuzz/mutate_scenes.py; docs/robustness.md). What breaks
# it is kept in build-asan/mutants.
FUZZ_RUNS ?= 1000
FUZZ_SEED ?= 1
fuzz-scenes:
	@scripts/setup
	cmake --preset asan > /dev/null
	cmake --build build-asan -j $(JOBS) --target svetlo
	python3 tests/fuzz/mutate_scenes.py build-asan/svetlo --runs $(FUZZ_RUNS) --seed $(FUZZ_SEED)

clean:
	rm -rf $(BUILD) $(WEB_BUILD) $(WEB_BUILD)-st out
