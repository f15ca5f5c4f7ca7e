#include "core/light_table.h"

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

}  // namespace lobe
