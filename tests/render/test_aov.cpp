// Per-object passes (render/aov.h) on the paper's rendering 1 (skull surface, cortex and density
// map volumes, backdrop; the shading roulette on and off):
//  - additivity: per pixel, Σ_objects (lambert + specular) + backdrop equals the beauty image to
//    float rounding (the passes are stored as floats: relative 2e-6 plus an absolute 1e-9);
//  - asking for passes changes no beauty pixel, and the passes do not depend on the thread count;
//  - the per-model specular layers (for `lobe assign`) give, for each object's own model, the
//    luminance of its specular pass: the layers of other models are computed from the same
//    events, so they are what a render with that model would give;
//  - the object contributing most is the backdrop exactly where no object contributes, and the
//    depth lies between the camera and the backdrop.
#include "core/error.h"
#include "render/aov.h"
#include "render/render_scene.h"
#include "render/scene_file.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace lobe {
namespace {

SceneSpec tinyPaperScene(double roulette) {
    SceneSpec spec =
        loadSceneFile(std::string(LOBE_SOURCE_DIR) + "/assets/scenes/paper/rendering-01.json");
    spec.width = spec.height = 40;
    spec.samplesPerPixel = 2;
    spec.shadingRoulette = roulette;
    return spec;
}

Film renderPasses(const RenderScene& scene, int threads, const AovRequest* request, AovImage* out) {
    RenderOptions options;
    options.threads = threads;
    options.progress = false;
    return scene.render(options, nullptr, request, out);
}

AovRequest everything() {
    AovRequest r = AovRequest::parse("all");
    r.setModels({"phong", "ward", "ashikhmin_shirley", "he_torrance"});
    return r;
}

void expectAdditive(const Film& beauty, const AovImage& a) {
    int checked = 0;
    for (size_t p = 0; p < a.pixelCount(); ++p) {
        Spectrum sum = a.backdropAt(p);
        for (int o = 0; o < a.objectCount; ++o) sum += a.lambertAt(p, o) + a.specularAt(p, o);
        const Spectrum& b = beauty.pixels()[p];
        for (int band = 0; band < 3; ++band) {
            EXPECT_NEAR(sum[band], b[band], 2e-6 * std::abs(b[band]) + 1e-9) << "pixel " << p;
            ++checked;
        }
    }
    EXPECT_EQ(checked, 3 * beauty.width() * beauty.height());
}

TEST(Aov, PassesAddUpToTheBeautyImage) {
    for (double roulette : {0.0, 0.03}) {
        const RenderScene scene(tinyPaperScene(roulette), false);
        const AovRequest request = everything();
        AovImage passes;
        const Film withPasses = renderPasses(scene, 2, &request, &passes);
        const Film plain = renderPasses(scene, 2, nullptr, nullptr);
        for (size_t p = 0; p < plain.pixels().size(); ++p)
            for (int band = 0; band < 3; ++band)
                ASSERT_EQ(withPasses.pixels()[p][band], plain.pixels()[p][band]) << p;
        expectAdditive(withPasses, passes);
        // The scene shows every part: the backdrop, the skull's specular, a volume's lambert.
        double backdrop = 0, skullSpec = 0, cortexLambert = 0;
        for (size_t p = 0; p < passes.pixelCount(); ++p) {
            backdrop += luminance(passes.backdropAt(p));
            skullSpec += luminance(passes.specularAt(p, 0));
            cortexLambert += luminance(passes.lambertAt(p, 1));
        }
        EXPECT_GT(backdrop, 0.0);
        EXPECT_GT(skullSpec, 0.0);
        EXPECT_GT(cortexLambert, 0.0);
    }
}

TEST(Aov, PassesDoNotDependOnTheThreadCount) {
    const RenderScene scene(tinyPaperScene(0.03), false);
    const AovRequest request = everything();
    AovImage one, two;
    renderPasses(scene, 1, &request, &one);
    renderPasses(scene, 2, &request, &two);
    EXPECT_EQ(one.lambert, two.lambert);
    EXPECT_EQ(one.specular, two.specular);
    EXPECT_EQ(one.modelSpecular, two.modelSpecular);
    EXPECT_EQ(one.objectDepth, two.objectDepth);
    EXPECT_EQ(one.depth, two.depth);
    EXPECT_EQ(one.normal, two.normal);
    EXPECT_EQ(one.topObject, two.topObject);
}

TEST(Aov, OwnModelLayerEqualsTheSpecularPass) {
    // Rendering 1: skull Ward, cortex Ashikhmin–Shirley, density maps He–Torrance — each one of
    // the request's models. The model layers evaluate each model's series, so He–Torrance is
    // rendered from its series too (full renders read a table within 0.5 %, render/scene.cpp).
    SceneSpec spec = tinyPaperScene(0.03);
    spec.exactBrdf = true;
    const RenderScene scene(spec, false);
    const AovRequest request = everything();
    AovImage a;
    renderPasses(scene, 2, &request, &a);
    std::vector<size_t> own;
    for (const ObjectSpec& o : scene.spec().objects) {
        const auto it = std::find(request.models.begin(), request.models.end(), o.brdfModel);
        ASSERT_NE(it, request.models.end()) << o.brdfModel;
        own.push_back(size_t(it - request.models.begin()));
    }
    double total = 0.0;
    for (size_t p = 0; p < a.pixelCount(); ++p)
        for (int o = 0; o < a.objectCount; ++o) {
            const double layer = luminance(a.modelSpecularAt(p, o, int(own[size_t(o)])));
            const double pass = luminance(a.specularAt(p, o));
            EXPECT_NEAR(layer, pass, 2e-6 * pass + 1e-9) << "pixel " << p << " object " << o;
            total += layer;
        }
    EXPECT_GT(total, 0.0);
}

TEST(Aov, TopObjectAndDepthAreConsistent) {
    const RenderScene scene(tinyPaperScene(0.03), false);
    const AovRequest request = everything();
    AovImage a;
    renderPasses(scene, 2, &request, &a);
    const SceneSpec& spec = scene.spec();
    const double cameraToTarget = (spec.cameraTarget - spec.cameraPosition).length();
    int objectPixels = 0, backdropPixels = 0;
    for (size_t p = 0; p < a.pixelCount(); ++p) {
        double objects = 0.0;
        for (int o = 0; o < a.objectCount; ++o)
            objects += luminance(a.lambertAt(p, o) + a.specularAt(p, o));
        if (objects == 0.0) {
            EXPECT_EQ(a.topObject[p], -1.0f) << p;
            ++backdropPixels;
        } else if (a.topObject[p] >= 0.0f) {
            ++objectPixels;
        }
        // Every ray reaches opacity 0.5 by the backdrop (opaque): depth in (0, 3 × camera-target).
        EXPECT_GT(a.depth[p], 0.0f) << p;
        EXPECT_LT(a.depth[p], 3.0 * cameraToTarget) << p;
        const double n = std::sqrt(a.normal[p * 3] * a.normal[p * 3] +
                                   a.normal[p * 3 + 1] * a.normal[p * 3 + 1] +
                                   a.normal[p * 3 + 2] * a.normal[p * 3 + 2]);
        EXPECT_NEAR(n, 1.0, 1e-5) << p;
    }
    EXPECT_GT(objectPixels, 100);
    EXPECT_GT(backdropPixels, 100);
}

// Coverage (alpha, render/background.h) from composited events, by hand: one sample through an
// opaque surface (T 1 → 0, coverage 1) and one that meets nothing (coverage 0) average to 0.5;
// two volume samples of opacity 0.5 leave T = 0.25 before the backdrop: coverage 0.75 (the
// backdrop event does not count as coverage).
TEST(Aov, AlphaIsOneMinusTheTransmittanceThroughTheObjects) {
    AovRequest request;
    request.alpha = true;
    const std::vector<PointLight> lights;
    AovAccumulator acc(request, 2, lights);
    AovImage out = makeAovImage(request, 3, 1, 2);
    ASSERT_EQ(out.alpha.size(), 3u);
    acc.beginPixel();
    acc.beginSample(Vec3(0, 0, 1));
    acc.onEvent({0, 1.0, 1.0, 1.0, 1.0, nullptr, Spectrum(0.0)});
    acc.beginSample(Vec3(0, 0, 1));
    acc.finishPixel(2, 0, out);
    acc.beginPixel();
    acc.beginSample(Vec3(0, 0, 1));
    acc.onEvent({1, 1.0, 0.5, 1.0, 0.5, nullptr, Spectrum(0.0)});
    acc.onEvent({1, 1.1, 0.5, 0.5, 0.25, nullptr, Spectrum(0.0)});
    acc.onEvent({ShadingEvent::kBackdrop, 9.0, 1.0, 0.25, 0.25, nullptr, Spectrum(1.0)});
    acc.finishPixel(1, 1, out);
    acc.beginPixel();
    acc.beginSample(Vec3(0, 0, 1));
    acc.onEvent({ShadingEvent::kBackdrop, 9.0, 1.0, 1.0, 1.0, nullptr, Spectrum(1.0)});
    acc.finishPixel(1, 2, out);
    EXPECT_EQ(out.alpha[0], 0.5f);
    EXPECT_EQ(out.alpha[1], 0.75f);
    EXPECT_EQ(out.alpha[2], 0.0f);
}

// Asking for alpha changes no beauty pixel, and on rendering 1 alpha lies in [0, 1] with both
// covered and uncovered pixels.
TEST(Aov, AlphaLeavesTheBeautyAlone) {
    const RenderScene scene(tinyPaperScene(0.03), false);
    AovRequest request;
    request.alpha = true;
    AovImage passes;
    const Film withAlpha = renderPasses(scene, 2, &request, &passes);
    const Film plain = renderPasses(scene, 2, nullptr, nullptr);
    for (size_t p = 0; p < plain.pixels().size(); ++p)
        for (int band = 0; band < 3; ++band)
            ASSERT_EQ(withAlpha.pixels()[p][band], plain.pixels()[p][band]) << p;
    float lo = 1.0f, hi = 0.0f;
    for (float a : passes.alpha) {
        ASSERT_TRUE(a >= 0.0f && a <= 1.0f);
        lo = std::min(lo, a);
        hi = std::max(hi, a);
    }
    EXPECT_EQ(lo, 0.0f);
    EXPECT_GT(hi, 0.9f);
}

TEST(Aov, ParseNamesABadPass) {
    EXPECT_THROW(AovRequest::parse("objects,specularity"), Error);
    EXPECT_THROW(AovRequest::parse(""), Error);
    const AovRequest r = AovRequest::parse("depth,id");
    EXPECT_TRUE(r.depth && r.topObject && !r.objects && !r.normal);
}

}  // namespace
}  // namespace lobe
