// The integrator: radiance along one camera ray through a Scene (render/scene.h).
//
// Surface hits and the samples of every volume are composited front to back in depth order
// (render/compositor.h): the segment up to the next surface hit is filled with the volumes'
// samples, merged by depth across volumes (each keeps its own sample lattice,
// volume/volume_marcher.h), then the surface is composited with its opacity (the skull's 0.97
// lets what is behind it show), and the ray goes on behind it, until the transmittance drops
// below the scene's termination threshold or the ray reaches the backdrop. Every surface hit and
// every volume sample is lit with its own object's material (render/shading.h); shading is
// two-sided, since a ray passing through a translucent shell sees its inner side.
#pragma once

#include "core/ray.h"
#include "core/spectrum.h"
#include "volume/volume_marcher.h"

#include <vector>

namespace lobe {

class Rng;
class Scene;

// Counters of one render (summed over all rays), for reports and benchmarks.
struct RenderStats {
    double seconds = 0.0;
    long long rays = 0;
    long long surfaceHits = 0;
    long long volumeSamples = 0;  // samples composited (non-zero opacity)
    long long volumeShaded = 0;   // of those, shaded (not dropped by the shading roulette)
    // Lattice points reconstructed, and jumped over by empty-space skipping (VolumeRaySampler
    // counters, summed over threads and volumes; filled by RenderScene::render).
    long long volumeEvaluated = 0;
    long long volumeSkipped = 0;

    RenderStats& operator+=(const RenderStats& o);
};

// Per-thread marching state: one sampler per volume object (samplers hold OpenVDB accessors and
// must not be shared between threads) and the pending sample of each.
struct TraceState {
    std::vector<VolumeRaySampler> samplers;
    std::vector<VolumeSample> pending;
    std::vector<char> hasPending;
};

class Integrator {
public:
    explicit Integrator(const Scene& scene) : scene_(scene) {}

    TraceState newState() const;
    // Radiance along `ray`; `jitter` ∈ [0,1) places the volumes' sample lattices, `rng` drives
    // the shading roulette (SceneSpec::shadingRoulette).
    Spectrum trace(const Ray& ray, double jitter, Rng& rng, TraceState& state,
                   RenderStats& stats) const;

private:
    const Scene& scene_;
};

}  // namespace lobe
