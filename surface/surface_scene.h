// Surfaces that Embree intersects, and the scene that owns them.
//
// SurfaceGeometry is the small interface every surface method satisfies (the meshed iso-surface,
// the exact iso-surface, later implicit primitives): it creates its Embree geometry, and turns an
// Embree hit into shading information (refined distance, world position, unit shading normal).
//
// SurfaceScene owns the Embree device and scene and answers single-ray queries in double
// precision: intersect(ray) returns the first hit with t ∈ [ray.tMin, ray.tMax]; callers that need
// every hit in depth order (volume compositing through translucent surfaces) call collectHits(),
// which gathers a ray's hits in depth order in one Embree traversal (HitList, below), or
// allHits(). Queries are thread-safe once commit() has run.
//
// Precision. Embree's rays are float; user geometries (the exact iso-surface) receive the
// caller's double ray through RayContext and report their double hit distance back through it,
// so exact hits keep ~1e-10-voxel accuracy independent of float rounding of the origin. Built-in
// Embree geometries (the quad mesh) are intersected in float.
//
// Normal convention (all methods): the shading normal is unit length and points out of the region
// where the value is above the iso value, i.e. along −∇f (for a CT skull at iso 0.5 it points from
// bone into air). It is NOT flipped towards the viewer; callers flip it for two-sided shading.
#pragma once

#include "core/clip.h"
#include "core/math.h"
#include "core/ray.h"
#include "surface/embree_device.h"

#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <vector>

namespace lobe {

struct SurfaceHit {
    double t = 0.0;
    Vec3 position{0.0};    // world space, ray.at(t)
    Vec3 normal{0, 0, 1};  // unit, world space, see "Normal convention"
    int objectId = -1;     // index returned by SurfaceScene::add
    unsigned primId = 0;   // the Embree primitive (quad or brick)
};

// The hits of one ray in depth order, gathered by one traversal (SurfaceScene::collectHits):
// Embree visits the primitives in no particular order, so every candidate hit is inserted into
// this sorted list instead of ending the search, and the search goes on. Each primitive reports
// all its roots in turn, the next searched from just beyond the last (kHitStep, the step the
// integrator has always taken between hits), so a primitive holding two walls of a thin bone
// reports both. The list is cut short where it can no longer matter (limit()):
// - at kCapacity hits (the farthest is dropped), and
// - at the first hit where the product of (1 − opacity) of the hits before it and itself, each
//   object's transmittance given by the caller, falls below `cutoff`: the surfaces alone make the
//   ray opaque there (an opaque object ends the list at its first hit, as intersect() does).
// Hits beyond the limit are not searched for: user geometries search only up to it and Embree's
// ray is shortened to it, so it culls the primitives behind.
struct HitList {
    static constexpr int kCapacity = 16;
    // The step beyond a hit to the next search (world units, relative to 1 + t): the
    // integrator's; hits closer than that to the previous one are one hit found twice (a root on
    // a face shared by two bricks, within their 1e-7-voxel overlap).
    static double nextStart(double t) { return t + 1e-6 * (1.0 + t); }
    struct Entry {
        double t;
        unsigned geomId;
        unsigned primId;
    };
    Entry hits[kCapacity];
    int count = 0;
    // False when hits were dropped or never searched for beyond hits[count − 1] (the capacity or
    // the opacity cut): a caller that needs more searches again from nextStart of the last.
    bool complete = true;

    // Set by SurfaceScene::collectHits: transmittance (1 − opacity) per Embree geometry ID and
    // the cut-off (render/compositor.h's termination transmittance).
    const double* transmittanceOfGeom = nullptr;
    unsigned geomCount = 0;
    double cutoff = 0.0;
    double tMin = 0.0, tMax = std::numeric_limits<double>::infinity();  // the caller's ray's
    double limitT = std::numeric_limits<double>::infinity();

