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
//
// Shadows (SceneSpec::shadows). Each light's irradiance at a shaded point is multiplied by the
// transmittance from the point to the light (ShadingPoint::shadow): the product of (1 − opacity)
// over the casting surfaces' crossings and of (1 − α) over the casting volumes' samples on the
// shadow ray (the same marcher, step, opacity correction, clipping and empty-space skipping as
// camera rays; the discrete form of T = exp(−∫σ), Max 1995 eq. 3), stopped at 0 once below the
// scene's termination threshold. The shadow ray's lattice offset is drawn from the pixel
// sample's random stream, so images are the same for any thread count. With "cached", every
// shaded point reads the transmittance from a per-light cache (render/shadow_cache.h) over the
// casting objects' box, each node an exact shadow ray through surfaces and volumes; a point
// outside the box reads it where its shadow ray enters the box (nothing casts before). Volume
// samples read it at the point. A surface hit reads it off the surface: moved to the light's
// side along the normal by the interpolation cell's reach along it, h·(|nx| + |ny| + |nz|) (h
// the node spacing), so that all 8 nodes it interpolates lie beyond the surface's tangent plane
// and the surface does not shadow itself — the "normal offset" of shadow maps (D. Holbert,
// "Normal offset shadows", GDC 2011 poster), applied to a transmittance grid ("light volume":
// Behrens & Ratering 1998). Shadows of other surfaces closer than that reach are partly lost,
// and shadow edges are blurred over about a node spacing. With "surfaces": "exact"
// (SceneSpec::shadowCacheSurfaces false) surface hits cast exact shadow rays through the
// surfaces instead (sharp) and read the volumes' part from a second cache of the volumes alone.
// The caches' node rays march at SceneSpec::shadowCacheStepVoxels (or the scene's step if
// coarser). Caps cast no shadow.
#pragma once

#include "core/light.h"
#include "core/ray.h"
#include "core/spectrum.h"
#include "render/compositor.h"
#include "render/render_cost.h"
#include "volume/volume_marcher.h"

#include <memory>
#include <optional>
#include <vector>

namespace lobe {

struct SurfaceHit;  // surface/surface_scene.h

class ShadowCache;

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

// A cut face crossed by a camera ray (render/integrator.cpp, "Caps").
struct CapHit {
    double t = 0.0;
    int object = 0;  // surface object ID
    Vec3 normal{0.0};
};

// Per-thread marching state: one sampler per volume object (samplers hold OpenVDB accessors and
// must not be shared between threads) and the pending sample of each.
struct TraceState {
    std::vector<VolumeRaySampler> samplers;
    std::vector<VolumeSample> pending;
    std::vector<char> hasPending;
    CostCounters cost;  // counted and timed only when enabled (render/render_cost.h)
    std::vector<CapHit> caps;
    std::vector<VolumeRaySampler> shadowSamplers;  // shadow rays' own samplers, per volume
    std::vector<double> shadow;                    // per light: the transmittance of a point
};

struct ShadingPoint;

// One composited event along a ray — a volume sample, a surface hit or the backdrop — as the
// integrator adds it to the pixel: radiance `radiance` enters with factor `weight` = T·α (times
// the shading roulette's w0/w where it applies), so the pixel is Σ weight · radiance over the
// events. `point` is what was lit (null for the backdrop and for volume samples the roulette did
// not shade: those enter with weight 0). Per-object passes (render/aov.h) are built from these.
struct ShadingEvent {
    static constexpr int kBackdrop = -1;
    int object = kBackdrop;            // index into SceneSpec::objects, or kBackdrop
    double t = 0.0;                    // ray parameter
    double alpha = 0.0;                // the event's opacity
    double transmittanceBefore = 1.0;  // T in front of the event
    double weight = 0.0;               // factor of `radiance` in the pixel
    const ShadingPoint* point = nullptr;
    Spectrum radiance{0.0};
};

class EventSink {
public:
    virtual ~EventSink() = default;
    virtual void onEvent(const ShadingEvent& event) = 0;
};

class Integrator {
public:
    explicit Integrator(const Scene& scene);
    ~Integrator();
    // Forgets cached shadows (after the scene's lights moved: Scene::setView).
    void resetCaches();

