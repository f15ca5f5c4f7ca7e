// libFuzzer target: `lobe brdf eval` input lines, parsed and evaluated with every model at its
// defaults: whatever the line, the values are finite.
#include "apps/brdf_input.h"
#include "fuzz_common.h"
#include "materials/registry.h"

#include <algorithm>
#include <cmath>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string line(reinterpret_cast<const char*>(data), size);
    double v[6];
    if (!lobe::parseSixNumbers(line, v)) return 0;
    for (double x : v)
        if (!std::isfinite(x)) std::abort();
    auto unit = [](double x, double y, double z) {
        const double m = std::max({std::abs(x), std::abs(y), std::abs(z)});
        return m > 0.0 ? lobe::Vec3(x / m, y / m, z / m).normalized() : lobe::Vec3(0, 0, 1);
    };
    static const std::vector<lobe::Brdf> models = [] {
        std::vector<lobe::Brdf> all;
        for (const lobe::BrdfModelInfo& m : lobe::brdfModels()) all.push_back(lobe::makeBrdf(m.name, {}));
        return all;
    }();
    for (const lobe::Brdf& brdf : models) {
        const lobe::Spectrum f = lobe::evalBrdf(brdf, unit(v[0], v[1], v[2]), unit(v[3], v[4], v[5]));
        for (int b = 0; b < 3; ++b)
            if (!std::isfinite(f[b]) || f[b] < 0.0) std::abort();
    }
    return 0;
}
