// RenderOptions::cost (render/render_cost.h): BRDF evaluations counted per object, exactly, and
// the image unchanged by counting. Times are not asserted (they depend on the machine), only that
// the parts add up to the total.
//
// Set-up (as tests/render/test_hybrid_compositing.cpp): a 4×4×360 ramp f(i, j, k) = k + 0.75 i + 1
// whose iso-surface is a tilted plane with normal ∝ (0.75, 0, 1), seen straight down from
// z = 200 through a 0.5° field of view, so every camera ray meets it at x ∈ 1.5 ± 0.9, inside
// the grid: a W × H image at S samples per pixel has exactly W·H·S plane hits. Two lights far
// above (+z) are above the plane at every hit; one far below is below it, so the light loop
// evaluates the BRDF twice per hit, never three times.
#include "materials/registry.h"
#include "render/render_scene.h"
#include "render/scene_file.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace lobe {
namespace {

namespace fs = std::filesystem;

constexpr int kWidth = 20, kHeight = 16, kSpp = 2;
constexpr long long kRays = kWidth * kHeight * kSpp;

fs::path dataDir() {
    static const fs::path dir = [] {
        const fs::path d =
            fs::temp_directory_path() / ("lobe_render_cost_" + std::to_string(getpid()));
        fs::create_directories(d);
        std::vector<float> ramp(4 * 4 * 360), slab(4 * 4 * 40, 1.0f);
        for (int k = 0; k < 360; ++k)
            for (int j = 0; j < 4; ++j)
                for (int i = 0; i < 4; ++i) ramp[(k * 4 + j) * 4 + i] = float(k + 0.75 * i + 1.0);
        std::ofstream(d / "ramp.raw", std::ios::binary)
            .write(reinterpret_cast<const char*>(ramp.data()), std::streamsize(ramp.size() * 4));
        std::ofstream(d / "slab.raw", std::ios::binary)
            .write(reinterpret_cast<const char*>(slab.data()), std::streamsize(slab.size() * 4));
        return d;
    }();
    return dir;
}

// The plane at height ≈ 20 (opaque, named "plane", with `brdf`), optionally under a translucent
// slab z ∈ [24.5, 64.5] named "fog".
SceneSpec scene(const std::string& brdf, bool withSlab) {
    const std::string plane =
        R"({"name": "plane", "kind": "isosurface", "source": {"path": "ramp.raw",
            "dims": [4, 4, 360], "type": "float32"}, "transform": {"translate": [0, 0, -120]},
            "iso": 142.425, "color": [1, 0.5, 0.25], "brdf": )" +
        brdf + "}";
    const std::string slab =
        R"(, {"name": "fog", "kind": "volume", "source": {"path": "slab.raw", "dims": [4, 4, 40],
            "type": "float32"}, "transform": {"translate": [0, 0, 25]},
            "transfer_function": {"points": [{"value": 0.5, "opacity": 0},
              {"value": 0.5, "opacity": 0.03, "color": [0.2, 1, 0.5]}]},
            "brdf": {"model": "ward"}})";
    char head[1024];
    std::snprintf(head, sizeof head,
                  R"({"image": {"width": %d, "height": %d, "samples_per_pixel": %d},
                      "camera": {"position": [1.5, 1.5, 200], "target": [1.5, 1.5, 0],
                      "up": [0, 1, 0], "fov_deg": 0.5},
                      "lights": [{"position": [1.5, 1.5, 1e6], "intensity": 1e12},
                                 {"position": [3e5, 1.5, 1e6], "intensity": 1e12},
                                 {"position": [1.5, 1.5, -1e6], "intensity": 1e12}],
                      "backdrop": {"enabled": false},
                      "volume": {"step_voxels": 0.25, "shading_roulette": 0},
                      "objects": [)",
                  kWidth, kHeight, kSpp);
    return parseScene(std::string(head) + plane + (withSlab ? slab : "") + "]}", dataDir().string(),
                      "render-cost");
}

RenderOptions quietOptions(int threads, RenderCost* cost) {
    RenderOptions o;
    o.progress = false;
    o.threads = threads;
    o.cost = cost;
    return o;
}

void expectSameImage(const Film& a, const Film& b) {
    ASSERT_EQ(a.pixels().size(), b.pixels().size());
    size_t differing = 0;
    for (size_t i = 0; i < a.pixels().size(); ++i)
        for (int k = 0; k < kBandCount; ++k) differing += a.pixels()[i][k] != b.pixels()[i][k];
    EXPECT_EQ(differing, 0u);
}

