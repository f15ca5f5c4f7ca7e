// Ashikhmin–Shirley anisotropic Phong, specular term, with Schlick's Fresnel F(h·wi; F0 = rs):
//   f = sqrt((nu+1)(nv+1))/(8π) · (h.z)^e / ((h·wi) · max(cos θi, cos θo)) · F,
//   e = (nu·h.x² + nv·h.y²) / (h.x² + h.y²)   (at h = n the power is 1).
// M. Ashikhmin, P. Shirley, "An anisotropic Phong BRDF model", J. Graphics Tools 5(2), 2000,
// eq. (4) with eq. (5)'s Fresnel. Definition: docs/models.md, model 9.
// Parameters: rs ∈ [0, 1] specular reflectance at normal incidence; nu, nv ∈ [0, 1e6] Phong
// exponents along the tangent and the bitangent.
#pragma once

#include "materials/brdf_common.h"
#include "materials/param_table.h"

namespace lobe {

struct AshikhminShirley {
    static constexpr const char* kName = "ashikhmin_shirley";
    static constexpr const char* kTitle = "Ashikhmin-Shirley";
    static constexpr const char* kCitation =
        "M. Ashikhmin, P. Shirley, An anisotropic Phong BRDF model, J. Graphics Tools 5(2), 2000";
    // Reciprocity: h, h·wi = h·wo, max(cos θi, cos θo) and F(h·wi) are symmetric (the max makes it
    // reciprocal; Ashikhmin–Shirley chose it for that).
    static constexpr BrdfFlags kFlags = {Reciprocal::yes, Costly::no};
    static const ParamTable& paramTable();
    static AshikhminShirley fromParams(const ParamValues& p);
    Spectrum eval(const Vec3& wi, const Vec3& wo) const;
    // The normalisation sqrt((nu+1)(nv+1))/(8π) per band, and eval with it given: eval(wi, wo) is
    // eval(wi, wo, norms()) (ModelAtView, materials/brdf.h, works the norms out once per point).
    Spectrum norms() const;
    Spectrum eval(const Vec3& wi, const Vec3& wo, const Spectrum& norm) const;

    Spectrum rs{0.05};
    Spectrum nu{10.0};
    Spectrum nv{1000.0};
};

inline Spectrum AshikhminShirley::norms() const {
    Spectrum norm;  // one sqrt per distinct (nu, nv): bands usually share them
    for (int b = 0; b < kBandCount; ++b)
        norm[b] = b > 0 && nu[b] == nu[b - 1] && nv[b] == nv[b - 1]
                      ? norm[b - 1]
                      : std::sqrt((nu[b] + 1.0) * (nv[b] + 1.0)) / (8.0 * kPi);
    return norm;
}

inline Spectrum AshikhminShirley::eval(const Vec3& wi, const Vec3& wo) const {
    return eval(wi, wo, norms());
}

// Inline: render/shading.cpp evaluates it in its light loop (materials/brdf.h, ModelAtView).
inline Spectrum AshikhminShirley::eval(const Vec3& wi, const Vec3& wo, const Spectrum& norm) const {
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
    for (int b = 0; b < kBandCount; ++b) {
        // At h = n, h.z^e = 1 for any e: take e = 1 (h.z = 1) instead of dividing 0 by 0.
        const double e = sin2 > 0.0 ? (nu[b] * hx2 + nv[b] * hy2) / sin2 : 1.0;
        if (e != lastE) {
            power = std::pow(h.z, e);
            lastE = e;
        }
        f[b] = norm[b] * power / denom * fresnelSchlick(rs[b], hDotWi);
    }
    return f;
}

}  // namespace lobe
