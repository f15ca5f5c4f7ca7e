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

}  // namespace lobe
