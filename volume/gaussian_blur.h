// Gaussian blur of a volume given as a full width at half maximum in world units (millimetres
// for NIfTI data): the smoothing that turns a grey-matter probability map into a voxel-based
// morphometry "density map" (the paper's "isotropic Gaussian kernel (full width at half maximum
// of 8 mm)"). σ = FWHM / (2 sqrt(2 ln 2)) ≈ FWHM / 2.3548.
//
// Implementation: the grid is copied to a dense array over its voxel lattice (Volume::dims),
// convolved separably along the three index axes with a sampled, normalised Gaussian of
// σ_axis = σ / spacing_axis voxels truncated at 4σ, with zeros outside the lattice (the
// background), and copied back (zeros unstored, everything else active). Separable convolution
// in index space is the isotropic world-space Gaussian exactly when the index axes are
// orthogonal in world space — true for every volume we ship (diagonal affines, possibly
// flipped); for an oblique affine it is refused.
#pragma once

#include "volume/volume.h"

#include <array>
#include <vector>

namespace lobe {

// Throws lobe::Error naming the volume's file for fwhm < 0 or an oblique index → world map.
void gaussianBlurFwhm(Volume& volume, double fwhmWorld);

// The same separable convolution on a dense array (dims[0]·dims[1]·dims[2] values, x fastest),
// with a sampled, normalised Gaussian of σ = sigmaVoxels[axis] voxels along each axis (0: that
// axis is left alone), truncated at 4σ, zeros outside the array.
void gaussianBlurDense(std::vector<float>& data, const std::array<int, 3>& dims,
                       const std::array<double, 3>& sigmaVoxels);

}  // namespace lobe
