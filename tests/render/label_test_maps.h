// Synthetic label maps for the label tests, written at test time as NIfTI-1 files (int16, unit
// voxels, identity sform): a box of label a = 1 (x < 12) and b = 3 (x ≥ 12) touching along the
// plane x = 11.5, a ball of label k = 2 (radius 5, centre (12, 12, 12)) between them, and a cube
// of label 4 (6³ voxels) apart. 1 < 2 < 3: the a|b plane is where an iso value between 1 and 3
// on the labels themselves would draw a false shell of label 2.
#pragma once

#include <unistd.h>

#include <array>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace lobe::test {

constexpr int kMapN = 32;

inline int syntheticLabel(int i, int j, int k) {
    if (i >= 22 && i < 28 && j >= 22 && j < 28 && k >= 22 && k < 28) return 4;
    if (i < 2 || j < 2 || k < 2 || i > 21 || j > 21 || k > 21) return 0;
    const double dx = i - 12.0, dy = j - 12.0, dz = k - 12.0;
    if (dx * dx + dy * dy + dz * dz <= 25.0) return 2;
    return i < 12 ? 1 : 3;
}

// A NIfTI-1 single file (nifti1.h): int16 voxels, pixdim 1, sform = identity (code 1).
inline void writeNiftiInt16(const std::string& path, const std::array<int, 3>& n,
                            const std::vector<std::int16_t>& data) {
    unsigned char h[352] = {};
    auto put32 = [&](int at, std::int32_t v) { std::memcpy(h + at, &v, 4); };
    auto put16 = [&](int at, std::int16_t v) { std::memcpy(h + at, &v, 2); };
    auto putf = [&](int at, float v) { std::memcpy(h + at, &v, 4); };
    put32(0, 348);
    put16(40, 3);
    for (int a = 0; a < 3; ++a) put16(42 + 2 * a, std::int16_t(n[size_t(a)]));
    put16(70, 4);   // NIFTI_TYPE_INT16
    put16(72, 16);  // bitpix
    for (int a = 0; a < 4; ++a) putf(76 + 4 * a, 1.0f);
    putf(108, 352.0f);
    put16(254, 1);  // sform_code
    putf(280, 1.0f);
    putf(300, 1.0f);
    putf(320, 1.0f);
    std::memcpy(h + 344, "n+1\0", 4);
    std::ofstream out(path, std::ios::binary);
    out.write(reinterpret_cast<const char*>(h), 352);
    out.write(reinterpret_cast<const char*>(data.data()), std::streamsize(data.size() * 2));
}

inline std::string writeSyntheticMap(const std::string& name, bool fractional = false) {
    const std::string dir = (std::filesystem::temp_directory_path() / "lobe-label-tests").string();
    std::filesystem::create_directories(dir);
    const std::string path = dir + "/" + name;
    std::vector<std::int16_t> data(size_t(kMapN) * kMapN * kMapN);
    for (int k = 0; k < kMapN; ++k)
        for (int j = 0; j < kMapN; ++j)
            for (int i = 0; i < kMapN; ++i)
                data[(size_t(k) * kMapN + j) * kMapN + i] = std::int16_t(syntheticLabel(i, j, k));
    // Written under a name of this process's own and renamed: the tests of one binary run as
    // parallel processes under ctest and would otherwise read a map another is rewriting.
    const std::string own = path + "." + std::to_string(::getpid());
    writeNiftiInt16(own, {kMapN, kMapN, kMapN}, data);
    if (fractional) {
        // The same map with a slope of 0.5: labels 0.5, 1, 1.5, 2 — not a label map.
        std::fstream f(own, std::ios::in | std::ios::out | std::ios::binary);
        const float slope = 0.5f;
        f.seekp(112);
        f.write(reinterpret_cast<const char*>(&slope), 4);
    }
    std::filesystem::rename(own, path);
    return path;
}

}  // namespace lobe::test
