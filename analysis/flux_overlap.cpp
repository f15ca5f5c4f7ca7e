// Total flux overlap metric (docs/flux-overlap.md; paper eqs. 1.21–1.25, Figure 5).
#include "analysis/flux_overlap.h"

#include "core/error.h"

#include <algorithm>

namespace lobe {

OverlapVariant parseOverlapVariant(const std::string& text) {
    if (text == "sum") return OverlapVariant::Sum;
    if (text == "mse") return OverlapVariant::Mse;
    throw Error("--variant: expected 'sum' or 'mse', got '" + text + "'");
}

const char* overlapVariantName(OverlapVariant variant) {
    return variant == OverlapVariant::Sum ? "sum" : "mse";
}

FluxOverlap fluxOverlap(const float* a, const float* b, size_t count, double threshold) {
    FluxOverlap r;
    r.count = int64_t(count);
    for (size_t i = 0; i < count; ++i) {
        const double fa = a[i], fb = b[i];
        r.areaA += fa > threshold;
        r.areaB += fb > threshold;
        const OverlapContribution cd = overlapContribution(fa, fb, threshold);
        r.OA += cd.c;
        r.OB += cd.d;
        r.sumC2 += cd.c * cd.c;
        r.sumD2 += cd.d * cd.d;
    }
    if (r.areaA == 0 || r.areaB == 0) return r;  // e = 0: one lattice has no lobe at all
    const double areaA = double(r.areaA), areaB = double(r.areaB), mn = double(count);
    // e_sum = min(OA/areaA, OB/areaB)  (Figure 5, overlap2 = OB/areaB per flux-overlap.md)
    r.eSum = std::min(r.OA / areaA, r.OB / areaB);
    // e_mse = min((1/mn) Σ (c/areaA)², (1/mn) Σ (d/areaB)²)  (eq. 1.21 with eq. 1.22's choice
    // made on the whole-lattice sums, flux-overlap.md "Variant mse")
    r.eMse = std::min(r.sumC2 / (areaA * areaA) / mn, r.sumD2 / (areaB * areaB) / mn);
    return r;
}

}  // namespace lobe
