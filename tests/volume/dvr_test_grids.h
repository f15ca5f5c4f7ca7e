// Small analytic grids shared by the DVR tests.
#pragma once

#include <openvdb/openvdb.h>

#include <functional>

namespace lobe::test {

// A grid whose voxel (i, j, k) holds f(i, j, k) for i, j, k in [lo, hi]³ (all active), with a
// uniform or per-axis voxel size and an origin offset.
inline openvdb::FloatGrid::Ptr makeGrid(const std::function<double(int, int, int)>& f,
                                        const openvdb::Coord& lo, const openvdb::Coord& hi,
                                        const openvdb::Vec3d& voxelSize = openvdb::Vec3d(1.0),
                                        const openvdb::Vec3d& origin = openvdb::Vec3d(0.0)) {
    openvdb::initialize();
    auto grid = openvdb::FloatGrid::create(0.0f);
    openvdb::math::Transform::Ptr xf = openvdb::math::Transform::createLinearTransform(1.0);
    xf->preScale(voxelSize);
    xf->postTranslate(origin);
    grid->setTransform(xf);
    auto acc = grid->getAccessor();
    for (int k = lo.z(); k <= hi.z(); ++k)
        for (int j = lo.y(); j <= hi.y(); ++j)
            for (int i = lo.x(); i <= hi.x(); ++i)
                acc.setValue(openvdb::Coord(i, j, k), float(f(i, j, k)));
    return grid;
}

}  // namespace lobe::test