    double limit() const { return limitT; }
    // Empties the list for a new ray: every field but the entries (assigning HitList() would
    // zero and copy all kCapacity entries, half of collectHits' time in the preview). A field
    // added above is reset here.
    void restart(const double* transmittance, unsigned geoms, double cutoffT, double rayTMin,
                 double rayTMax) {
        count = 0;
        complete = true;
        transmittanceOfGeom = transmittance;
        geomCount = geoms;
        cutoff = cutoffT;
        tMin = rayTMin;
        tMax = rayTMax;
        limitT = std::numeric_limits<double>::infinity();
    }
    // Inserts a hit in depth order and recomputes the limit (the surface_scene.cpp definition).
    void add(double t, unsigned geomId, unsigned primId);
};

// Passed to rtcIntersect1/rtcOccluded1 in place of a plain RTCIntersectContext (it starts with
// one, the classic Embree 3 way of handing user data to geometry callbacks). User geometries read
// the double ray and record their double hit distance.
struct RayContext {
    RTCIntersectContext base;
    const Ray* ray = nullptr;  // the caller's ray in double precision
    double tHit = 0.0;         // double distance of the last accepted user-geometry hit
    unsigned geomId = RTC_INVALID_GEOMETRY_ID;
    unsigned primId = RTC_INVALID_GEOMETRY_ID;
    // Clipping (core/clip.h): the kept intervals of this ray per Embree geometry ID (null: not
    // clipped), filled by SurfaceScene for single rays. Hits outside them are not reported.
    const ClipIntervals* const* clips = nullptr;
    unsigned clipCount = 0;
    const ClipIntervals* clipOf(unsigned geomId) const {
        return clips && geomId < clipCount ? clips[geomId] : nullptr;
    }
    // Not null: gather every hit into this list instead of keeping the nearest
    // (SurfaceScene::collectHits); tHit/geomId/primId are then unused.
    HitList* collector = nullptr;
    // Masks (SurfaceScene::setMask), by Embree geometry ID; empty functions keep every hit.
    const std::vector<std::function<bool(const Vec3&)>>* masks = nullptr;
    // Whether the mask of geomId keeps world point x.
    bool maskKeeps(unsigned geomId, const Vec3& x) const {
        return !masks || geomId >= masks->size() || !(*masks)[geomId] || (*masks)[geomId](x);
    }
    // The ray in the primitive space of user geometry primitiveRayGeom, made by its first
    // callback of this query and read by the next (user_geometry.h, primitiveRay): raw storage,
    // so that this header needs no surface's types. Left uninitialised until then.
    mutable unsigned primitiveRayGeom = RTC_INVALID_GEOMETRY_ID;
    alignas(16) mutable unsigned char primitiveRay[128];
    // A packet's rays (SurfaceScene::intersect8), by Embree ray ID (the lane): each lane's double
    // ray, its best double hit and its primitive-space ray, as the single-ray fields above are
    // for one ray. Null for single rays.
    struct Lane {
        const Ray* ray = nullptr;
        double tHit = 0.0;
        unsigned geomId = RTC_INVALID_GEOMETRY_ID;
        unsigned primId = RTC_INVALID_GEOMETRY_ID;
        unsigned primitiveRayGeom = RTC_INVALID_GEOMETRY_ID;
        alignas(16) unsigned char primitiveRay[128];
    };
    Lane* lanes = nullptr;
    unsigned laneCount = 0;
};

class SurfaceGeometry {
public:
    virtual ~SurfaceGeometry() = default;
    // A new, uncommitted Embree geometry (the scene commits, attaches and releases it). The
    // geometry's callbacks may keep `this` as user data: the scene keeps the object alive.
    virtual RTCGeometry createGeometry(RTCDevice device) const = 0;
    // Shading for a hit at distance t on primitive primId. Never returns a non-finite normal.
    virtual SurfaceHit shade(const Ray& ray, double t, unsigned primId) const = 0;
};

class SurfaceScene {
public:
    explicit SurfaceScene(const std::string& embreeConfig = "");

