// libFuzzer target: headerless raw volumes. The first 8 bytes choose the layout (dims up to
// 32 a side, voxel type, byte order, offset, gzip), the rest is the file.
#include "fuzz_common.h"
#include "volume/volume.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size < 8) return 0;
    static const lobe::VoxelType kTypes[] = {lobe::VoxelType::kUint8,   lobe::VoxelType::kInt8,
                                             lobe::VoxelType::kUint16,  lobe::VoxelType::kInt16,
                                             lobe::VoxelType::kUint32,  lobe::VoxelType::kInt32,
                                             lobe::VoxelType::kFloat32, lobe::VoxelType::kFloat64};
    lobe::RawLayout layout;
    layout.dims = {int(data[0] % 33), int(data[1] % 33), int(data[2] % 33)};
    layout.type = kTypes[data[3] % 8];
    layout.endian = data[4] & 1 ? lobe::Endian::kBig : lobe::Endian::kLittle;
    layout.gzip = data[4] & 2;
    layout.offset = data[5] % 64;
    layout.spacing = {0.5 + data[6] % 4, 1.0, data[7] % 3 == 0 ? 0.0 : 2.0};
    const std::string path =
        lobe::fuzz::writeInput(layout.gzip ? "in.raw.gz" : "in.raw", data + 8, size - 8);
    lobe::fuzz::expectOnlyInputErrors([&] { lobe::loadRaw(path, layout); });
    return 0;
}
