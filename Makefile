# The README's two commands: `make demo` and `make test`. Each installs what is missing
# (scripts/setup.sh), configures and builds in build/ (Release), then renders or tests.
BUILD_DIR ?= build
JOBS ?= $(shell nproc)
LOBE := $(BUILD_DIR)/apps/lobe

.PHONY: demo test build setup bench clean fuzz sanitize

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

# Fuzzing (clang, libFuzzer) in an ASan + UBSan build of its own (build-fuzz): every target in
# fuzz/ for FUZZ_SECONDS (default 60) from the seeds in fuzz/corpus/ and what earlier runs found.
FUZZ_DIR ?= build-fuzz
FUZZ_SECONDS ?= 60
FUZZ_TARGETS := fuzz_nifti fuzz_nrrd fuzz_raw fuzz_vdb fuzz_scene fuzz_brdf_line
fuzz: setup
	@CC=clang CXX=clang++ cmake -S . -B $(FUZZ_DIR) -DCMAKE_BUILD_TYPE=RelWithDebInfo \
	  -DLOBE_SANITIZE=ON -DLOBE_FUZZ=ON -DLOBE_BUILD_BENCHMARKS=OFF -DLOBE_BUILD_TESTS=OFF >/dev/null
	@cmake --build $(FUZZ_DIR) -j $(JOBS) --target $(FUZZ_TARGETS)
	scripts/run_fuzzers.sh $(FUZZ_DIR) $(FUZZ_SECONDS)

# The unit tests under ASan + UBSan (clang) in build-san: about 6 min to build on 2 cores, 30 s
# to run. fuzz/ubsan.supp silences a false positive inside oneTBB (reached from OpenVDB).
SAN_DIR ?= build-san
SAN_TESTS := core_tests dvr_tests materials_tests overlap_tests render_tests shading_tests \
  surface_unit_tests volume_limits_tests volume_tests
sanitize: setup
	@CC=clang CXX=clang++ cmake -S . -B $(SAN_DIR) -DCMAKE_BUILD_TYPE=RelWithDebInfo \
	  -DLOBE_SANITIZE=ON -DLOBE_BUILD_BENCHMARKS=OFF -DLOBE_BUILD_TESTS=ON >/dev/null
	@cmake --build $(SAN_DIR) -j $(JOBS) --target $(SAN_TESTS)
	cd $(SAN_DIR) && ASAN_OPTIONS=detect_leaks=0 \
	  UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1:suppressions=$(CURDIR)/fuzz/ubsan.supp \
	  ctest -L unit -E NOT_BUILT -j $(JOBS) --output-on-failure

bench: build
	$(BUILD_DIR)/bench/lobe_bench_brdf

clean:
	rm -rf $(BUILD_DIR) $(FUZZ_DIR) $(SAN_DIR) out