    // Adds an object; returns its object ID (0, 1, … in order of adding). Call commit() after the
    // last add and before the first query.
    int add(std::shared_ptr<const SurfaceGeometry> geometry);
    void commit();
    // Clips object `id` (before commit): only its parts every shape keeps are hit, exactly (the
    // ray's kept intervals, core/clip.h: user geometries search only inside them, meshes reject
    // hits outside them in an Embree filter function). Rays from intersect() and occluded().
    void setClip(int id, std::vector<ClipShape> shapes);
    // Masks object `id` (before commit): hits at world points where keeps(x) is false are not
    // reported, and the search goes on behind them (render/scene.cpp makes it from a
    // volume/volume_mask.h mask). Single rays only.
    void setMask(int id, std::function<bool(const Vec3&)> keeps);

    std::optional<SurfaceHit> intersect(const Ray& ray) const;
    // The first hits of up to 8 rays traced together (rtcIntersect8: Embree walks its tree once
    // for the packet, which pays for coherent rays such as a row of camera rays: T1's exact
    // skull, docs/performance.md). out[k] is what intersect(*rays[k]) returns: the user
    // geometries search each lane's double ray and keep its nearest double root. Only for
    // scenes without clips and masks (packetsSupported); n in 1 … 8.
    void intersect8(const Ray* const* rays, int n, std::optional<SurfaceHit>* out) const;
    bool packetsSupported() const { return committed_ && !anyClip_ && maskOfGeom_.empty(); }
    bool occluded(const Ray& ray) const;
    // The ray's hits in depth order from one traversal, into `out` (HitList: up to its capacity,
    // and up to the first hit where the product of objectTransmittance[objectId] over the hits so
    // far falls below cutoff). objectTransmittance: one per object, in [0, 1].
    // Hits closer than HitList::nextStart to the previous one are kept (callers skip them).
    void collectHits(const Ray& ray, const std::vector<double>& objectTransmittance, double cutoff,
                     HitList& out) const;
    // The shading of entry e of a HitList filled for `ray` (SurfaceGeometry::shade).
    SurfaceHit shadeHit(const Ray& ray, const HitList::Entry& e) const;
    int objectOfGeometry(unsigned geomId) const { return objectOfGeom_.at(geomId); }

    // Every hit along the ray in depth order, at most maxHits: repeated intersect() with tMin
    // moved epsilon (world units, relative to 1 + t) beyond the last hit.
    std::vector<SurfaceHit> allHits(const Ray& ray, int maxHits = 64, double epsilon = 1e-6) const;

    const SurfaceGeometry& object(int id) const { return *objects_.at(id); }
    int objectCount() const { return static_cast<int>(objects_.size()); }

private:
    // The hit an Embree query ended on (geomId, primId, Embree's float tfar): at the double
    // distance a user geometry left where it accepted that very hit (accepted*: RayContext's or
    // a packet lane's), else at tfar; none outside [ray.tMin, ray.tMax] (float rounding at the
    // ends). intersect() and intersect8() alike.
    std::optional<SurfaceHit> finalHit(const Ray& ray, unsigned geomId, unsigned primId,
                                       double tfar, unsigned acceptedGeom, unsigned acceptedPrim,
                                       double acceptedT) const;
    EmbreeDevice device_;
    EmbreeScene scene_;
    std::vector<std::shared_ptr<const SurfaceGeometry>> objects_;
    std::vector<int> objectOfGeom_;                   // Embree geometry ID → object ID
    std::vector<std::vector<ClipShape>> clipOfGeom_;  // by Embree geometry ID
    bool anyClip_ = false;
    std::vector<std::function<bool(const Vec3&)>> maskOfGeom_;  // by Embree geometry ID
    // Starts a query's context for `ray`: Embree's context, the ray, the clip intervals of every
    // clipped geometry and the masks (for intersect, occluded and collectHits alike).
    void beginQuery(const Ray& ray, RayContext& ctx) const;
    bool committed_ = false;
};

// Float copies of a double ray for Embree. tMax = ∞ stays ∞.
void fillEmbreeRay(const Ray& ray, RTCRay& out);
// The same, with the hit's IDs set to none (for rtcIntersect1).
void fillEmbreeRay(const Ray& ray, RTCRayHit& out);

}  // namespace lobe
