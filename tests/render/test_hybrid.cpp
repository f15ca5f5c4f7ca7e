// The hybrid integrator's depth merge of several volumes, against a closed form: two coloured
// slabs overlapping along one ray (test_hybrid_compositing.cpp checks surfaces against slabs,
// opacity, thread invariance and skipping; this test checks that samples of two volumes interleave
// in depth order, which equal-colour slabs cannot show).
//
// Set-up: the camera looks down −z through (1.5, 1.5). A slab volume of 4×4×40 voxels of value 1
// (spacing 1) with a step transfer function (opacity α per voxel above value 0.5) fills
// z ∈ [−0.5, 39.5] (the trilinear value crosses 0.5 half a voxel beyond the last centre); a copy
// shifted up by 20 overlaps it. One light far up the z axis with I/d² = 1 at the origin, so a
// sample with no normal (zero gradient) sends colour·kd/π.
#include "core/error.h"
#include "render/render_scene.h"
#include "render/scene_file.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

namespace lobe {
namespace {

namespace fs = std::filesystem;

fs::path writeVolumes() {
    const fs::path dir =
        fs::temp_directory_path() / ("lobe_hybrid_test-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    std::vector<float> slab(4 * 4 * 40, 1.0f);
    std::ofstream(dir / "slab.raw", std::ios::binary)
        .write(reinterpret_cast<const char*>(slab.data()), slab.size() * 4);
    // Half the bytes a 4×4×40 float volume needs: loads fail (the scene file only checks that
    // the file exists).
    for (const char* name : {"short.raw", "short2.raw"})
        std::ofstream(dir / name, std::ios::binary)
            .write(reinterpret_cast<const char*>(slab.data()), slab.size() * 2);
    return dir;
}

const double kLightIntensity = 1e12;  // at z = 1e6: I/d² = 1 at the origin

std::string slabObject(double alpha, double kd, const std::string& colour, double dz,
                       const std::string& file = "slab.raw") {
    char buf[768];
    std::snprintf(buf, sizeof buf,
                  R"({"kind": "volume", "source": {"path": "%s", "dims": [4, 4, 40],
                     "type": "float32"}, "transform": {"translate": [0, 0, %g]},
                     "transfer_function": {"points": [{"value": 0.5, "opacity": 0},
                       {"value": 0.5, "opacity": %g, "color": %s}]},
                     "brdf": {"model": "lambert", "kd": 0}, "kd": %g})",
                  file.c_str(), dz, alpha, colour.c_str(), kd);
    return buf;
}

// The scene of `objects` seen from above; roulette = the shading-roulette threshold (0: every
// sample shaded, the exact sums the closed forms below describe).
SceneSpec sceneOf(const std::vector<std::string>& objects, double step, double roulette,
                  bool preIntegrated = false) {
    static const fs::path dir = writeVolumes();
    std::string list;
    for (const auto& o : objects) list += (list.empty() ? "" : ",") + o;
    char head[512];
    std::snprintf(head, sizeof head,
                  R"({"camera": {"position": [1.5, 1.5, 200], "target": [1.5, 1.5, 0],
                      "up": [0, 1, 0]}, "lights": [{"position": [1.5, 1.5, 1e6],
                      "intensity": %g}], "backdrop": {"enabled": false},
                      "volume": {"step_voxels": %g, "termination_transmittance": 0,
                                 "shading_roulette": %.17g, "pre_integrated": %s},
                      "objects": [)",
                  kLightIntensity, step, roulette, preIntegrated ? "true" : "false");
    return parseScene(std::string(head) + list + "]}", dir.string(), "hybrid");
}

Ray downRay() {
    Ray ray;
    ray.o = Vec3(1.5, 1.5, 200);
    ray.d = Vec3(0, 0, -1);
    return ray;
}

Spectrum traceDown(const std::vector<std::string>& objects, double step = 0.05,
                   bool preIntegrated = false) {
    const RenderScene scene(sceneOf(objects, step, 0.0, preIntegrated), false);
    return scene.traceRay(downRay(), 0.5);
}

}  // namespace

