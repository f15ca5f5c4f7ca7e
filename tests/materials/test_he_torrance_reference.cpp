// He–Torrance (materials/he_torrance.cpp) against the straightforward implementation it was
// optimised from, kept below verbatim as the reference: the D series walked in log space with
// lnΓ and a logarithm per term, z0 by Newton with a step-size stop only, and no shortcut for
// tiny K. The optimised code sums the same terms in linear space with the term-ratio
// recurrence, forms the peak term's logarithm without cancellation, stops Newton at the
// rounding level of its residual and skips z0 where it cannot change σ (he_torrance.cpp
// explains each step).
//
// Agreement: 1e-10 relative, plus, where g is large, the reference's own rounding. Its peak
// term exp(m ln g − g − lnΓ(m+1) − …) cancels parts of size ~g ln g, an absolute error of a few
// ε·g·ln g in the exponent (~1e-9 relative at g ~ 1e6, σ0/λ ~ 100). Which side is right there
// is settled by values of the doc's series under its own stopping rule in 50-digit arithmetic.
#include "core/rng.h"
#include "materials/registry.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace lobe {
namespace {

// ---- Reference: he_torrance.cpp as of commit 347412d (before the optimisation), verbatim
// ---- except that the members are free functions (eval takes the model).
namespace reference {

constexpr double kWaveNumber = 2.0 * kPi;
constexpr double kSeriesTolerance = 1e-12;

double effectiveRoughnessK(double cosTheta, double sigma0, double tau) {
    const double sinTheta = std::sqrt(std::max(0.0, 1.0 - cosTheta * cosTheta));
    if (!(sinTheta > 0.0)) return 0.0;  // K(0) = 0 (brdf-models.md model 7)
    const double tanTheta = sinTheta / cosTheta;
    return tanTheta * std::erfc(tau / (2.0 * sigma0 * tanTheta));
}

double solveZ0(double sigma0, double kSum) {
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

double distributionD(double g, double vxy2, double tau) {
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

double shadowingS(double cosTheta, double sigma0, double tau) {
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

Spectrum eval(const HeTorrance& m, const Vec3& wi, const Vec3& wo) {
    const Spectrum &ks = m.ks, &sigma0 = m.sigma0, &tau = m.tau, &eta = m.eta, &kappa = m.kappa;
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

}  // namespace reference
// ---- End of the reference.

// ---- The previous optimised distributionD, he_torrance.cpp as of commit 42cddf8 (walked term
// by term with the rolling reciprocals), verbatim except for its name space. The blocked walks
// that replaced it sum the same terms under the same stopping rule, with the same term ratios;
// only roundings differ, so the two must agree to far better than the rule's 1e-12.
namespace previous {

constexpr double kSeriesTolerance = 1e-12;

// e^d for |d| ≤ 1/64: the Taylor polynomial to degree 6, whose remainder |d|⁷/7! · e^{|d|} is
// below 10⁻¹⁶ — under one rounding of the result.
inline double expSmall(double d) {
    return 1.0 +
           d * (1.0 + d * (1.0 / 2 + d * (1.0 / 6 + d * (1.0 / 24 + d * (1.0 / 120 + d / 720)))));
}
constexpr double kSmallStep = 1.0 / 64.0;
// A fresh std::exp at least this often keeps the rounding carried along a product of expSmall
// factors below ~kResync ulps (~1e-14 relative).
constexpr int kResync = 32;

// L(m) = ln T_m = m ln g − g − lnΓ(m+1) − ln m − a/m. Written so, m ln g, g and lnΓ(m+1) are each
// ~g ln g for the peak m ≈ g and cancel to O(ln g): an absolute rounding error of ~ε·g·ln g, i.e.
// ~1e-9 relative in T for g ~ 1e6 (σ0/λ ~ 100). For m ≥ 30 the Stirling series (Abramowitz &
// Stegun 6.1.41, for ln m! = lnΓ(m+1))
//   lnΓ(m+1) = m ln m − m + ½ ln(2πm) + 1/(12m) − 1/(360m³) + 1/(1260m⁵) − 1/(1680m⁷) + …
// (next term 1/(1188m⁹) < 1e-16 there) turns the cancelling part into
//   m ln g − g − m ln m + m = m·(ln(1+u) − u),  u = (g − m)/m,
// formed with log1p and accurate to ~ε·|g − m|. Below m = 30 the direct form loses < 1e-13.
double logSeriesTerm(double m, double g, double lnG, double a) {
    if (m < 30.0) return m * lnG - g - std::lgamma(m + 1.0) - std::log(m) - a / m;
    const double u = (g - m) / m, inv = 1.0 / m, inv2 = inv * inv;
    const double stirlingTail =
        inv * (1.0 / 12 - inv2 * (1.0 / 360 - inv2 * (1.0 / 1260 - inv2 / 1680)));
    return m * (std::log1p(u) - u) - 0.5 * std::log(2.0 * kPi * m) - stirlingTail -
           std::log(m) - a / m;
}

double distributionD(double g, double vxy2, double tau) {
    // Terms T_m = g^m e^{−g} / (m!·m) · exp(−a/m), a = vxy2·τ²/4; in log space
    //   L(m) = m ln g − g − lnΓ(m+1) − ln m − a/m.
    // L is concave in m (−lnΓ'' ≤ −1/m, +1/m² from −ln m, −2a/m³), so the terms rise to one peak
    // and then fall. The doc's rule — sum until past the peak (m > g) and the term is below 1e-12
    // of the sum — is applied walking up from the peak; walking down from it the terms only fall,
    // so the same threshold ends the walk there. Starting at the peak keeps large g (thousands of
    // terms before the peak, all below 1e-12 of it far from it) cheap.
    //
    // The walks run in linear space relative to the peak term (nothing underflows before the sum
    // is formed), with the term ratio (a/m − a/(m+1) = a/(m(m+1)) =: x_m)
    //   T_{m+1}/T_m = g·m/(m+1)² · e^{x_m},
    // so no logarithm or lnΓ per term. The factor e^{±x_m} follows m by its own recurrence:
    //   x_{m+1} − x_m = −2a/(m(m+1)(m+2)),
    // small once m is past ∛a, so e^{x_{m+1}} = e^{x_m} · expSmall(x_{m+1} − x_m) there (a fresh
    // std::exp where the step is not small, and every kResync terms). Reciprocals of m, m+1, m+2
    // roll along so that each term costs one division.
    if (!(g > 0.0)) return 0.0;
    const double a = vxy2 * tau * tau / 4.0;
    const double lnG = std::log(g);

    // Peak: the root of L'(m) ≈ s(m) = ln g − ln(m + ½) − 1/m + a/m² (digamma(m+1) ≈ ln(m + ½)),
    // which is decreasing (s' = −1/(m+½) + 1/m² − 2a/m³ < 0 for m ≥ 1) and negative at
    // m = e·g + sqrt(a) + 2. Newton from m = max(1, g) (the root when a = 0, up to ~½), kept inside
    // the bracket [lo, hi] by bisection where it would leave it, to a quarter of a term.
    double peak = 1.0;
    if (lnG - std::log(1.5) - 1.0 + a > 0.0) {  // s(1) > 0: the root is past 1
        double lo = 1.0, hi = std::exp(1.0) * g + std::sqrt(a) + 2.0;
        double m = std::min(std::max(1.0, g), hi);
        for (int it = 0; it < 100; ++it) {
            const double inv = 1.0 / m;
            const double s = lnG - std::log(m + 0.5) - inv + a * inv * inv;
            if (s > 0.0)
                lo = m;
            else
                hi = m;
            const double ds = -1.0 / (m + 0.5) + inv * inv - 2.0 * a * inv * inv * inv;
            double next = m - s / ds;
            if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
            const bool done = std::abs(next - m) < 0.25 || hi - lo < 0.25;
            m = next;
            if (done) break;
        }
        peak = std::max(1.0, std::floor(m));
    }
    // The integer peak is floor(root) or the next one: step up while the ratio says T_{m+1} > T_m.
    for (int k = 0; k < 2 && g * peak / ((peak + 1.0) * (peak + 1.0)) *
                                     std::exp(a / (peak * (peak + 1.0))) >
                                 1.0;
         ++k)
        peak += 1.0;
    const double logPeak = logSeriesTerm(peak, g, lnG, a);

    // Up from the peak (the peak's own term included): T_{m+1} = T_m · g·m/(m+1)² · e^{x_m}.
    double sum = 0.0, t = 1.0;
    {
        double invM = 1.0 / peak, invM1 = 1.0 / (peak + 1.0);
        double e = std::exp(a * invM * invM1);  // e^{x_m}
        int fresh = 0;
        for (double m = peak;; m += 1.0) {
            sum += t;
            if (m > g && t < kSeriesTolerance * sum) break;
            if (m > 1e9) break;  // unreachable for the parameter ranges; a guard, not a limit
            t *= g * m * invM1 * invM1 * e;
            const double invM2 = 1.0 / (m + 2.0);
            const double step = -2.0 * a * invM * invM1 * invM2;  // x_{m+1} − x_m
            if (++fresh < kResync && step >= -kSmallStep) {
                e *= expSmall(step);
            } else {
                fresh = 0;
                e = std::exp(a * invM1 * invM2);
            }
            invM = invM1;
            invM1 = invM2;
        }
    }
    // Down from the peak: T_m = T_{m+1} · (m+1)²/(g·m) · e^{−x_m}.
    if (peak > 1.0) {
        const double invG = 1.0 / g;
        double invM = 1.0 / (peak - 1.0), invM1 = 1.0 / peak;
        double e = std::exp(-a * invM * invM1);  // e^{−x_m}
        int fresh = 0;
        t = 1.0;
        for (double m = peak - 1.0; m >= 1.0; m -= 1.0) {
            t *= (m + 1.0) * (m + 1.0) * invG * invM * e;
            sum += t;
            if (t < kSeriesTolerance * sum || m <= 1.0) break;
            const double invM0 = 1.0 / (m - 1.0);
            const double step = -2.0 * a * invM0 * invM * invM1;  // −(x_{m−1} − x_m)
            if (++fresh < kResync && step >= -kSmallStep) {
                e *= expSmall(step);
            } else {
                fresh = 0;
                e = std::exp(-a * invM0 * invM);
            }
            invM1 = invM;
            invM = invM0;
        }
    }
    return kPi * kPi * tau * tau / 4.0 * std::exp(logPeak) * sum;
}

}  // namespace previous
// ---- End of the previous implementation.

Vec3 directionCos(double cosTheta, double phi) {
    const double s = std::sqrt(std::max(0.0, 1.0 - cosTheta * cosTheta));
    return Vec3(s * std::cos(phi), s * std::sin(phi), cosTheta);
}

double relativeDifference(double x, double reference) {
    if (x == reference) return 0.0;
    return std::abs(x - reference) / std::max(std::abs(x), std::abs(reference));
}

constexpr double kAgreement = 1e-10;

// The reference's rounding at g (see the head comment): a few ε·g·ln g, negligible below g ~ 1e4.
double referenceRounding(double g) { return 4.0 * 2.2e-16 * g * std::max(1.0, std::log(g)); }

// g = [kσ(cos θi + cos θo)]² of band b, computed by the reference's own steps.
double referenceG(const HeTorrance& m, const Vec3& wi, const Vec3& wo, int b) {
    const double s0 = m.sigma0[b], t = m.tau[b];
    const double kSum = reference::effectiveRoughnessK(wi.z, s0, t) +
                        reference::effectiveRoughnessK(wo.z, s0, t);
    const double z0 = reference::solveZ0(s0, kSum);
    const double sigma = s0 / std::sqrt(1.0 + (z0 / s0) * (z0 / s0));
    const double root = reference::kWaveNumber * sigma * (wi.z + wo.z);
    return root * root;
}

TEST(HeTorranceReference, SeriesDMatchesAcrossGAndA) {
    // g = [kσ(cos θi + cos θo)]² ≤ (2π·100·2)² ≈ 1.6e6; a = k²|H_xy|²τ²/4 ≤ π²·4·1000² ≈ 3.9e7.
    for (const double g : {1e-12, 1e-4, 0.05, 0.7, 3.0, 17.0, 158.0, 900.0, 2.5e4, 2e5, 1.6e6})
        for (const double a : {0.0, 1e-6, 0.2, 5.0, 60.0, 987.0, 3948.0, 1e5, 3.9e7}) {
            const double tau = 10.0, vxy2 = 4.0 * a / (tau * tau);
            const double d = HeTorrance::distributionD(g, vxy2, tau);
            const double r = reference::distributionD(g, vxy2, tau);
            ASSERT_TRUE(std::isfinite(d));
            EXPECT_LE(relativeDifference(d, r), kAgreement + referenceRounding(g))
                << "g " << g << " a " << a;
        }
}

// The doc's series under its own stopping rule, in 50-digit arithmetic (python3 + mpmath):
//   import mpmath, math
//   mpmath.mp.dps = 50
//   def D(g, a, tau=10):
//       g, a = mpmath.mpf(g), mpmath.mpf(a)
//       lg = mpmath.log(g)
//       L = lambda m: m*lg - g - mpmath.loggamma(m+1) - mpmath.log(m) - a/m
//       lo, hi = 1, int(math.e*float(g) + math.sqrt(float(a)) + 3)
//       while hi - lo > 1:  # integer argmax of the concave L
//           mid = (lo + hi)//2
//           if L(mid+1) > L(mid): lo = mid
//           else: hi = mid
//       p = lo if L(lo) >= L(lo+1) else lo+1
//       Lp = L(p); s = mpmath.mpf(0); m = p
//       while True:  # up from the peak: past m > g and the term < 1e-12 of the sum
//           t = mpmath.exp(L(m) - Lp); s += t
//           if m > g and t < mpmath.mpf('1e-12')*s: break
//           m += 1
//       m = p - 1
//       while m >= 1:  # down from the peak: the term < 1e-12 of the sum
//           t = mpmath.exp(L(m) - Lp); s += t
//           if t < mpmath.mpf('1e-12')*s: break
//           m -= 1
//       return mpmath.pi**2*tau**2/4*mpmath.exp(Lp)*s
//   for g, a in [(1.6e6, 0), (1.6e6, 987), (2e5, 3.9e7), (2.5e4, 3948), (900, 1e5), (158, 987),
//                (0.05, 3948), (3, 60)]:
//       print(g, a, mpmath.nstr(D(g, a), 17))
// At g = 1.6e6 the reference implementation is 1.1e-9 off these (its cancellation); the
// optimised code is within 1e-12.
TEST(HeTorranceReference, SeriesDMatchesHighPrecisionValuesOfTheRule) {
    struct Case {
        double g, a, d;
    };
    const Case cases[] = {
        {1.6e6, 0.0, 0.00015421266510486201},    {1.6e6, 987.0, 0.00015411756438386221},
        {2e5, 3.9e7, 2.780745977751942e-88},      {2.5e4, 3948.0, 0.0084280686187229647},
        {900.0, 1e5, 4.0013906646949721e-47},     {158.0, 987.0, 0.0031755618342940173},
        {0.05, 3948.0, 1.6111708836300001e-125},  {3.0, 60.0, 0.00058624138311903002},
    };
    for (const Case& c : cases) {
        const double tau = 10.0, vxy2 = 4.0 * c.a / (tau * tau);
        EXPECT_LE(relativeDifference(HeTorrance::distributionD(c.g, vxy2, tau), c.d), 1e-11)
            << "g " << c.g << " a " << c.a;
    }
}

TEST(HeTorranceReference, SeriesDMatchesThePreviousWalkOverRandomArguments) {
    // g log-uniform over [1e-6, 1e6] (the model's g reaches ~1.6e6), a = vxy2·τ²/4 zero for one
    // draw in eight, else log-uniform over [1e-8, 4e7], τ log-uniform over the table's range.
    Rng rng(42, 3);
    const auto logUniform = [&](double lo, double hi) {
        return lo * std::pow(hi / lo, rng.uniform());
    };
    double worst = 0.0;
    for (int i = 0; i < 3000; ++i) {
        const double g = logUniform(1e-6, 1e6);
        const double a = i % 8 == 0 ? 0.0 : logUniform(1e-8, 4e7);
        const double tau = logUniform(0.01, 1000.0), vxy2 = 4.0 * a / (tau * tau);
        const double d = HeTorrance::distributionD(g, vxy2, tau);
        const double r = previous::distributionD(g, vxy2, tau);
        ASSERT_TRUE(std::isfinite(d) && d >= 0.0) << "g " << g << " a " << a;
        EXPECT_LE(std::abs(d - r), 1e-12 * r + 1e-300) << "g " << g << " a " << a << " tau " << tau;
        if (r > 0.0) worst = std::max(worst, std::abs(d - r) / r);
    }
    std::printf("largest relative difference from the previous walk: %.3g\n", worst);
}

TEST(HeTorranceReference, NewtonZ0MatchesAcrossSigma0AndKSum) {
    for (const double sigma0 : {0.01, 0.3, 1.0, 7.0, 100.0})
        for (double kSum = 1e-30; kSum < 1e8; kSum *= 3.7) {
            const double z = HeTorrance::solveZ0(sigma0, kSum);
            const double r = reference::solveZ0(sigma0, kSum);
            EXPECT_LE(relativeDifference(z, r), kAgreement) << sigma0 << " " << kSum;
        }
}

void expectSameBrdf(const HeTorrance& m, const Vec3& wi, const Vec3& wo, const std::string& what) {
    const Spectrum f = m.eval(wi, wo), r = reference::eval(m, wi, wo);
    for (int b = 0; b < kBandCount; ++b)
        ASSERT_LE(relativeDifference(f[b], r[b]),
                  kAgreement + referenceRounding(referenceG(m, wi, wo, b)))
            << what << " band " << b << ": " << f[b] << " vs " << r[b] << " wi " << wi << " wo "
            << wo;
}

TEST(HeTorranceReference, BrdfMatchesAtDefaultsOverRandomAndGrazingPairs) {
    const HeTorrance m = std::get<HeTorrance>(makeBrdf("he_torrance", {}));
    Rng rng(2003, 7);
    for (int i = 0; i < 3000; ++i) {
        const Vec3 wi = directionCos(rng.uniform(), 2.0 * kPi * rng.uniform());
        Vec3 wo = directionCos(rng.uniform(), 2.0 * kPi * rng.uniform());
        if (i % 2) wo = (mirrorLocal(wi) + 0.2 * Vec3(rng.uniform() - 0.5, rng.uniform() - 0.5,
                                                      rng.uniform() - 0.5)).normalized();
        if (wo.z > 0.0) expectSameBrdf(m, wi, wo, "defaults, random pair");
    }
    for (const double ci : {1e-7, 1e-5, 1e-3, 0.02, 0.1, 0.3})
        for (const double co : {1e-7, 1e-4, 0.01, 0.05, 0.5, 1.0})
            for (const double dphi : {0.0, 0.3, 1.5, 3.1}) {
                const Vec3 wi = directionCos(ci, 0.4);
                expectSameBrdf(m, wi, directionCos(co, 0.4 + kPi + dphi), "defaults, grazing");
            }
}

TEST(HeTorranceReference, BrdfMatchesAcrossTheParameterRanges) {
    // Parameters drawn over the table's ranges (σ0/λ and τ/λ log-uniform, since their effects
    // are multiplicative), each band its own, plus the corners; random and grazing pairs.
    Rng rng(11, 5);
    const auto logUniform = [&](double lo, double hi) {
        return lo * std::pow(hi / lo, rng.uniform());
    };
    std::vector<HeTorrance> models;
    for (const double s0 : {0.01, 100.0})
        for (const double t : {0.01, 1000.0}) {
            HeTorrance m;
            m.sigma0 = Spectrum(s0);
            m.tau = Spectrum(t);
            models.push_back(m);
        }
    for (int n = 0; n < 60; ++n) {
        HeTorrance m;
        for (int b = 0; b < kBandCount; ++b) {
            m.ks[b] = rng.uniform();
            m.sigma0[b] = logUniform(0.01, 100.0);
            m.tau[b] = logUniform(0.01, 1000.0);
            m.eta[b] = logUniform(0.01, 10.0);
            m.kappa[b] = 20.0 * rng.uniform();
        }
        models.push_back(m);
    }
    for (const HeTorrance& m : models) {
        for (int i = 0; i < 40; ++i) {
            const double ci = i % 4 == 0 ? std::pow(10.0, -6.0 * rng.uniform()) : rng.uniform();
            const Vec3 wi = directionCos(ci, 2.0 * kPi * rng.uniform());
            const Vec3 wo = directionCos(rng.uniform(), 2.0 * kPi * rng.uniform());
            expectSameBrdf(m, wi, wo, "random parameters");
        }
    }
}

}  // namespace
}  // namespace lobe
