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
    static const std::vector<lobe::Brdf> models = [] {
        std::vector<lobe::Brdf> all;
        for (const lobe::BrdfModelInfo& m : lobe::brdfModels())
            all.push_back(lobe::makeBrdf(m.name, {}));
        return all;
    }();
    lobe::Vec3 wi, wo;
    if (!lobe::unitDirection(v[0], v[1], v[2], wi) || !lobe::unitDirection(v[3], v[4], v[5], wo))
        return 0;
    for (const lobe::Brdf& brdf : models) {
        const lobe::Spectrum f = lobe::evalBrdf(brdf, wi, wo);
        for (int b = 0; b < 3; ++b)
            if (!std::isfinite(f[b]) || f[b] < 0.0) std::abort();
    }
    return 0;
}