// Two slabs overlapping over z ∈ [19.5, 39.5]: B (green) in front from 59.5 down, A (red)
// behind down to −0.5. In the continuous limit (extinction σ = −ln(1 − α) per voxel, summed where
// they overlap) the green band gets L(1 − e^{−20σ}) + e^{−20σ} L ½ (1 − e^{−40σ}) and the red band
// e^{−20σ} L ½ (1 − e^{−40σ}) + e^{−60σ} L (1 − e^{−20σ}).
TEST(Hybrid, TwoOverlappingVolumesMergeByDepth) {
    const double alpha = 0.04, kd = 0.5;
    const double l = kd / kPi, s = -std::log(1.0 - alpha);
    const double green =
        l * (1 - std::exp(-20 * s)) + std::exp(-20 * s) * l * 0.5 * (1 - std::exp(-40 * s));
    const double red = std::exp(-20 * s) * l * 0.5 * (1 - std::exp(-40 * s)) +
                       std::exp(-60 * s) * l * (1 - std::exp(-20 * s));
    // Point-sampled at a fine step, and pre-integrated (scene key "pre_integrated") at steps of
    // 0.5 and 1.3 voxels: the slabs' edges, where the value falls from 1 to 0 across the
    // transfer function's step within one voxel, are integrated exactly.
    for (const auto& [step, pre] : {std::pair{0.02, false}, {0.5, true}, {1.3, true}}) {
        const Spectrum L = traceDown(
            {slabObject(alpha, kd, "[1, 0, 0]", 0), slabObject(alpha, kd, "[0, 1, 0]", 20)}, step,
            pre);
        EXPECT_NEAR(L[1], green, 0.01 * green) << step;
        // Red lies behind the overlap, where the two volumes' lattices interleave: at 1.3 voxels
        // the order of a red and a green segment within one step moves red by ~2 %.
        EXPECT_NEAR(L[0], red, (step > 1.0 ? 0.03 : 0.02) * red) << step;
        EXPECT_NEAR(L[2], 0.0, 1e-12);
    }
}

// The shading roulette (render_scene.cpp) shades a sample of weight w = T·α < w0 with
// probability w/w0 and counts it w0/w times: unbiased. A slab of α = 0.01 per voxel at step 0.1
// has samples of weight ≤ 1e-3, all under w0 = 0.05, so every sample plays. Over 4000 seeds the
// mean must match the exact (w0 = 0) radiance within 4 standard errors, the spread must be
// non-zero (the roulette really dropped samples), and with w0 = 0 the seed must not matter.
TEST(Hybrid, ShadingRouletteIsUnbiased) {
    const std::vector<std::string> slab = {slabObject(0.01, 0.5, "[1, 1, 1]", 0)};
    const RenderScene exactScene(sceneOf(slab, 0.1, 0.0), false);
    const double exact = exactScene.traceRay(downRay(), 0.5)[1];
    ASSERT_GT(exact, 0.0);
    EXPECT_EQ(exactScene.traceRay(downRay(), 0.5, 12345)[1], exact);

    const RenderScene roulette(sceneOf(slab, 0.1, 0.05), false);
    const int n = 4000;
    double sum = 0.0, sum2 = 0.0;
    for (int seed = 0; seed < n; ++seed) {
        const double v = roulette.traceRay(downRay(), 0.5, uint64_t(seed))[1];
        ASSERT_TRUE(std::isfinite(v));
        sum += v;
        sum2 += v * v;
    }
    const double mean = sum / n, sd = std::sqrt(std::max(0.0, sum2 / n - mean * mean));
    EXPECT_GT(sd, 0.01 * exact);
    EXPECT_NEAR(mean, exact, 4.0 * sd / std::sqrt(double(n)));

    // render() shades fewer samples than it composites, and none are lost from the count.
    SceneSpec small = sceneOf(slab, 0.1, 0.05);
    small.width = small.height = 4;
    small.fovDegrees = 0.1;
    RenderOptions options;
    options.progress = false;
    RenderStats stats;
    RenderScene(small, false).render(options, &stats);
    EXPECT_GT(stats.volumeSamples, 0);
    EXPECT_LT(stats.volumeShaded, stats.volumeSamples / 2);
}

// Sources load in parallel (render_scene.cpp, loadSources), but a failure is reported once, for
// the first failing object in scene order, with its index and the file's own message.
TEST(Hybrid, LoadFailureNamesTheFirstFailingObject) {
    auto errorOf = [](const std::vector<std::string>& objects) {
        try {
            RenderScene scene(sceneOf(objects, 0.1, 0.0), false);
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    const std::string good = slabObject(0.01, 0.5, "[1, 1, 1]", 0);
    const std::string bad = slabObject(0.01, 0.5, "[1, 1, 1]", 0, "short.raw");
    const std::string bad2 = slabObject(0.01, 0.5, "[1, 1, 1]", 0, "short2.raw");
    for (int run = 0; run < 20; ++run) {  // whichever load finishes first
        const std::string e = errorOf({good, bad, good, bad2, bad});
        EXPECT_NE(e.find("objects[1]"), std::string::npos) << e;
        EXPECT_NE(e.find("short.raw"), std::string::npos) << e;
    }
    EXPECT_EQ(errorOf({good, good}), "no error");
}

}  // namespace lobe
