// SurfaceScene: the Embree scene of all surface objects; see surface_scene.h.
#include "surface/surface_scene.h"

#include "core/error.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace lobe {

void fillEmbreeRay(const Ray& ray, RTCRay& out) {
    out.org_x = static_cast<float>(ray.o.x);
    out.org_y = static_cast<float>(ray.o.y);
    out.org_z = static_cast<float>(ray.o.z);
    out.dir_x = static_cast<float>(ray.d.x);
    out.dir_y = static_cast<float>(ray.d.y);
    out.dir_z = static_cast<float>(ray.d.z);
    out.tnear = static_cast<float>(std::max(0.0, ray.tMin));
    out.tfar = std::isfinite(ray.tMax) ? static_cast<float>(ray.tMax)
                                       : std::numeric_limits<float>::infinity();
    out.time = 0.0f;
    out.mask = 0xFFFFFFFFu;
    out.id = 0;
    out.flags = 0;
}

void fillEmbreeRay(const Ray& ray, RTCRayHit& out) {
    fillEmbreeRay(ray, out.ray);
    out.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    out.hit.primID = RTC_INVALID_GEOMETRY_ID;
    out.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
}

namespace {

// Embree filter for built-in geometries (the quad mesh): a candidate hit outside the ray's
// kept intervals is rejected, and Embree goes on to the next one. tfar holds the candidate's
// distance while the filter runs.
// With a hit collector (SurfaceScene::collectHits) a kept hit is recorded and then rejected too,
// so that Embree goes on to the hits behind it.
void clipFilter(const RTCFilterFunctionNArguments* args) {
    const auto* ctx = reinterpret_cast<const RayContext*>(args->context);
    if (!ctx || (!ctx->clips && !ctx->masks && !ctx->collector) || args->N != 1 ||
        args->valid[0] != -1)
        return;
    const unsigned geomId = RTCHitN_geomID(args->hit, args->N, 0);
    const float t = RTCRayN_tfar(args->ray, args->N, 0);
    const ClipIntervals* clip = ctx->clipOf(geomId);
    if (clip && !clip->contains(t))
        args->valid[0] = 0;
    else if (ctx->masks && ctx->ray && !ctx->maskKeeps(geomId, ctx->ray->at(t)))
        args->valid[0] = 0;
    else if (ctx->collector) {
        ctx->collector->add(t, geomId, RTCHitN_primID(args->hit, args->N, 0));
        args->valid[0] = 0;
    }
}

}  // namespace

SurfaceScene::SurfaceScene(const std::string& embreeConfig)
    : device_(embreeConfig), scene_(device_) {}

int SurfaceScene::add(std::shared_ptr<const SurfaceGeometry> geometry) {
    if (!geometry) throw Error("SurfaceScene::add: null surface object");
    if (committed_) throw Error("SurfaceScene::add: the scene is already committed");
    RTCGeometry g = geometry->createGeometry(device_.get());
    device_.check("creating the Embree geometry of surface object " +
                  std::to_string(objects_.size()));
    // Clipping of built-in geometries (user geometries clip in their own callbacks, which do not
    // call the filters).
    rtcSetGeometryIntersectFilterFunction(g, &clipFilter);
    rtcSetGeometryOccludedFilterFunction(g, &clipFilter);
    const unsigned geomId = scene_.attach(g);
    const int objectId = static_cast<int>(objects_.size());
    objects_.push_back(std::move(geometry));
    if (objectOfGeom_.size() <= geomId) objectOfGeom_.resize(geomId + 1, -1);
    objectOfGeom_[geomId] = objectId;
    return objectId;
}

void SurfaceScene::setClip(int id, std::vector<ClipShape> shapes) {
    if (committed_) throw Error("SurfaceScene::setClip: the scene is already committed");
    if (shapes.empty()) return;
    for (size_t g = 0; g < objectOfGeom_.size(); ++g)
        if (objectOfGeom_[g] == id) {
            if (clipOfGeom_.size() <= g) clipOfGeom_.resize(g + 1);
            clipOfGeom_[g] = std::move(shapes);
            anyClip_ = true;
            return;
        }
    throw Error("SurfaceScene::setClip: no object " + std::to_string(id));
}

