// Total flux overlap of two lattices of specular flux: the metric of the paper's "BRDF flux
// overlap" section (eqs. 1.21–1.25, Figure 5) as fixed by docs/flux-overlap.md, "The metric
// for one pair of lattices". High values mean lobes that stay apart (a good pair), low values much
// overlap.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace lobe {

// The paper's threshold t (eq. 1.23; "a threshold (t) of 0.0001 ... was used").
constexpr double kFluxThreshold = 1e-4;

enum class OverlapVariant {
    Sum,  // e_sum = min(OA/areaA, OB/areaB): Figure 5 with its slips corrected
    Mse,  // e_mse = min((1/mn)Σ(c/areaA)², (1/mn)Σ(d/areaB)²): eq. 1.21 read as a mean square
};

// "sum" | "mse"; throws lobe::Error otherwise.
OverlapVariant parseOverlapVariant(const std::string& text);
const char* overlapVariantName(OverlapVariant variant);

// Everything the metric computes for one pair of lattices.
struct FluxOverlap {
    int64_t areaA = 0;   // #{Φa > t}
    int64_t areaB = 0;   // #{Φb > t}
    double OA = 0.0;     // Σ c_xy (flux of A not covered by B)
    double OB = 0.0;     // Σ d_xy
    double sumC2 = 0.0;  // Σ c_xy² (for the mse variant)
    double sumD2 = 0.0;  // Σ d_xy²
    int64_t count = 0;   // m·n
    double eSum = 0.0;
    double eMse = 0.0;

    double value(OverlapVariant v) const { return v == OverlapVariant::Sum ? eSum : eMse; }
};

// The per-pixel contributions of eqs. 1.24 and 1.25 (with eq. 1.23's "Φ < t" read as "Φ > t", as
// Figure 5 does): c is A's flux where only A is above t, and Φa − Φb where both are and A is
// brighter; d likewise for B. At every pixel at least one of c, d is 0.
struct OverlapContribution {
    double c = 0.0;
    double d = 0.0;
};
inline OverlapContribution overlapContribution(double a, double b, double t) {
    const bool inA = a > t, inB = b > t;
    OverlapContribution out;
    if (inA && !inB)
        out.c = a;
    else if (inB && !inA)
        out.d = b;
    else if (inA && inB) {
        if (a > b)
            out.c = a - b;
        else if (b > a)
            out.d = b - a;
    }
    return out;
}

// The metric over `count` pixels of two lattices (same layout). Values ≤ t (including 0) are "no
// lobe". Both variants are 0 when either area is 0 (nothing to compare).
FluxOverlap fluxOverlap(const float* a, const float* b, size_t count,
                        double threshold = kFluxThreshold);

}  // namespace lobe
