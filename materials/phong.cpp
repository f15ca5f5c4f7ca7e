#include "materials/phong.h"

namespace lobe {

const ParamTable& Phong::paramTable() {
    static const ParamTable table = {
        {"ks", 0.8, 0.0, 1.0, "specular coefficient", false},
        {"exponent", 10.0, 0.0, 1e6, "shininess: power of cos α", false},
    };
    return table;
}

Phong Phong::fromParams(const ParamValues& p) { return Phong{p.get("ks"), p.get("exponent")}; }

Spectrum Phong::eval(const Vec3& wi, const Vec3& wo) const {
    if (!aboveHorizon(wi, wo)) return Spectrum(0.0);
    const double c = cosAlpha(wi, wo);
    Spectrum f;
    // One power per distinct exponent (the bands usually share it; the same bits either way).
    double power = powerOf(c, exponent[0]);
    for (int b = 0; b < kBandCount; ++b) {
        if (b > 0 && exponent[b] != exponent[b - 1]) power = powerOf(c, exponent[b]);
        f[b] = ks[b] * power;
    }
    return f;
}

}  // namespace lobe
