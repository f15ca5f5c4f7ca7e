// What every fuzz target shares: the input written to a file of this process's own (the volume
// readers take paths), and the rule that bad input may throw lobe::Error — one clear message —
// while anything else (another exception, a crash, a sanitizer report, a hang) is a finding.
#pragma once

#include "core/error.h"

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

namespace lobe::fuzz {

inline std::string writeInput(const std::string& name, const uint8_t* data, size_t size) {
    const std::string path = "/tmp/lobe-fuzz-" + std::to_string(::getpid()) + "-" + name;
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
