#include "volume/dense_field.h"

#include "core/memory.h"

namespace lobe {

DenseField::DenseField(const openvdb::FloatGrid& grid, const openvdb::CoordBBox& box) {
    const openvdb::Coord dim = box.dim();
    const double voxels = double(dim.x()) * double(dim.y()) * double(dim.z());
    checkFits(4.0 * voxels, "a dense copy of " + std::to_string(dim.x()) + " x " +
                                std::to_string(dim.y()) + " x " + std::to_string(dim.z()) +
                                " voxels");
    dense_ = std::make_unique<openvdb::tools::Dense<float, openvdb::tools::LayoutZYX>>(box);
    openvdb::tools::copyToDense(grid, *dense_);  // parallel (TBB); background outside the tree
    data_ = dense_->data();
    for (int a = 0; a < 3; ++a) {
        lo_[a] = box.min()[a];
        hi_[a] = box.max()[a];
    }
    xStride_ = dense_->xStride();
    yStride_ = dense_->yStride();
    bytes_ = size_t(voxels) * sizeof(float);
}

}  // namespace lobe