void SurfaceScene::setMask(int id, std::function<bool(const Vec3&)> keeps) {
    if (committed_) throw Error("SurfaceScene::setMask: the scene is already committed");
    for (size_t g = 0; g < objectOfGeom_.size(); ++g)
        if (objectOfGeom_[g] == id) {
            if (maskOfGeom_.size() <= g) maskOfGeom_.resize(g + 1);
            maskOfGeom_[g] = std::move(keeps);
            return;
        }
    throw Error("SurfaceScene::setMask: no object " + std::to_string(id));
}

void SurfaceScene::beginQuery(const Ray& ray, RayContext& ctx) const {
    rtcInitIntersectContext(&ctx.base);
    ctx.ray = &ray;
    if (anyClip_) {
        // The clip intervals of every clipped geometry, in the thread's buffers (queries of one
        // thread never overlap).
        thread_local std::vector<ClipIntervals> buffer;
        thread_local std::vector<const ClipIntervals*> pointers;
        buffer.resize(clipOfGeom_.size());
        pointers.assign(clipOfGeom_.size(), nullptr);
        for (size_t g = 0; g < clipOfGeom_.size(); ++g)
            if (!clipOfGeom_[g].empty()) {
                buffer[g] = clipRay(ray, clipOfGeom_[g]);
                pointers[g] = &buffer[g];
            }
        ctx.clips = pointers.data();
        ctx.clipCount = unsigned(pointers.size());
    }
    if (!maskOfGeom_.empty()) ctx.masks = &maskOfGeom_;
}

void SurfaceScene::commit() {
    scene_.commit();
    committed_ = true;
}

std::optional<SurfaceHit> SurfaceScene::intersect(const Ray& ray) const {
    if (!committed_) throw Error("SurfaceScene::intersect: commit() was not called");
    RayContext ctx;
    beginQuery(ray, ctx);
    RTCRayHit rh;
    fillEmbreeRay(ray, rh);
    rtcIntersect1(scene_.get(), &ctx.base, &rh);
    return finalHit(ray, rh.hit.geomID, rh.hit.primID, rh.ray.tfar, ctx.geomId, ctx.primId,
                    ctx.tHit);
}

