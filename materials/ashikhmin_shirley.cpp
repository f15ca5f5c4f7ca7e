#include "materials/ashikhmin_shirley.h"

namespace lobe {

const ParamTable& AshikhminShirley::paramTable() {
    static const ParamTable table = {
        {"rs", 0.05, 0.0, 1.0, "specular reflectance at normal incidence (Schlick F0)", false},
        {"nu", 10.0, 0.0, 1e6, "Phong exponent along the tangent", false},
        {"nv", 1000.0, 0.0, 1e6, "Phong exponent along the bitangent", false},
    };
    return table;
}

AshikhminShirley AshikhminShirley::fromParams(const ParamValues& p) {
    return AshikhminShirley{p.get("rs"), p.get("nu"), p.get("nv")};
}

Spectrum AshikhminShirley::eval(const Vec3& wi, const Vec3& wo) const {
    Vec3 h;
    if (!aboveHorizon(wi, wo) || !halfVector(wi, wo, h)) return Spectrum(0.0);
    const double hx2 = h.x * h.x, hy2 = h.y * h.y;
    const double sin2 = hx2 + hy2;
    // h·wi = |wi + wo|/2 ≥ 0 in exact arithmetic, but rounds below 0 when wi ≈ −wo at grazing
    // angles (a fuzz finding: wi ≈ (0, 1, 2e-57), wo ≈ (0, −1, 3e-32) gave f < 0). There h is
    // rounding noise and the value has no meaning: 0.
    const double hDotWi = h.dot(wi);
    const double denom = hDotWi * std::max(wi.z, wo.z);
    if (!(hDotWi > 0.0) || !(denom > 0.0)) return Spectrum(0.0);
    Spectrum f;
    double lastE = -1.0, power = 0.0;  // one pow per distinct exponent (bands usually share it)
    double lastNu = -1.0, lastNv = -1.0, norm = 0.0;  // and one sqrt per distinct (nu, nv)
    for (int b = 0; b < kBandCount; ++b) {
        // At h = n, h.z^e = 1 for any e: take e = 1 (h.z = 1) instead of dividing 0 by 0.
        const double e = sin2 > 0.0 ? (nu[b] * hx2 + nv[b] * hy2) / sin2 : 1.0;
        if (e != lastE) {
            power = std::pow(h.z, e);
            lastE = e;
        }
        if (nu[b] != lastNu || nv[b] != lastNv) {
            lastNu = nu[b];
            lastNv = nv[b];
            norm = std::sqrt((nu[b] + 1.0) * (nv[b] + 1.0)) / (8.0 * kPi);
        }
        f[b] = norm * power / denom * fresnelSchlick(rs[b], hDotWi);
    }
    return f;
}

}  // namespace lobe
