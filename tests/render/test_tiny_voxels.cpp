// Tiny voxels (issue 32): a volume of 1e-5 mm voxels, or a scene transform scaling 1 mm voxels by
// 1e-5, renders the image the same data gives at 1 mm with the camera and lights scaled alike.
// OpenVDB refuses such maps (determinant below 3e-15); Lobe keeps the grid's transform rescaled by
// a power of two and the scale beside it (volume/grid_world.h). Before, both scenes were refused.
//
// Why the images agree: opacities are per voxel and steps in voxels (transfer_function.h), a
// point light's irradiance is I/d² (docs/scene-format.md), so scaling every length by k and the
// intensities by k² leaves every pixel unchanged up to rounding.
#include "core/error.h"
#include "render/render_scene.h"
#include "render/scene_file.h"
#include "test_files.h"
#include "volume/grid_world.h"
#include "volume/volume.h"

#include <gtest/gtest.h>
#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

namespace lobe {
namespace {

namespace fs = std::filesystem;

constexpr int kN = 28;

// A ball of radius 9 voxels (the iso-surface at 0.5 of a linear ramp) around a denser off-centre
// core (the volume).
float shellValue(int i, int j, int k) {
    const double r =
        std::sqrt((i - 13.6) * (i - 13.6) + (j - 13.2) * (j - 13.2) + (k - 14.1) * (k - 14.1));
    return float(std::clamp(9.5 - r, 0.0, 1.0));
}
float coreValue(int i, int j, int k) {
    const double r = std::sqrt((i - 15.0) * (i - 15.0) + 2.0 * (j - 12.0) * (j - 12.0) +
                               (k - 14.0) * (k - 14.0));
    return float(std::max(0.0, 6.0 - r));
}

fs::path dataDir() {
    static const fs::path dir = [] {
        const fs::path d = fs::temp_directory_path() / ("lobe_tiny_" + std::to_string(getpid()));
        fs::create_directories(d);
        std::vector<float> shell(size_t(kN) * kN * kN), core(shell.size());
        for (int k = 0; k < kN; ++k)
            for (int j = 0; j < kN; ++j)
                for (int i = 0; i < kN; ++i) {
                    shell[(size_t(k) * kN + j) * kN + i] = shellValue(i, j, k);
                    core[(size_t(k) * kN + j) * kN + i] = coreValue(i, j, k);
                }
        test::writeFloatsAtomically(d / "shell.raw", shell);
        test::writeFloatsAtomically(d / "core.raw", core);
        return d;
    }();
    return dir;
}

std::string num(double x) {
    char t[40];
    std::snprintf(t, sizeof t, "%.17g", x);
    return t;
}

std::string vec(double k, double x, double y, double z) {
    return "[" + num(k * x) + ", " + num(k * y) + ", " + num(k * z) + "]";
}

// The scene with every length times k (intensities times k²): the voxels' spacing
// (`spacing` k) or the objects' transform (`transform` k), camera, lights.
std::string sceneText(double k, bool byTransform, const std::string& method) {
    const double s = byTransform ? 1.0 : k;
    const auto source = [&](const char* file) {
        return std::string(R"({"path": ")") + file + R"(", "dims": [28, 28, 28], "type": "float32",
                   "spacing": )" +
               vec(s, 1, 1, 1) + "}";
    };
    const std::string transform =
        byTransform ? R"(, "transform": {"scale": )" + vec(k, 1, 1, 1) + "}" : "";
    return R"({"image": {"width": 40, "height": 32, "samples_per_pixel": 2, "seed": 5},
               "camera": {"position": )" +
           vec(k, -30, -40, 38) + R"(, "target": )" + vec(k, 14, 13, 14) +
           R"(, "up": [0, 0, 1], "fov_deg": 36},
               "lights": [{"position": )" +
           vec(k, -50, -20, 60) + R"(, "intensity": )" + num(9000.0 * k * k) + R"(},
                          {"position": )" +
           vec(k, 40, -60, 10) + R"(, "intensity": )" + num(4000.0 * k * k) + R"(}],
               "backdrop": {"enabled": false},
               "volume": {"step_voxels": 0.25},
               "objects": [
                 {"name": "shell", "kind": "isosurface", "source": )" +
           source("shell.raw") + R"(, "iso": 0.5, "method": ")" + method +
           R"(", "opacity": 0.45, "brdf": {"model": "ward", "alpha_x": 0.25, "alpha_y": 0.25})" +
           transform + R"(},
                 {"name": "core", "kind": "volume", "source": )" +
           source("core.raw") + R"(, "transfer_function": {"points": [
                   {"value": 0.5, "opacity": 0.0, "color": [0.9, 0.5, 0.4]},
                   {"value": 3.0, "opacity": 0.4, "color": [0.9, 0.5, 0.4]}]},
                  "brdf": {"model": "lambert"})" +
           transform + R"(}]})";
}

