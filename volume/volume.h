// Volumes as OpenVDB float grids, and their loaders: headerless raw files with an explicit layout,
// NIfTI-1 (.nii, .nii.gz), simple detached NRRD headers (.nhdr), DICOM series (a folder or a list
// of slice files, through GDCM) and OpenVDB files (.vdb).
//
// Index and world space. A Volume's grid stores voxel (i, j, k), 0 ≤ i < dims[0] …, at the integer
// index coordinate (i, j, k) (plus indexOrigin for foreign .vdb files): voxel *centres* sit on the
// integer lattice, which is both OpenVDB's and NIfTI's convention. The grid's transform is the
// full index → world affine map: diag(spacing) for raw files, the sform/qform/pixdim map for NIfTI
// (nifti1.h, "METHOD 1/2/3"), the spacings / space directions for NRRD, the slice positions and
// orientation for DICOM (converted from DICOM's LPS to the RAS frame NIfTI's sform uses). Voxels
// below 1e-3 units³ (OpenVDB refuses maps below 3e-15) get the map divided by a power of two and
// the factor kept in the grid's metadata: read a grid's world positions through
// volume/grid_world.h, not its transform alone.
//
// Values. A stored value is (raw · slope + intercept) · valueScale, in float. slope/intercept are
// the file's own rescaling (NIfTI scl_slope / scl_inter, slope 0 meaning 1); valueScale is ours:
// LoadOptions::scale, or 1/divisor with LoadOptions::normalize (e.g. the CThead's v/3272 so the
// paper's iso-value 0.5 means raw 1636). Normalisation lives in the loader, not in the renderer,
// so every consumer (iso-surfaces, ray marching, `lobe info`) sees the same numbers; the Volume
// remembers valueScale and the unscaled range so the original units are never lost.
//
// Sparsity. The grid's background is 0. Voxels whose value is exactly 0 are not stored (they read
// back as the background 0, so nothing is lost); whole 8³ leaves and larger regions of zeros
// collapse into tiles. Non-zero voxels are stored with their values; those ≤ LoadOptions::
// background are stored *inactive*, the others active. Stored-but-inactive voxels still answer
// every accessor lookup with their true value, so trilinear/B-spline reconstruction and
// iso-surfacing are exact across the threshold, while the active topology (and the tree's
// tiles) give empty-space skipping: the air around a head and the outside of a skull-stripped
// brain are inactive. Non-finite voxels (NaN, ±Inf) are refused at load, never stored.
//
// Errors. Every problem with a file (missing, truncated, a header contradicting the data size,
// an unknown type, wrong magic, gzip damage, NaN/Inf voxels) throws one lobe::Error whose message
// names the file and the problem. writeVdb writes to a temporary name and renames, so a failed
// write leaves nothing.
#pragma once

#include "volume/volume_array.h"
#include "volume/volume_layout.h"

#include <openvdb/openvdb.h>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace lobe {

struct Volume {
    openvdb::FloatGrid::Ptr grid;
    std::string sourcePath;
    std::array<int, 3> dims{0, 0, 0};
    std::array<int, 3> indexOrigin{0, 0, 0};  // index of voxel (0,0,0); 0 except foreign .vdb
    std::array<double, 3> spacing{1, 1, 1};   // world lengths of the index unit vectors
    double originalMin = 0.0;                 // value range before valueScale
    double originalMax = 0.0;
    double valueScale = 1.0;
    double background = 0.0;
    // Something about how the data was read that the image depends on and nothing else shows,
    // one line for a warning (e.g. a single DICOM slice drawn as a slab of its SliceThickness);
    // "" when there is none.
    std::string note;
};

Volume loadRaw(const std::string& path, const RawLayout& layout, const LoadOptions& options = {});
Volume loadNifti(const std::string& path, const LoadOptions& options = {});
Volume loadNrrd(const std::string& path, const LoadOptions& options = {});  // detached .nhdr
Volume loadVdb(const std::string& path, const LoadOptions& options = {});
// FreeSurfer .mgh (.mgz gzip-compressed): header, vox2ras affine (volume_file.cpp, readMghDense).
Volume loadMgh(const std::string& path, const LoadOptions& options = {});
// A DICOM series from folders or files (volume/dicom_file.h: sorting, checks, LPS → RAS, rescale);
// options.series picks one series by SeriesInstanceUID. A raw layout in options is an error.
Volume loadDicom(const std::vector<std::string>& inputs, const LoadOptions& options = {});
// Dispatches on the name: .nii / .nii.gz, .nhdr, .mgh / .mgz, .vdb; a folder, or a file with the
// DICOM magic
// ('DICM' at byte 128, whatever its name), is a DICOM series; otherwise raw (.raw, .raw.gz, …),
// which needs options.hasLayout. A DICOM file is never read as raw voxels.
Volume loadVolume(const std::string& path, const LoadOptions& options = {});
// One path as loadVolume; several are the files of one DICOM series (loadDicom).
Volume loadVolume(const std::vector<std::string>& paths, const LoadOptions& options = {});
// An array in memory (volume/volume_array.h): its values as a file's (raw · slope + inter, then
// options' scaling and background; non-finite values refused), named array.name in errors and
// as the Volume's sourcePath. A raw layout in options is an error.
Volume loadArray(const VolumeArray& array, const LoadOptions& options = {});

// Writes the volume's grid (named gridName, or "density") with its metadata (dims, source,
// original range, value scale) so loadVdb restores the whole Volume. Temporary name + rename.
void writeVdb(const Volume& volume, const std::string& path, const std::string& gridName = "");

// A hash of what a loaded volume holds (FNV-1a 64, in 16 hex digits): its index-to-world map,
// dims, value scale and background, and every value the grid stores (each leaf's voxels and
// active mask, each tile) in the tree's order. Two loads of the same data give the same hash on
// any machine; a volume re-exported or a differing node-local copy gives another. Shard parts
// carry it (`lobe merge` compares them) and MPI ranks compare it before rendering.
std::string volumeContentHash(const Volume& volume);

struct VolumeStats {
    double min = 0.0, max = 0.0, mean = 0.0;  // over all dims voxels, stored values
    std::int64_t voxels = 0;
    std::int64_t activeVoxels = 0;
    std::int64_t memoryBytes = 0;  // the grid's tree, from memUsage()
    openvdb::BBoxd worldBox;       // world box of the voxel lattice grown by half a voxel
};
VolumeStats computeStats(const Volume& volume);

// A histogram of the stored values: `bins` equal bins over [lo, hi], counting every voxel of the
// box (what the tree stores, each tile by its voxels, and the background for the rest) or only
// the active ones. Time in proportion to the stored data, like computeStats.
struct ValueHistogram {
    double lo = 0.0, hi = 0.0;
    std::vector<std::int64_t> counts;
    // Nearest rank: the smallest value v with at least p % of the counted voxels ≤ v, to within
    // one bin, (hi − lo)/bins (the lower edge of the bin reaching that rank; hi for p = 100).
    double percentile(double p) const;
};
ValueHistogram valueHistogram(const Volume& volume, double lo, double hi, int bins,
                              bool activeOnly);
// The histogram every percentile of Lobe is read from: 65 536 equal bins over [min, max] of the
// stored values (after valueScale and any blur), every voxel of the box (or the active ones).
// percentileHistogram(v).percentile(p) is the number `lobe info` prints for p % and what a
// scene's "divide_by": "pNN" of a .vdb and a transfer-function value "pNN" stand for.
ValueHistogram percentileHistogram(const Volume& volume, bool activeOnly = false);

}  // namespace lobe
