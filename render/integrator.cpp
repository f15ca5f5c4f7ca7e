#include "render/integrator.h"

#include "core/rng.h"
#include "render/compositor.h"
#include "render/scene.h"
#include "render/shading.h"
#include "render/shadow_cache.h"
#include "surface/surface_scene.h"
#include "volume/grid_world.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

namespace lobe {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
// At most this many surfaces are composited along one ray: a guard against pathological
// geometry, far above what a head (skin, two skull walls, …) produces.
constexpr int kMaxSurfaceHits = 64;

// Shades a point (render/shading.h); under `lobe cost` (cost non-null) also counts the object's
// BRDF evaluations and shaded points and adds the shading time to the object and to `part`
// (the volume or surface shading seconds). The radiance is the same either way, bit for bit.
Spectrum shadeCounted(const ShadingPoint& point, const Vec3& toViewer,
                      const std::vector<PointLight>& lights, CostCounters* cost, int objectIndex,
                      double CostCounters::*part) {
    if (!cost) return shade(point, toViewer, lights);
    ObjectCost& oc = cost->objects[size_t(objectIndex)];
    const double t0 = steadySeconds();
    const Spectrum L = shade(point, toViewer, lights, oc.brdfEvaluations);
    const double dt = steadySeconds() - t0;
    cost->*part += dt;
    oc.shadingSeconds += dt;
    ++oc.shadedPoints;
    return L;
}
}  // namespace

RenderStats& RenderStats::operator+=(const RenderStats& o) {
    rays += o.rays;
    surfaceHits += o.surfaceHits;
    volumeSamples += o.volumeSamples;
    volumeShaded += o.volumeShaded;
    volumeEvaluated += o.volumeEvaluated;
    volumeSkipped += o.volumeSkipped;
    return *this;
}

Integrator::Integrator(const Scene& scene) : scene_(scene) {
    for (const SceneSurface& so : scene_.surfaceObjects()) {
        surfaceTransmittance_.push_back(1.0 - so.spec->opacity);
        if (so.spec->opacity < 1.0) gatherSurfaceHits_ = true;
    }
    bool anyCaps = false;
    for (const SceneSurface& so : scene_.surfaceObjects()) anyCaps = anyCaps || so.caps;
    firstHitsInPackets_ = scene_.surfaces() && scene_.surfaces()->packetsSupported() &&
                          scene_.volumeObjects().empty() && !gatherSurfaceHits_ && !anyCaps;
    resetCaches();
}

Integrator::~Integrator() = default;

void Integrator::resetCaches() {
    cache_.reset();
    volumeCache_.reset();
    const SceneSpec& spec = scene_.spec();
    shadowsOn_ = spec.shadows != "off" && !spec.lights.empty();
    cachedOn_ = shadowsOn_ && spec.shadows == "cached";
    if (!cachedOn_) return;
    // Over the world boxes (as clipped) of what the cache holds — the casting volumes, and with
    // cached surface shadows the casting surfaces too — nodes shadowCacheVoxels of the finest
    // such object's voxels apart. Outside that box nothing casts a shadow.
    Vec3 lo(kInf), hi(-kInf), vlo(kInf), vhi(-kInf);
    double voxel = kInf;
    auto grow = [&](int objectIndex, const openvdb::GridBase& grid, Vec3& a, Vec3& b) {
        const WorldBox& box = scene_.objectBoxes()[size_t(objectIndex)];
        if (box.empty()) return;
        for (int k = 0; k < 3; ++k) {
            a[k] = std::min(a[k], box.lo[k]);
            b[k] = std::max(b[k], box.hi[k]);
        }
        const openvdb::Vec3d v = gridVoxelSize(grid);
        voxel = std::min(voxel, std::min(v.x(), std::min(v.y(), v.z())));
    };
    for (const SceneVolume& vo : scene_.volumeObjects())
        if (vo.spec->castsShadows) {
            grow(vo.objectIndex, vo.volume->grid(), lo, hi);
            grow(vo.objectIndex, vo.volume->grid(), vlo, vhi);
        }
    if (spec.shadowCacheSurfaces)
        for (const SceneSurface& so : scene_.surfaceObjects())
            if (so.spec->castsShadows && so.field) grow(so.objectIndex, *so.field, lo, hi);
    if (!std::isfinite(voxel)) return;  // nothing casts: no shadows to cache
    const int lights = int(spec.lights.size());
    if (lo.x <= hi.x)
        cache_ = std::make_unique<ShadowCache>(lo, hi, voxel * spec.shadowCacheVoxels, lights);
    if (!spec.shadowCacheSurfaces && vlo.x <= vhi.x)
        volumeCache_ =
            std::make_unique<ShadowCache>(vlo, vhi, voxel * spec.shadowCacheVoxels, lights);
}

