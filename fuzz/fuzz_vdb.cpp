// libFuzzer target: OpenVDB files through loadVdb (foreign grids: any metadata, any extent).
#include "fuzz_common.h"
#include "volume/volume.h"

#include <cstdlib>
#include <new>

// OpenVDB allocates what a file's size fields say before it reads the data. Without ASan an
// absurd size throws std::bad_alloc, which loadVdb turns into an input error; ASan would abort
// instead. These replacements restore the first behaviour for sizes over 16 GB.
void* operator new(size_t n) {
    if (n > (size_t(1) << 34)) throw std::bad_alloc();
    if (void* p = std::malloc(n ? n : 1)) return p;
    throw std::bad_alloc();
}
void* operator new[](size_t n) { return operator new(n); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, size_t) noexcept { std::free(p); }
void operator delete[](void* p, size_t) noexcept { std::free(p); }

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string path = lobe::fuzz::writeInput("in.vdb", data, size);
    lobe::fuzz::expectOnlyInputErrors([&] {
        const lobe::Volume v = lobe::loadVdb(path);
        lobe::computeStats(v);  // what `lobe info` does next
    });
    return 0;
}
