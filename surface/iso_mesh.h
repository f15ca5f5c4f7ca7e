// The meshed iso-surface of a voxel grid: OpenVDB's volumeToMesh (dual contouring of the sign
// changes at adaptivity 0, which yields quads; any triangles are stored as quads with a repeated
// last vertex) placed in an Embree quad geometry, in world space (volumeToMesh applies the grid
// transform). The shading normal is not the facet normal: it is the analytic gradient of the
// grid's trilinear interpolant at the hit point (trilinear_cell.h), carried to world space by A⁻ᵀ
// and oriented along −∇f like the exact method (surface_scene.h, "Normal convention"), so both
// methods shade with the same field and differ only in where they place the surface.
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

    double iso() const { return iso_; }
    std::size_t vertexCount() const { return vertices_.size() / 3; }
    std::size_t quadCount() const { return quads_.size() / 4; }  // triangles included
    std::size_t triangleCount() const { return triangles_; }
    std::size_t memoryBytes() const;

private:
    double iso_ = 0.0;
    AffineMap map_;
    openvdb::FloatGrid::ConstPtr grid_;  // shares the caller's tree, for the shading gradient
    std::vector<float> vertices_;        // xyz per vertex, world space
    std::vector<std::uint32_t> quads_;   // 4 vertex indices per quad
    std::size_t triangles_ = 0;
};

}  // namespace lobe
