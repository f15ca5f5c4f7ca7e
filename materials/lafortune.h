// Lafortune generalised cosine lobe, one lobe:
//   f = rho_s · max(0, cx·wi.x·wo.x + cy·wi.y·wo.y + cz·wi.z·wo.z)^exponent.
// E. P. F. Lafortune, S.-C. Foo, K. E. Torrance, D. P. Greenberg, "Non-linear approximation of
// reflectance functions", SIGGRAPH 1997, eq. (4) with one term. Definition:
// docs/models.md, model 8. cx = cy = −1 with cz = 1 is Phong's lobe; cx ≠ cy makes it
// anisotropic. Parameters: rho_s ∈ [0, 100]; cx, cy, cz ∈ [−10, 10]; exponent ∈ [0, 1e4].
#pragma once

#include "materials/brdf_common.h"
#include "materials/param_table.h"

namespace lobe {

struct Lafortune {
    static constexpr const char* kName = "lafortune";
    static constexpr const char* kTitle = "Lafortune";
    static constexpr const char* kCitation =
        "E. P. F. Lafortune et al., Non-linear approximation of reflectance functions, "
        "SIGGRAPH 1997";
    // Reciprocity: cx wi.x wo.x + cy wi.y wo.y + cz wi.z wo.z is symmetric.
    static constexpr BrdfFlags kFlags = {Reciprocal::yes, Costly::no};
    static const ParamTable& paramTable();
    static Lafortune fromParams(const ParamValues& p);
    Spectrum eval(const Vec3& wi, const Vec3& wo) const;

    Spectrum rhoS{1.0};
    Spectrum cx{-1.0};
    Spectrum cy{-1.0};
    Spectrum cz{0.95};
    Spectrum exponent{20.0};
};

}  // namespace lobe
