// What `lobe info` and `lobe convert` need from lobe_volume, without OpenVDB in the header (each
// OpenVDB include costs ~8 s of compile time; the command-line files stay cheap).
#pragma once

#include "volume/volume_layout.h"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace lobe {

struct VolumeSummary {
    std::string path;        // as given
    std::string sourcePath;  // the data's origin (for a converted .vdb, the original file)
    std::string gridName;
    std::array<int, 3> dims{0, 0, 0};
    std::array<int, 3> indexOrigin{0, 0, 0};
    std::array<double, 3> spacing{1, 1, 1};
    std::array<double, 3> worldMin{0, 0, 0}, worldMax{0, 0, 0};  // voxel lattice ± half a voxel
    std::array<double, 3> worldOfFirstVoxel{0, 0, 0};            // centre of voxel (0, 0, 0)
    double originalMin = 0.0, originalMax = 0.0, valueScale = 1.0, background = 0.0;
    double min = 0.0, max = 0.0, mean = 0.0;  // stored values over all voxels
    std::int64_t voxels = 0, activeVoxels = 0, memoryBytes = 0;
    double loadSeconds = 0.0;
    double blurFwhm = 0.0;  // world units; 0: no blur
    // Percentiles 1, 5, 50, 95, 99 % of the stored values over every voxel of the box and over
    // the active voxels (ValueHistogram::percentile).
    static constexpr std::array<double, 5> kPercents{1, 5, 50, 95, 99};
    std::array<double, 5> percentilesAll{}, percentilesActive{};
    struct Histogram {
        double lo = 0.0, hi = 0.0;         // equal bins over [lo, hi]
        std::vector<std::int64_t> counts;  // voxels per bin, every voxel of the box
    } histogram;                           // empty unless asked for
};

// Loads the file (loadVolume), blurs it by blurFwhm (world units, as a scene's
// source.blur_fwhm_mm; 0: not at all) and measures it; with histogramBins > 0 also a histogram.
VolumeSummary summarizeVolume(const std::string& path, const LoadOptions& options,
                              double blurFwhm = 0.0, int histogramBins = 0);

// Loads `in` and writes it as a .vdb grid to `out` (temporary name + rename: on any error
// nothing is written). Returns the summary of what was written.
VolumeSummary convertVolume(const std::string& in, const std::string& out,
                            const LoadOptions& options, const std::string& gridName);

// The same for several inputs: the slice files of one DICOM series (loadVolume's list form).
VolumeSummary summarizeVolume(const std::vector<std::string>& paths, const LoadOptions& options,
                              double blurFwhm = 0.0, int histogramBins = 0);
VolumeSummary convertVolume(const std::vector<std::string>& in, const std::string& out,
                            const LoadOptions& options, const std::string& gridName);

}  // namespace lobe
