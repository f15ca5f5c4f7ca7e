// Sparse grids whose stored voxels lie far apart (foreign .vdb files): statistics in time
// proportional to what is stored, and volume rendering refused by the size of its dense table
// before anything is allocated (it used to overflow the table's size and crash, or hang).
#include "core/error.h"
#include "volume/volume.h"
#include "volume/volume_marcher.h"

#include <gtest/gtest.h>

#include <chrono>

namespace lobe {
namespace {

Volume volumeOf(openvdb::FloatGrid::Ptr grid, std::array<int, 3> dims, std::array<int, 3> origin) {
    Volume v;
    v.grid = grid;
    v.dims = dims;
    v.indexOrigin = origin;
    return v;
}

// The statistics summed voxel by voxel, for small boxes: the reference.
VolumeStats denseStats(const Volume& volume) {
    VolumeStats s;
    auto acc = volume.grid->getConstAccessor();
    double lo = 1e300, hi = -1e300, sum = 0.0;
    for (int k = 0; k < volume.dims[2]; ++k)
        for (int j = 0; j < volume.dims[1]; ++j)
            for (int i = 0; i < volume.dims[0]; ++i) {
                const double v = acc.getValue(openvdb::Coord(volume.indexOrigin[0] + i,
                                                             volume.indexOrigin[1] + j,
                                                             volume.indexOrigin[2] + k));
                lo = std::min(lo, v);
                hi = std::max(hi, v);
                sum += v;
            }
    s.voxels = int64_t(volume.dims[0]) * volume.dims[1] * volume.dims[2];
    s.min = lo;
    s.max = hi;
    s.mean = sum / double(s.voxels);
    return s;
}

TEST(SparseVolumes, StatisticsOverTilesAndVoxelsEqualTheDenseSum) {
    openvdb::initialize();
    auto grid = openvdb::FloatGrid::create(-0.5f);                 // a background that is not 0
    grid->tree().addTile(1, openvdb::Coord(8, 0, 0), 2.0f, true);  // an 8³ tile
    grid->tree().setValue(openvdb::Coord(3, 4, 5), 7.0f);
    grid->tree().setValue(openvdb::Coord(30, 2, 1), -3.0f);
    // Boxes that cut the tile, miss the voxels, cover everything, and hold only background.
    for (const auto& [dims, origin] :
         std::vector<std::pair<std::array<int, 3>, std::array<int, 3>>>{{{40, 12, 10}, {-2, -1, 0}},
                                                                        {{5, 3, 3}, {10, 1, 1}},
                                                                        {{4, 4, 4}, {100, 0, 0}},
                                                                        {{1, 1, 1}, {3, 4, 5}}}) {
        const Volume v = volumeOf(grid, dims, origin);
        const VolumeStats fast = computeStats(v), dense = denseStats(v);
        EXPECT_EQ(fast.voxels, dense.voxels);
        EXPECT_DOUBLE_EQ(fast.min, dense.min);
        EXPECT_DOUBLE_EQ(fast.max, dense.max);
        EXPECT_NEAR(fast.mean, dense.mean, 1e-12 * std::abs(dense.mean) + 1e-15);
    }
}

openvdb::FloatGrid::Ptr twoVoxels(int apart) {
    openvdb::initialize();
    auto grid = openvdb::FloatGrid::create(0.0f);
    grid->tree().setValue(openvdb::Coord(0, 0, 0), 1.0f);
    grid->tree().setValue(openvdb::Coord(apart, apart, apart), 1.0f);
    return grid;
}

TEST(SparseVolumes, StatisticsOfTwoVoxels1e5ApartAreImmediate) {
    const Volume v = volumeOf(twoVoxels(100000), {100001, 100001, 100001}, {0, 0, 0});
    const auto start = std::chrono::steady_clock::now();
    const VolumeStats s = computeStats(v);
    // Generous: the dense walk over 1e15 voxels would take days.
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
              10.0);
    EXPECT_EQ(s.voxels, int64_t(100001) * 100001 * 100001);
    EXPECT_EQ(s.max, 1.0);
    EXPECT_EQ(s.min, 0.0);
    EXPECT_DOUBLE_EQ(s.mean, 2.0 / double(s.voxels));
}

TEST(SparseVolumes, VolumeRenderingRefusesAnActiveBoxBeyondItsTable) {
    try {
        DvrVolume(twoVoxels(100000), TransferFunction::densityMaps(), DvrSettings(), "far.vdb");
        FAIL() << "expected an error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("far.vdb: the active voxels span 100001 x 100001 x "
                                             "100001 voxels"),
                  std::string::npos)
            << e.what();
    }
    // A far but thin arrangement is fine: 2000 voxels apart along x only.
    auto grid = openvdb::FloatGrid::create(0.0f);
    grid->tree().setValue(openvdb::Coord(0, 0, 0), 1.0f);
    grid->tree().setValue(openvdb::Coord(2000, 0, 0), 1.0f);
    EXPECT_NO_THROW(DvrVolume(grid, TransferFunction::densityMaps(), DvrSettings(), "thin"));
}

}  // namespace
}  // namespace lobe
