// The index → world map of Lobe's grids, with a world scale OpenVDB does not see.
//
// OpenVDB refuses an affine map whose determinant (a voxel's volume in world units³) is below
// 3e-15 whatever its conditioning (openvdb/math/Maps.h, AffineMap::updateAcceleration): a
// volume of 1e-5 mm voxels, or a scene transform scaling 1 mm voxels by 1e-5, could not be given
// to a grid at all. Lobe's own test of a map is relative (core/math.h, nearlySingular), so such a
// map is kept: the grid's OpenVDB transform is the map divided by a power of two s chosen to make
// its voxels about 1 unit across, and s is stored in the grid's metadata (kMetaWorldScale; absent
// means 1), which OpenVDB copies with the grid (Grid::copy) and writes into .vdb files. The full
// map is then
//
//     world = s · (index ↦ world of grid.transform()),
//
// and every consumer of a grid's world position reads it through these functions (or
// GridGeometry / surface AffineMap, built from them). Dividing by a power of two is exact in
// binary floating point, so the grid's map is the given map to the last bit, only rescaled; maps
// whose voxels are not tiny (|det| ≥ 1e-9) get s = 1 and no metadata: their grids are exactly
// what they were before.
#pragma once

#include <openvdb/openvdb.h>

#include <cmath>

namespace lobe {

inline constexpr const char* kMetaWorldScale = "lobe_world_scale";

// Below this |det| (world units³ per voxel) a map is rescaled: far above OpenVDB's 3e-15.
inline constexpr double kRescaleBelowDeterminant = 1e-9;

// s: 1 without the metadata.
inline double gridWorldScale(const openvdb::GridBase& grid) {
    const auto meta = grid.getMetadata<openvdb::DoubleMetadata>(kMetaWorldScale);
    return meta ? meta->value() : 1.0;
}

// Whether `s` is a world scale Lobe writes: a power of two in [2^-340, 2^-9] (setGridWorldMap's
// for voxels of 1e-300 … 1e-9 units³; GridGeometry refuses smaller ones).
inline bool validWorldScale(double s) {
    if (!(s >= std::ldexp(1.0, -340) && s <= std::ldexp(1.0, -9))) return false;
    int e = 0;
    return std::frexp(s, &e) == 0.5;
}

// Gives `grid` the index → world map `m` (row-vector form, world = index · m, as OpenVDB's
// Mat4d: the linear part in rows 0–2, the translation in row 3), rescaled as above when its
// voxels are tiny. The caller has checked m is finite and not nearly singular (relative test);
// OpenVDB's exceptions pass through.
inline void setGridWorldMap(openvdb::GridBase& grid, openvdb::math::Mat4d m) {
    const double det = std::abs(m.getMat3().det());
    double scale = 1.0;
    if (det > 0.0 && det < kRescaleBelowDeterminant) {
        // s = 2^round(log2(det)/3): the grid's voxels between 0.8 and 1.26 units across (cube
        // root of their volume).
        scale = std::ldexp(1.0, int(std::lround(std::log2(det) / 3.0)));
        for (int r = 0; r < 4; ++r)
            for (int c = 0; c < 3; ++c) m[r][c] /= scale;
    }
    grid.setTransform(openvdb::math::Transform::createLinearTransform(m));
    grid.removeMeta(kMetaWorldScale);
    if (scale != 1.0) grid.insertMeta(kMetaWorldScale, openvdb::DoubleMetadata(scale));
}

// The full map (row-vector form, as setGridWorldMap takes it). The transform must be linear.
inline openvdb::math::Mat4d gridWorldMatrix(const openvdb::GridBase& grid) {
    openvdb::math::Mat4d m = grid.transform().baseMap()->getAffineMap()->getMat4();
    const double s = gridWorldScale(grid);
    if (s != 1.0)
        for (int r = 0; r < 4; ++r)
            for (int c = 0; c < 3; ++c) m[r][c] *= s;
    return m;
}

inline openvdb::Vec3d gridIndexToWorld(const openvdb::GridBase& grid, const openvdb::Vec3d& p) {
    return grid.transform().indexToWorld(p) * gridWorldScale(grid);
}

inline openvdb::Vec3d gridWorldToIndex(const openvdb::GridBase& grid, const openvdb::Vec3d& x) {
    return grid.transform().worldToIndex(x / gridWorldScale(grid));
}

// World lengths of the index unit vectors.
inline openvdb::Vec3d gridVoxelSize(const openvdb::GridBase& grid) {
    return grid.transform().voxelSize() * gridWorldScale(grid);
}

}  // namespace lobe
