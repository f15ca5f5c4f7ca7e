// A volume in memory instead of a file: a typed array with its strides and index → world affine,
// as a NumPy array and a NIfTI affine give it (the Python module, docs/python.md). loadArray
// (volume/volume.h) turns it into a Volume as the file loaders do — the same value scaling,
// normalisation, background and sparsity — without writing a file. Kept free of OpenVDB, so the
// scene description can name one cheaply.
#pragma once

#include "volume/volume_layout.h"

#include <array>
#include <cstdint>
#include <string>

namespace lobe {

struct VolumeArray {
    // What messages call it, and its identity in a cache of loaded sources (render/scene.h):
    // unique per array, e.g. "array 3 (objects[0].source)".
    std::string name;
    // Voxel (i, j, k), 0 ≤ i < dims[0] …, at data + i·strides[0] + j·strides[1] + k·strides[2]
    // bytes, of `type` in the machine's byte order. Not owned: whoever made the VolumeArray keeps
    // the memory alive and unchanged while it may be loaded.
    const void* data = nullptr;
    VoxelType type = VoxelType::kFloat32;
    std::array<int, 3> dims{0, 0, 0};
    std::array<std::int64_t, 3> strides{0, 0, 0};
    // Index → world: world = A · (i, j, k, 1)ᵀ, rows of A are x, y, z (a NIfTI affine's first
    // three rows).
    std::array<std::array<double, 4>, 3> affine{{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}}};
    // value = raw · slope + inter, as a NIfTI file's scl_slope / scl_inter (volume/volume.h).
    double slope = 1.0;
    double inter = 0.0;
};

}  // namespace lobe
