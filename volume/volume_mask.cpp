#include "volume/volume_mask.h"

#include "core/error.h"
#include "volume/grid_world.h"

#include <openvdb/tools/Interpolation.h>

#include <algorithm>
#include <cmath>

namespace lobe {

VolumeMask::VolumeMask(openvdb::FloatGrid::ConstPtr grid, double iso, bool invert,
                       std::vector<int> labels)
    : grid_(std::move(grid)), iso_(iso), invert_(invert), labels_(std::move(labels)) {
    if (!grid_) throw Error("mask: no grid");
    if (!std::isfinite(iso_)) throw Error("mask: the iso value must be finite");
    std::sort(labels_.begin(), labels_.end());
}

bool VolumeMask::keeps(const Vec3& x) const {
    const openvdb::Vec3d u = gridWorldToIndex(*grid_, openvdb::Vec3d(x.x, x.y, x.z));
    bool inside;
    if (!labels_.empty()) {
        const openvdb::Coord c(int(std::floor(u.x() + 0.5)), int(std::floor(u.y() + 0.5)),
                               int(std::floor(u.z() + 0.5)));
        const double v = grid_->tree().getValue(c);
        inside = std::binary_search(labels_.begin(), labels_.end(), int(std::lround(v)));
    } else {
        inside = openvdb::tools::BoxSampler::sample(grid_->tree(), u) > iso_;
    }
    return inside != invert_;
}

}  // namespace lobe