double Integrator::lightTransmittance(const Vec3& from, const PointLight& light, double jitter,
                                      TraceState& st, double tMin, double stepScale,
                                      bool withSurfaces, bool withVolumes) const {
    const Vec3 toLight = light.position - from;
    const double d = toLight.length();
    if (!(d > tMin)) return 1.0;
    Ray r;
    r.o = from;
    r.d = toLight / d;
    r.tMin = tMin;
    r.tMax = d;
    const double cutoff = scene_.spec().terminationTransmittance;
    double T = 1.0;
    const SurfaceScene* surfaces = withSurfaces ? scene_.surfaces() : nullptr;
    if (surfaces) {
        Ray seg = r;
        for (int h = 0; h < kMaxSurfaceHits; ++h) {
            const std::optional<SurfaceHit> hit = surfaces->intersect(seg);
            if (!hit) break;
            const ObjectSpec& o = *scene_.surfaceObjects()[size_t(hit->objectId)].spec;
            if (o.castsShadows) {
                T *= 1.0 - o.opacity;
                if (T < cutoff || T <= 0.0) return 0.0;
            }
            seg.tMin = hit->t + 1e-6 * (1.0 + hit->t);
        }
    }
    const std::vector<SceneVolume>& volumes = scene_.volumeObjects();
    for (size_t i = 0; i < volumes.size() && withVolumes; ++i) {
        if (!volumes[i].spec->castsShadows) continue;
        VolumeRaySampler& sampler = st.shadowSamplers[i];
        const double xi = jitter + 0.6180339887498949 * double(i);
        if (!sampler.begin(r, xi - std::floor(xi), stepScale)) continue;
        VolumeSample s;
        while (sampler.next(d, s, false)) {
            T *= 1.0 - s.alpha;
            if (T < cutoff) return 0.0;
        }
    }
    return T;
}

const double* Integrator::shadowsAt(const Vec3& p, const Vec3* normal, Rng& rng,
                                    TraceState& st) const {
    const SceneSpec& spec = scene_.spec();
    if (!shadowsOn_) return nullptr;
    st.shadow.resize(spec.lights.size());
    const bool volumeSample = normal == nullptr;
    // Surfaces start their shadow rays a hair off the surface (relative to the coordinates'
    // size: the exact roots are ~1e-10 voxel accurate, Embree's float meshes ~1e-7 relative).
    const double tMin =
        volumeSample
            ? 0.0
            : 1e-5 * (1.0 + std::max(std::abs(p.x), std::max(std::abs(p.y), std::abs(p.z))));
    const double jitter = rng.uniform();
    if (!cachedOn_) {
        for (size_t l = 0; l < spec.lights.size(); ++l)
            st.shadow[l] = lightTransmittance(p, spec.lights[l], jitter, st, tMin);
        return st.shadow.data();
    }
    const double scale = std::max(1.0, spec.shadowCacheStepVoxels / spec.volumeStepVoxels);
    // The cache's value at q, or where the segment q → light enters its box (nothing casts
    // outside it); 1 when the segment misses the box or there is no cache.
    auto cached = [&](const ShadowCache* cache, int l, const Vec3& q, bool surfaces) {
        const PointLight& light = spec.lights[size_t(l)];
        Vec3 e;
        if (!cache || !cache->entry(q, light.position, e)) return 1.0;
        return cache->lookup(l, e, [&](const Vec3& node) {
            return lightTransmittance(node, light, 0.5, st, 0.0, scale, surfaces, true);
        });
    };
    for (size_t l = 0; l < spec.lights.size(); ++l) {
        const PointLight& light = spec.lights[l];
        if (volumeSample) {
            // Volume samples: surfaces and volumes from the cache (header, "Shadows").
            st.shadow[l] = cached(cache_.get(), int(l), p, true);
        } else if (spec.shadowCacheSurfaces) {
            // Surface hits: from the nodes on the light's side of the tangent plane (header,
            // "Shadows"); outside the cache's box from where the shadow ray enters it.
            Vec3 e;
            if (!cache_ || !cache_->entry(p, light.position, e)) {
                st.shadow[l] = 1.0;
                continue;
            }
            const Vec3 n = normal->dot(light.position - p) >= 0.0 ? *normal : -*normal;
            const auto node = [&](const Vec3& x) {
                return lightTransmittance(x, light, 0.5, st, 0.0, scale, true, true);
            };
            double T =
                e != p ? cache_->lookup(int(l), e, node) : cache_->lookupAbove(int(l), p, n, node);
            if (T < 0.0) {
                // No node of the cell above the plane (p on a cell face, n along an axis): the
                // cell beyond, reached by moving off the surface by its reach along n.
                const double reach =
                    1.01 * cache_->spacing() * (std::abs(n.x) + std::abs(n.y) + std::abs(n.z));
                T = cached(cache_.get(), int(l), p + n * reach, true);
            }
            st.shadow[l] = T;
        } else {
            // Surfaces exactly, volumes from their own cache.
            double T = lightTransmittance(p, light, jitter, st, tMin, 1.0, true, false);
            if (T > 0.0) T *= cached(volumeCache_.get(), int(l), p, false);
            st.shadow[l] = T;
        }
    }
    return st.shadow.data();
}

