// The real volumes against values measured independently (nibabel / numpy): the shipped CThead
// (assets/cthead, values in assets/cthead/README.md) and brain volumes (assets/brain), and
// colin27 from Debian's mricron-data (scripts/setup.sh).
#include "volume/volume.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace lobe {
namespace {

const std::string kAssets = LOBE_SOURCE_DIR "/assets";
// Debian mricron-data: colin27 (Holmes et al. 1998) in the MNI 1 mm grid, brain only.
const std::string kColin27 = "/usr/share/mricron/templates/ch2bet.nii.gz";

struct Counts {
    std::int64_t nonZero = 0;
    std::int64_t above[4] = {0, 0, 0, 0};
    double sum = 0.0, min = 1e300, max = -1e300;
};

// Counts over every voxel of the volume's dims: non-zero voxels and voxels strictly above each
// threshold (stored units).
Counts count(const Volume& v, const double (&thresholds)[4]) {
    Counts c;
    auto acc = v.grid->getConstAccessor();
    for (int k = 0; k < v.dims[2]; ++k)
        for (int j = 0; j < v.dims[1]; ++j)
            for (int i = 0; i < v.dims[0]; ++i) {
                const double x = acc.getValue(openvdb::Coord(i, j, k));
                c.nonZero += x != 0.0;
                for (int t = 0; t < 4; ++t) c.above[t] += x > thresholds[t];
                c.sum += x;
                c.min = std::min(c.min, x);
                c.max = std::max(c.max, x);
            }
    return c;
}

void expectWorld(const Volume& v, openvdb::Vec3d index, openvdb::Vec3d expected) {
    const openvdb::Vec3d w = v.grid->transform().indexToWorld(index);
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(w[a], expected[a], 1e-4) << "axis " << a;
}

// assets/cthead/README.md: range 0..3272, mean 379.5, 4.0 % of voxels above the paper's iso 0.5 of
// v/3272, i.e. raw 1636. The asset opens with no options through its NRRD header.
TEST(RealData, CtheadAssetMatchesMeasuredValues) {
    LoadOptions o;
    o.normalize = 3272;
    const Volume v = loadVolume(kAssets + "/cthead/cthead.nhdr", o);
    EXPECT_EQ(v.dims, (std::array<int, 3>{256, 256, 113}));
    EXPECT_DOUBLE_EQ(v.originalMin, 0.0);
    EXPECT_DOUBLE_EQ(v.originalMax, 3272.0);
    expectWorld(v, {255, 255, 112}, {255, 255, 224});  // spacing 1:1:2
    const Counts c = count(v, {0.5, 2047.0 / 3272.0, 2.0, 2.0});
    const double n = 256.0 * 256.0 * 113.0;
    EXPECT_NEAR(c.sum / n * 3272.0, 379.5, 0.05);
    EXPECT_NEAR(100.0 * c.above[0] / n, 4.0, 0.05);
    EXPECT_NEAR(100.0 * c.above[1] / n, 2.4, 0.05);  // the 12-bit normalisation, README
    EXPECT_FLOAT_EQ(static_cast<float>(c.max), 1.0f);
}

// colin27 brain (Debian mricron-data 1.2.20211006, ch2bet.nii.gz, sha256 592a2d20…7c5dd1):
// 181×217×181 uint8, little-endian, scl_slope 1, sform (code 4) diag(1, 1, 1) origin
// (−90, −125, −71); measured with nibabel 5.0 on the raw values: range 0..133, 1,737,193
// non-zero, above 30.5 / 60.5 / 90.5 / 120.5: 1,726,464 / 1,619,672 / 915,390 / 5,646.
TEST(RealData, Colin27FromDebianMatchesMeasuredValues) {
    ASSERT_TRUE(std::filesystem::exists(kColin27)) << "Debian mricron-data (scripts/setup.sh)";
    const Volume v = loadVolume(kColin27);
    EXPECT_EQ(v.dims, (std::array<int, 3>{181, 217, 181}));
    expectWorld(v, {0, 0, 0}, {-90, -125, -71});
    expectWorld(v, {180, 216, 180}, {90, 91, 109});
    const Counts c = count(v, {30.5, 60.5, 90.5, 120.5});
    EXPECT_EQ(c.nonZero, 1737193);
    EXPECT_EQ(c.above[0], 1726464);
    EXPECT_EQ(c.above[1], 1619672);
    EXPECT_EQ(c.above[2], 915390);
    EXPECT_EQ(c.above[3], 5646);
    EXPECT_EQ(c.min, 0.0);
    EXPECT_EQ(c.max, 133.0);
}

// assets/brain/README.md: 197×233×189 uint8, sform diag(1,1,1) origin (−98, −134, −72); GM
// non-zero in 1,961,850 voxels, above prob 0.70/0.75/0.80/0.85 (raw > 178.5/191.25/204/216.75,
// prob = raw/255) in 760,002 / 655,603 / 538,136 / 415,626. The thresholds are applied to the raw
// values so none falls on an integer after rounding; 204 is exactly 0.80·255, and "above 0.80"
// means raw ≥ 205.
TEST(RealData, MniGreyMatterAssetCounts) {
    const Volume v =
        loadVolume(kAssets + "/brain/mni_icbm152_gm_tal_nlin_sym_09a_converted.nii.gz");
    EXPECT_EQ(v.dims, (std::array<int, 3>{197, 233, 189}));
    expectWorld(v, {0, 0, 0}, {-98, -134, -72});
    expectWorld(v, {196, 232, 188}, {98, 98, 116});
    const Counts c = count(v, {178.5, 191.25, 204.5, 216.75});
    EXPECT_EQ(c.nonZero, 1961850);
    EXPECT_EQ(c.above[0], 760002);
    EXPECT_EQ(c.above[1], 655603);
    EXPECT_EQ(c.above[2], 538136);
    EXPECT_EQ(c.above[3], 415626);
    EXPECT_EQ(static_cast<std::int64_t>(v.grid->activeVoxelCount()), c.nonZero)
        << "background 0: exactly the non-zero voxels are active";
    EXPECT_EQ(c.max, 255.0);
}

TEST(RealData, MniT1AssetNonZeroVoxels) {
    const Volume v =
        loadVolume(kAssets + "/brain/mni_icbm152_t1_tal_nlin_sym_09a_converted.nii.gz");
    EXPECT_EQ(v.dims, (std::array<int, 3>{197, 233, 189}));
    const Counts c = count(v, {0, 0, 0, 0});
    EXPECT_EQ(c.nonZero, 1886539);
    EXPECT_EQ(c.min, 0.0);
    EXPECT_EQ(c.max, 255.0);
}

// assets/brain/README.md: 91×109×91, affine diag(−2, 2, 2) origin (90, −126, −72) (LAS), prob = raw
// × scl_slope. FieldMap grey (little-endian, slope 0.0037677817): max 0.9608, non-zero 338,634,
// above 0.70/0.75/0.80/0.85: 40,766 / 23,712 / 13,165 / 5,369.
TEST(RealData, SpmFieldMapGreyAsset) {
    const Volume v = loadVolume(kAssets + "/brain/grey_icbm151_smooth8mm_FieldMap.nii.gz");
    EXPECT_EQ(v.dims, (std::array<int, 3>{91, 109, 91}));
    expectWorld(v, {0, 0, 0}, {90, -126, -72});
    expectWorld(v, {1, 2, 3}, {88, -122, -66});
    const Counts c = count(v, {0.70, 0.75, 0.80, 0.85});
    EXPECT_NEAR(c.max, 255 * 0.0037677817, 1e-6);
    EXPECT_NEAR(c.max, 0.9608, 5e-5);
    EXPECT_EQ(c.nonZero, 338634);
    EXPECT_EQ(c.above[0], 40766);
    EXPECT_EQ(c.above[1], 23712);
    EXPECT_EQ(c.above[2], 13165);
    EXPECT_EQ(c.above[3], 5369);
}

// The asset's raw file read with the explicit layout gives the same volume as through its NRRD
// header.
TEST(RealData, CtheadRawLayoutEqualsNrrd) {
    const std::string path = kAssets + "/cthead/cthead_256x256x113_int16be.raw.gz";
    LoadOptions o;
    o.hasLayout = true;
    o.layout.dims = {256, 256, 113};
    o.layout.type = VoxelType::kInt16;
    o.layout.endian = Endian::kBig;
    o.layout.spacing = {1, 1, 2};
    const Volume raw = loadVolume(path, o);
    const Volume nrrd = loadVolume(kAssets + "/cthead/cthead.nhdr");
    EXPECT_EQ(raw.grid->activeVoxelCount(), nrrd.grid->activeVoxelCount());
    auto a = raw.grid->getConstAccessor();
    auto b = nrrd.grid->getConstAccessor();
    for (int k = 0; k < 113; k += 7)
        for (int j = 0; j < 256; j += 3)
            for (int i = 0; i < 256; ++i)
                ASSERT_EQ(a.getValue(openvdb::Coord(i, j, k)), b.getValue(openvdb::Coord(i, j, k)));
    expectWorld(raw, {10, 20, 30}, {10, 20, 60});
}

}  // namespace
}  // namespace lobe
