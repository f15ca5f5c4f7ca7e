// He–Torrance–Sillion–Greenberg: physical-optics reflection from a Gaussian random rough surface,
// directional-diffuse term ρ_dd only (the specular delta and the uniform-diffuse term left out).
// X. D. He, K. E. Torrance, F. X. Sillion, D. P. Greenberg, "A comprehensive physical model for
// light reflection", SIGGRAPH 1991: the directional-diffuse term ρ_dd with its distribution D,
// geometric factor G, shadowing S (Λ in the form of the paper's errata) and the effective
// roughness σ(z0). The paper's text is not in this repository, so its equation numbers are not
// quoted; the formulas below are the normative transcription.
// Definition: docs/models.md, model 7, in units of the wavelength λ (k = 2π):
//   K(θ) = tan θ · erfc(τ / (2σ0 tan θ))
//   z0 solves sqrt(π/2)·z0 = (σ0/4)(K(θi) + K(θo))·exp(−z0²/(2σ0²)) (by Newton)
//   σ = σ0 / sqrt(1 + z0²/σ0²);  g = [k σ (cos θi + cos θo)]²
//   D = (π²τ²/4) Σ_{m≥1} g^m e^{−g} / (m!·m) · exp(−k²(H·t² + H·b²) τ² / (4m))
//   G = (|H|² / H·n)²;  S = S(θi) S(θo), S(θ) = [1 − ½ erfc(c)] / [Λ(c) + 1], c = τ cot θ / (2σ0),
//   Λ(c) = ½ [e^{−c²}/(√π c) − erfc(c)]
//   f = ks · F(wi·h) · S · G · D / (π cos θi cos θo), F the exact complex Fresnel term.
// Parameters: ks ∈ [0, 1]; sigma0_over_lambda ∈ [0.01, 100] RMS surface height σ0/λ;
// tau_over_lambda ∈ [0.01, 1000] autocorrelation length τ/λ; eta ∈ [0.01, 10] and kappa ∈ [0, 20],
// the complex index of refraction. Every parameter may differ per band.
#pragma once

#include "materials/brdf_common.h"
#include "materials/param_table.h"

#include <cstdint>
#include <memory>

namespace lobe {

class HeTorranceTable;

struct HeTorrance {
    static constexpr const char* kName = "he_torrance";
    static constexpr const char* kTitle = "He-Torrance";
    static constexpr const char* kCitation =
        "X. D. He, K. E. Torrance, F. X. Sillion, D. P. Greenberg, A comprehensive physical model "
        "for light reflection, SIGGRAPH 1991";
    // Reciprocity: K(θi) + K(θo), g ∝ (cos θi + cos θo)², D and G of H, S(θi)S(θo), F(wi·h) with
    // wi·h = wo·h are all symmetric. Costly: a series and a Newton solve per evaluation.
    static constexpr BrdfFlags kFlags = {Reciprocal::yes, Costly::yes};
    static const ParamTable& paramTable();
    static HeTorrance fromParams(const ParamValues& p);
    Spectrum eval(const Vec3& wi, const Vec3& wo) const;

    Spectrum ks{0.8};
    Spectrum sigma0{1.0};  // sigma0_over_lambda
    Spectrum tau{10.0};    // tau_over_lambda
    Spectrum eta{1.6};
    Spectrum kappa{0.2};
    // When set (he_torrance_table.h; render/scene.cpp attaches one unless `--exact-brdf`),
    // eval() reads this table of the same parameters instead of summing the series. Null: the
    // exact series.
    std::shared_ptr<const HeTorranceTable> table;

    // The pieces of the definition, public so that tests can check each one (lengths in λ).
    // K(θ) for cos θ = cosTheta.
    static double effectiveRoughnessK(double cosTheta, double sigma0, double tau);
    // z0 ≥ 0 solving sqrt(π/2)·z0 = (σ0/4)·kSum·exp(−z0²/(2σ0²)), kSum = K(θi) + K(θo).
    static double solveZ0(double sigma0, double kSum);
    // D for given g and vxy2 = k²(H·t² + H·b²). maxStride 1 sums every term (the unit walk);
    // the default lets wide series be summed every h-th term (he_torrance.cpp, strideFor).
    static double distributionD(double g, double vxy2, double tau, int maxStride = 16);
    // The series terms this thread has summed so far (all evaluations): the operation count by
    // which tests bound an evaluation's cost (he_torrance.cpp, termCap).
    static std::uint64_t termsSummed();
    // S(θ) for cos θ = cosTheta.
    static double shadowingS(double cosTheta, double sigma0, double tau);
    // K(θ) and S(θ) together: they share erfc(τ cot θ / (2σ0)).
    struct DirectionTerms {
        double k, s;
    };
    static DirectionTerms directionTerms(double cosTheta, double sigma0, double tau);

    // The viewer's half of an evaluation: K(θo) and S(θo) per band (render/shading.cpp lights a
    // point with several lights and one wo). eval(wi, wo, viewTerms(wo)) is eval(wi, wo) bit for
    // bit; wo must be above the horizon (wo.z > 0).
    struct ViewTerms {
        DirectionTerms out[kBandCount];
    };
    ViewTerms viewTerms(const Vec3& wo) const;
    Spectrum eval(const Vec3& wi, const Vec3& wo, const ViewTerms& view) const;
};

}  // namespace lobe
