// Meshed iso-surface (OpenVDB volumeToMesh → quads, a watertight test per quad); see iso_mesh.h.
#include "surface/iso_mesh.h"

#include "core/error.h"
#include "surface/trilinear_cell.h"
#include "surface/user_geometry.h"

#include <openvdb/tools/VolumeToMesh.h>

#include <cmath>
#include <cstring>
#include <limits>

namespace lobe {

constexpr double kInf = std::numeric_limits<double>::infinity();

IsoMeshSurface::IsoMeshSurface(const openvdb::FloatGrid& grid, double iso, const std::string& name)
    : iso_(iso), map_(AffineMap::fromGrid(grid, name)), grid_(grid.copy()) {
    if (!std::isfinite(iso)) throw Error(name + ": iso value must be finite");
    std::vector<openvdb::Vec3s> points;
    std::vector<openvdb::Vec3I> triangles;
    std::vector<openvdb::Vec4I> quads;
    // Adaptivity 0: no simplification, so the mesh error is the method's, not the decimation's.
    openvdb::tools::volumeToMesh(grid, points, triangles, quads, iso, 0.0);
    vertices_.reserve(points.size() * 3);
    // volumeToMesh's vertices are in the grid transform's world: times the world scale of tiny
    // voxels (volume/grid_world.h; a power of two, exact).
    const float s = float(gridWorldScale(grid));
    for (const openvdb::Vec3s& p : points) {
        if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
            throw Error(name + ": volumeToMesh produced a non-finite vertex (non-finite voxels?)");
        vertices_.insert(vertices_.end(), {p[0] * s, p[1] * s, p[2] * s});
    }
    quads_.reserve((quads.size() + triangles.size()) * 4);
    for (const openvdb::Vec4I& q : quads) quads_.insert(quads_.end(), {q[0], q[1], q[2], q[3]});
    // Embree's quad geometry takes a triangle as a quad whose last two vertices coincide.
    for (const openvdb::Vec3I& t : triangles) quads_.insert(quads_.end(), {t[0], t[1], t[2], t[2]});
    triangles_ = triangles.size();
    bounds_.reserve(quadCount());
    for (std::size_t i = 0; i < quadCount(); ++i) {
        double mn[3] = {kInf, kInf, kInf}, mx[3] = {-kInf, -kInf, -kInf};
        for (int c = 0; c < 4; ++c)
            for (int a = 0; a < 3; ++a) {
                const double x = vertices_[3 * std::size_t(quads_[4 * i + c]) + a];
                mn[a] = std::min(mn[a], x);
                mx[a] = std::max(mx[a], x);
            }
        std::array<float, 6> box{};
        for (int a = 0; a < 3; ++a) {
            const double pad = 1e-5 * (std::abs(mn[a]) + std::abs(mx[a]) + 1.0);
            box[a] = std::nextafter(static_cast<float>(mn[a] - pad),
                                    -std::numeric_limits<float>::infinity());
            box[a + 3] = std::nextafter(static_cast<float>(mx[a] + pad),
                                        std::numeric_limits<float>::infinity());
        }
        bounds_.push_back(box);
    }
}

std::size_t IsoMeshSurface::memoryBytes() const {
    return vertices_.size() * sizeof(float) + quads_.size() * sizeof(std::uint32_t) +
           bounds_.size() * sizeof(bounds_[0]);
}

namespace {

// Watertight ray/triangle intersection (Woop, Benthin & Wald, "Watertight Ray/Triangle
// Intersection", JCGT 2(1), 2013), in double. The ray is made the +z axis of a sheared frame
// (axis kz its largest component); each vertex's 2-D position in that frame depends on the
// vertex and the ray only, so two triangles sharing an edge evaluate the same edge function.
// Each edge function is computed in one canonical vertex order (lower index first) and negated
// for the other, so the two triangles see exactly opposite values even if the compiler fuses
// multiply-adds: a ray through an edge or a vertex hits at least one triangle (edges are
// inclusive). Embree's native quads, robust mode included, let ~1 in 2 300 rays aimed exactly
// at vertices through (tests/surface/test_iso_surface.cpp, the leak test).
struct ShearedRay {
    int kx, ky, kz;
    double sx, sy, sz;
    Vec3 o;

