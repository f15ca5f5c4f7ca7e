// The Embree user-geometry glue shared by the surfaces that find their own roots (the exact
// iso-surface and the level set): bounds, intersect and occluded callbacks over a Surface that
// provides
//   const AffineMap& primitiveSpace() const;   // world → the space its primitives live in
//   const std::array<float, 6>& primitiveBounds(unsigned prim) const;   // world AABB
//   bool intersectPrimitive(unsigned prim, const Vec3& o, const Vec3& d, double tMin,
//                           double tMax, double& t) const;   // the ray in primitive space
// (An affine map keeps the ray parameter t, so t is the same in both spaces.)
// Single rays from SurfaceScene carry their double-precision ray in RayContext (surface_scene.h)
// and get their double hit distance back through it.
#pragma once

#include "surface/affine_map.h"
#include "surface/surface_scene.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <new>
#include <type_traits>

namespace lobe::user_geometry {

// The smallest float not below t (Embree's tfar for a double hit distance t).
inline float floatAtLeast(double t) {
    const float f = static_cast<float>(t);
    return double(f) < t ? std::nextafter(f, std::numeric_limits<float>::infinity()) : f;
}

// The packet lane of lane i (RayContext::lanes, SurfaceScene::intersect8), or null.
inline RayContext::Lane* packetLane(RTCRayN* ray, unsigned N, unsigned i, const RayContext* ctx) {
    if (!ctx || !ctx->lanes) return nullptr;
    const unsigned id = RTCRayN_id(ray, N, i);
    return id < ctx->laneCount && ctx->lanes[id].ray ? &ctx->lanes[id] : nullptr;
}

// The ray of lane i: the caller's double ray when SurfaceScene passed one (single rays; for a
// packet's lanes `lane`, packetLane's answer, which the caller needs too), else Embree's float
// copy. tMax also respects the best double hit recorded so far. Inlined, as are primitiveRay and
// intersectClipped: they run once per brick a ray reaches.
[[gnu::always_inline]] inline void laneRay(RTCRayN* ray, unsigned N, unsigned i,
                                           const RayContext* ctx, const RayContext::Lane* lane,
                                           Vec3& o, Vec3& d, double& tMin, double& tMax) {
    const double tfar = RTCRayN_tfar(ray, N, i);
    if (N == 1 && ctx && ctx->ray) {
        o = ctx->ray->o;
        d = ctx->ray->d;
        tMin = std::max(0.0, ctx->ray->tMin);
        tMax = std::min(tfar, ctx->ray->tMax);
        if (ctx->geomId != RTC_INVALID_GEOMETRY_ID) tMax = std::min(tMax, ctx->tHit);
    } else if (const RayContext::Lane* l = N == 1 ? packetLane(ray, N, i, ctx) : lane) {
        // The same for a packet's lane.
        o = l->ray->o;
        d = l->ray->d;
        tMin = std::max(0.0, l->ray->tMin);
        tMax = std::min(tfar, l->ray->tMax);
        if (l->geomId != RTC_INVALID_GEOMETRY_ID) tMax = std::min(tMax, l->tHit);
    } else {
        o = Vec3(RTCRayN_org_x(ray, N, i), RTCRayN_org_y(ray, N, i), RTCRayN_org_z(ray, N, i));
        d = Vec3(RTCRayN_dir_x(ray, N, i), RTCRayN_dir_y(ray, N, i), RTCRayN_dir_z(ray, N, i));
        tMin = RTCRayN_tnear(ray, N, i);
        tMax = tfar;
    }
}

// The ray in a surface's primitive space: its origin and direction there, unless the surface
// names a type of its own (`using PrimitiveRay = …`, constructible from them, with members o
// and d), which its intersectPrimitive(prim, ray, tMin, tMax, t) then takes (the brick walk's
// WalkRay, brick_walk.h: what every brick derives from the ray alone, made once per ray).
struct IndexRay {
    Vec3 o, d;
    IndexRay() = default;
    IndexRay(const Vec3& origin, const Vec3& direction) : o(origin), d(direction) {}
};
template <typename Surface, typename = void>
struct PrimitiveRayOf {
    using type = IndexRay;
};
template <typename Surface>
struct PrimitiveRayOf<Surface, std::void_t<typename Surface::PrimitiveRay>> {
    using type = typename Surface::PrimitiveRay;
};
template <typename Surface>
bool intersectPrimitive(const Surface& self, unsigned prim, const IndexRay& r, double tMin,
                        double tMax, double& t) {
    return self.intersectPrimitive(prim, r.o, r.d, tMin, tMax, t);
}
template <typename Surface, typename PrimitiveRay>
bool intersectPrimitive(const Surface& self, unsigned prim, const PrimitiveRay& r, double tMin,
                        double tMax, double& t) {
    return self.intersectPrimitive(prim, r, tMin, tMax, t);
}

// The ray (o, d) in the primitive space of `self`. A single ray with its double ray in the
// context (SurfaceScene's queries) keeps it in the context for the geometry's next primitive
// (RayContext::primitiveRay: Embree calls a geometry's primitives of one ray in turn); others are
// made in `local`. Either way the same arithmetic, so the same numbers.
template <typename Surface>
[[gnu::always_inline]] inline const typename PrimitiveRayOf<Surface>::type& primitiveRay(
    const Surface& self, unsigned N, const RayContext* ctx, RayContext::Lane* lane, unsigned geomId,
    const Vec3& o, const Vec3& d, typename PrimitiveRayOf<Surface>::type& local) {
    using PrimitiveRay = typename PrimitiveRayOf<Surface>::type;
    static_assert(sizeof(PrimitiveRay) <= sizeof(RayContext::primitiveRay) &&
                      sizeof(PrimitiveRay) <= sizeof(RayContext::Lane::primitiveRay) &&
                      alignof(PrimitiveRay) <= alignof(RayContext::Lane) &&
                      alignof(PrimitiveRay) <= alignof(RayContext) &&
                      std::is_trivially_destructible_v<PrimitiveRay>,
                  "RayContext::primitiveRay holds the primitive ray");
    const AffineMap& space = self.primitiveSpace();
    if (N == 1 && ctx && ctx->ray) {
        auto* cached = std::launder(reinterpret_cast<PrimitiveRay*>(ctx->primitiveRay));
        if (ctx->primitiveRayGeom != geomId) {
            new (ctx->primitiveRay) PrimitiveRay(space.toIndex(o), space.directionToIndex(d));
            ctx->primitiveRayGeom = geomId;
        }
        return *cached;
    }
    if (lane) {
        auto* cached = std::launder(reinterpret_cast<PrimitiveRay*>(lane->primitiveRay));
        if (lane->primitiveRayGeom != geomId) {
            new (lane->primitiveRay) PrimitiveRay(space.toIndex(o), space.directionToIndex(d));
            lane->primitiveRayGeom = geomId;
        }
        return *cached;
    }
    local = PrimitiveRay(space.toIndex(o), space.directionToIndex(d));
    return local;
}

// The first root in [tMin, tMax] that lies in one of the clip's kept intervals (core/clip.h;
// all of [tMin, tMax] without a clip): the primitive is searched inside each interval in turn,
// so a root cut away never hides one behind it.
// With a mask (RayContext::masks) a root the mask refuses is passed over and the search goes on
// behind it.
template <typename Surface, typename PrimitiveRay>
[[gnu::always_inline]] inline bool intersectClipped(const Surface& self, unsigned prim,
                                                    const PrimitiveRay& r, double tMin, double tMax,
                                                    const ClipIntervals* clip, double& t,
                                                    const RayContext* ctx = nullptr,
                                                    unsigned geomId = 0) {
    const bool masked =
        ctx && ctx->masks && ctx->ray && geomId < ctx->masks->size() && (*ctx->masks)[geomId];
    const auto search = [&](double a, double b) {
        for (int guard = 0; guard < 1024 && a <= b; ++guard) {
            if (!intersectPrimitive(self, prim, r, a, b, t)) return false;
            if (!masked || ctx->maskKeeps(geomId, ctx->ray->at(t))) return true;
            a = t + 1e-9 * (1.0 + std::abs(t));
        }
        return false;
    };
    if (!clip) return search(tMin, tMax);
    for (int i = 0; i < clip->count; ++i) {
        const double a = std::max(tMin, clip->v[i].lo.t), b = std::min(tMax, clip->v[i].hi.t);
        if (a > b) continue;
        if (search(a, b)) return true;
    }
    return false;
}

template <typename Surface>
void bounds(const RTCBoundsFunctionArguments* args) {
    const auto* self = static_cast<const Surface*>(args->geometryUserPtr);
    const std::array<float, 6>& b = self->primitiveBounds(args->primID);
    args->bounds_o->lower_x = b[0];
    args->bounds_o->lower_y = b[1];
    args->bounds_o->lower_z = b[2];
    args->bounds_o->upper_x = b[3];
    args->bounds_o->upper_y = b[4];
    args->bounds_o->upper_z = b[5];
}

template <typename Surface>
void intersect(const RTCIntersectFunctionNArguments* args) {
    const auto* self = static_cast<const Surface*>(args->geometryUserPtr);
    auto* ctx = reinterpret_cast<RayContext*>(args->context);
    RTCRayN* ray = RTCRayHitN_RayN(args->rayhit, args->N);
    RTCHitN* hit = RTCRayHitN_HitN(args->rayhit, args->N);
    for (unsigned i = 0; i < args->N; ++i) {
        if (args->valid[i] != -1) continue;
        Vec3 o, d;
        double tMin, tMax;
        RayContext::Lane* lane = args->N == 1 ? nullptr : packetLane(ray, args->N, i, ctx);
        laneRay(ray, args->N, i, ctx, lane, o, d, tMin, tMax);
        typename PrimitiveRayOf<Surface>::type local;
        const auto& pr = primitiveRay(*self, args->N, ctx, lane, args->geomID, o, d, local);
        double t;
        const ClipIntervals* clip = args->N == 1 && ctx ? ctx->clipOf(args->geomID) : nullptr;
        if (args->N == 1 && ctx && ctx->collector) {
            // Gathering (SurfaceScene::collectHits): every root of the primitive up to the list's
            // limit, each searched from just beyond the last; no hit is reported to Embree, but
            // its ray is shortened to the limit so that it culls what lies behind.
            HitList& list = *ctx->collector;
            double a = tMin;
            for (int guard = 0; guard < 128 && a <= std::min(tMax, list.limit()); ++guard) {
                if (!intersectClipped(*self, args->primID, pr, a, std::min(tMax, list.limit()),
                                      clip, t, ctx, args->geomID))
                    break;
                list.add(t, args->geomID, args->primID);
                a = HitList::nextStart(t);
            }
            if (list.limit() < RTCRayN_tfar(ray, args->N, i))
                RTCRayN_tfar(ray, args->N, i) = std::nextafter(
                    static_cast<float>(list.limit()), std::numeric_limits<float>::infinity());
            continue;
        }
        if (!intersectClipped(*self, args->primID, pr, tMin, tMax, clip, t,
                              args->N == 1 ? ctx : nullptr, args->geomID))
            continue;
        // No geometric normal: nothing reads Embree's Ng (shade() computes the shading normal
        // once, for the hit that wins), so none is computed for every candidate hit.
        // Embree's tfar is a float: rounded up, never down, so that a root of another user
        // geometry between float(t) and t (within one float step of this one) is still searched
        // for; laneRay bounds that search by the double tHit, so the nearer root wins.
        RTCRayN_tfar(ray, args->N, i) = floatAtLeast(t);
        RTCHitN_Ng_x(hit, args->N, i) = 0.0f;
        RTCHitN_Ng_y(hit, args->N, i) = 0.0f;
        RTCHitN_Ng_z(hit, args->N, i) = 0.0f;
        RTCHitN_u(hit, args->N, i) = 0.0f;
        RTCHitN_v(hit, args->N, i) = 0.0f;
        RTCHitN_primID(hit, args->N, i) = args->primID;
        RTCHitN_geomID(hit, args->N, i) = args->geomID;
        RTCHitN_instID(hit, args->N, i, 0) = args->context->instID[0];
        if (args->N == 1 && ctx && ctx->ray) {
            ctx->tHit = t;
            ctx->geomId = args->geomID;
            ctx->primId = args->primID;
        } else if (lane) {
            lane->tHit = t;
            lane->geomId = args->geomID;
            lane->primId = args->primID;
        }
    }
}

template <typename Surface>
void occluded(const RTCOccludedFunctionNArguments* args) {
    const auto* self = static_cast<const Surface*>(args->geometryUserPtr);
    const auto* ctx = reinterpret_cast<const RayContext*>(args->context);
    for (unsigned i = 0; i < args->N; ++i) {
        if (args->valid[i] != -1) continue;
        Vec3 o, d;
        double tMin, tMax;
        RayContext::Lane* lane = args->N == 1 ? nullptr : packetLane(args->ray, args->N, i, ctx);
        laneRay(args->ray, args->N, i, ctx, lane, o, d, tMin, tMax);
        typename PrimitiveRayOf<Surface>::type local;
        const auto& pr = primitiveRay(*self, args->N, ctx, lane, args->geomID, o, d, local);
        double t;
        const ClipIntervals* clip = args->N == 1 && ctx ? ctx->clipOf(args->geomID) : nullptr;
        if (intersectClipped(*self, args->primID, pr, tMin, tMax, clip, t,
                             args->N == 1 ? ctx : nullptr, args->geomID))
            RTCRayN_tfar(args->ray, args->N, i) = -std::numeric_limits<float>::infinity();
    }
}

// SurfaceGeometry::shade for the surfaces whose normal is −∇f (surface_scene.h, "Normal
// convention"): gradientAt(world position) gives the world-space ∇f; a zero or non-finite
// gradient (a saddle on the surface) falls back to −ray direction.
template <typename GradientAt>
SurfaceHit shadeByGradient(const Ray& ray, double t, unsigned primId,
                           const GradientAt& gradientAt) {
    SurfaceHit hit;
    hit.t = t;
    hit.position = ray.at(t);
    hit.primId = primId;
    const Vec3 n = isFinite(hit.position) ? normalized(-gradientAt(hit.position)) : Vec3(0.0);
    hit.normal = (n.length2() > 0.0 && isFinite(n)) ? n : normalized(-ray.d);
    return hit;
}

// A user geometry of `count` primitives whose callbacks call `self`.
template <typename Surface>
RTCGeometry create(RTCDevice device, const Surface* self, std::size_t count) {
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
    rtcSetGeometryUserPrimitiveCount(g, static_cast<unsigned>(count));
    rtcSetGeometryUserData(g, const_cast<Surface*>(self));
    rtcSetGeometryBoundsFunction(g, &bounds<Surface>, nullptr);
    rtcSetGeometryIntersectFunction(g, &intersect<Surface>);
    rtcSetGeometryOccludedFunction(g, &occluded<Surface>);
    return g;
}

}  // namespace lobe::user_geometry
