#include "materials/schlick_lewis.h"

namespace lobe {

const ParamTable& SchlickLewis::paramTable() {
    static const ParamTable table = {
        {"ks", 0.8, 0.0, 1.0, "specular coefficient", false},
        {"exponent", 10.0, 1e-3, 1e6, "shininess n of Schlick's u/(n - n u + u)", false},
    };
    return table;
}

SchlickLewis SchlickLewis::fromParams(const ParamValues& p) {
    return SchlickLewis{p.get("ks"), p.get("exponent")};
}

Spectrum SchlickLewis::eval(const Vec3& wi, const Vec3& wo) const {
    if (!aboveHorizon(wi, wo)) return Spectrum(0.0);
    const double u = cosAlpha(wi, wo);
    Spectrum f;
    for (int b = 0; b < kBandCount; ++b) {
        const double n = exponent[b];
        const double s = u / (n - n * u + u);  // denominator ≥ min(n, 1) > 0 for u ∈ [0, 1]
        f[b] = ks[b] * (n + 2.0) / (2.0 * kPi) * s;
    }
    return f;
}

}  // namespace lobe
