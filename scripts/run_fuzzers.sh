#!/usr/bin/env bash
# Runs every libFuzzer target of a LOBE_FUZZ build for SECONDS each, starting from the seeds in
# fuzz/corpus/NAME and the corpus grown by earlier runs (BUILD/fuzz-corpus/NAME). An input that
# crashes, trips a sanitizer, throws anything but lobe::Error or runs over 10 s is saved under
# BUILD/fuzz-findings/ and makes the script fail.
# FUZZ_SEED, when set, fixes libFuzzer's random seed (the short run in `make test` does, so that
# the same commit fuzzes the same inputs).
# Usage: scripts/run_fuzzers.sh BUILD_DIR SECONDS [TARGET...]
set -euo pipefail
build=$(cd "$1" && pwd) seconds=$2
here=$(cd "$(dirname "$0")/.." && pwd)
shift 2
targets=("$@")
[[ ${#targets[@]} -eq 0 ]] && targets=(nifti nrrd raw vdb scene brdf_line)
here=$(cd "$(dirname "$0")/.." && pwd)
# allocator_may_return_null: an allocation beyond ASan's limit throws std::bad_alloc, as it does
# without ASan, so the readers' answer to an absurd size field is what is tested; fuzz_vdb
# replaces operator new for that (fuzz/fuzz_vdb.cpp), hence no new/delete pairing check.
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=0:abort_on_error=1:allocator_may_return_null=1:alloc_dealloc_mismatch=0}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1:suppressions=$here/fuzz/ubsan.supp}
mkdir -p "$build/fuzz-findings"
status=0
for t in "${targets[@]}"; do
  corpus="$build/fuzz-corpus/$t"
  mkdir -p "$corpus"
  work=$(mktemp -d)
  echo "fuzz_$t: ${seconds} s"
  # Each run in a folder of its own: the NRRD target's data files are found beside the header.
  # OpenVDB leaks the node it was reading when a read fails inside a tree's topology (RootNode::
  # readTopology: `new ChildT` before the child's read, which throws at the end of the file), so
  # the vdb target's memory grows by ~270 kB per such input over a run: its total limit is
  # higher. (A single allocation the file asks for but never fills, e.g. a 4 GB compressed-block
  # buffer, is virtual memory only; the harness refuses beyond 16 GB, fuzz/fuzz_vdb.cpp.)
  rss=2560
  [[ $t == vdb ]] && rss=12288
  if ! (cd "$work" && "$build/fuzz/fuzz_$t" -max_total_time="$seconds" -timeout=10 ${FUZZ_SEED:+-seed=$FUZZ_SEED} \
          -rss_limit_mb=$rss -max_len=65536 -print_final_stats=1 \
          -artifact_prefix="$build/fuzz-findings/$t-" "$corpus" "$here/fuzz/corpus/$t" \
          >"$build/fuzz-findings/$t.log" 2>&1); then
    echo "fuzz_$t: FOUND an input that fails (see $build/fuzz-findings/$t.log)" >&2
    tail -30 "$build/fuzz-findings/$t.log" >&2
    status=1
  fi
  grep -E "^stat::number_of_executed_runs|^stat::new_units_added" "$build/fuzz-findings/$t.log" |
    tr '\n' ' ' || true
  echo
  rm -rf "$work"
done
exit $status
