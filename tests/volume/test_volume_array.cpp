// loadArray (volume/volume_array.h): an array in memory gives the Volume a file of the same voxels
// gives — values, scaling, background, transform — whatever its memory order; bad arrays are one
// lobe::Error naming the array.
#include "core/error.h"
#include "volume/volume.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

namespace lobe {
namespace {

namespace fs = std::filesystem;

constexpr int X = 3, Y = 4, Z = 5;

// The test voxel (i, j, k): distinct values, some 0 and some below the background.
std::int16_t voxel(int i, int j, int k) { return std::int16_t((i * 7 + j * 3 + k * 11) % 17 - 2); }

std::string rawFile() {
    const fs::path dir = fs::path(LOBE_BINARY_DIR) / "test-output" / "volume" / "array";
    fs::create_directories(dir);
    const fs::path p = dir / "voxels.raw";
    std::ofstream out(p, std::ios::binary | std::ios::trunc);
    for (int k = 0; k < Z; ++k)
        for (int j = 0; j < Y; ++j)
            for (int i = 0; i < X; ++i) {
                const std::int16_t v = voxel(i, j, k);  // x fastest, little-endian (this machine)
                out.write(reinterpret_cast<const char*>(&v), sizeof v);
            }
    return p.string();
}

void expectSameVolume(const Volume& a, const Volume& b) {
    EXPECT_EQ(a.dims, b.dims);
    EXPECT_EQ(a.valueScale, b.valueScale);
    EXPECT_EQ(a.originalMin, b.originalMin);
    EXPECT_EQ(a.originalMax, b.originalMax);
    for (int k = -1; k <= Z; ++k)
        for (int j = -1; j <= Y; ++j)
            for (int i = -1; i <= X; ++i) {
                const openvdb::Coord c(i, j, k);
                EXPECT_EQ(a.grid->tree().getValue(c), b.grid->tree().getValue(c)) << i << j << k;
                EXPECT_EQ(a.grid->tree().isValueOn(c), b.grid->tree().isValueOn(c)) << i << j << k;
            }
    EXPECT_EQ(a.grid->transform(), b.grid->transform());
}

TEST(VolumeArray, EqualsTheRawFileInAnyMemoryOrder) {
    RawLayout layout;
    layout.dims = {X, Y, Z};
    layout.type = VoxelType::kInt16;
    layout.spacing = {0.5, 2.0, 3.0};
    LoadOptions options;
    options.normalize = 4.0;
    options.background = 1.0;
    const Volume file = loadRaw(rawFile(), layout, options);

    // C order (k fastest), as a NumPy array indexed [i, j, k] is by default.
    std::vector<std::int16_t> c(size_t(X) * Y * Z);
    for (int i = 0; i < X; ++i)
        for (int j = 0; j < Y; ++j)
            for (int k = 0; k < Z; ++k) c[size_t((i * Y + j) * Z + k)] = voxel(i, j, k);
    VolumeArray a;
    a.name = "array 1 (test)";
    a.data = c.data();
    a.type = VoxelType::kInt16;
    a.dims = {X, Y, Z};
    a.strides = {Y * Z * 2, Z * 2, 2};
    a.affine = {{{0.5, 0, 0, 0}, {0, 2.0, 0, 0}, {0, 0, 3.0, 0}}};
    const Volume fromC = loadArray(a, options);
    EXPECT_EQ(fromC.sourcePath, "array 1 (test)");
    expectSameVolume(fromC, file);

    // A view with j reversed (a negative stride) of float64 values scaled as a NIfTI file's
    // scl_slope and scl_inter: raw · 2 + 1 is the file's voxel again.
    std::vector<double> d(size_t(X) * Y * Z);
    for (int i = 0; i < X; ++i)
        for (int j = 0; j < Y; ++j)
            for (int k = 0; k < Z; ++k)
                d[size_t((i * Y + (Y - 1 - j)) * Z + k)] = (voxel(i, j, k) - 1.0) / 2.0;
    VolumeArray r = a;
    r.type = VoxelType::kFloat64;
    r.data = d.data() + (Y - 1) * Z;  // element (0, 0, 0) of the view
    r.strides = {Y * Z * 8, -Z * 8, 8};
    r.slope = 2.0;
    r.inter = 1.0;
    expectSameVolume(loadArray(r, options), file);
}

TEST(VolumeArray, BadArraysAreErrorsNamingTheArray) {
    std::vector<float> v(8, 1.0f);
    VolumeArray a;
    a.name = "array 7 (objects[0].source)";
    a.data = v.data();
    a.dims = {2, 2, 2};
    a.strides = {4, 8, 16};
    v[5] = std::numeric_limits<float>::quiet_NaN();  // (1, 0, 1)
    try {
        loadArray(a);
        FAIL() << "NaN accepted";
    } catch (const Error& e) {
        EXPECT_EQ(
            std::string(e.what()),
            "array 7 (objects[0].source): voxel (1, 0, 1) is NaN; volumes must hold finite values");
    }
    v[5] = 1.0f;
    a.dims = {2, 0, 2};
    EXPECT_THROW(loadArray(a), Error);
    a.dims = {2, 2, 2};
    a.affine[1][1] = 0.0;  // singular
    EXPECT_THROW(loadArray(a), Error);
    a.affine[1][1] = std::numeric_limits<double>::infinity();
    EXPECT_THROW(loadArray(a), Error);
    a.affine[1][1] = 1.0;
    LoadOptions raw;
    raw.hasLayout = true;
    EXPECT_THROW(loadArray(a, raw), Error);
    EXPECT_NO_THROW(loadArray(a));
}

}  // namespace
}  // namespace lobe
