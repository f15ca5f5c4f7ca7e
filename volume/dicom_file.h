// Internal to lobe_volume: reading a DICOM image series (one slice per file) into a DenseVolume
// through GDCM, without OpenVDB. volume.cpp's loadDicom turns it into a grid.
//
// Input. A folder (its regular files, not its subfolders; files without the DICOM magic 'DICM'
// at byte 128 — a README, a DICOMDIR index — are skipped) or a list of files (each must be a
// DICOM file). The files may hold several series: `series` picks one by SeriesInstanceUID; when
// it is empty and there are several, the error lists them (UID, description, slice count).
//
// Geometry (DICOM PS3.3 C.7.6.2, Image Plane Module). Slices are sorted by their position along
// the slice normal n = row direction × column direction (ImageOrientationPatient), and must share
// one orientation, one size and one pixel spacing, and be evenly spaced: a gap (missing slices),
// uneven spacing, two slices at one position or mixed orientations are each one error. The
// index → world affine follows C.7.6.2.1.1: voxel (i, j, k), i the column and j the row of slice
// k, sits at P = S₀ + i·Δc·X + j·Δr·Y + k·(S_last − S₀)/(N − 1), X and Y the row and column
// direction cosines, Δr, Δc = PixelSpacing (row spacing first), S the ImagePositionPatient
// of the sorted slices. One slice gets k·n·(SpacingBetweenSlices, else SliceThickness, else 1).
//
// World frame. DICOM's patient coordinates are LPS (+x to the patient's left, +y posterior,
// +z superior; PS3.3 C.7.6.2.1.1). Lobe's world, like NIfTI's sform (nifti1.h) and so like a
// NIfTI written by dcm2niix from the same series, is RAS: x and y are negated, so the same
// anatomy read from DICOM or from that NIfTI lands at the same world position.
//
// Values. The stored pixel values (BitsStored bits, signed when PixelRepresentation is 1) times
// RescaleSlope plus RescaleIntercept (C.11.1.1.2, Modality LUT; CT: Hounsfield units), slice by
// slice. Only single-sample (grey-level) single-frame images; pixel data in any transfer syntax
// GDCM decodes (uncompressed, JPEG, JPEG-LS, JPEG 2000, RLE); the others get an error naming it.
#pragma once

#include "volume/volume_file.h"

#include <string>
#include <vector>

namespace lobe {
namespace detail {

// True when the file exists and holds "DICM" at byte 128 (PS3.10 7.1, the DICOM File Meta
// Information preamble and prefix).
bool hasDicomMagic(const std::string& path);

// True for a folder or a file with the DICOM magic: what loadVolume hands to the DICOM reader.
bool isDicomInput(const std::string& path);

// The series the inputs (folders or files) hold, without decoding pixels; in the order of their
// UIDs. Errors as readDicomDense for files that cannot be read.
struct DicomSeriesInfo {
    std::string uid, description;
    int slices = 0;
};
std::vector<DicomSeriesInfo> listDicomSeries(const std::vector<std::string>& inputs);

// The one series of the inputs (or the one named by `series`) as a volume in RAS world
// coordinates. Throws lobe::Error naming the file (or folder) and the problem.
DenseVolume readDicomDense(const std::vector<std::string>& inputs, const std::string& series = "");

}  // namespace detail
}  // namespace lobe