    explicit ShearedRay(const Vec3& origin, const Vec3& d) : o(origin) {
        kz = std::abs(d.x) > std::abs(d.y) ? (std::abs(d.x) > std::abs(d.z) ? 0 : 2)
                                           : (std::abs(d.y) > std::abs(d.z) ? 1 : 2);
        kx = (kz + 1) % 3;
        ky = (kx + 1) % 3;
        if (d[kz] < 0.0) std::swap(kx, ky);  // keeps the frame's winding
        sx = d[kx] / d[kz];
        sy = d[ky] / d[kz];
        sz = 1.0 / d[kz];
    }
    // The vertex in the sheared frame: (x, y) across the ray, z along it (unscaled).
    Vec3 project(const Vec3& v) const {
        const Vec3 a = v - o;
        return Vec3(a[kx] - sx * a[kz], a[ky] - sy * a[kz], a[kz]);
    }
};

// Edge function of the directed edge p → q (2-D cross product), computed in the order of the
// lower vertex index so that q → p yields exactly its negation.
double edgeFunction(const Vec3& p, std::uint32_t ip, const Vec3& q, std::uint32_t iq) {
    if (ip < iq) return q.x * p.y - q.y * p.x;
    return -(p.x * q.y - p.y * q.x);
}

bool intersectTriangle(const ShearedRay& ray, const Vec3 v[3], const std::uint32_t id[3],
                       double tMin, double tMax, double& t) {
    // U: edge 1→2, V: edge 2→0, W: edge 0→1 (Woop et al., Fig. 2).
    const double u = edgeFunction(v[1], id[1], v[2], id[2]);
    const double w = edgeFunction(v[0], id[0], v[1], id[1]);
    const double vv = edgeFunction(v[2], id[2], v[0], id[0]);
    if ((u < 0.0 || vv < 0.0 || w < 0.0) && (u > 0.0 || vv > 0.0 || w > 0.0)) return false;
    const double det = u + vv + w;
    if (det == 0.0) return false;  // degenerate, or the ray lies in the triangle's plane
    const double tScaled = ray.sz * (u * v[0].z + vv * v[1].z + w * v[2].z);
    const double tHit = tScaled / det;
    if (!(tHit >= tMin && tHit <= tMax)) return false;
    t = tHit;
    return true;
}

}  // namespace

bool IsoMeshSurface::intersectPrimitive(unsigned quad, const Vec3& o, const Vec3& d, double tMin,
                                        double tMax, double& t) const {
    if (!(d.length2() > 0.0) || !isFinite(d) || !isFinite(o)) return false;
    const ShearedRay ray(o, d);
    const std::uint32_t* q = &quads_[4 * std::size_t(quad)];
    Vec3 p[4];
    for (int i = 0; i < 4; ++i) {
        const float* v = &vertices_[3 * std::size_t(q[i])];
        p[i] = ray.project(Vec3(v[0], v[1], v[2]));
    }
    // The two triangles Embree would make of the quad, (v0, v1, v3) and (v2, v3, v1).
    bool hit = false;
    const Vec3 a[3] = {p[0], p[1], p[3]}, b[3] = {p[2], p[3], p[1]};
    const std::uint32_t ia[3] = {q[0], q[1], q[3]}, ib[3] = {q[2], q[3], q[1]};
    double ta = 0.0, tb = 0.0;
    if (intersectTriangle(ray, a, ia, tMin, tMax, ta)) {
        t = ta;
        hit = true;
        tMax = ta;
    }
    if (intersectTriangle(ray, b, ib, tMin, tMax, tb)) {
        t = tb;
        hit = true;
    }
    return hit;
}

RTCGeometry IsoMeshSurface::createGeometry(RTCDevice device) const {
    return user_geometry::create(device, this, quadCount());
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
    return user_geometry::shadeByGradient(ray, t, primId,
                                          [&](const Vec3& x) { return worldGradient(x); });
}

}  // namespace lobe
