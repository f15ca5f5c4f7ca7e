// The hybrid surface/volume renderer. A RenderScene is built once from a SceneSpec — volumes
// loaded (each file once, however many objects use it), object transforms applied, iso-surfaces
// handed to Embree (exact or meshed), density volumes prepared for ray marching with
// empty-space skipping — and then renders images in parallel tiles.
//
// Along each camera ray, surface hits and the samples of every volume are composited front to
// back in depth order (Porter & Duff "over"; Levoy 1990): the segment up to the next surface hit
// is filled with the volumes' samples, merged by depth across volumes (each keeps its own sample
// lattice, volume/volume_marcher.h), then the surface is composited with its opacity (the
// skull's 0.97 lets what is behind it show), and the ray goes on behind it, until the
// transmittance drops below the scene's termination threshold or the ray reaches the backdrop.
// Every surface hit and every volume sample is shaded with its own object's BRDF plus Lambert
// under the point lights (materials/material.h); shading is two-sided, since a ray passing
// through a translucent shell sees its inner side.
#pragma once

#include "render/backdrop.h"
#include "render/scene_description.h"
#include "core/camera.h"
#include "core/film.h"

#include <memory>
#include <string>
#include <vector>

namespace lobe {

class ProgressReporter;
class Rng;
class SurfaceScene;
class DvrVolume;

struct RenderOptions {
    int threads = 0;
    bool progress = true;
    std::string label = "render";
    ProgressReporter* sharedProgress = nullptr;  // see core/tile_scheduler.h
};

// Counters of one render (summed over all rays), for reports and benchmarks.
struct RenderStats {
    double seconds = 0.0;
    long long rays = 0;
    long long surfaceHits = 0;
    long long volumeSamples = 0;  // samples composited (non-zero opacity)
    long long volumeShaded = 0;   // of those, shaded (not dropped by the shading roulette)
    // render() only: lattice points reconstructed, and jumped over by empty-space skipping
    // (VolumeRaySampler counters, summed over threads and volumes).
    long long volumeEvaluated = 0;
    long long volumeSkipped = 0;
};

class RenderScene {
public:
    // Loads every source and builds the acceleration structures; throws lobe::Error naming the
    // scene file and the object for anything it cannot load.
    explicit RenderScene(const SceneSpec& spec, bool progress = true);
    ~RenderScene();
    RenderScene(const RenderScene&) = delete;
    RenderScene& operator=(const RenderScene&) = delete;

    const SceneSpec& spec() const { return spec_; }
    // Renders at the spec's size, samples and seed.
    Film render(const RenderOptions& options, RenderStats* stats = nullptr) const;
    // Radiance along one ray; `jitter` ∈ [0,1) places the volumes' sample lattices, `seed`
    // drives the shading roulette (SceneSpec::shadingRoulette). For tests.
    Spectrum traceRay(const Ray& ray, double jitter, uint64_t seed = 0) const;
    // The value render() gives pixel (x, y): the mean over the spec's jittered samples. For
    // benchmarks that compare a subset of pixels against a reference.
    Spectrum renderPixel(int x, int y) const;

private:
    struct SurfaceObject;
    struct VolumeObject;
    struct ThreadState;
    ThreadState newThreadState() const;
    Spectrum trace(const Ray& ray, double jitter, Rng& rng, ThreadState& state,
                   RenderStats& stats) const;
    Spectrum pixel(int x, int y, ThreadState& state, RenderStats& stats) const;

    SceneSpec spec_;
    PinholeCamera camera_;
    Backdrop backdrop_;
    std::unique_ptr<SurfaceScene> surfaces_;
    std::vector<SurfaceObject> surfaceObjects_;  // by surface object ID
    std::vector<VolumeObject> volumeObjects_;
};

}  // namespace lobe
