// Strauss' model, specular term, used directly as f_s (never divided by cos θi). With
// x(θ) = θ/(π/2), constants kf = 1.12, kg = 1.01, kj = 0.1:
//   F(x) = [1/(x−kf)² − 1/kf²] / [1/(1−kf)² − 1/kf²]
//   G(x) = [1/(1−kg)² − 1/(x−kg)²] / [1/(1−kg)² − 1/kg²]
//   rd = (1 − s³)(1 − t);  rn = (1 − t) − rd;  h = 3/(1 − s)
//   j = F(x(θi))·G(x(θi))·G(x(θo));  rj = min(1, rn + (rn + kj)·j)
//   Cs = 1 + m·(1 − F(x(θi)))·(color − 1)
//   f = ks · Cs · rj · cos^h α
// P. S. Strauss, "A realistic lighting model for computer animators", IEEE CG&A 10(6), 1990,
// pp. 56–64 (specular reflectivity and colour equations). Definition: docs/models.md,
// model 2. Parameters: ks ∈ [0, 1]; smoothness s ∈ [0, 0.99]; metalness m ∈ [0, 1];
// transparency t ∈ [0, 1]; color ∈ [0, 1] (the surface colour per band; its specular highlight
// takes this colour as metalness grows).
#pragma once

#include "materials/brdf_common.h"
#include "materials/param_table.h"

namespace lobe {

struct Strauss {
    static constexpr const char* kName = "strauss";
    static constexpr const char* kTitle = "Strauss";
    static constexpr const char* kCitation =
        "P. S. Strauss, A realistic lighting model for computer animators, IEEE CG&A 10(6), 1990";
    // Reciprocity: j = F(x(θi))·G(x(θi))·G(x(θo)) and Cs = 1 + m(1 − F(x(θi)))(color − 1) depend on
    // θi through F but not on θo: swapping wi and wo changes rj (when rj < 1), so NOT reciprocal.
    static constexpr BrdfFlags kFlags = {Reciprocal::no, Costly::no};
    static const ParamTable& paramTable();
    static Strauss fromParams(const ParamValues& p);
    Spectrum eval(const Vec3& wi, const Vec3& wo) const;

    Spectrum ks{0.5};
    Spectrum smoothness{0.75};
    Spectrum metalness{0.5};
    Spectrum transparency{0.0};
    Spectrum color{1.0};
};

}  // namespace lobe
