// libFuzzer target: NIfTI-1 files, plain (.nii) and gzipped (.nii.gz), through loadNifti.
#include "fuzz_common.h"
#include "volume/volume.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const bool gz = size >= 2 && data[0] == 0x1f && data[1] == 0x8b;
    const std::string path = lobe::fuzz::writeInput(gz ? "in.nii.gz" : "in.nii", data, size);
    lobe::fuzz::expectOnlyInputErrors([&] { lobe::loadNifti(path); });
    return 0;
}
