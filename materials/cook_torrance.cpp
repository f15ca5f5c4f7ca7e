#include "materials/cook_torrance.h"

namespace lobe {

const ParamTable& CookTorrance::paramTable() {
    static const ParamTable table = {
        {"ks", 0.8, 0.0, 1.0, "specular coefficient", false},
        {"m", 0.08, 1e-3, 1.0, "RMS slope of the Beckmann facets", false},
        {"eta", 1.6, 0.01, 10.0, "index of refraction, real part", false},
        {"kappa", 0.2, 0.0, 20.0, "index of refraction, imaginary part (extinction)", false},
    };
    return table;
}

CookTorrance CookTorrance::fromParams(const ParamValues& p) {
    return CookTorrance{p.get("ks"), p.get("m"), p.get("eta"), p.get("kappa")};
}

Spectrum CookTorrance::eval(const Vec3& wi, const Vec3& wo) const {
    Vec3 h;
    if (!aboveHorizon(wi, wo) || !halfVector(wi, wo, h)) return Spectrum(0.0);
    const double cosH = h.z;  // > 0 since both directions are above the horizon
    const double cosH2 = cosH * cosH;
    const double tan2H = (1.0 - cosH2) / cosH2;
    const double woDotH = wo.dot(h);  // = wi·h > 0
    const double g = std::min(1.0, 2.0 * cosH * std::min(wo.z, wi.z) / woDotH);
    Spectrum f;
    for (int b = 0; b < kBandCount; ++b) {
        const double m2 = m[b] * m[b];
        const double d = std::exp(-tan2H / m2) / (kPi * m2 * cosH2 * cosH2);
        const double fresnel = fresnelExact(eta[b], kappa[b], wi.dot(h));
        f[b] = ks[b] * fresnel * d * g / (4.0 * wi.z * wo.z);
    }
    return f;
}

}  // namespace lobe
