// Ward's anisotropic elliptical Gaussian, the original form (not the Ward–Dür or bounded
// variants), with the unnormalised half vector H = wi + wo:
//   f = rho_s · exp(−[(H·t/αx)² + (H·b/αy)²] / (H·n)²) / (4π αx αy sqrt(cos θi cos θo)).
// G. J. Ward, "Measuring and modeling anisotropic reflection", SIGGRAPH 1992, eq. (5).
// Definition: docs/models.md, model 4.
// Parameters: rho_s ∈ [0, 1] specular reflectance; alpha_x, alpha_y ∈ [1e-3, 1] RMS slopes along
// the tangent and the bitangent.
#pragma once

#include "materials/brdf_common.h"
#include "materials/param_table.h"

namespace lobe {

struct Ward {
    static constexpr const char* kName = "ward";
    static constexpr const char* kTitle = "Ward";
    static constexpr const char* kCitation =
        "G. J. Ward, Measuring and modeling anisotropic reflection, SIGGRAPH 1992";
    // Reciprocity: H = wi + wo and sqrt(cos θi cos θo) are symmetric.
    static constexpr BrdfFlags kFlags = {Reciprocal::yes, Costly::no};
    static const ParamTable& paramTable();
    static Ward fromParams(const ParamValues& p);
    Spectrum eval(const Vec3& wi, const Vec3& wo) const;

    Spectrum rhoS{0.05};
    Spectrum alphaX{0.05};
    Spectrum alphaY{0.3};
};

// Inline: render/shading.cpp evaluates it in its light loop (materials/brdf.h, ModelAtView).
inline Spectrum Ward::eval(const Vec3& wi, const Vec3& wo) const {
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
