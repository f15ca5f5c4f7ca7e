#include "materials/lafortune.h"

namespace lobe {

const ParamTable& Lafortune::paramTable() {
    static const ParamTable table = {
        {"rho_s", 1.0, 0.0, 100.0, "lobe scale", false},
        {"cx", -1.0, -10.0, 10.0, "weight of wi.x·wo.x (tangent)", false},
        {"cy", -1.0, -10.0, 10.0, "weight of wi.y·wo.y (bitangent)", false},
        {"cz", 0.95, -10.0, 10.0, "weight of wi.z·wo.z (normal)", false},
        {"exponent", 20.0, 0.0, 1e4, "lobe power", false},
    };
    return table;
}

Lafortune Lafortune::fromParams(const ParamValues& p) {
    return Lafortune{p.get("rho_s"), p.get("cx"), p.get("cy"), p.get("cz"), p.get("exponent")};
}

Spectrum Lafortune::eval(const Vec3& wi, const Vec3& wo) const {
    if (!aboveHorizon(wi, wo)) return Spectrum(0.0);
    const double px = wi.x * wo.x, py = wi.y * wo.y, pz = wi.z * wo.z;
    Spectrum f;
    for (int b = 0; b < kBandCount; ++b) {
        const double base = std::max(0.0, cx[b] * px + cy[b] * py + cz[b] * pz);
        f[b] = rhoS[b] * std::pow(base, exponent[b]);
    }
    return f;
}

}  // namespace lobe
