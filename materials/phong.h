// Phong specular term, used directly as f_s (never divided by cos θi):
//   f = ks · cos^exponent α,  cos α = max(0, r(wi)·wo).
// B. T. Phong, "Illumination for computer generated pictures", CACM 18(6):311–317, 1975, eq. (1)
// (specular part only). Definition: docs/models.md, model 1.
// Parameters: ks ∈ [0, 1] specular coefficient; exponent ∈ [0, 1e6] shininess.
// Reciprocal (cos α is symmetric in wi and wo); whether it conserves energy depends on ks and the
// exponent, and is measured by `lobe brdf props`, not assumed.
#pragma once

#include "materials/brdf_common.h"
#include "materials/param_table.h"

namespace lobe {

struct Phong {
    static constexpr const char* kName = "phong";
    static constexpr const char* kTitle = "Phong";
    static constexpr const char* kCitation =
        "B. T. Phong, Illumination for computer generated pictures, CACM 18(6), 1975";
    // Reciprocity: a function of cos α = r(wi)·wo = −wi.x wo.x − wi.y wo.y + wi.z wo.z, symmetric
    // in wi and wo.
    static constexpr BrdfFlags kFlags = {Reciprocal::yes, Costly::no};
    static const ParamTable& paramTable();
    static Phong fromParams(const ParamValues& p);
    Spectrum eval(const Vec3& wi, const Vec3& wo) const;

    Spectrum ks{0.8};
    Spectrum exponent{10.0};
};

// Inline: render/shading.cpp evaluates it in its light loop (materials/brdf.h, ModelAtView).
inline Spectrum Phong::eval(const Vec3& wi, const Vec3& wo) const {
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
