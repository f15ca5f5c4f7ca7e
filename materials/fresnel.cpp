// Exact Fresnel term; see brdf_common.h for the formula and its sources.
#include "materials/brdf_common.h"

#include <complex>

namespace lobe {

double fresnelExact(double eta, double kappa, double c) {
    using Complex = std::complex<double>;
    c = std::min(1.0, std::max(0.0, c));
    const Complex n(eta, kappa);
    // Principal root: Re g ≥ 0, which keeps |g − c| ≤ |g + c| and so F ≤ 1.
    const Complex g = std::sqrt(n * n + c * c - 1.0);
    const double ratio = std::norm(g - c) / std::norm(g + c);
    const double denom = std::norm(c * (g - c) + 1.0);
    // denom is 0 only for g = c − 1/c, impossible with Re g ≥ 0 and c ∈ (0,1]; at c = 0, g ≠ 0
    // and the second factor is 2.
    const double second = denom > 0.0 ? std::norm(c * (g + c) - 1.0) / denom : 1.0;
    const double f = 0.5 * ratio * (1.0 + second);
    return std::min(1.0, std::max(0.0, f));
}

}  // namespace lobe