TEST(RenderCost, EvaluationsAreLightsAboveTimesHits) {
    const RenderScene rs(scene(R"({"model": "ward"})", false), false);
    RenderCost cost;
    RenderStats stats;
    rs.render(quietOptions(2, &cost), &stats);
    EXPECT_EQ(stats.surfaceHits, kRays);  // the set-up: every ray meets the plane once
    ASSERT_EQ(cost.objects.size(), 1u);
    EXPECT_EQ(cost.objects[0].shadedPoints, kRays);
    EXPECT_EQ(cost.objects[0].brdfEvaluations, 2 * kRays);  // the light below is not evaluated
    EXPECT_EQ(cost.brdfEvaluations(), 2 * kRays);
    // The parts add up to the total (they are computed to); all non-negative.
    for (double s : {cost.surfaces, cost.volumes, cost.shading, cost.other}) EXPECT_GE(s, 0.0);
    EXPECT_NEAR(cost.surfaces + cost.volumes + cost.shading + cost.other, cost.cpuSeconds,
                1e-9 * (1.0 + cost.cpuSeconds));
    EXPECT_GT(cost.cpuSeconds, 0.0);
    EXPECT_EQ(cost.volumes, 0.0);  // no volume in the scene
    EXPECT_DOUBLE_EQ(cost.objects[0].shadingSeconds, cost.shading);
}

// Another model on the same object evaluates at the same points with the same lights.
TEST(RenderCost, AnotherModelHasTheSameEvaluations) {
    SceneSpec spec = scene(R"({"model": "lambert"})", true);
    SceneSpec ht = spec;
    ht.objects[0].material.specular = makeBrdf("he_torrance");
    RenderCost a, b;
    const Film fa = RenderScene(spec, false).render(quietOptions(1, &a));
    const Film fb = RenderScene(ht, false).render(quietOptions(2, &b));
    ASSERT_EQ(a.objects.size(), 2u);
    ASSERT_EQ(b.objects.size(), 2u);
    for (size_t i = 0; i < 2; ++i) {
        EXPECT_EQ(a.objects[i].shadedPoints, b.objects[i].shadedPoints) << i;
        EXPECT_EQ(a.objects[i].brdfEvaluations, b.objects[i].brdfEvaluations) << i;
    }
    EXPECT_EQ(a.objects[0].brdfEvaluations, 2 * kRays);
    double maxDiff = 0;
    for (size_t i = 0; i < fa.pixels().size(); ++i)
        for (int k = 0; k < kBandCount; ++k)
            maxDiff = std::max(maxDiff, std::abs(fa.pixels()[i][k] - fb.pixels()[i][k]));
    EXPECT_GT(maxDiff, 0.0);  // the swap did change the material
}

// Surface hits and volume samples are attributed to their own objects; the counts do not depend
// on the thread count; the image is the same bit for bit with and without counting.
TEST(RenderCost, PerObjectCountsMatchTheRenderStatsAndTheImageIsUnchanged) {
    const RenderScene rs(scene(R"({"model": "ward"})", true), false);
    RenderCost one, two;
    RenderStats stats;
    const Film plain = rs.render(quietOptions(2, nullptr), &stats);
    const Film counted1 = rs.render(quietOptions(1, &one));
    const Film counted2 = rs.render(quietOptions(2, &two));
    expectSameImage(plain, counted1);
    expectSameImage(plain, counted2);
    ASSERT_EQ(one.objects.size(), 2u);
    EXPECT_EQ(one.objects[0].shadedPoints, stats.surfaceHits);
    EXPECT_EQ(one.objects[1].shadedPoints, stats.volumeShaded);
    EXPECT_GT(stats.volumeShaded, 0);
    EXPECT_EQ(one.objects[0].brdfEvaluations, 2 * stats.surfaceHits);
    // Inside the slab the gradient is zero (no BRDF, volume_marcher.h "Normals"); its top face
    // has a normal along +z, where both upper lights are evaluated.
    EXPECT_GT(one.objects[1].brdfEvaluations, 0);
    EXPECT_LE(one.objects[1].brdfEvaluations, 2 * stats.volumeShaded);
    for (size_t i = 0; i < 2; ++i) {
        EXPECT_EQ(one.objects[i].shadedPoints, two.objects[i].shadedPoints) << i;
        EXPECT_EQ(one.objects[i].brdfEvaluations, two.objects[i].brdfEvaluations) << i;
    }
    EXPECT_NEAR(one.surfaces + one.volumes + one.shading + one.other, one.cpuSeconds,
                1e-9 * (1.0 + one.cpuSeconds));
}

}  // namespace
}  // namespace lobe
