// libFuzzer target: scene files through parseScene (keys, types, ranges, nesting, duplicates).
#include "fuzz_common.h"
#include "render/scene_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    lobe::fuzz::expectOnlyInputErrors([&] { lobe::parseScene(text, "/tmp", "fuzz.json"); });
    return 0;
}
