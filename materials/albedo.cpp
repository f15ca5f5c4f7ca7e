#include "materials/albedo.h"

#include "core/error.h"

#include <cmath>
#include <cstdio>

namespace lobe {

Spectrum normalIncidenceAlbedoBands(const Brdf& brdf) {
    // 8-point Gauss–Legendre on [−1, 1] (Abramowitz & Stegun, Table 25.4).
    static const double x[4] = {0.1834346424956498, 0.5255324099163290, 0.7966664774136267,
                                0.9602898564975363};
    static const double w[4] = {0.3626837833783620, 0.3137066458778873, 0.2223810344533745,
                                0.1012285362903763};
    constexpr int kPanels = 80, kPhi = 64;
    constexpr double kFirst = 1e-7;
    const double halfPi = 0.5 * kPi;
    const Vec3 wi(0, 0, 1);
    Spectrum sum(0.0);
    double lo = 0.0;
    for (int p = 0; p <= kPanels; ++p) {
        const double hi = p == 0 ? kFirst : kFirst * std::pow(halfPi / kFirst, double(p) / kPanels);
        const double mid = 0.5 * (lo + hi), half = 0.5 * (hi - lo);
        for (int g = 0; g < 8; ++g) {
            const double theta = mid + (g < 4 ? -x[g] : x[g - 4]) * half;
            const double weight = w[g % 4] * half;
            const double st = std::sin(theta), ct = std::cos(theta);
            Spectrum ring(0.0);
            for (int k = 0; k < kPhi; ++k) {
                const double phi = 2.0 * kPi * (k + 0.5) / kPhi;
                ring += evalBrdf(brdf, wi, Vec3(st * std::cos(phi), st * std::sin(phi), ct));
            }
            sum += ring * (2.0 * kPi / kPhi * weight * ct * st);
        }
        lo = hi;
    }
    return sum;
}

double normalIncidenceAlbedo(const Brdf& brdf) {
    return normalIncidenceAlbedoBands(brdf).average();
}

double albedoScale(const Brdf& brdf, double target) {
    const double a = normalIncidenceAlbedo(brdf);
    if (!(a > 0.0) || !std::isfinite(a)) {
        char buf[160];
        std::snprintf(buf, sizeof buf,
                      "the %s lobe's albedo at normal incidence is %g: it cannot be scaled to %g",
                      brdfName(brdf), a, target);
        throw Error(buf);
    }
    return target / a;
}

}  // namespace lobe
