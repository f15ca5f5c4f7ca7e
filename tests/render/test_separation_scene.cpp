// The separation score end to end on a scene whose answer is known by construction: two spheres
// (iso-surfaces of one ball volume, Phong, a light at the camera), the front one translucent.
// With the back sphere straight behind, both highlights lie at the image centre — the front one
// brighter and larger — so one highlight lies inside the other and the score is (near) zero; as
// the back sphere moves sideways its highlight moves out from behind, and once the spheres are
// side by side the highlights are disjoint and the score is the smaller mean contrast. Also:
// lobe assign's layers reproduce the score of a render made with the chosen models.
#include "analysis/scene_passes.h"
#include "core/error.h"
#include "materials/albedo.h"
#include "render/render_scene.h"
#include "render/scene_file.h"
#include "render/shading.h"
#include "test_files.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

namespace lobe {
namespace {

namespace fs = std::filesystem;

fs::path ballFile() {
    const fs::path dir = fs::path(LOBE_BINARY_DIR) / "test-output" / "separation_scene";
    fs::create_directories(dir);
    std::vector<float> v(32 * 32 * 32);
    for (int z = 0; z < 32; ++z)
        for (int y = 0; y < 32; ++y)
            for (int x = 0; x < 32; ++x) {
                const double r = std::sqrt((x - 15.5) * (x - 15.5) + (y - 15.5) * (y - 15.5) +
                                           (z - 15.5) * (z - 15.5));
                v[size_t((z * 32 + y) * 32 + x)] = float(std::max(0.0, 1.0 - r / 12.0));
            }
    test::writeFloatsAtomically(dir / "ball.raw", v);
    return dir;
}

SceneSpec twoSpheres(double dx, const std::string& backModel = "phong",
                     const std::string& backColour = "1", const std::string& frontModel = "phong") {
    static const fs::path dir = ballFile();
    auto sphere = [](const char* name, double tx, double tz, double opacity,
                     const std::string& model, const std::string& colour) {
        char buf[512];
        std::snprintf(buf, sizeof buf,
                      R"({"name": "%s", "kind": "isosurface", "source": {"path": "ball.raw",
                          "dims": [32, 32, 32], "type": "float32"}, "iso": 0.5,
                          "transform": {"translate": [%g, 0, %g]}, "opacity": %g,
                          "brdf": {"model": "%s"}, "kd": 0.2, "color": %s})",
                      name, tx, tz, opacity, model.c_str(), colour.c_str());
        return std::string(buf);
    };
    const std::string json =
        R"({"image": {"width": 64, "height": 64, "samples_per_pixel": 2},
            "camera": {"position": [15.5, 15.5, -90], "target": [15.5, 15.5, 15.5],
                       "up": [0, 1, 0], "fov_deg": 24},
            "lights": [{"position": [15.5, 15.5, -90], "intensity": 20000}],
            "backdrop": {"enabled": false}, "objects": [)" +
        sphere("front", 0, -16, 0.5, frontModel, "1") + "," +
        sphere("back", dx, 0, 1.0, backModel, backColour) + "]}";
    return parseScene(json, dir.string(), "two-spheres");
}

SeparationReport reportOf(const SceneSpec& spec) {
    const RenderScene scene(spec, false);
    AovRequest request;
    request.objects = request.backdrop = true;
    RenderOptions options;
    options.progress = false;
    AovImage aovs;
    scene.render(options, nullptr, &request, &aovs);
    return measureSeparation(separationLayers(spec, aovs));
}

// The highlight term alone (grey spheres: identity 1; the score also weighs visibility and
// veiling).
double scoreOf(const SceneSpec& spec) { return reportOf(spec).highlight; }

// One render of `spec` with every candidate's per-model layers, as `lobe assign` makes it.
AssignmentLayers layersOf(const SceneSpec& spec, const std::vector<BrdfCandidate>& candidates) {
    AovRequest request;
    request.objects = request.backdrop = true;
    requestCandidateLayers(candidates, request);
    const RenderScene scene(spec, false);
    RenderOptions options;
    options.progress = false;
    AovImage aovs;
    scene.render(options, nullptr, &request, &aovs);
    return assignmentLayers(spec, aovs, candidates);
}

TEST(SeparationScene, HighlightsMovedApartScoreHigher) {
    const double behind = scoreOf(twoSpheres(0));
    const double half = scoreOf(twoSpheres(6));
    const double apart = scoreOf(twoSpheres(16));
    EXPECT_LT(behind, 0.25 * apart) << behind << " " << half << " " << apart;
    EXPECT_LE(behind, half);
    EXPECT_LE(half, apart + 1e-9);
    EXPECT_GT(apart, 0.05);
}

TEST(SeparationScene, TheTranslucentFrontSphereVeilsTheRedOneBehind) {
    // A red sphere half behind a grey translucent one (opacity 0.5), the front sphere with
    // Phong's narrow highlight or Schlick–Lewis's broad bright one (albedo about 5× Phong's
    // at these defaults: docs/separation.md). Nothing lies in front of the front sphere; its
    // highlight lies over the red sphere, veils it and washes out its red, the more so the broader.
    const std::string red = "[1, 0.08, 0.08]";
    const SeparationReport narrow = reportOf(twoSpheres(6, "phong", red, "phong"));
    const SeparationReport broad = reportOf(twoSpheres(6, "phong", red, "schlick_lewis"));
    for (const SeparationReport* r : {&narrow, &broad}) {
        EXPECT_EQ(r->objects[0].veiling, 0.0);
        EXPECT_FALSE(r->objects[0].chromatic);
        EXPECT_TRUE(r->objects[1].chromatic);
        EXPECT_GT(r->objects[1].veiling, 0.0);
    }
    EXPECT_GT(broad.objects[1].veiling, 2.0 * narrow.objects[1].veiling);
    EXPECT_LT(broad.objects[1].identity, narrow.objects[1].identity);
    EXPECT_LT(broad.objects[1].chroma, narrow.objects[1].chroma);
    EXPECT_LT(broad.objects[1].quality, narrow.objects[1].quality);
    EXPECT_LT(broad.score, narrow.score) << broad.highlight << " " << narrow.highlight;
    std::printf(
        "narrow: highlight %.4f score %.4f W %.3f I %.3f C %.1f; broad: highlight %.4f "
        "score %.4f W %.3f I %.3f C %.1f\n",
        narrow.highlight, narrow.score, narrow.objects[1].veiling, narrow.objects[1].identity,
        narrow.objects[1].chroma, broad.highlight, broad.score, broad.objects[1].veiling,
        broad.objects[1].identity, broad.objects[1].chroma);
}

