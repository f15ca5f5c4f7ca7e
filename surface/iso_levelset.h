// An iso-surface kept as an OpenVDB narrow-band level set and intersected exactly.
//
// Conversion. A density grid's iso-surface becomes a signed distance field φ (negative inside,
// where the density is above iso; OpenVDB's level-set convention): the distance is OpenVDB's
// unsigned distance to the iso-surface's mesh (volumeToMesh, then meshToUnsignedDistanceField in
// a band of ±halfWidth voxels), the sign is the density's own (its trilinear interpolant against
// iso at each band voxel), and signedFloodFill carries the band's signs to the tiles inside and
// outside. Why not levelSetRebuild: its meshToVolume decides the sign by what the outside can
// reach, so a shell's cavity (the skull's cranial cavity) becomes inside and its inner wall
// disappears. The rebuild may resample: at the source grid's own transform (the default) or at
// an isotropic voxel size.
// A .vdb whose grid is already a level set (class GRID_LEVEL_SET: vdb_tool, Houdini, `lobe
// convert` output of a level set) is used as it is.
//
// Storage. The level set's tree is the only copy of the values: nothing is copied into bricks.
// Per 8³ block of cells that holds a sign change (aligned with OpenVDB's leaf nodes) the surface
// keeps only its cell classes (BrickCells: 2 × 512 bits and a box) and its world bounds.
//
// Intersection. Embree's BVH over those blocks' bounds skips to the band (it plays the role of
// OpenVDB's HDDA over the tree, and shares one hierarchy with the scene's other objects); inside a
// block the walk and the per-cell cubic root of φ's trilinear interpolant are the exact method's
// (brick_walk.h), with corner values read from the tree through a value accessor. So the level
// set and the exact method differ only in the field they solve: the exact method solves the
// density's interpolant, this one the distance field's.
//
// Normals: the analytic gradient of φ's trilinear interpolant at the hit, carried to world space
// (∇φ points out of the object, the convention of surface_scene.h).
#pragma once

#include "surface/affine_map.h"
#include "surface/brick_walk.h"
#include "surface/surface_scene.h"

#include <openvdb/openvdb.h>

#include <array>
#include <memory>
#include <string>
#include <vector>

namespace lobe {

struct LevelSetOptions {
    double voxelSize = 0.0;  // world units; 0: rebuild at the source grid's own transform
    double halfWidth = 3.0;  // voxels on each side of the surface (OpenVDB's default)
    // Iterations of mean-curvature flow (OpenVDB's LevelSetFilter::meanCurvature, which keeps
    // the band a distance field): smooths the slice terraces of an anisotropic scan while thin
    // structures keep their place (docs/performance.md, "The skull without terraces"). The
    // filter needs cubic voxels: with voxelSize 0 and a non-cubic source, the level set is
    // built at the source's smallest voxel side.
    int smoothIterations = 0;
};

class LevelSetSurface : public SurfaceGeometry {
public:
    // The iso-surface of a density grid, rebuilt as a level set. Throws lobe::Error (naming
    // `name`) for a non-finite iso value, a non-affine transform, an empty surface or one whose
    // level set would not fit in memory.
    static std::shared_ptr<LevelSetSurface> fromDensity(const openvdb::FloatGrid& density,
                                                        double iso, const LevelSetOptions& options,
                                                        const std::string& name = "grid");

    // A level set as it is (φ < 0 inside); its zero crossing is the surface.
    explicit LevelSetSurface(openvdb::FloatGrid::ConstPtr levelSet,
                             const std::string& name = "grid");

    RTCGeometry createGeometry(RTCDevice device) const override;
    SurfaceHit shade(const Ray& ray, double t, unsigned primId) const override;

    const openvdb::FloatGrid& levelSet() const { return *phi_; }
    const AffineMap& map() const { return map_; }
    std::size_t blockCount() const { return origins_.size(); }
    // The level set's tree plus the per-block classes and bounds.
    std::size_t memoryBytes() const;

    // The Embree user-geometry callbacks (user_geometry.h), in the level set's index space.
    const AffineMap& primitiveSpace() const { return map_; }
    using PrimitiveRay = WalkRay;  // made once per ray (user_geometry.h)
    bool intersectPrimitive(unsigned block, const WalkRay& ray, double tMin, double tMax,
                            double& t) const;
    bool intersectPrimitive(unsigned block, const Vec3& o, const Vec3& d, double tMin, double tMax,
                            double& t) const;
    const std::array<float, 6>& primitiveBounds(unsigned block) const { return bounds_[block]; }
    Vec3 worldGradient(unsigned block, const Vec3& u) const;  // −∇φ in world space at index u

private:
    openvdb::FloatGrid::ConstPtr phi_;
    AffineMap map_;
    std::vector<openvdb::Coord> origins_;       // first cell of each block holding a sign change
    std::vector<BrickCells> cells_;             // cell classes of −φ against 0 (brick_walk.h)
    std::vector<std::array<float, 6>> bounds_;  // world AABB per block
};

}  // namespace lobe
