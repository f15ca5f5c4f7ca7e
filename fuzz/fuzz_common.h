// What every fuzz target shares: the input written to a file of this process's own (the volume
// readers take paths), and the rule that bad input may throw lobe::Error — one clear message —
// while anything else (another exception, a crash, a sanitizer report, a hang) is a finding.
// What a target runs must depend on the input alone, so that a fixed count of inputs with a fixed
// seed (scripts/run_fuzzers.sh --runs, `make test`) explores the same inputs on every machine:
// the input's file has the same name in every run, in the working folder (the script makes one
// for each target; a name with the PID in it made messages — and the code paths that build them —
// differ in length from run to run, and put NRRD's "data.raw" where its header did not look),
// oneTBB runs on one thread (how work is split between threads changed the coverage counts
// libFuzzer steers by), and the memory budget is fixed (core/memory.h: checkFits refuses what
// exceeds half of it; measured, it is the machine's RAM, rlimits and cgroup limit, and the
// parsing of /proc/self/cgroup that finds the limit follows the cgroup's path, which differs
// from job to job: the first edges two runs of the same seeds differed in, found by diffing
// libFuzzer's -print_full_coverage). The rest was addresses: scripts/run_fuzzers.sh.
#pragma once

#include "core/error.h"
#include "core/memory.h"

#include <tbb/global_control.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

namespace lobe::fuzz {

inline const tbb::global_control kOneThread(tbb::global_control::max_allowed_parallelism, 1);

// 4 GB: checkFits refuses buffers over 2 GB, below the scripts' -rss_limit_mb (2560; vdb 12288).
inline const bool kFixedMemoryBudget = [] {
    setMemoryBudget({4e9, "the fuzz harness's fixed budget"});
    return true;
}();

inline std::string writeInput(const std::string& name, const uint8_t* data, size_t size) {
    const std::string& path = name;  // in the working folder (beside each other: NRRD's data file)
    if (FILE* f = std::fopen(path.c_str(), "wb")) {
        if (size) std::fwrite(data, 1, size, f);
        std::fclose(f);
    }
    return path;
}

// Runs fn; lobe::Error is the expected answer to bad input, anything else aborts (a finding).
template <class Fn>
void expectOnlyInputErrors(Fn&& fn) {
    try {
        fn();
    } catch (const Error&) {
    } catch (const std::exception& e) {
        std::fprintf(stderr, "internal error (not lobe::Error): %s\n", e.what());
        std::abort();
    }
}

}  // namespace lobe::fuzz
