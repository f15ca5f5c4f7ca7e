#include "materials/ward.h"

namespace lobe {

const ParamTable& Ward::paramTable() {
    static const ParamTable table = {
        {"rho_s", 0.05, 0.0, 1.0, "specular reflectance", false},
        {"alpha_x", 0.05, 1e-3, 1.0, "RMS slope along the tangent", false},
        {"alpha_y", 0.3, 1e-3, 1.0, "RMS slope along the bitangent", false},
    };
    return table;
}

Ward Ward::fromParams(const ParamValues& p) {
    return Ward{p.get("rho_s"), p.get("alpha_x"), p.get("alpha_y")};
}

Spectrum Ward::eval(const Vec3& wi, const Vec3& wo) const {
    if (!aboveHorizon(wi, wo)) return Spectrum(0.0);
    const Vec3 h = wi + wo;  // h.z > 0 because both directions are above the horizon
    const double tx = h.x / h.z, ty = h.y / h.z;
    const double root = std::sqrt(wi.z * wo.z);
    Spectrum f;
    // One exp and one normalisation per distinct (αx, αy): bands usually share them, and equal
    // inputs give the same bits, so sharing changes no value.
    double lastAx = -1.0, lastAy = -1.0, gauss = 0.0, norm = 0.0;
    for (int b = 0; b < kBandCount; ++b) {
        const double ax = alphaX[b], ay = alphaY[b];
        if (ax != lastAx || ay != lastAy) {
            lastAx = ax;
            lastAy = ay;
            gauss = std::exp(-((tx / ax) * (tx / ax) + (ty / ay) * (ty / ay)));
            norm = 4.0 * kPi * ax * ay * root;
        }
        f[b] = rhoS[b] * gauss / norm;
    }
    return f;
}

}  // namespace lobe