std::optional<SurfaceHit> SurfaceScene::finalHit(const Ray& ray, unsigned geomId, unsigned primId,
                                                 double tfar, unsigned acceptedGeom,
                                                 unsigned acceptedPrim, double acceptedT) const {
    if (geomId == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
    const double t = acceptedGeom == geomId && acceptedPrim == primId ? acceptedT : tfar;
    if (t < ray.tMin || t > ray.tMax) return std::nullopt;
    return shadeHit(ray, {t, geomId, primId});
}

void SurfaceScene::intersect8(const Ray* const* rays, int n, std::optional<SurfaceHit>* out) const {
    if (!packetsSupported())
        throw Error("SurfaceScene::intersect8: not for clipped or masked scenes");
    if (n < 1 || n > 8) throw Error("SurfaceScene::intersect8: 1 to 8 rays");
    RayContext ctx;
    rtcInitIntersectContext(&ctx.base);
    ctx.base.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    RayContext::Lane lanes[8];
    ctx.lanes = lanes;
    ctx.laneCount = 8;
    RTCRayHit8 rh;
    alignas(32) int valid[8];
    for (int k = 0; k < 8; ++k) {
        RTCRayHit one;
        fillEmbreeRay(*rays[std::min(k, n - 1)], one);
        rh.ray.org_x[k] = one.ray.org_x;
        rh.ray.org_y[k] = one.ray.org_y;
        rh.ray.org_z[k] = one.ray.org_z;
        rh.ray.dir_x[k] = one.ray.dir_x;
        rh.ray.dir_y[k] = one.ray.dir_y;
        rh.ray.dir_z[k] = one.ray.dir_z;
        rh.ray.tnear[k] = one.ray.tnear;
        rh.ray.tfar[k] = one.ray.tfar;
        rh.ray.time[k] = one.ray.time;
        rh.ray.mask[k] = one.ray.mask;
        rh.ray.id[k] = unsigned(k);  // the lane, for the user geometries (RayContext::lanes)
        rh.ray.flags[k] = one.ray.flags;
        rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
        rh.hit.primID[k] = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
        valid[k] = k < n ? -1 : 0;
        if (k < n) lanes[k].ray = rays[k];
    }
    rtcIntersect8(valid, scene_.get(), &ctx.base, &rh);
    for (int k = 0; k < n; ++k)
        out[k] = finalHit(*rays[k], rh.hit.geomID[k], rh.hit.primID[k], rh.ray.tfar[k],
                          lanes[k].geomId, lanes[k].primId, lanes[k].tHit);
}

bool SurfaceScene::occluded(const Ray& ray) const {
    if (!committed_) throw Error("SurfaceScene::occluded: commit() was not called");
    RayContext ctx;
    beginQuery(ray, ctx);
    RTCRay r;
    fillEmbreeRay(ray, r);
    rtcOccluded1(scene_.get(), &ctx.base, &r);
    return r.tfar < 0.0f;  // Embree sets tfar = −∞ on occlusion
}

void HitList::add(double t, unsigned geomId, unsigned primId) {
    if (!(t >= tMin && t <= tMax)) return;  // float rounding at the ray's ends (as intersect())
    if (!(t <= limitT)) {
        complete = false;
        return;
    }
    if (count == kCapacity) {
        complete = false;
        if (t >= hits[count - 1].t) {  // behind every kept hit: dropped
            limitT = std::min(limitT, hits[count - 1].t);
            return;
        }
        --count;  // the farthest makes room
    }
    int i = count++;
    for (; i > 0 && hits[i - 1].t > t; --i) hits[i] = hits[i - 1];  // equal t: after, stable
    hits[i] = {t, geomId, primId};
    // The opacity cut: the product of the transmittances of the hits so far, skipping those
    // closer than nextStart to the previous one, exactly as the integrator composites them.
    double T = 1.0, next = -std::numeric_limits<double>::infinity();
    for (int k = 0; k < count; ++k) {
        if (hits[k].t < next) continue;
        const unsigned g = hits[k].geomId;
        T *= g < geomCount ? transmittanceOfGeom[g] : 1.0;
        next = nextStart(hits[k].t);
        if (T <= 0.0 || T < cutoff) {
            if (k + 1 < count) count = k + 1;
            complete = false;
            limitT = std::min(limitT, hits[k].t);
            return;
        }
    }
    if (count == kCapacity) {
        complete = false;
        limitT = std::min(limitT, hits[count - 1].t);
    }
}

void SurfaceScene::collectHits(const Ray& ray, const std::vector<double>& objectTransmittance,
                               double cutoff, HitList& out) const {
    if (!committed_) throw Error("SurfaceScene::collectHits: commit() was not called");
    thread_local std::vector<double> transmittanceOfGeom;
    transmittanceOfGeom.assign(objectOfGeom_.size(), 1.0);
    for (size_t g = 0; g < objectOfGeom_.size(); ++g)
        if (objectOfGeom_[g] >= 0 && size_t(objectOfGeom_[g]) < objectTransmittance.size())
            transmittanceOfGeom[g] = objectTransmittance[size_t(objectOfGeom_[g])];
    out.restart(transmittanceOfGeom.data(), unsigned(transmittanceOfGeom.size()), cutoff, ray.tMin,
                ray.tMax);
    RayContext ctx;
    beginQuery(ray, ctx);
    ctx.collector = &out;
    RTCRayHit rh;
    fillEmbreeRay(ray, rh);
    rtcIntersect1(scene_.get(), &ctx.base, &rh);
    out.transmittanceOfGeom = nullptr;  // the thread's buffer: not valid beyond this call
    out.geomCount = 0;
}

SurfaceHit SurfaceScene::shadeHit(const Ray& ray, const HitList::Entry& e) const {
    const int objectId = objectOfGeom_.at(e.geomId);
    SurfaceHit hit = objects_[size_t(objectId)]->shade(ray, e.t, e.primId);
    hit.objectId = objectId;
    return hit;
}

std::vector<SurfaceHit> SurfaceScene::allHits(const Ray& ray, int maxHits, double epsilon) const {
    std::vector<SurfaceHit> hits;
    Ray r = ray;
    while (static_cast<int>(hits.size()) < maxHits) {
        const std::optional<SurfaceHit> hit = intersect(r);
        if (!hit) break;
        hits.push_back(*hit);
        r.tMin = hit->t + epsilon * (1.0 + std::abs(hit->t));
    }
    return hits;
}

}  // namespace lobe
