// Cook–Torrance: Beckmann distribution D, Blinn's / Torrance–Sparrow's shadowing G and the exact
// complex Fresnel term at c = wi·h, in the energy-consistent normalisation (the 1982 paper's form
// divides by π cos θi cos θo, which is 4/π × this):
//   D = exp(−tan²θh / m²) / (π m² cos⁴θh)
//   G = min(1, 2 cosθh cosθo/(wo·h), 2 cosθh cosθi/(wo·h))
//   f = ks · F(wi·h) · D · G / (4 cos θi cos θo)
// R. L. Cook, K. E. Torrance, "A reflectance model for computer graphics", ACM TOG 1(1), 1982,
// eqs. (3), (5), (7), (8). Definition: docs/models.md, model 5.
// Parameters: ks ∈ [0, 1]; m ∈ [1e-3, 1] RMS facet slope; eta ∈ [0.01, 10] and kappa ∈ [0, 20],
// the real and imaginary parts of the relative index of refraction.
#pragma once

#include "materials/brdf_common.h"
#include "materials/param_table.h"

namespace lobe {

struct CookTorrance {
    static constexpr const char* kName = "cook_torrance";
    static constexpr const char* kTitle = "Cook-Torrance";
    static constexpr const char* kCitation =
        "R. L. Cook, K. E. Torrance, A reflectance model for computer graphics, ACM TOG 1(1), 1982";
    // Reciprocity: D(h), F(wi·h) with wi·h = wo·h, G = min(1, 2cosθh cosθo/(wo·h), 2cosθh
    // cosθi/(wo·h)) and 4 cos θi cos θo are symmetric.
    static constexpr BrdfFlags kFlags = {Reciprocal::yes, Costly::no};
    static const ParamTable& paramTable();
    static CookTorrance fromParams(const ParamValues& p);
    Spectrum eval(const Vec3& wi, const Vec3& wo) const;

    Spectrum ks{0.8};
    Spectrum m{0.08};
    Spectrum eta{1.6};
    Spectrum kappa{0.2};
};

}  // namespace lobe
