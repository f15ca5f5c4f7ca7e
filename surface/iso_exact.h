// The exact iso-surface of a voxel grid's trilinear interpolant as an Embree user geometry.
//
// Method (Marmitt et al., "Fast and Accurate Ray-Voxel Intersection Techniques for Iso-Surface Ray
// Tracing", VMV 2004; the same scheme as Mitsuba 3's src/shapes/sdfgrid.cpp):
// - The cells of the grid (the cubes between 8 neighbouring voxel centres) are grouped into
//   bricks of 8³ cells aligned with OpenVDB's leaf nodes. A brick needs the 9³ lattice values of
//   its cells (its leaf plus the +1 neighbours); the interpolant over a cell is a convex
//   combination of its 8 corners, so the min/max of those 9³ values bounds the interpolant over
//   the brick exactly. Bricks whose range excludes the iso value (min > iso or max < iso) are
//   never built; the others are the user geometry's primitives, each holding its own 9³ values
//   (so memory grows with the surface's area, and the callbacks never touch the VDB tree).
// - Inside a brick the ray is cut at every crossing of a cell face: a 3-D DDA (Amanatides & Woo,
//   "A Fast Voxel Traversal Algorithm for Ray Tracing", Eurographics 1987) that keeps, per axis,
//   the next integer plane and the integer cell index, and steps every axis whose plane is reached
//   at the segment's end (all of them at once on a tie, so through a voxel edge or corner the
//   zero-length segments are skipped and no cell the ray's interior passes through is missed).
//   Each crossing time is recomputed from its integer plane, (k − o)/d, so nothing drifts.
// - Each brick also stores two 512-bit masks, built once with the brick: the cells whose 8 corners
//   straddle the iso value, and the cells whose corners are all above it. A cell that does not
//   straddle costs one bit test (it cannot hold a root: the interpolant is a convex combination
//   of its corners); only straddling cells read their 8 corners and build the cubic in t
//   (trilinear_cell.h), split at its derivative's roots and refined to ~1e-10 voxel. A ray that
//   misses the box of a brick's straddling cells (most calls: the box is a slab clip, 6 divisions)
//   returns at once: the cells it would visit all lie on one side of iso (consecutive cells of
//   the walk share at least one corner, so two non-straddling ones have the same side), and the
//   walk could only have reported a hit at a sign change.
//   A sign change exactly across a cell face (rounding between two cells' cubics) is caught by
//   comparing each segment's start value with the previous segment's end value, and bricks are
//   entered 1e-7 voxel early and left 1e-7 voxel late so a root on a brick face is never lost.
// - Normal: the analytic gradient of the same trilinear interpolant at the hit, carried to world
//   space by A⁻ᵀ (affine_map.h) and oriented along −∇f: out of the region where value > iso
//   (surface_scene.h, "Normal convention"). A zero gradient (a saddle exactly on the surface)
//   falls back to −ray direction.
// The grid may have any affine index → world transform (voxel centres at integer index
// coordinates, OpenVDB's convention); values outside the stored tree read as its background.
#pragma once

#include "surface/affine_map.h"
#include "surface/brick_walk.h"
#include "surface/surface_scene.h"

#include <openvdb/Grid.h>
#include <openvdb/openvdb.h>
#include <openvdb/tree/Tree.h>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace lobe {

class IsoExactSurface : public SurfaceGeometry {
public:
    static constexpr int kBrickCells = BrickCells::kCells;    // cells per brick side
    static constexpr int kBrickPoints = BrickCells::kPoints;  // lattice points per brick side
    static constexpr int kBrickValues = BrickCells::kValues;

    // Throws lobe::Error (naming `name`) for a non-affine transform, a non-finite iso value or
    // non-finite voxel values.
    IsoExactSurface(const openvdb::FloatGrid& grid, double iso, const std::string& name = "grid");

    RTCGeometry createGeometry(RTCDevice device) const override;
    SurfaceHit shade(const Ray& ray, double t, unsigned primId) const override;

    // First root of the interpolant minus iso along the index-space ray o + t·d with t ∈ [tMin,
    // tMax] inside brick `brick`; the Embree callbacks and the tests use it.
    bool intersectBrick(unsigned brick, const Vec3& o, const Vec3& d, double tMin, double tMax,
                        double& t) const;

    double iso() const { return iso_; }
    const AffineMap& map() const { return map_; }
    std::size_t brickCount() const { return origins_.size(); }
    std::size_t candidateBrickCount() const { return candidateBricks_; }  // skipped ones included
    std::size_t memoryBytes() const;
    // Index of the first cell (= first lattice point) of brick `brick`; the tests use it.
    const openvdb::Coord& brickOrigin(unsigned brick) const { return origins_[brick]; }

    // The Embree user-geometry callbacks (user_geometry.h), in index space.
    const AffineMap& primitiveSpace() const { return map_; }
    using PrimitiveRay = WalkRay;  // made once per ray (user_geometry.h)
    bool intersectPrimitive(unsigned brick, const WalkRay& ray, double tMin, double tMax,
                            double& t) const;
    bool intersectPrimitive(unsigned brick, const Vec3& o, const Vec3& d, double tMin, double tMax,
                            double& t) const {
        return intersectBrick(brick, o, d, tMin, tMax, t);
    }
    const std::array<float, 6>& primitiveBounds(unsigned brick) const { return bounds_[brick]; }
    Vec3 worldGradient(unsigned brick, const Vec3& u) const;  // ∇f in world space at index u

private:
    void cellCorners(unsigned brick, const openvdb::Coord& cell, double c[8]) const;

    double iso_ = 0.0;
    AffineMap map_;
    std::vector<openvdb::Coord> origins_;       // first cell (= first lattice point) of each brick
    std::vector<float> values_;                 // kBrickValues per brick, x fastest
    std::vector<BrickCells> cells_;             // cell classes per brick (brick_walk.h)
    std::vector<std::array<float, 6>> bounds_;  // world AABB per brick (min xyz, max xyz)
    std::size_t candidateBricks_ = 0;
};

}  // namespace lobe
