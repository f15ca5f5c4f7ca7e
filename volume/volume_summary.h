// What `lobe info` and `lobe convert` need from lobe_volume, without OpenVDB in the header (each
// OpenVDB include costs ~8 s of compile time; the command-line files stay cheap).
#pragma once

#include "volume/volume_layout.h"

#include <array>
#include <cstdint>
#include <string>

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
};

// Loads the file (loadVolume) and measures it.
VolumeSummary summarizeVolume(const std::string& path, const LoadOptions& options);

// Loads `in` and writes it as a .vdb grid to `out` (temporary name + rename: on any error
// nothing is written). Returns the summary of what was written.
VolumeSummary convertVolume(const std::string& in, const std::string& out,
                            const LoadOptions& options, const std::string& gridName);

}  // namespace lobe
