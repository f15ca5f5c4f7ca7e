// The renderer: a Scene (render/scene.h) and its Integrator (render/integrator.h) behind one
// object that renders images through the one pixel loop (core/pixel_loop.h). Sample s of pixel
// (x, y) takes its jitter from the pixel's stream, a camera ray through the jittered point, one
// more draw for the volumes' lattice offset, and the rest of the stream for the shading
// roulette; the pixel is the mean over the scene's samples per pixel.
#pragma once

#include "core/film.h"
#include "render/aov.h"
#include "render/integrator.h"
#include "render/scene.h"

#include <string>
#include <vector>

namespace lobe {

class ProgressReporter;
class TileSource;

struct RenderOptions {
    int threads = 0;
    bool progress = true;
    std::string label = "render";
    ProgressReporter* sharedProgress = nullptr;  // see core/tile_scheduler.h
    int rowBegin = 0, rowEnd = -1;               // render only these rows (a shard; others 0)
    // With rows given: the film (and the passes) hold only rows [rowBegin, rowEnd), its row 0
    // being image row rowBegin — one band of a poster (figure/figure_output.h), whose memory is
    // the band's, not the image's. The pixels are the same as in the whole image.
    bool bandOnly = false;
    TileSource* tileSource = nullptr;  // tiles shared with other processes (cluster/cluster.h)
    // When set, the render also counts BRDF evaluations per object and times its parts into
    // *cost (render/render_cost.h); the image is the same with or without.
    RenderCost* cost = nullptr;
};

class RenderScene {
public:
    // Loads every source and builds the acceleration structures; throws lobe::Error naming the
    // scene file and the object for anything it cannot load.
    // With `cache`, sources come from (and are kept in) it: a batch loads each file once.
    explicit RenderScene(const SceneSpec& spec, bool progress = true, VolumeCache* cache = nullptr)
        : scene_(spec, progress, cache), integrator_(scene_) {}

    const SceneSpec& spec() const { return scene_.spec(); }
    // Another view of the same scene (Scene::setView): an orbit's next frame.
    void setView(const SceneSpec& frame) {
        scene_.setView(frame);
        integrator_.resetCaches();  // the lights moved with the camera
    }
    const Scene& scene() const { return scene_; }
    // Renders at the spec's size, samples and seed. With `aov` and `aovs`, also the per-object
    // passes (render/aov.h) of the same samples; the beauty image is the same either way.
    Film render(const RenderOptions& options, RenderStats* stats = nullptr,
                const AovRequest* aov = nullptr, AovImage* aovs = nullptr) const;
    // Radiance along one ray; `jitter` ∈ [0,1) places the volumes' sample lattices, `seed`
    // drives the shading roulette (SceneSpec::shadingRoulette). For tests.
    Spectrum traceRay(const Ray& ray, double jitter, uint64_t seed = 0) const;
    // The value render() gives pixel (x, y). For benchmarks that compare a subset of pixels
    // against a reference.
    Spectrum renderPixel(int x, int y) const;
    // A pilot of the render's cost, for an honest progress display (core/progress.h,
    // CostSchedule): one sample traced through every `stride`-th pixel of every `stride`-th row
    // (from stride/2), each such row timed by its thread's CPU clock (threadCpuSeconds,
    // render/render_cost.h) and scaled to the stride² pixels and the samples per pixel it stands
    // for. Returns the estimated CPU seconds of each image row (0 for the rows between). The
    // image and every later render are unaffected.
    std::vector<double> costProfile(int stride, int threads = 0) const;

private:
    Scene scene_;
    Integrator integrator_;
};

}  // namespace lobe
