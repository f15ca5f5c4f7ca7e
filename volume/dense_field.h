// A dense copy of a grid's values over an index box, for the ray marcher's reads.
//
// Why: an OpenVDB ValueAccessor walks (or checks its cached path through) the tree for every
// voxel it reads. Trilinear reconstruction reads 8 voxels per sample and central differences 48
// more per shaded sample; on the CThead (task t2 of bench/peers) the accessor's reads were ~22 % of
// the render and the marcher's own bookkeeping ~32 %. Read from a flat array instead, a voxel is
// one load at base + x·sx + y·sy + z. The values are those getValue would return (the copy is
// OpenVDB's own tools::copyToDense, in parallel), so every reconstruction gives the same bits.
//
// Memory: 4 bytes per voxel of the box. A DvrVolume keeps a copy only when it is at most
// kMaxBytes and an eighth of the machine's memory (core/memory.h); otherwise it reads the tree.
#pragma once

#include <openvdb/openvdb.h>
#include <openvdb/tools/Dense.h>

#include <cstddef>
#include <memory>

namespace lobe {

class DenseField {
public:
    // Larger boxes are read from the tree (1 GiB: a 645³ box).
    static constexpr double kMaxBytes = double(1u << 30);

    // Copies `grid` over `box` (inclusive index bounds). Throws lobe::Error if it cannot fit.
    DenseField(const openvdb::FloatGrid& grid, const openvdb::CoordBBox& box);

    // Whether the n³ block of voxels starting at (i, j, k) lies in the box.
    bool holds(int i, int j, int k, int n) const {
        return i >= lo_[0] && j >= lo_[1] && k >= lo_[2] && i + n - 1 <= hi_[0] &&
               j + n - 1 <= hi_[1] && k + n - 1 <= hi_[2];
    }
    // The voxel (i, j, k), which must be in the box; neighbours along z are contiguous, along y
    // yStride() apart and along x xStride() apart (OpenVDB's leaf order, x slowest).
    const float* at(int i, int j, int k) const {
        return data_ +
               (size_t(i - lo_[0]) * xStride_ + size_t(j - lo_[1]) * yStride_ + size_t(k - lo_[2]));
    }
    // The box's inclusive bounds along axis a (0 = x).
    int lo(int a) const { return lo_[a]; }
    int hi(int a) const { return hi_[a]; }
    size_t xStride() const { return xStride_; }
    size_t yStride() const { return yStride_; }
    size_t bytes() const { return bytes_; }

private:
    std::unique_ptr<openvdb::tools::Dense<float, openvdb::tools::LayoutZYX>> dense_;
    const float* data_ = nullptr;
    int lo_[3] = {0, 0, 0}, hi_[3] = {-1, -1, -1};
    size_t xStride_ = 0, yStride_ = 0, bytes_ = 0;
};

}  // namespace lobe
