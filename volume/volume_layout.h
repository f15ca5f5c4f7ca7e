// The layout vocabulary of volume files (voxel types, byte order, the layout of a headerless raw
// file), kept free of OpenVDB so parsers and command lines can use it cheaply. See volume.h.
#pragma once

#include <array>
#include <cstdint>
#include <string>

namespace lobe {

enum class VoxelType { kUint8, kInt8, kUint16, kInt16, kUint32, kInt32, kFloat32, kFloat64 };
enum class Endian { kLittle, kBig };

// "uint8", "int16", "float32" …; also the common aliases "uchar", "short", "float", "double".
// Throws lobe::Error listing the known names for anything else.
VoxelType parseVoxelType(const std::string& name);
const char* voxelTypeName(VoxelType type);
int voxelTypeSize(VoxelType type);
Endian parseEndian(const std::string& name);  // "little" | "big"

// The layout of a headerless raw file: dims[0] × dims[1] × dims[2] voxels, x fastest, starting
// `offset` bytes into the (decompressed) file. The file must hold exactly offset + voxel bytes.
struct RawLayout {
    std::array<int, 3> dims{0, 0, 0};
    VoxelType type = VoxelType::kUint8;
    Endian endian = Endian::kLittle;
    std::array<double, 3> spacing{1.0, 1.0, 1.0};
    std::int64_t offset = 0;
    bool gzip = false;  // set by loadVolume for names ending in .gz
};

struct LoadOptions {
    bool hasLayout = false;  // raw files need one; header formats ignore it
    RawLayout layout;
    double scale = 1.0;           // stored = original · scale
    double normalize = 0.0;       // if > 0: scale = 1/normalize (takes precedence over scale)
    bool normalizeByMax = false;  // scale = 1/(max of the original values)
    // If > 0: scale = 1/(this percentile of the original values over every voxel, as `lobe info`
    // prints it: nearest rank over 65 536 bins of the value range).
    double normalizePercentile = 0.0;
    double background =
        0.0;               // original units (before scale): voxels ≤ this are inactive (volume.h)
    std::string gridName;  // .vdb: which grid (empty: the first float grid)
    std::string series;    // DICOM: the SeriesInstanceUID (empty: the only series)
};

// The volume options of the command line as typed (empty string: not given), turned into
// LoadOptions by parseLoadOptions, which throws lobe::Error naming the option on bad text.
// normalize is a positive number, "max" or a percentile "pNN" (0 < NN ≤ 100, e.g. "p99", "p99.5").
struct VolumeOptionText {
    std::string dims, type, endian, spacing, normalize, gridName, series;
    std::int64_t offset = 0;
    double scale = 1.0;
    double background = 0.0;
};
LoadOptions parseLoadOptions(const VolumeOptionText& text);

// "pNN" → NN when 0 < NN ≤ 100; -1 for text that is not of the form p<number>, 0 for a number out
// of range (the callers name the key or option in their error).
double parsePercentileText(const std::string& text);

// Parses "X,Y,Z" (three numbers, commas or 'x' between them) for the command line's --dims and
// --spacing; throws lobe::Error naming `option` and the expected form.
std::array<double, 3> parseTriple(const std::string& text, const std::string& option);

}  // namespace lobe