TraceState Integrator::newState() const {
    TraceState st;
    for (const SceneVolume& vo : scene_.volumeObjects()) st.samplers.emplace_back(*vo.volume);
    if (scene_.spec().shadows != "off")
        for (const SceneVolume& vo : scene_.volumeObjects())
            st.shadowSamplers.emplace_back(*vo.volume);
    st.pending.resize(scene_.volumeObjects().size());
    st.hasPending.resize(scene_.volumeObjects().size());
    return st;
}

double Integrator::backdropDistance(const Ray& ray) const {
    const Backdrop& backdrop = scene_.backdrop();
    const double t = backdrop.enabled() ? backdrop.intersect(ray) : kInf;
    return t > ray.tMax ? kInf : t;
}

Ray Integrator::firstSurfaceSegment(const Ray& ray) const {
    Ray segment = ray;
    segment.tMax = std::min(ray.tMax, backdropDistance(ray));
    return segment;
}

Spectrum Integrator::trace(const Ray& ray, double jitter, Rng& rng, TraceState& st,
                           RenderStats& stats, EventSink* sink,
                           const std::optional<SurfaceHit>* firstHit) const {
    const SceneSpec& spec = scene_.spec();
    const Backdrop& backdrop = scene_.backdrop();
    if (firstHit && !firstHit->has_value() && !backdrop.enabled() && !sink) {
        // A camera ray of a packet scene (firstHitsInPackets: opaque surfaces only, no volumes
        // or caps) that met no surface, with no backdrop: nothing is composited, so its radiance
        // is the empty compositor's, as the loop below would return it (T1: 69 % of the rays;
        // the pixel loop calls traceMissedPacketRay for them instead).
        return traceMissedPacketRay(stats);
    }
    ++stats.rays;
    const SurfaceScene* surfaces = scene_.surfaces();
    const std::vector<SceneVolume>& volumeObjects = scene_.volumeObjects();
    const double rouletteOffset = rng.uniform();  // the shading roulette's offset (below)
    FrontToBackCompositor out(spec.terminationTransmittance);

    const size_t nv = volumeObjects.size();
    CostCounters* cost = st.cost.enabled ? &st.cost : nullptr;  // `lobe cost` only
    const double tBegin = cost && nv > 0 ? steadySeconds() : 0.0;
    for (size_t i = 0; i < nv; ++i) {
        // Each volume gets its own jitter (a fixed irrational offset), so coincident lattices of
        // volumes sharing a grid do not sample the same depths.
        const double xi = jitter + 0.6180339887498949 * double(i);
        st.samplers[i].begin(ray, xi - std::floor(xi));
        st.hasPending[i] = 0;
    }
    if (cost && nv > 0)
        cost->volumeSeconds += steadySeconds() - tBegin;  // clipping, lattice set-up
    // The ray ends at ray.tMax (the volume samplers clip to it too): a backdrop beyond it is not
    // seen.
    const double tBackdrop = backdropDistance(ray);
    const Vec3 toViewer = -ray.d;

    const double w0 = spec.shadingRoulette;
    ShadingRoulette roulette(rouletteOffset, w0);
    // Composites every volume sample with t < tEnd in depth order; false once opaque. Each volume
    // without a pending sample is asked once for its next sample before tEnd; after that only
    // the volume whose sample was composited is asked again (a sampler that returned false for
    // tEnd returns false for it again and moves nothing: VolumeRaySampler::next).
    auto volumesUpTo = [&](double tEnd) {
        if (nv == 0) return true;
        for (size_t i = 0; i < nv; ++i)
            if (!st.hasPending[i])
                st.hasPending[i] = st.samplers[i].next(tEnd, st.pending[i], false);
        for (;;) {
            int best = -1;
            if (nv == 1) {
                best = st.hasPending[0] ? 0 : -1;
            } else {
                double tBest = kInf;
                for (size_t i = 0; i < nv; ++i)
                    if (st.hasPending[i] && (best < 0 || st.pending[i].t < tBest)) {
                        best = int(i);
                        tBest = st.pending[i].t;
                    }
            }
            if (best < 0) return true;
            const SceneVolume& vo = volumeObjects[best];
            VolumeSample& s = st.pending[best];
            // Russian roulette on shading (Arvo & Kirk 1990): a sample whose weight in the pixel,
            // w = T·α, is below the scene's threshold w0 is shaded with probability w/w0 and then
            // counted w0/w times; the expected radiance is unchanged (no bias), only the
            // gradient and BRDF work of faint samples is saved. The transmittance is always
            // updated exactly, so the weights along a ray do not depend on the draws. The draws
            // are systematic (one uniform offset per ray, as in systematic resampling — Kitagawa
            // 1996): a running sum of w/w0 from that offset, and a sample is shaded when the sum
            // crosses an integer (ShadingRoulette, render/compositor.h). Each sample's
            // probability is still exactly w/w0, but the shaded samples are spread evenly over
            // the ray's faint weight instead of clumping, which lowers the noise at the same cost.
            const double weight = out.transmittance * s.alpha;
            const bool shade = weight >= w0 || roulette.draw(weight);
            if (shade) {
                st.samplers[best].addNormal(s);
                ShadingPoint point;
                point.material = &vo.spec->material;
                point.colour = s.colour;
                point.highlight = vo.spec->highlightTakesLight ? Spectrum(1.0) : s.colour;
                point.position = s.position;
                point.hasFrame = s.hasNormal;
                // The tangents only where the material needs them (render/shading.h, setNormal).
                if (s.hasNormal) point.setNormal(s.normal, vo.tangent.axis, vo.tangent.fallback);
                point.shadow = shadowsAt(s.position, nullptr, rng, st);
                Spectrum L = shadeCounted(point, toViewer, spec.lights, cost, vo.objectIndex,
                                          &CostCounters::volumeShadingSeconds);
                const double scale = weight < w0 ? w0 / weight : 1.0;
                if (weight < w0) L *= scale;
                ++stats.volumeShaded;
                if (sink)
                    sink->onEvent({vo.objectIndex, s.t, s.alpha, out.transmittance, weight * scale,
                                   &point, L});
                out.add(s.alpha, L);
            } else {
                if (sink)
                    sink->onEvent({vo.objectIndex, s.t, s.alpha, out.transmittance, 0.0, nullptr,
                                   Spectrum(0.0)});
                // Radiance 0: only the transmittance changes (FrontToBackCompositor::pass).
                out.pass(s.alpha);
            }
            ++stats.volumeSamples;
            if (out.terminated()) {
                st.hasPending[best] = 0;
                return false;
            }
            st.hasPending[best] = st.samplers[best].next(tEnd, s, false);
        }
    };

    Ray segment = ray;
    segment.tMax = std::min(ray.tMax, tBackdrop);
    // Caps (core/clip.h): where the ray crosses a capped clip boundary inside a clipped
    // iso-surface's solid, the cut face is a surface of that object with the boundary's normal.
    std::vector<CapHit>& caps = st.caps;
    caps.clear();
    if (surfaces)
        for (const SceneSurface& so : scene_.surfaceObjects()) {
            if (!so.caps) continue;
            const ClipIntervals iv = clipRay(segment, so.clip);
            for (int i = 0; i < iv.count; ++i)
                for (const ClipBound* b : {&iv.v[i].lo, &iv.v[i].hi})
                    if (b->clipped && b->cap && so.inside(ray.at(b->t)))
                        caps.push_back(
                            {b->t, int(&so - scene_.surfaceObjects().data()), b->normal});
        }
    std::sort(caps.begin(), caps.end(), [](const CapHit& a, const CapHit& b) { return a.t < b.t; });
    size_t nextCap = 0;
    // The next surface hit at or beyond segment.tMin: with translucent surfaces from the hits
    // one traversal gathered (SurfaceScene::collectHits), searching again only when that list
    // was cut short and is used up; entries before segment.tMin (consumed, or one hit found twice)
    // are passed over. An entry returned is not consumed until segment.tMin moves past it (a cap
    // may come first).
    HitList gathered;
    int gatheredPos = 0;
    bool gatheredValid = false;
    const auto nextSurfaceHit = [&]() -> std::optional<SurfaceHit> {
        if (!gatherSurfaceHits_) return surfaces->intersect(segment);
        for (int guard = 0; guard < kMaxSurfaceHits; ++guard) {
            if (!gatheredValid) {
                surfaces->collectHits(segment, surfaceTransmittance_, spec.terminationTransmittance,
                                      gathered);
                gatheredPos = 0;
                gatheredValid = true;
            }
            for (; gatheredPos < gathered.count; ++gatheredPos)
                if (gathered.hits[gatheredPos].t >= segment.tMin)
                    return surfaces->shadeHit(segment, gathered.hits[gatheredPos]);
            if (gathered.complete) return std::nullopt;
            gatheredValid = false;
        }
        return std::nullopt;
    };
    for (int hits = 0;; ++hits) {
        std::optional<SurfaceHit> hit;
        const double t0 = cost ? steadySeconds() : 0.0;
        if (firstHit) {
            // Found beforehand on this very segment (firstHitsInPackets: no caps;
            // firstSurfaceSegment).
            hit = *firstHit;
            firstHit = nullptr;
        } else if (surfaces && hits < kMaxSurfaceHits) {
            hit = nextSurfaceHit();
        }
        if (nextCap < caps.size() && (!hit || caps[nextCap].t <= hit->t)) {
            // The cap comes first: it is the event, the surface hit is found again after it.
            const CapHit& c = caps[nextCap++];
            hit = SurfaceHit{c.t, ray.at(c.t), c.normal, c.object, 0};
        }
        const double t1 = cost ? steadySeconds() : 0.0;
        const double tEnd = hit ? hit->t : std::min(tBackdrop, kInf);
        const bool open = volumesUpTo(tEnd);
        if (cost) {
            cost->surfaceSeconds += t1 - t0;
            if (nv > 0) cost->volumeSeconds += steadySeconds() - t1;
        }
        if (!open) return out.radiance;
        if (!hit) break;
        ++stats.surfaceHits;
        const SceneSurface& so = scene_.surfaceObjects()[hit->objectId];
        ShadingPoint point;
        point.material = &so.spec->material;
        point.colour = so.spec->color;
        point.highlight = so.spec->highlightTakesLight ? Spectrum(1.0) : so.spec->color;
        point.position = hit->position;
        const Vec3 normal = so.smoothGrid ? smoothIsoNormal(*so.smoothGrid, so.smoothGeometry,
                                                            hit->position, hit->normal)
                                          : hit->normal;
        point.setNormal(normal, so.tangent.axis, so.tangent.fallback);
        point.shadow = shadowsAt(hit->position, &hit->normal, rng, st);
        const Spectrum L = shadeCounted(point, toViewer, spec.lights, cost, so.objectIndex,
                                        &CostCounters::surfaceShadingSeconds);
        if (sink)
            sink->onEvent({so.objectIndex, hit->t, so.spec->opacity, out.transmittance,
                           out.transmittance * so.spec->opacity, &point, L});
        out.add(so.spec->opacity, L);
        if (out.terminated()) return out.radiance;
        segment.tMin = hit->t + 1e-6 * (1.0 + hit->t);
    }
    if (tBackdrop < kInf) {
        const Spectrum L = backdrop.radiance(ray.at(tBackdrop), spec.lights);
        if (sink)
            sink->onEvent({ShadingEvent::kBackdrop, tBackdrop, 1.0, out.transmittance,
                           out.transmittance, nullptr, L});
        out.add(1.0, L);
    }
    return out.radiance;
}

}  // namespace lobe
