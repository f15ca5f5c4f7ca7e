#include "volume/volume_mask.h"

#include "core/error.h"
#include "volume/grid_world.h"

#include <openvdb/tools/Interpolation.h>

#include <algorithm>
#include <cmath>

namespace lobe {

VolumeMask::VolumeMask(openvdb::FloatGrid::ConstPtr grid, double iso, bool invert)
    : grid_(std::move(grid)), iso_(iso), invert_(invert) {
    if (!grid_) throw Error("mask: no grid");
    if (!std::isfinite(iso_)) throw Error("mask: the iso value must be finite");
}

bool VolumeMask::keeps(const Vec3& x) const {
    const openvdb::Vec3d u = gridWorldToIndex(*grid_, openvdb::Vec3d(x.x, x.y, x.z));
    const bool inside = openvdb::tools::BoxSampler::sample(grid_->tree(), u) > iso_;
    return inside != invert_;
}

}  // namespace lobe
