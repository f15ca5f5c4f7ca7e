// The meshed iso-surface of a voxel grid: OpenVDB's volumeToMesh (dual contouring of the sign
// changes at adaptivity 0, which yields quads; any triangles are stored as quads with a repeated
// last vertex) in world space (volumeToMesh applies the grid transform), as an Embree user
// geometry over the quads' bounds whose callback runs a watertight ray/triangle test in double
// (Woop et al. 2013; iso_mesh.cpp): no ray slips between two triangles, through an edge or a
// vertex, which Embree's native quads allowed. The shading normal is not the facet normal: it is
// the analytic gradient of the grid's trilinear interpolant at the hit point (trilinear_cell.h),
// carried to world space by A⁻ᵀ and oriented along −∇f like the exact method (surface_scene.h,
// "Normal convention"), so both methods shade with the same field and differ only in where they
// place the surface.
#pragma once

#include "surface/affine_map.h"
#include "surface/surface_scene.h"

#include <openvdb/openvdb.h>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace lobe {

class IsoMeshSurface : public SurfaceGeometry {
public:
    // Throws lobe::Error (naming `name`) for a non-affine transform or a non-finite iso value.
    IsoMeshSurface(const openvdb::FloatGrid& grid, double iso, const std::string& name = "grid");

    RTCGeometry createGeometry(RTCDevice device) const override;
    SurfaceHit shade(const Ray& ray, double t, unsigned primId) const override;

    // ∇f of the trilinear interpolant at a world position, in world space.
    Vec3 worldGradient(const Vec3& world) const;

    // The Embree user-geometry callbacks (user_geometry.h), in world space; one primitive per
    // quad, intersected by the watertight test (iso_mesh.cpp).
    const AffineMap& primitiveSpace() const { return identity_; }
    const std::array<float, 6>& primitiveBounds(unsigned quad) const { return bounds_[quad]; }
    bool intersectPrimitive(unsigned quad, const Vec3& o, const Vec3& d, double tMin, double tMax,
                            double& t) const;

    double iso() const { return iso_; }
    std::size_t vertexCount() const { return vertices_.size() / 3; }
    std::size_t quadCount() const { return quads_.size() / 4; }  // triangles included
    std::size_t triangleCount() const { return triangles_; }
    std::size_t memoryBytes() const;
    const std::vector<float>& vertices() const { return vertices_; }    // xyz, world
    const std::vector<std::uint32_t>& quads() const { return quads_; }  // 4 indices each

private:
    double iso_ = 0.0;
    AffineMap map_;
    openvdb::FloatGrid::ConstPtr grid_;  // shares the caller's tree, for the shading gradient
    std::vector<float> vertices_;        // xyz per vertex, world space
    std::vector<std::uint32_t> quads_;   // 4 vertex indices per quad
    std::size_t triangles_ = 0;
    std::vector<std::array<float, 6>> bounds_;  // world AABB per quad
    AffineMap identity_ = AffineMap::fromMatrix(Mat3(), Vec3(0.0));
};

}  // namespace lobe
