// Meshed iso-surface (OpenVDB volumeToMesh → Embree quads); see iso_mesh.h.
#include "surface/iso_mesh.h"

#include "core/error.h"
#include "surface/trilinear_cell.h"

#include <openvdb/tools/VolumeToMesh.h>

#include <cmath>
#include <cstring>

namespace lobe {

IsoMeshSurface::IsoMeshSurface(const openvdb::FloatGrid& grid, double iso,
                               const std::string& name)
    : iso_(iso), map_(AffineMap::fromTransform(grid.transform(), name)), grid_(grid.copy()) {
    if (!std::isfinite(iso)) throw Error(name + ": iso value must be finite");
    std::vector<openvdb::Vec3s> points;
    std::vector<openvdb::Vec3I> triangles;
    std::vector<openvdb::Vec4I> quads;
    // Adaptivity 0: no simplification, so the mesh error is the method's, not the decimation's.
    openvdb::tools::volumeToMesh(grid, points, triangles, quads, iso, 0.0);
    vertices_.reserve(points.size() * 3);
    for (const openvdb::Vec3s& p : points) {
        if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
            throw Error(name + ": volumeToMesh produced a non-finite vertex (non-finite voxels?)");
        vertices_.insert(vertices_.end(), {p[0], p[1], p[2]});
    }
    quads_.reserve((quads.size() + triangles.size()) * 4);
    for (const openvdb::Vec4I& q : quads) quads_.insert(quads_.end(), {q[0], q[1], q[2], q[3]});
    // Embree's quad geometry takes a triangle as a quad whose last two vertices coincide.
    for (const openvdb::Vec3I& t : triangles) quads_.insert(quads_.end(), {t[0], t[1], t[2], t[2]});
    triangles_ = triangles.size();
}

std::size_t IsoMeshSurface::memoryBytes() const {
    return vertices_.size() * sizeof(float) + quads_.size() * sizeof(std::uint32_t);
}

RTCGeometry IsoMeshSurface::createGeometry(RTCDevice device) const {
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_QUAD);
    if (quadCount() == 0) {
        // No surface: one degenerate quad keeps the buffers non-empty; Embree never hits it.
        float* v = static_cast<float*>(rtcSetNewGeometryBuffer(
            g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 1));
        std::uint32_t* q = static_cast<std::uint32_t*>(rtcSetNewGeometryBuffer(
            g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT4, 4 * sizeof(std::uint32_t), 1));
        if (v) v[0] = v[1] = v[2] = 0.0f;
        if (q) q[0] = q[1] = q[2] = q[3] = 0;
        return g;
    }
    // Embree pads its own buffers (it reads vertices with 16-byte loads).
    float* v = static_cast<float*>(rtcSetNewGeometryBuffer(
        g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), vertexCount()));
    std::uint32_t* q = static_cast<std::uint32_t*>(rtcSetNewGeometryBuffer(
        g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT4, 4 * sizeof(std::uint32_t), quadCount()));
    if (v) std::memcpy(v, vertices_.data(), vertices_.size() * sizeof(float));
    if (q) std::memcpy(q, quads_.data(), quads_.size() * sizeof(std::uint32_t));
    return g;
}

Vec3 IsoMeshSurface::worldGradient(const Vec3& world) const {
    const Vec3 u = map_.toIndex(world);
    const openvdb::Coord cell(static_cast<int>(std::floor(u.x)), static_cast<int>(std::floor(u.y)),
                              static_cast<int>(std::floor(u.z)));
    // An unregistered accessor: cheap to make per call, and one per call is thread-safe.
    auto acc = grid_->getConstUnsafeAccessor();
    double c[8];
    for (int i = 0; i < 8; ++i)
        c[i] = acc.getValue(cell + openvdb::Coord(i & 1, (i >> 1) & 1, (i >> 2) & 1));
    const Vec3 local(u.x - cell.x(), u.y - cell.y(), u.z - cell.z());
    return map_.gradientToWorld(trilinearGradient(c, local));
}

SurfaceHit IsoMeshSurface::shade(const Ray& ray, double t, unsigned primId) const {
    SurfaceHit hit;
    hit.t = t;
    hit.position = ray.at(t);
    hit.primId = primId;
    const Vec3 n = isFinite(hit.position) ? normalized(-worldGradient(hit.position)) : Vec3(0.0);
    hit.normal = (n.length2() > 0.0 && isFinite(n)) ? n : normalized(-ray.d);
    return hit;
}

}  // namespace lobe
