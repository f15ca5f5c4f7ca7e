// Volumes the render tests write for themselves. ctest runs each test as its own process, in
// parallel, and tests of one file share their data files: each process writes under its own name
// and renames, so no test reads a file while another is rewriting it.
#pragma once

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace lobe::test {

inline void writeFloatsAtomically(const std::filesystem::path& path, const std::vector<float>& v) {
    const std::filesystem::path own = path.string() + "." + std::to_string(::getpid());
    std::ofstream(own, std::ios::binary)
        .write(reinterpret_cast<const char*>(v.data()), std::streamsize(v.size() * sizeof(float)));
    std::filesystem::rename(own, path);
}

}  // namespace lobe::test
