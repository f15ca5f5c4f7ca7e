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

    Spectrum rs{0.05};
    Spectrum nu{10.0};
    Spectrum nv{1000.0};
};

}  // namespace lobe
