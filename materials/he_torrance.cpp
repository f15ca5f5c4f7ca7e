// He–Torrance directional-diffuse BRDF; the model and its sources are described in he_torrance.h.
#include "materials/he_torrance.h"

#include <cmath>

namespace lobe {
namespace {

constexpr double kWaveNumber = 2.0 * kPi;   // k = 2π/λ with lengths in units of λ
constexpr double kSeriesTolerance = 1e-12;  // stop when a term is below this fraction of the sum

}  // namespace

const ParamTable& HeTorrance::paramTable() {
    static const ParamTable table = {
        {"ks", 0.8, 0.0, 1.0, "specular coefficient", false},
        {"sigma0_over_lambda", 1.0, 0.01, 100.0, "RMS surface height σ0 / wavelength", false},
        {"tau_over_lambda", 10.0, 0.01, 1000.0, "autocorrelation length τ / wavelength", false},
        {"eta", 1.6, 0.01, 10.0, "index of refraction, real part", false},
        {"kappa", 0.2, 0.0, 20.0, "index of refraction, imaginary part (extinction)", false},
    };
    return table;
}

HeTorrance HeTorrance::fromParams(const ParamValues& p) {
    return HeTorrance{p.get("ks"), p.get("sigma0_over_lambda"), p.get("tau_over_lambda"),
                      p.get("eta"), p.get("kappa")};
}

double HeTorrance::effectiveRoughnessK(double cosTheta, double sigma0, double tau) {
    const double sinTheta = std::sqrt(std::max(0.0, 1.0 - cosTheta * cosTheta));
    if (!(sinTheta > 0.0)) return 0.0;  // K(0) = 0 (brdf-models.md model 7)
    const double tanTheta = sinTheta / cosTheta;
    return tanTheta * std::erfc(tau / (2.0 * sigma0 * tanTheta));
}

double HeTorrance::solveZ0(double sigma0, double kSum) {
    // z = A·exp(−z²/(2σ0²)), A = (σ0/4)·kSum/sqrt(π/2). In the form h(z) = ln z − ln A + z²/(2σ0²)
    // h is increasing on (0, ∞) with h(0⁺) = −∞ and h(A) ≥ 0, so the root is unique in (0, A];
    // Newton on h converges from either side, and a bisection step keeps it in the bracket. The
    // log form matters at grazing angles, where K ~ tan θ makes A ~ 1e7 σ0.
    const double a = sigma0 / 4.0 * kSum / std::sqrt(kPi / 2.0);
    if (!(a > 0.0)) return 0.0;
    const double logA = std::log(a), inv2s2 = 1.0 / (2.0 * sigma0 * sigma0);
    double lo = 0.0, hi = a;
    // Start: the root of ln z = ln A − z²/(2σ0²) with ln z ≈ ln σ0 when A ≫ σ0, else one
    // fixed-point step from A.
    double z = a > sigma0 ? std::min(a, sigma0 * std::sqrt(2.0 * std::log(a / sigma0)))
                          : a * std::exp(-a * a * inv2s2);
    if (!(z > lo && z <= hi)) z = 0.5 * (lo + hi);
    for (int it = 0; it < 200; ++it) {
        const double h = std::log(z) - logA + z * z * inv2s2;
        if (h > 0.0)
            hi = z;
        else
            lo = z;
        const double dh = 1.0 / z + 2.0 * z * inv2s2;
        double next = z - h / dh;
        if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
        if (std::abs(next - z) <= 1e-15 * z) return next;
        z = next;
    }
    return z;
}

double HeTorrance::distributionD(double g, double vxy2, double tau) {
    // Terms T_m = g^m e^{−g} / (m!·m) · exp(−a/m), a = vxy2·τ²/4, in log space:
    //   L(m) = m ln g − g − lnΓ(m+1) − ln m − a/m.
    // L is concave in m (−lnΓ'' ≤ −1/m, +1/m² from −ln m, −2a/m³), so the terms rise to one peak
    // and then fall. The doc's rule — sum until past the peak (m > g) and the term is below 1e-12
    // of the sum — is applied walking up from the peak; walking down from it the terms only fall,
    // so the same threshold ends the walk there. Starting at the peak keeps large g (thousands of
    // terms before the peak, all below 1e-12 of it far from it) cheap. The sum is scaled by
    // e^{L(peak)} so that no term underflows before the sum is formed.
    if (!(g > 0.0)) return 0.0;
    const double a = vxy2 * tau * tau / 4.0;
    const double lnG = std::log(g);
    const auto logTerm = [&](double m) {
        return m * lnG - g - std::lgamma(m + 1.0) - std::log(m) - a / m;
    };
    // Peak: L'(m) ≈ ln g − ln(m + ½) − 1/m + a/m² (digamma(m+1) ≈ ln(m + ½)) is decreasing; it
    // is negative at m = e·g + sqrt(a) + 2, so bisect on [1, that].
    double lo = 1.0, hi = std::exp(1.0) * g + std::sqrt(a) + 2.0;
    const auto slope = [&](double m) { return lnG - std::log(m + 0.5) - 1.0 / m + a / (m * m); };
    if (slope(lo) <= 0.0) {
        hi = lo;
    } else {
        while (hi - lo > 0.5) {
            const double mid = 0.5 * (lo + hi);
            if (slope(mid) > 0.0)
                lo = mid;
            else
                hi = mid;
        }
    }
    double peak = std::max(1.0, std::floor(lo));
    if (logTerm(peak + 1.0) > logTerm(peak)) peak += 1.0;
    const double logPeak = logTerm(peak);

    // Up from the peak (the peak's own term included), with the recurrence
    // L(m+1) − L(m) = ln g − 2 ln(m+1) + ln m + a/m − a/(m+1).
    double sum = 0.0, logT = logPeak, logM = std::log(peak);
    for (double m = peak;; m += 1.0) {
        const double t = std::exp(logT - logPeak);
        sum += t;
        if (m > g && t < kSeriesTolerance * sum) break;
        if (m > 1e9) break;  // unreachable for the parameter ranges; a guard, not a limit
        const double logM1 = std::log(m + 1.0);
        logT += lnG - 2.0 * logM1 + logM + a / m - a / (m + 1.0);
        logM = logM1;
    }
    // Down from the peak.
    logT = logPeak;
    logM = std::log(peak);
    for (double m = peak - 1.0; m >= 1.0; m -= 1.0) {
        const double logM0 = std::log(m);
        logT -= lnG - 2.0 * logM + logM0 + a / m - a / (m + 1.0);  // L(m) = L(m+1) − Δ
        logM = logM0;
        const double t = std::exp(logT - logPeak);
        sum += t;
        if (t < kSeriesTolerance * sum) break;
    }
    return kPi * kPi * tau * tau / 4.0 * std::exp(logPeak) * sum;
}

double HeTorrance::shadowingS(double cosTheta, double sigma0, double tau) {
    const double sinTheta = std::sqrt(std::max(0.0, 1.0 - cosTheta * cosTheta));
    if (!(sinTheta > 0.0)) return 1.0;  // S(0) = 1
    const double c = tau * cosTheta / (2.0 * sigma0 * sinTheta);
    // Beyond c = 26, erfc(c) < 1e-295 and Λ(c) < e^{−676}: S = 1 to double precision, and the
    // difference in Λ would only be rounding noise.
    if (c > 26.0) return 1.0;
    if (!(c > 0.0)) return 0.0;
    // Λ(c) = ½ [e^{−c²}/(√π c) − erfc(c)] (errata form) is ≥ 0; clamp the cancellation's noise.
    const double lambda =
        std::max(0.0, 0.5 * (std::exp(-c * c) / (std::sqrt(kPi) * c) - std::erfc(c)));
    return (1.0 - 0.5 * std::erfc(c)) / (lambda + 1.0);
}

Spectrum HeTorrance::eval(const Vec3& wi, const Vec3& wo) const {
    Vec3 h;
    if (!aboveHorizon(wi, wo) || !halfVector(wi, wo, h)) return Spectrum(0.0);
    const Vec3 sum = wi + wo;  // H, unnormalised; H·n > 0 above the horizon
    const double hLen2 = sum.length2();
    const double geometry = (hLen2 / sum.z) * (hLen2 / sum.z);  // G
    const double vxy2 = kWaveNumber * kWaveNumber * (sum.x * sum.x + sum.y * sum.y);
    const double cosI = wi.z, cosO = wo.z;
    const double c = std::min(1.0, std::max(0.0, wi.dot(h)));
    Spectrum f;
    double lastSigma0 = -1.0, lastTau = -1.0, dsg = 0.0;  // D·S·G, shared by equal bands
    for (int b = 0; b < kBandCount; ++b) {
        if (sigma0[b] != lastSigma0 || tau[b] != lastTau) {
            lastSigma0 = sigma0[b];
            lastTau = tau[b];
            const double s0 = sigma0[b], t = tau[b];
            const double kSum = effectiveRoughnessK(cosI, s0, t) + effectiveRoughnessK(cosO, s0, t);
            const double z0 = solveZ0(s0, kSum);
            const double sigma = s0 / std::sqrt(1.0 + (z0 / s0) * (z0 / s0));
            const double root = kWaveNumber * sigma * (cosI + cosO);
            const double d = distributionD(root * root, vxy2, t);
            const double s = shadowingS(cosI, s0, t) * shadowingS(cosO, s0, t);
            dsg = d * s * geometry;
        }
        const double value = ks[b] * fresnelExact(eta[b], kappa[b], c) * dsg / (kPi * cosI * cosO);
        f[b] = std::isfinite(value) ? value : 0.0;
    }
    return f;
}

}  // namespace lobe
