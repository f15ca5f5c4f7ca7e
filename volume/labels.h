// Label maps (segmentations, atlases): volumes whose voxels hold whole-number labels, 0 the
// background. What a scene's label objects are made of (docs/scene-format.md, "Labels"):
//
// - The map is loaded once per process however many objects use it (loadLabelMap: a memo by
//   path), and indexed once: the labels present, each with its voxel count and index box.
// - A label *set* S selects the voxels whose label is in S: labelMask is that indicator, 1 in
//   S and 0 elsewhere, voxel for voxel (the mask nibabel gives as np.isin(data, S)).
// - Its surface (labelSurfaceField) is the 0.5 level of the indicator anti-aliased by a sampled
//   Gaussian of σ voxels (default 0.6; gaussian_blur.h) and interpolated trilinearly. Why:
//   * No false shells. The field depends on S's indicator only, so where labels a < k < b meet
//     nothing of k appears (an iso value on the labels themselves, 36.5 < 37 < 37.5, makes a
//     shell wherever the interpolation passes through 37 between a and b).
//   * Faithful. For a plane boundary the blurred step is odd-symmetric about the voxel face, so
//     it crosses 0.5 exactly on the face. Corners are rounded: for a continuous Gaussian the 0.5
//     level lies 0.55σ inside an edge (Φ(x/σ)² = ½) and 0.82σ inside a corner (Φ(x/σ)³ = ½) of
//     the voxel cubes, and a curved boundary moves inward by about σ²/R. At σ = 0.6 that is
//     0.33 and 0.49 voxel: within half a voxel of the boundary of S's voxel cubes, which the
//     tests measure on a sphere and a box. Larger σ (label_smooth) smooths more — an atlas
//     resampled from coarser voxels (AAL's 2 mm blocks on a 1 mm grid) needs ~1.5 — and rounds
//     corners by 0.82σ.
//   * Smooth. The trilinear interpolant of the raw indicator (σ = 0) has the voxels' staircase;
//     the blur rounds it off (σ = 0.6: weights 0.003, 0.17, 0.66, 0.17, 0.003 per axis).
//   * Thin parts. A sheet one voxel thick keeps a peak of 0.66 at σ = 0.6; a line one voxel
//     thick (0.44) and a single voxel (0.29) fall below 0.5 and vanish: label_smooth 0 keeps
//     every voxel (the raw staircase).
//   Cost: the field lives on S's box grown by 4σ + 1 voxels only, and the surface keeps only its
//   bricks (surface/iso_exact.h), so a label costs in proportion to its own size.
// Active voxels of both grids are S's voxels, so an object's box (framing) is the label's own.
#pragma once

#include "volume/volume.h"

#include <map>
#include <memory>
#include <string>
#include <vector>

namespace lobe {

struct LabelInfo {
    int id = 0;
    std::int64_t voxels = 0;
    openvdb::CoordBBox box;  // index box of its voxels
};

struct LabelMap {
    std::shared_ptr<const Volume> volume;
    std::map<int, LabelInfo> labels;  // present labels (0 is the background, never listed)
    std::string path;

    const LabelInfo* find(int id) const;
    // Up to `count` present labels nearest to `id` by value, for "label 250 is not in the map
    // (nearest present: 116, 115)" messages.
    std::vector<int> nearestPresent(int id, int count = 3) const;
    // The union of the index boxes of `ids` (all must be present).
    openvdb::CoordBBox boxOf(const std::vector<int>& ids) const;
};

// Indexes a loaded volume as a label map; throws lobe::Error naming the file and a voxel when a
// value is not a whole number (a label map holds labels: an intensity image or a probability
// map is not one) or is beyond ±2³¹.
LabelMap indexLabelMap(std::shared_ptr<const Volume> volume);
// The map of `path` loaded (default load options) and indexed, once per process: later calls
// return the same map.
std::shared_ptr<const LabelMap> loadLabelMap(const std::string& path);
// The map of an array in memory (volume/volume_array.h; the Python module), loaded as loadArray
// does with default options and indexed. Not memoised: whoever holds the array holds the map
// (render/scene_description.h, VolumeSourceSpec::labelMap).
std::shared_ptr<const LabelMap> loadLabelMap(const VolumeArray& array);

// The indicator of `ids`: 1 on their voxels (active), nothing stored elsewhere. Same transform.
openvdb::FloatGrid::Ptr labelMask(const LabelMap& map, const std::vector<int>& ids);
// The anti-aliased indicator above (σ in voxels; 0: the raw indicator); its 0.5 level is the
// surface. Active voxels: those of `ids`.
openvdb::FloatGrid::Ptr labelSurfaceField(const LabelMap& map, const std::vector<int>& ids,
                                          double sigmaVoxels);

constexpr double kLabelSmoothDefault = 0.6;  // σ in voxels

}  // namespace lobe