TEST(SeparationScene, AssignmentLayersReproduceAFullRender) {
    // Layers of one render (both spheres Phong) for three candidates; the score they give an
    // assignment equals the score of a render made with that assignment, to float rounding.
    const SceneSpec spec = twoSpheres(8);
    std::vector<BrdfCandidate> candidates = {
        {"phong", {}, {}, ""}, {"ward", {}, {}, ""}, {"schlick_lewis", {}, {}, ""}};
    const AssignmentLayers layers = layersOf(spec, candidates);
    // The front sphere keeps Phong (it is Phong in `spec` too); the back one takes each model.
    for (int c = 0; c < 3; ++c) {
        const double fromLayers = assignmentScore(layers, {0, c});
        const double rendered = reportOf(twoSpheres(8, candidates[size_t(c)].model)).score;
        EXPECT_NEAR(fromLayers, rendered, 1e-5 * rendered + 1e-7) << candidates[size_t(c)].model;
        EXPECT_GT(rendered, 0.0);
    }
}

TEST(SeparationScene, ANarrowLobeSpecksAndABroadOneDoesNot) {
    // The two spheres at 64², lit from the camera: Phong's default lobe makes a highlight several
    // pixels across on each sphere; Cook–Torrance at m = 0.03 (a --tune variant) one narrower
    // than a pixel, which `lobe assign` must not offer (kSparkleLimit).
    const SceneSpec spec = twoSpheres(16);
    std::vector<BrdfCandidate> candidates = {{"phong", {}, {}, ""},
                                             {"cook_torrance", {"m=0.03"}, {}, ""}};
    const AssignmentLayers layers = layersOf(spec, candidates);
    // The front sphere faces the light at its centre: its narrow highlight is a speck. (On the
    // back sphere, 16 voxels aside, the 2 samples per pixel miss that narrow a highlight entirely
    // — the other face of sub-pixel highlights: they flicker in and out with the sampling.)
    const double broad = sparkleShare(layers.layer(0, 0).data(), spec.width, spec.height);
    const double narrow = sparkleShare(layers.layer(0, 1).data(), spec.width, spec.height);
    EXPECT_LT(broad, 0.05);
    EXPECT_GT(narrow, 2.0 * kSparkleLimit);
    EXPECT_LT(sparkleShare(layers.layer(1, 0).data(), spec.width, spec.height), 0.05);
}

TEST(SeparationScene, BrdfAlbedoKeyScalesTheLobeAndItsShading) {
    const std::string object =
        R"({"image": {"width": 8, "height": 8, "samples_per_pixel": 1},
            "camera": {"position": [15.5, 15.5, -90], "target": [15.5, 15.5, 15.5], "up": [0, 1, 0]},
            "lights": [{"position": [15.5, 15.5, -90], "intensity": 1}],
            "objects": [{"name": "ball", "kind": "isosurface", "source": {"path": "ball.raw",
              "dims": [32, 32, 32], "type": "float32"}, "iso": 0.5,
              "brdf": {"model": "ward", ALBEDO}}]})";
    const fs::path dir = fs::path(LOBE_BINARY_DIR) / "test-output" / "separation_scene";
    ballFile();
    auto with = [&](const std::string& albedo) {
        std::string json = object;
        json.replace(json.find("ALBEDO"), 6, albedo);
        return parseScene(json, dir.string(), "albedo");
    };
    const SceneSpec plain = with(R"("alpha_x": 0.1)");
    const SceneSpec scaled = with(R"("alpha_x": 0.1, "albedo": 0.05)");
    EXPECT_EQ(plain.objects[0].material.specularScale, 1.0);
    const double k = scaled.objects[0].material.specularScale;
    EXPECT_NEAR(k * normalIncidenceAlbedo(scaled.objects[0].material.specular), 0.05, 1e-12);
    // The shaded specular term is k times the unscaled one; the Lambert term is unchanged.
    ShadingPoint p;
    p.frame = Frame::fromNormal(Vec3(0, 0, 1));
    p.position = Vec3(0, 0, 0);
    const std::vector<PointLight> lights = {{Vec3(0.2, 0, 5), Spectrum(1.0)}};
    p.material = &plain.objects[0].material;
    const ShadingTerms a = shadeTerms(p, Vec3(0, 0, 1), lights);
    p.material = &scaled.objects[0].material;
    const ShadingTerms b = shadeTerms(p, Vec3(0, 0, 1), lights);
    EXPECT_GT(a.specular[0], 0.0);
    EXPECT_NEAR(b.specular[0], k * a.specular[0], 1e-12 * k * a.specular[0]);
    EXPECT_EQ(b.lambert[0], a.lambert[0]);
    // Out of range: one error naming the key.
    try {
        with(R"("albedo": 1.5)");
        ADD_FAILURE() << "albedo 1.5 accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("albedo"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace lobe