Film renderOf(const std::string& text) {
    const RenderScene scene(parseScene(text, dataDir().string(), "tiny.json"), false);
    RenderOptions o;
    o.threads = 2;
    o.progress = false;
    return scene.render(o);
}

// Largest difference and largest value over all pixels and bands.
void compare(const Film& a, const Film& b, double& maxDiff, double& maxValue, double& meanDiff) {
    ASSERT_EQ(a.pixels().size(), b.pixels().size());
    maxDiff = maxValue = meanDiff = 0.0;
    for (size_t i = 0; i < a.pixels().size(); ++i)
        for (int c = 0; c < kBandCount; ++c) {
            const double d = std::abs(double(a.pixels()[i][c]) - double(b.pixels()[i][c]));
            maxDiff = std::max(maxDiff, d);
            meanDiff += d;
            maxValue = std::max(maxValue, double(a.pixels()[i][c]));
        }
    meanDiff /= double(a.pixels().size() * kBandCount);
}

class TinyVoxels : public ::testing::TestWithParam<const char*> {};

TEST_P(TinyVoxels, RenderAsTheSameDataAtOneMillimetre) {
    const std::string method = GetParam();
    const Film reference = renderOf(sceneText(1.0, false, method));
    for (const bool byTransform : {false, true}) {
        SCOPED_TRACE(byTransform ? "transform scale 1e-5" : "1e-5 mm voxels");
        const Film tiny = renderOf(sceneText(1e-5, byTransform, method));
        double maxDiff, maxValue, meanDiff;
        compare(reference, tiny, maxDiff, maxValue, meanDiff);
        EXPECT_GT(maxValue, 0.05);  // something is in the picture
        // Rounding only (measured: 4e-13 for the exact method, 1.5e-8 meshed, 1e-7 level set, of
        // 0.14): positions agree to ~1e-16 relative, hits to the root finders' accuracy. A wrong
        // scale anywhere — a march in the wrong voxels, a light 1e5 times too close — changes
        // pixels by tens of percent.
        EXPECT_LT(maxDiff, 1e-5 * maxValue);
        EXPECT_LT(meanDiff, 1e-7 * maxValue);
    }
}

INSTANTIATE_TEST_SUITE_P(Methods, TinyVoxels, ::testing::Values("exact", "mesh", "levelset"));

