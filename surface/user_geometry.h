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

namespace lobe::user_geometry {

// The ray of lane i: the caller's double ray when SurfaceScene passed one (single rays), else
// Embree's float copy. tMax also respects the best double hit recorded so far.
// The smallest float not below t (Embree's tfar for a double hit distance t).
inline float floatAtLeast(double t) {
    const float f = static_cast<float>(t);
    return double(f) < t ? std::nextafter(f, std::numeric_limits<float>::infinity()) : f;
}

inline void laneRay(RTCRayN* ray, unsigned N, unsigned i, const RayContext* ctx, Vec3& o, Vec3& d,
                    double& tMin, double& tMax) {
    const double tfar = RTCRayN_tfar(ray, N, i);
    if (N == 1 && ctx && ctx->ray) {
        o = ctx->ray->o;
        d = ctx->ray->d;
        tMin = std::max(0.0, ctx->ray->tMin);
        tMax = std::min(tfar, ctx->ray->tMax);
        if (ctx->geomId != RTC_INVALID_GEOMETRY_ID) tMax = std::min(tMax, ctx->tHit);
    } else {
        o = Vec3(RTCRayN_org_x(ray, N, i), RTCRayN_org_y(ray, N, i), RTCRayN_org_z(ray, N, i));
        d = Vec3(RTCRayN_dir_x(ray, N, i), RTCRayN_dir_y(ray, N, i), RTCRayN_dir_z(ray, N, i));
        tMin = RTCRayN_tnear(ray, N, i);
        tMax = tfar;
    }
}

// The first root in [tMin, tMax] that lies in one of the clip's kept intervals (core/clip.h;
// all of [tMin, tMax] without a clip): the primitive is searched inside each interval in turn,
// so a root cut away never hides one behind it.
// With a mask (RayContext::masks) a root the mask refuses is passed over and the search goes on
// behind it.
template <typename Surface>
bool intersectClipped(const Surface& self, unsigned prim, const Vec3& o, const Vec3& d, double tMin,
                      double tMax, const ClipIntervals* clip, double& t,
                      const RayContext* ctx = nullptr, unsigned geomId = 0) {
    const bool masked =
        ctx && ctx->masks && ctx->ray && geomId < ctx->masks->size() && (*ctx->masks)[geomId];
    const auto search = [&](double a, double b) {
        for (int guard = 0; guard < 1024 && a <= b; ++guard) {
            if (!self.intersectPrimitive(prim, o, d, a, b, t)) return false;
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
        laneRay(ray, args->N, i, ctx, o, d, tMin, tMax);
        const Vec3 oi = self->primitiveSpace().toIndex(o),
                   di = self->primitiveSpace().directionToIndex(d);
        double t;
        const ClipIntervals* clip = args->N == 1 && ctx ? ctx->clipOf(args->geomID) : nullptr;
        if (args->N == 1 && ctx && ctx->collector) {
            // Gathering (SurfaceScene::collectHits): every root of the primitive up to the list's
            // limit, each searched from just beyond the last; no hit is reported to Embree, but
            // its ray is shortened to the limit so that it culls what lies behind.
            HitList& list = *ctx->collector;
            double a = tMin;
            for (int guard = 0; guard < 128 && a <= std::min(tMax, list.limit()); ++guard) {
                if (!intersectClipped(*self, args->primID, oi, di, a, std::min(tMax, list.limit()),
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
        if (!intersectClipped(*self, args->primID, oi, di, tMin, tMax, clip, t,
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
        laneRay(args->ray, args->N, i, ctx, o, d, tMin, tMax);
        double t;
        const ClipIntervals* clip = args->N == 1 && ctx ? ctx->clipOf(args->geomID) : nullptr;
        if (intersectClipped(*self, args->primID, self->primitiveSpace().toIndex(o),
                             self->primitiveSpace().directionToIndex(d), tMin, tMax, clip, t,
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
