// Schlick–Lewis: Phong's lobe with Schlick's rational replacement of the power and Lewis'
// energy normalisation:
//   S(u) = u / (n − n·u + u),  u = cos α, n = exponent;   f = ks · (n + 2)/(2π) · S(u).
// C. Schlick, "A customizable reflectance model for everyday rendering", EGWR 1993, eq. (5)
// (the rational approximation of t^n); R. R. Lewis, "Making shaders more physically plausible",
// EGWR 1993, eq. (10) (the (n+2)/2π normalisation). Definition: docs/models.md, 3.
// Parameters: ks ∈ [0, 1]; exponent ∈ [1e-3, 1e6].
#pragma once

#include "materials/brdf_common.h"
#include "materials/param_table.h"

namespace lobe {

struct SchlickLewis {
    static constexpr const char* kName = "schlick_lewis";
    static constexpr const char* kTitle = "Schlick-Lewis";
    static constexpr const char* kCitation =
        "C. Schlick, A customizable reflectance model for everyday rendering, EGWR 1993; "
        "R. R. Lewis, Making shaders more physically plausible, EGWR 1993";
    // Reciprocity: a function of cos α = r(wi)·wo, symmetric in wi and wo.
    static constexpr BrdfFlags kFlags = {Reciprocal::yes, Costly::no};
    static const ParamTable& paramTable();
    static SchlickLewis fromParams(const ParamValues& p);
    Spectrum eval(const Vec3& wi, const Vec3& wo) const;

    Spectrum ks{0.8};
    Spectrum exponent{10.0};
};

}  // namespace lobe