    TraceState newState() const;
    // Radiance along `ray`; `jitter` ∈ [0,1) places the volumes' sample lattices, `rng` drives
    // the shading roulette (SceneSpec::shadingRoulette).
    // `sink`, when given, is told of every composited event (ShadingEvent).
    // `firstHit`, when given, is the ray's first surface hit found beforehand
    // (SurfaceScene::intersect8 on firstSurfaceSegment(ray); only where firstHitsInPackets()):
    // trace uses it in place of its own first search, the same hit.
    Spectrum trace(const Ray& ray, double jitter, Rng& rng, TraceState& state, RenderStats& stats,
                   EventSink* sink = nullptr,
                   const std::optional<SurfaceHit>* firstHit = nullptr) const;
    // Whether a camera ray's first surface hit is all trace() searches the surfaces for, on
    // firstSurfaceSegment(ray), so that the pixel loop may find it for 8 rays at once
    // (render_scene.cpp, renderRow): surfaces all opaque, no volumes, caps, clips or masks (T1's
    // exact skull: docs/performance.md).
    bool firstHitsInPackets() const { return firstHitsInPackets_; }
    // What trace() returns, at once, for a camera ray whose packet search met no surface when the
    // scene has no backdrop (and no sink is given): nothing is composited, so the empty
    // compositor's radiance, and the ray is counted. Inline, so that the pixel loop makes no call
    // for these rays (render_scene.cpp, renderRow; T1: 69 % of the rays).
    Spectrum traceMissedPacketRay(RenderStats& stats) const {
        ++stats.rays;
        return FrontToBackCompositor().radiance;
    }
    // The part of `ray` trace() first searches the surfaces on: up to the backdrop, if the ray
    // meets it before its end.
    Ray firstSurfaceSegment(const Ray& ray) const;

    // Transmittance from `from` to `light` through the casting objects (header, "Shadows"),
    // the shadow ray starting at distance tMin; `jitter` ∈ [0, 1) places the volumes' lattices.
    // stepScale ≥ 1 multiplies the volumes' steps (the cache's node rays); `surfaces` and
    // `volumes` choose what is counted.
    double lightTransmittance(const Vec3& from, const PointLight& light, double jitter,
                              TraceState& state, double tMin = 0.0, double stepScale = 1.0,
                              bool surfaces = true, bool volumes = true) const;
    const ShadowCache* shadowCache() const { return cache_.get(); }

private:
    // Distance to the backdrop along `ray`; ∞ when there is none or it lies beyond ray.tMax.
    double backdropDistance(const Ray& ray) const;
    // Fills state.shadow for a point (exact, or from the cache for volume samples); null when
    // the scene has no shadows.
    // `normal` is a surface hit's (geometric) normal, null for a volume sample.
    const double* shadowsAt(const Vec3& p, const Vec3* normal, Rng& rng, TraceState& state) const;

    const Scene& scene_;
    // Surfaces (with SceneSpec::shadowCacheSurfaces) and volumes; for all shaded points.
    std::unique_ptr<ShadowCache> cache_;
    std::unique_ptr<ShadowCache>
        volumeCache_;  // volumes only, for surface hits with exact surfaces
    bool shadowsOn_ = false;
    // Camera rays through translucent surfaces gather their hits in one traversal
    // (SurfaceScene::collectHits) instead of one traversal per hit; with opaque surfaces only
    // the first hit is ever needed and intersect() is used. 1 − opacity per surface object.
    bool gatherSurfaceHits_ = false;
    bool firstHitsInPackets_ = false;
    std::vector<double> surfaceTransmittance_;
    bool cachedOn_ = false;  // SceneSpec::shadows == "cached"
};

}  // namespace lobe
