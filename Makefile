# The README's two commands: `make demo` and `make test`. Each installs what is missing
# (scripts/setup.sh), configures and builds in build/ (Release), then renders or tests.
BUILD_DIR ?= build
JOBS ?= $(shell nproc)
LOBE := $(BUILD_DIR)/apps/lobe

.PHONY: demo test build setup bench clean fuzz sanitize san-build

setup:
	@scripts/setup.sh

build: setup
	@cmake -S . -B $(BUILD_DIR) -DCMAKE_BUILD_TYPE=Release >/dev/null
	@cmake --build $(BUILD_DIR) -j $(JOBS)

demo: build
	@mkdir -p out
	$(LOBE) demo --out out

# The format check (scripts/check_format.sh: every C++ file as .clang-format says), the whole suite, then the unit tests under AddressSanitizer + UndefinedBehaviorSanitizer and a
# fixed number of inputs through every fuzz target (the same inputs on any machine), both from one
# clang build (build-san).
test: build
	@scripts/check_format.sh
	cd $(BUILD_DIR) && ctest --output-on-failure -j $(JOBS)
	@$(MAKE) --no-print-directory sanitize

# One ASan + UBSan clang build (build-san) serves both the sanitised unit tests and the libFuzzer
# targets in fuzz/ (the library is compiled once, with -fsanitize=fuzzer-no-link). About 8 min to
# build on 2 cores, 30 s of tests. fuzz/ubsan.supp silences a false positive inside oneTBB
# (reached from OpenVDB).
SAN_DIR ?= build-san
FUZZ_SECONDS ?= 60
FUZZ_TARGETS := fuzz_nifti fuzz_nrrd fuzz_raw fuzz_vdb fuzz_scene fuzz_brdf_line
FUZZ_QUICK_TARGETS := nifti nrrd raw vdb scene brdf_line
SAN_TESTS := core_tests dvr_tests materials_tests overlap_tests render_tests shading_tests \
  surface_unit_tests volume_limits_tests volume_tests image_io_tests framing_tests dicom_tests \
  study_tests
san-build: setup
	@CC=clang CXX=clang++ cmake -S . -B $(SAN_DIR) -DCMAKE_BUILD_TYPE=RelWithDebInfo \
	  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -gline-tables-only -DNDEBUG" \
	  -DLOBE_SANITIZE=ON -DLOBE_FUZZ=ON -DLOBE_BUILD_BENCHMARKS=OFF -DLOBE_BUILD_TESTS=ON >/dev/null
	@cmake --build $(SAN_DIR) -j $(JOBS) --target $(SAN_TESTS) $(FUZZ_TARGETS)

# The unit tests sanitised, then a fixed count of inputs (scripts/run_fuzzers.sh --runs, fixed
# seed, the regression corpus in fuzz/corpus/ replayed first) through each of FUZZ_QUICK_TARGETS.
sanitize: san-build
	cd $(SAN_DIR) && ASAN_OPTIONS=detect_leaks=0 \
	  UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1:suppressions=$(CURDIR)/fuzz/ubsan.supp \
	  ctest -L unit -E NOT_BUILT -j $(JOBS) --output-on-failure
	FUZZ_SEED=1 scripts/run_fuzzers.sh $(SAN_DIR) --runs $(FUZZ_QUICK_TARGETS)

# Fuzzing by time, to find new inputs (not a test: what it reaches depends on the machine): every
# target for FUZZ_SECONDS (default 60; e.g. make fuzz FUZZ_SECONDS=3600) from the seeds in
# fuzz/corpus/ and what earlier runs found.
fuzz: san-build
	scripts/run_fuzzers.sh $(SAN_DIR) $(FUZZ_SECONDS)

bench: build
	$(BUILD_DIR)/bench/lobe_bench_brdf

clean:
	rm -rf $(BUILD_DIR) $(SAN_DIR) out
