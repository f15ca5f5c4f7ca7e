#!/usr/bin/env bash
# Runs every libFuzzer target of a LOBE_FUZZ build, in one of two modes:
#   scripts/run_fuzzers.sh BUILD_DIR SECONDS [TARGET...]
#     fuzzing for SECONDS per target from the seeds in fuzz/corpus/NAME and the corpus grown by
#     earlier runs (BUILD/fuzz-corpus/NAME), which this run grows (`make fuzz`). What it reaches
#     depends on the machine's speed and load, so it is not a test.
#   scripts/run_fuzzers.sh BUILD_DIR --runs [TARGET...]
#     the test (`make test`): a fixed number of inputs per target (kRuns below, libFuzzer
#     -runs=N) with a fixed seed (FUZZ_SEED, default 1), from the seeds in fuzz/corpus/NAME only
#     (the regression corpus, replayed first) into a throw-away corpus, without -reload (which
#     re-reads the corpus folder every second, so that what is fuzzed after it depends on timing)
#     and without comparison-guided mutation (-use_cmp=0: libFuzzer files the operands of traced
#     comparisons by their XOR, so stack and heap addresses — the environment's size, ASLR —
#     changed which values it mutated towards; two runs with environments 3 kB apart differed with
#     it and agreed without it), so a commit tests the same
#     inputs on any machine, however fast or busy. It prints each target's count and a digest of
#     the inputs it kept (libFuzzer names them by content), which two runs can compare.
#     The volume readers' coverage also depended on the process's addresses: a few edges in
#     inlined library code (shared_ptr and string clean-up in OpenVDB's and the standard
#     library's headers) were taken or not with the stack's and libraries' placement, so runs
#     kept other inputs under ASLR and with environments of other sizes. So each target runs
#     with address-space randomisation off (setarch -R) and the same process image everywhere:
#     an empty environment but for fixed sanitizer options, and argv, the executable's name and
#     the suppressions file given by fixed relative names inside the target's scratch folder
#     (the checkout's and the build's paths differ in length from machine to machine).
# An input that crashes, trips a sanitizer, throws anything but lobe::Error or runs over the
# per-input limit (-timeout: 10 s when fuzzing; 120 s in --runs mode, where it only guards
# against a hang, since no finding may depend on speed) is saved under BUILD/fuzz-findings/ and
# makes the script fail.
set -euo pipefail
build=$(cd "$1" && pwd)
mode=$2
shift 2
targets=("$@")
[[ ${#targets[@]} -eq 0 ]] && targets=(nifti nrrd raw vdb scene brdf_line)
# Inputs per target in --runs mode: about 10 s each on an idle 2-core machine of this project's
# kind in the sanitised build (fuzz/README.md lists the rates).
declare -A kRuns=([nifti]=30000 [nrrd]=40000 [raw]=30000 [vdb]=6000 [scene]=80000 [brdf_line]=400000)
here=$(cd "$(dirname "$0")/.." && pwd)
# allocator_may_return_null: an allocation beyond ASan's limit throws std::bad_alloc, as it does
# without ASan, so the readers' answer to an absurd size field is what is tested; fuzz_vdb
# replaces operator new for that (fuzz/fuzz_vdb.cpp), hence no new/delete pairing check.
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=0:abort_on_error=1:allocator_may_return_null=1:alloc_dealloc_mismatch=0}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1:suppressions=$here/fuzz/ubsan.supp}
mkdir -p "$build/fuzz-findings"
status=0
for t in "${targets[@]}"; do
  work=$(mktemp -d)
  if [[ $mode == --runs ]]; then
    corpus="$work/corpus"
    limits=(-runs="${kRuns[$t]}" -seed="${FUZZ_SEED:-1}" -reload=0 -use_cmp=0 -timeout=120)
    echo "fuzz_$t: ${kRuns[$t]} inputs, seed ${FUZZ_SEED:-1}"
  else
    corpus="$build/fuzz-corpus/$t"
    limits=(-max_total_time="$mode" -timeout=10 ${FUZZ_SEED:+-seed=$FUZZ_SEED})
    echo "fuzz_$t: ${mode} s"
  fi
  mkdir -p "$corpus" "$work/run" "$work/findings"
  # Each run in a folder of its own: the NRRD target's data files are found beside the header.
  # OpenVDB leaks the node it was reading when a read fails inside a tree's topology (RootNode::
  # readTopology: `new ChildT` before the child's read, which throws at the end of the file), so
  # the vdb target's memory grows by ~270 kB per such input over a run: its total limit is
  # higher. (A single allocation the file asks for but never fills, e.g. a 4 GB compressed-block
  # buffer, is virtual memory only; the harness refuses beyond 16 GB, fuzz/fuzz_vdb.cpp.)
  rss=2560
  [[ $t == vdb ]] && rss=12288
  if [[ $mode == --runs ]]; then
    ln -s "$build/fuzz/fuzz_$t" "$work/fuzz_$t"
    ln -s "$here/fuzz/corpus/$t" "$work/seeds"
    cp "$here/fuzz/ubsan.supp" "$work/ubsan.supp"
    run=(env -i PATH=/usr/bin:/bin
         ASAN_OPTIONS=detect_leaks=0:abort_on_error=1:allocator_may_return_null=1:alloc_dealloc_mismatch=0
         UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1:suppressions=../ubsan.supp)
    if setarch "$(uname -m)" -R true 2>/dev/null; then
      run+=(setarch "$(uname -m)" -R)
    else
      echo "fuzz_$t: note: setarch -R is not permitted here; addresses are randomised, so the" \
           "digest may differ from other machines'" >&2
    fi
    run+=("../fuzz_$t" "${limits[@]}" -rss_limit_mb=$rss -max_len=65536 -print_final_stats=1
          -artifact_prefix=../findings/ ../corpus ../seeds)
  else
    run=("$build/fuzz/fuzz_$t" "${limits[@]}" -rss_limit_mb=$rss -max_len=65536
         -print_final_stats=1 -artifact_prefix="$work/findings/" "$corpus" "$here/fuzz/corpus/$t")
  fi
  status_t=0
  (cd "$work/run" && "${run[@]}" >"$build/fuzz-findings/$t.log" 2>&1) || status_t=1
  for f in "$work/findings"/*; do
    if [[ -e $f ]]; then mv "$f" "$build/fuzz-findings/$t-$(basename "$f")"; fi
  done
  if [[ $status_t != 0 ]]; then
    echo "fuzz_$t: FOUND an input that fails (see $build/fuzz-findings/$t.log)" >&2
    tail -30 "$build/fuzz-findings/$t.log" >&2
    status=1
  fi
  grep -E "^stat::number_of_executed_units|^stat::new_units_added" "$build/fuzz-findings/$t.log" |
    tr '\n' ' ' || true
  if [[ $mode == --runs ]]; then
    echo "corpus digest $(ls "$corpus" | sort | sha256sum | cut -c1-16)"
  else
    echo
  fi
  rm -rf "$work"
done
exit $status
