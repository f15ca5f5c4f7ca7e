// libFuzzer target: detached NRRD headers. The input is the header; after its first blank line
// come the bytes of the data file it may name as "data.raw".
#include "fuzz_common.h"
#include "volume/volume.h"

#include <cstring>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    const size_t split = text.find("\n\n");
    const size_t headerSize = split == std::string::npos ? size : split + 1;
    const std::string header = lobe::fuzz::writeInput("in.nhdr", data, headerSize);
    const size_t dataStart = std::min(size, headerSize + 1);
    lobe::fuzz::writeInput("data.raw", data + dataStart, size - dataStart);
    // The header names its data file relative to itself: "data.raw" is the file beside it.
    lobe::fuzz::expectOnlyInputErrors([&] { lobe::loadNrrd(header); });
    return 0;
}
