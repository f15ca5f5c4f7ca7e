// An in-memory array (volume/volume_array.h) to the dense float volume every loader produces
// (volume/volume_file.h): the same conversion as a file's voxels (decodeVoxels: raw · slope +
// inter in double, stored as float, non-finite values refused), read through the array's strides
// so that any memory order (C or Fortran, a view) is taken as it is.
#include "volume/volume_array.h"

#include "core/error.h"
#include "core/memory.h"
#include "volume/volume_file.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace lobe {
namespace detail {

namespace {

template <typename T>
void convert(const VolumeArray& a, DenseVolume& v) {
    const auto* base = static_cast<const unsigned char*>(a.data);
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    size_t n = 0;
    for (int k = 0; k < a.dims[2]; ++k)
        for (int j = 0; j < a.dims[1]; ++j) {
            // Offsets summed as integers: with negative strides (a reversed view) a partial sum
            // may lie outside the array, which a pointer must not.
            const std::int64_t row = k * a.strides[2] + j * a.strides[1];
            for (int i = 0; i < a.dims[0]; ++i, ++n) {
                T raw;
                std::memcpy(&raw, base + (row + i * a.strides[0]), sizeof(T));
                const double value = double(raw) * a.slope + a.inter;
                const float stored = static_cast<float>(value);
                if (!std::isfinite(double(raw)) || !std::isfinite(stored))
                    throw Error(a.name + ": voxel (" + std::to_string(i) + ", " +
                                std::to_string(j) + ", " + std::to_string(k) + ") is " +
                                (std::isnan(double(raw))   ? "NaN"
                                 : std::isinf(double(raw)) ? "infinite"
                                                           : "outside the float range") +
                                "; volumes must hold finite values");
                v.values[n] = stored;
                lo = std::min(lo, double(stored));
                hi = std::max(hi, double(stored));
            }
        }
    v.min = lo;
    v.max = hi;
}

}  // namespace

DenseVolume readArrayDense(const VolumeArray& a) {
    std::int64_t count = 1;
    for (int d = 0; d < 3; ++d) {
        if (a.dims[d] < 1 || a.dims[d] > (1 << 20))
            throw Error(a.name + ": dimensions " + std::to_string(a.dims[0]) + " x " +
                        std::to_string(a.dims[1]) + " x " + std::to_string(a.dims[2]) +
                        "; each must be between 1 and 1048576");
        count *= a.dims[d];
    }
    if (count > (std::int64_t(1) << 34))
        throw Error(a.name + ": " + std::to_string(count) + " voxels, too many to load");
    if (!a.data) throw Error(a.name + ": no data");
    if (!std::isfinite(a.slope) || !std::isfinite(a.inter))
        throw Error(a.name + ": a non-finite value scaling");
    for (const auto& row : a.affine)
        for (double x : row)
            if (!std::isfinite(x)) throw Error(a.name + ": the affine holds a non-finite number");
    checkFits(double(count) * sizeof(float),
              a.name + ": a float copy of its " + std::to_string(count) + " voxels");
    DenseVolume v;
    v.dims = a.dims;
    v.affine = a.affine;
    v.values.resize(size_t(count));
    switch (a.type) {
        case VoxelType::kUint8:
            convert<std::uint8_t>(a, v);
            break;
        case VoxelType::kInt8:
            convert<std::int8_t>(a, v);
            break;
        case VoxelType::kUint16:
            convert<std::uint16_t>(a, v);
            break;
        case VoxelType::kInt16:
            convert<std::int16_t>(a, v);
            break;
        case VoxelType::kUint32:
            convert<std::uint32_t>(a, v);
            break;
        case VoxelType::kInt32:
            convert<std::int32_t>(a, v);
            break;
        case VoxelType::kFloat32:
            convert<float>(a, v);
            break;
        case VoxelType::kFloat64:
            convert<double>(a, v);
            break;
    }
    return v;
}

}  // namespace detail
}  // namespace lobe
