#include "core/light_table.h"

#include <cstdint>
#include <cstring>

namespace lobe {

void LightTable::assign(const std::vector<PointLight>& lights) {
    source_ = lights;
    count = int(lights.size());
    const size_t padded = (lights.size() + kPad - 1) / kPad * kPad;
    storage_.assign(padded * 7, 0.0);
    double* x = storage_.data();
    double* y = x + padded;
    double* z = y + padded;
    double* in = z + padded;
    for (size_t k = 0; k < lights.size(); ++k) {
        x[k] = lights[k].position.x;
        y[k] = lights[k].position.y;
        z[k] = lights[k].position.z;
        for (int b = 0; b < kBandCount; ++b) in[4 * k + size_t(b)] = lights[k].intensity[b];
    }
    px = x;
    py = y;
    pz = z;
    intensity = in;
}

bool LightTable::holds(const std::vector<PointLight>& lights) const {
    if (source_.size() != lights.size()) return false;
    // The bits of every double (PointLight is six doubles), without a call to memcmp.
    static_assert(sizeof(PointLight) == 6 * sizeof(double));
    const size_t words = lights.size() * 6;
    const auto* a = reinterpret_cast<const unsigned char*>(source_.data());
    const auto* b = reinterpret_cast<const unsigned char*>(lights.data());
    std::uint64_t differ = 0;
    for (size_t i = 0; i < words; ++i) {
        std::uint64_t u, v;
        std::memcpy(&u, a + 8 * i, 8);
        std::memcpy(&v, b + 8 * i, 8);
        differ |= u ^ v;
    }
    return differ == 0;
}

const LightTable& lightTable(const std::vector<PointLight>& lights) {
    thread_local LightTable table;
    if (!table.holds(lights)) table.assign(lights);
    return table;
}

}  // namespace lobe
