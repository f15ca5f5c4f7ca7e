// SurfaceScene: the Embree scene of all surface objects; see surface_scene.h.
#include "surface/surface_scene.h"

#include "core/error.h"

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

namespace {

// Embree filter for built-in geometries (the quad mesh): a candidate hit outside the ray's
// kept intervals is rejected, and Embree goes on to the next one. tfar holds the candidate's
// distance while the filter runs.
void clipFilter(const RTCFilterFunctionNArguments* args) {
    const auto* ctx = reinterpret_cast<const RayContext*>(args->context);
    if (!ctx || (!ctx->clips && !ctx->masks) || args->N != 1 || args->valid[0] != -1) return;
    const unsigned geomId = RTCHitN_geomID(args->hit, args->N, 0);
    const float t = RTCRayN_tfar(args->ray, args->N, 0);
    const ClipIntervals* clip = ctx->clipOf(geomId);
    if (clip && !clip->contains(t))
        args->valid[0] = 0;
    else if (ctx->masks && ctx->ray && !ctx->maskKeeps(geomId, ctx->ray->at(t)))
        args->valid[0] = 0;
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

void SurfaceScene::fillClips(const Ray& ray, RayContext& ctx, std::vector<ClipIntervals>& buffer,
                             std::vector<const ClipIntervals*>& pointers) const {
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

void SurfaceScene::commit() {
    scene_.commit();
    committed_ = true;
}

std::optional<SurfaceHit> SurfaceScene::intersect(const Ray& ray) const {
    if (!committed_) throw Error("SurfaceScene::intersect: commit() was not called");
    RayContext ctx;
    rtcInitIntersectContext(&ctx.base);
    ctx.ray = &ray;
    thread_local std::vector<ClipIntervals> clipBuffer;
    thread_local std::vector<const ClipIntervals*> clipPointers;
    if (anyClip_) fillClips(ray, ctx, clipBuffer, clipPointers);
    if (!maskOfGeom_.empty()) ctx.masks = &maskOfGeom_;
    RTCRayHit rh;
    fillEmbreeRay(ray, rh.ray);
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene_.get(), &ctx.base, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
    // A user geometry that accepted the final hit left its double distance in the context.
    double t = rh.ray.tfar;
    if (ctx.geomId == rh.hit.geomID && ctx.primId == rh.hit.primID) t = ctx.tHit;
    if (t < ray.tMin || t > ray.tMax) return std::nullopt;  // float rounding at the ends
    const int objectId = objectOfGeom_.at(rh.hit.geomID);
    SurfaceHit hit = objects_[objectId]->shade(ray, t, rh.hit.primID);
    hit.objectId = objectId;
    return hit;
}

bool SurfaceScene::occluded(const Ray& ray) const {
    if (!committed_) throw Error("SurfaceScene::occluded: commit() was not called");
    RayContext ctx;
    rtcInitIntersectContext(&ctx.base);
    ctx.ray = &ray;
    thread_local std::vector<ClipIntervals> clipBuffer;
    thread_local std::vector<const ClipIntervals*> clipPointers;
    if (anyClip_) fillClips(ray, ctx, clipBuffer, clipPointers);
    if (!maskOfGeom_.empty()) ctx.masks = &maskOfGeom_;
    RTCRay r;
    fillEmbreeRay(ray, r);
    rtcOccluded1(scene_.get(), &ctx.base, &r);
    return r.tfar < 0.0f;  // Embree sets tfar = −∞ on occlusion
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
