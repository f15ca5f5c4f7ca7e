// Internal to lobe_volume: reading volume files into a dense float array plus an index → world
// affine, without OpenVDB (so the header parsers compile fast and can be tested on their own).
// volume.cpp turns a DenseVolume into an OpenVDB grid.
#pragma once

#include "volume/volume_array.h"
#include "volume/volume_layout.h"

#include <array>
#include <string>
#include <vector>

namespace lobe {
namespace detail {

struct DenseVolume {
    std::vector<float> values;  // dims[0]·dims[1]·dims[2], x fastest; file rescaling applied
    std::array<int, 3> dims{0, 0, 0};
    // Index → world: world = A · (i, j, k, 1)ᵀ, rows of A are x, y, z.
    std::array<std::array<double, 4>, 3> affine{{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}}};
    double min = 0.0, max = 0.0;  // of values
    std::string note;             // how the data was read, worth a warning (Volume::note)
};

// The whole file, decompressed when gzip is true (the gzip magic is checked first). A gzip
// stream that inflates past `maxBytes` (what its header or layout — `what` — describes) is
// refused there, so a small file cannot fill the memory (a 2 MB gzip bomb holds 2 GB). With
// `prefix`, the first `maxBytes` are returned and the rest is not read.
std::vector<unsigned char> readFileBytes(const std::string& path, bool gzip,
                                         size_t maxBytes = size_t(-1),
                                         const std::string& what = "header", bool prefix = false);

// Decodes count = dims product voxels of `type` from bytes[offset…], swapping bytes when the
// file's endianness differs from the machine's, applies value·slope + inter, and refuses
// non-finite results. Checks that bytes holds exactly offset + voxel bytes; `what` describes the
// source of the layout for the error message ("header", "layout").
DenseVolume decodeVoxels(const std::string& path, const std::vector<unsigned char>& bytes,
                         std::int64_t offset, const std::array<int, 3>& dims, VoxelType type,
                         Endian endian, double slope, double inter, const std::string& what);

DenseVolume readRawDense(const std::string& path, const RawLayout& layout);
DenseVolume readNiftiDense(const std::string& path);
DenseVolume readNrrdDense(const std::string& path);
DenseVolume readMghDense(const std::string& path);     // FreeSurfer .mgh / .mgz
DenseVolume readArrayDense(const VolumeArray& array);  // volume/volume_array.cpp

bool endsWith(const std::string& s, const std::string& suffix);  // case-insensitive

}  // namespace detail
}  // namespace lobe
