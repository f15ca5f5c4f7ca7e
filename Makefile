# The README's two commands: `make demo` and `make test`. Each installs what is missing
# (scripts/setup.sh), configures and builds in build/ (Release), then renders or tests.
BUILD_DIR ?= build
JOBS ?= $(shell nproc)
LOBE := $(BUILD_DIR)/apps/lobe

.PHONY: demo test build setup bench clean

setup:
	@scripts/setup.sh

build: setup
	@cmake -S . -B $(BUILD_DIR) -DCMAKE_BUILD_TYPE=Release >/dev/null
	@cmake --build $(BUILD_DIR) -j $(JOBS)

demo: build
	@mkdir -p out
	$(LOBE) demo --out out

test: build
	cd $(BUILD_DIR) && ctest --output-on-failure -j $(JOBS)

bench: build
	$(BUILD_DIR)/bench/lobe_bench_brdf

clean:
	rm -rf $(BUILD_DIR) out