// The grid keeps the map to the last bit: its OpenVDB transform times a power of two.
TEST(TinyVoxelMaps, GridKeepsTheExactMapRescaledByAPowerOfTwo) {
    openvdb::initialize();
    openvdb::math::Mat4d m = openvdb::math::Mat4d::identity();
    const double a[3][3] = {{0.7e-5, 0.3e-5, 0}, {-0.2e-5, 0.9e-5, 0.1e-5}, {0, 0.05e-5, 1.1e-5}};
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) m[r][c] = a[r][c];
    m[3][0] = 12.5;
    m[3][1] = -3e-4;
    m[3][2] = 7.25;
    // What OpenVDB alone does with it.
    EXPECT_THROW(openvdb::math::Transform::createLinearTransform(m), openvdb::ArithmeticError);
    openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(0.0f);
    setGridWorldMap(*grid, m);
    const double s = gridWorldScale(*grid);
    EXPECT_TRUE(validWorldScale(s));
    EXPECT_LT(s, 1e-4);
    EXPECT_EQ(gridWorldMatrix(*grid), m);  // bit for bit
    const double det = std::abs(grid->transform().baseMap()->getAffineMap()->getMat4().det());
    EXPECT_GT(det, 0.5);
    EXPECT_LT(det, 2.0);
    const openvdb::Vec3d idx(3.0, -2.0, 5.0);
    const openvdb::Vec3d w = gridIndexToWorld(*grid, idx);
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(w[c], m[3][c] + idx[0] * m[0][c] + idx[1] * m[1][c] + idx[2] * m[2][c],
                    1e-15 * (1.0 + std::abs(m[3][c])));
    const openvdb::Vec3d back = gridWorldToIndex(*grid, w);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(back[c], idx[c], 1e-6);  // translation 12.5 / 1e-5
    // The copy a scene places shares the scale; a later ordinary map drops it.
    openvdb::FloatGrid::Ptr copy = grid->copy();
    EXPECT_EQ(gridWorldScale(*copy), s);
    setGridWorldMap(*copy, openvdb::math::Mat4d::identity());
    EXPECT_EQ(gridWorldScale(*copy), 1.0);
    EXPECT_FALSE(copy->getMetadata<openvdb::DoubleMetadata>(kMetaWorldScale));
    EXPECT_EQ(gridWorldScale(*grid), s);
}

// 1 mm voxels (and anything down to 1e-3 mm) keep OpenVDB's map unchanged: no scale, no metadata.
TEST(TinyVoxelMaps, OrdinaryVoxelsAreNotRescaled) {
    openvdb::initialize();
    for (const double v : {1.0, 0.25, 2e-3, 500.0}) {
        openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(0.0f);
        openvdb::math::Mat4d m = openvdb::math::Mat4d::identity();
        m.preScale(openvdb::Vec3d(v, v, 1.5 * v));
        setGridWorldMap(*grid, m);
        EXPECT_FALSE(grid->getMetadata<openvdb::DoubleMetadata>(kMetaWorldScale)) << v;
        EXPECT_EQ(grid->transform().voxelSize(), openvdb::Vec3d(v, v, 1.5 * v));
    }
}

// A .vdb of tiny voxels keeps them (writeVdb writes the scale, loadVdb reads and checks it).
TEST(TinyVoxelMaps, VdbRoundTripKeepsTheWorldScale) {
    LoadOptions o;
    o.hasLayout = true;
    o.layout.dims = {kN, kN, kN};
    o.layout.type = VoxelType::kFloat32;
    o.layout.spacing = {1e-5, 2e-5, 1e-5};
    const Volume v = loadRaw((dataDir() / "core.raw").string(), o.layout, o);
    EXPECT_DOUBLE_EQ(v.spacing[1], 2e-5);
    const std::string path = (dataDir() / "tiny.vdb").string();
    writeVdb(v, path);
    const Volume back = loadVdb(path);
    EXPECT_EQ(gridWorldMatrix(*back.grid), gridWorldMatrix(*v.grid));
    for (int a = 0; a < 3; ++a) EXPECT_DOUBLE_EQ(back.spacing[a], v.spacing[a]);
    EXPECT_EQ(volumeContentHash(back), volumeContentHash(v));
    // A damaged scale is refused by name.
    openvdb::FloatGrid::Ptr bad = back.grid->deepCopy();
    for (const double scale : {3e-6, 1.0, -std::ldexp(1.0, -17), std::ldexp(1.0, -1000)}) {
        bad->insertMeta(kMetaWorldScale, openvdb::DoubleMetadata(scale));
        const std::string badPath = (dataDir() / "bad-scale.vdb").string();
        openvdb::io::File(badPath).write({bad});
        try {
            loadVdb(badPath);
            ADD_FAILURE() << "a scale of " << scale << " was accepted";
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find("lobe_world_scale"), std::string::npos)
                << e.what();
        }
    }
}

}  // namespace
}  // namespace lobe
