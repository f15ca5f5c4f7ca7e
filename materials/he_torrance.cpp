// He–Torrance directional-diffuse BRDF; the model and its sources are described in he_torrance.h.
#include "materials/he_torrance.h"

#include "materials/he_torrance_table.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

namespace lobe {
namespace {

constexpr double kWaveNumber = 2.0 * kPi;   // k = 2π/λ with lengths in units of λ
constexpr double kSeriesTolerance = 1e-12;  // stop when a term is below this fraction of the sum
constexpr double kEpsilon = 2.220446049250313e-16;  // the double precision unit roundoff × 2

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
    return HeTorrance{p.get("ks"),
                      p.get("sigma0_over_lambda"),
                      p.get("tau_over_lambda"),
                      p.get("eta"),
                      p.get("kappa"),
                      nullptr};
}

HeTorrance::DirectionTerms HeTorrance::directionTerms(double cosTheta, double sigma0, double tau) {
    // K(θ) = tan θ · erfc(c) and S(θ) = [1 − ½ erfc(c)] / [Λ(c) + 1] share c = τ cot θ / (2σ0),
    // so one erfc serves both.
    const double sinTheta = std::sqrt(std::max(0.0, 1.0 - cosTheta * cosTheta));
    if (!(sinTheta > 0.0)) return {0.0, 1.0};  // K(0) = 0, S(0) = 1 (docs/models.md model 7)
    const double c = tau * cosTheta / (2.0 * sigma0 * sinTheta);
    if (!(c > 0.0)) return {0.0, 0.0};
    const double erfcC = std::erfc(c);
    const double k = sinTheta / cosTheta * erfcC;
    // Beyond c = 26, erfc(c) < 1e-295 and Λ(c) < e^{−676}: S = 1 to double precision, and the
    // difference in Λ would only be rounding noise.
    if (c > 26.0) return {k, 1.0};
    // Λ(c) = ½ [e^{−c²}/(√π c) − erfc(c)] (errata form) is ≥ 0; clamp the cancellation's noise.
    const double lambda = std::max(0.0, 0.5 * (std::exp(-c * c) / (std::sqrt(kPi) * c) - erfcC));
    return {k, (1.0 - 0.5 * erfcC) / (lambda + 1.0)};
}

double HeTorrance::effectiveRoughnessK(double cosTheta, double sigma0, double tau) {
    return directionTerms(cosTheta, sigma0, tau).k;
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
        const double logZ = std::log(z), quad = z * z * inv2s2;
        const double h = logZ - logA + quad;
        const double dh = 1.0 / z + 2.0 * z * inv2s2;
        // Once h is within the rounding of its own evaluation (a few ulps of its largest part),
        // further steps only move z by noise: take the last Newton step and stop. (Testing the
        // step size alone, as below, can wander for many iterations at that noise level.)
        if (std::abs(h) <= 8.0 * kEpsilon * (std::abs(logZ) + std::abs(logA) + quad))
            return z - h / dh;
        if (h > 0.0)
            hi = z;
        else
            lo = z;
        double next = z - h / dh;
        if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
        if (std::abs(next - z) <= 1e-15 * z) return next;
        z = next;
    }
    return z;
}

namespace {

// e^d for |d| ≤ 1/64: the Taylor polynomial to degree 6, whose remainder |d|⁷/7! · e^{|d|} is
// below 10⁻¹⁶ — under one rounding of the result.
inline double expSmall(double d) {
    return 1.0 +
           d * (1.0 +
                d * (1.0 / 2 + d * (1.0 / 6 + d * (1.0 / 24 + d * (1.0 / 120 + d * (1.0 / 720))))));
}
constexpr double kSmallStep = 1.0 / 64.0;
// A fresh std::exp at least this often keeps the rounding carried along a product of expSmall
// factors below ~kResync ulps (~1e-14 relative).
constexpr int kResync = 32;
// The walks go in blocks of kBlock terms (a divisor of kResync): first the per-term factors of the
// block, which depend on m only (independent of each other, so the compiler vectorises them and
// the divisions and polynomials overlap), then the short running products and the sum. Walked
// term by term instead, each term's long chain (division, then the degree-6 polynomial) sat
// between the short recurrences and made the walk ~1.5× slower.
constexpr int kBlock = 16;

// The cost bound. Past its peak the series' log-term L(m) is concave with −L''(m) ≥ 1/(m + 1) −
// 1/m² (ψ'(m+1) ≥ 1/(m+1); the a-term only adds curvature), so M terms beyond the peak p fall
// below e^{−(M − p)²/(2(M + 1))} of it (below it likewise, walking down towards m = 1). With
// M − p = kCapBase + kCapPerSpread·√(p + 1) that exponent is over 100, where the doc's rule
// (a term below 1e-12 of the sum, e^{−27.6}) has long stopped every walk: each walk stops after
// at most this many terms, a bound never reached in range (tests count the terms over the
// parameter ranges and extreme grazing directions) that makes every evaluation's cost finite
// whatever its arithmetic meets (it bounded 1e9 terms before: issue 32's 7-s evaluation).
constexpr double kCapBase = 256.0;
constexpr double kCapPerSpread = 16.0;
double termCap(double peak) { return kCapBase + kCapPerSpread * std::sqrt(peak + 1.0); }

// Terms summed by this thread's walks: an operation count for the tests' cost bound.
thread_local std::uint64_t tTermsSummed = 0;

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
    return m * (std::log1p(u) - u) - 0.5 * std::log(2.0 * kPi * m) - stirlingTail - std::log(m) -
           a / m;
}

// The walk up from the peak (the peak's own term included), terms relative to T_peak = 1:
// T_{m+1} = T_m · g·m/(m+1)² · e^{x_m}. Where the step x_{m+1} − x_m = −2a/(m(m+1)(m+2)) is not
// small (small m, large a) each term takes a fresh exp; from there on, since the steps only
// shrink as m grows, blocks. Returns the sum of the terms the doc's rule keeps.
double sumUpFromPeak(double peak, double g, double a) {
    const double twoA = 2.0 * a, last = peak + termCap(peak);
    double sum = 0.0, m = peak, t = 1.0;
    const auto count = [&](double mEnd, double s) {
        tTermsSummed += static_cast<std::uint64_t>(mEnd - peak + 1.0);
        return s;
    };
    while (twoA / (m * (m + 1.0) * (m + 2.0)) > kSmallStep) {
        sum += t;
        if ((m > g && t < kSeriesTolerance * sum) || m >= last) return count(m, sum);
        const double invM1 = 1.0 / (m + 1.0);
        t *= g * m * invM1 * invM1 * std::exp(a / m * invM1);
        m += 1.0;
    }
    for (;;) {
        double e = std::exp(a * (1.0 / m) * (1.0 / (m + 1.0)));  // e^{x_m}, fresh
        for (int block = 0; block < kResync / kBlock; ++block) {
            // Term k of the block is T_{m+k}: ratio[k]·e^{x_{m+k}} = T_{m+k+1}/T_{m+k},
            // factor[k] = e^{x_{m+k+1} − x_{m+k}}.
            double inv[kBlock + 2], ratio[kBlock], factor[kBlock];
            for (int k = 0; k < kBlock + 2; ++k) inv[k] = 1.0 / (m + k);
            for (int k = 0; k < kBlock; ++k) {
                ratio[k] = g * (m + k) * inv[k + 1] * inv[k + 1];
                factor[k] = expSmall(-twoA * inv[k] * inv[k + 1] * inv[k + 2]);
            }
            for (int k = 0; k < kBlock; ++k) {
                sum += t;
                if (m + k > g && t < kSeriesTolerance * sum) return count(m + k, sum);
                t *= ratio[k] * e;
                e *= factor[k];
            }
            m += kBlock;
            if (m >= last) return count(m - 1.0, sum);  // the cost bound (termCap)
        }
    }
}

// The walk down from the peak, adding to `sum` (the up walk's, which the stopping rule is
// relative to): T_m = T_{m+1} · (m+1)²/(g·m) · e^{−x_m}. The steps
// −(x_{m−1} − x_m) = −2a/((m−1)m(m+1)) grow as m falls: blocks while they are small (m ≥
// mSmall), then a fresh exp per term. Returns the new sum.
double addDownFromPeak(double peak, double g, double a, double sum) {
    if (!(peak > 1.0)) return sum;
    const double twoA = 2.0 * a;
    const double invG = 1.0 / g;
    const double first = std::max(1.0, peak - termCap(peak));  // the cost bound (termCap)
    double m = peak - 1.0, t = 1.0;                            // the next term is T_m; t = T_{m+1}
    const auto count = [&](double mEnd, double s) {
        tTermsSummed += static_cast<std::uint64_t>(peak - mEnd);
        return s;
    };
    double mSmall = std::max(2.0, std::floor(std::cbrt(twoA / kSmallStep)));
    while (mSmall > 2.0 && twoA / ((mSmall - 2.0) * (mSmall - 1.0) * mSmall) <= kSmallStep)
        mSmall -= 1.0;
    while (twoA / ((mSmall - 1.0) * mSmall * (mSmall + 1.0)) > kSmallStep) mSmall += 1.0;
    const double blocksTo = std::max(mSmall, first);
    while (m >= blocksTo) {
        double e = std::exp(-a * (1.0 / m) * (1.0 / (m + 1.0)));  // e^{−x_m}, fresh
        for (int done = 0; done < kResync && m >= blocksTo;) {
            // Term k of the block is T_{m−k} = T_{m−k+1}·ratio[k]·e^{−x_{m−k}};
            // factor[k] = e^{−(x_{m−k−1} − x_{m−k})}. inv[j] = 1/(m + 1 − j) ≥ 1/(mSmall − 1).
            const int n = static_cast<int>(
                std::min({static_cast<double>(kBlock), static_cast<double>(kResync - done),
                          m - blocksTo + 1.0}));
            double inv[kBlock + 2], ratio[kBlock], factor[kBlock];
            for (int k = 0; k < n + 2; ++k) inv[k] = 1.0 / (m + 1.0 - k);
            for (int k = 0; k < n; ++k) {
                ratio[k] = (m + 1.0 - k) * (m + 1.0 - k) * invG * inv[k + 1];
                factor[k] = expSmall(-twoA * inv[k + 2] * inv[k + 1] * inv[k]);
            }
            for (int k = 0; k < n; ++k) {
                t *= ratio[k] * e;
                sum += t;
                if (t < kSeriesTolerance * sum) return count(m - k, sum);
                e *= factor[k];
            }
            m -= n;
            done += n;
        }
    }
    for (; m >= first; m -= 1.0) {
        const double invM = 1.0 / m;
        t *= (m + 1.0) * (m + 1.0) * invG * invM * std::exp(-a * invM / (m + 1.0));
        sum += t;
        if (t < kSeriesTolerance * sum || m <= 1.0) return count(m, sum);
    }
    return count(m + 1.0, sum);
}

// --- Strided walks -----------------------------------------------------------------------------
// Where the terms spread over many m, h times every h-th term gives the sum to far below the
// rule's 1e-12, for about 1/h of the work. The residue classes m ≡ r (mod h) of the Poisson
// weights g^m e^{−g}/m! each hold 1/h of the whole, up to a relative
//   |Σ_{k=1}^{h−1} e^{−2πikr/h} φ(2πk/h)| ≤ (h − 1)·e^{−g(1 − cos(2π/h))},
// φ(ω) = exp(g(e^{iω} − 1)) their characteristic function (the discrete Fourier sum over the
// classes; Poisson summation). The factor e^{−a/m}/m narrows the terms: their spread is
// s² = 1/(−L'') at the peak, ≤ g, which stands for g in the bound. strideFor picks the largest h
// ≤ 16 with s²(1 − cos(2π/h)) ≥ 40 (aliasing below (h − 1)·e^{−40} ≈ 6e-17), and h = 1 unless the
// first term T_1 is below e^{−40} of the peak's: the sum starts at m = 1, an edge the argument
// does not cover, and there the edge holds nothing. Tests compare the strided sums with the
// unit-step walk over the whole (g, a, τ) range (test_he_torrance_reference.cpp).
constexpr int kMaxStride = 16;
// Strided walks go in blocks of this many terms: a wide series needs about 7.4·s/h ≈ 10–20 of
// them each way, so blocks of 16 computed a third more ratios than were used.
constexpr int kStrideBlock = 8;
constexpr double kAliasExponent = 40.0;

int strideFor(double peak, double g, double a, double lnG, double logPeak, int maxStride) {
    // L(1) = ln g − g − a (lnΓ(2) = ln 1 = 0).
    if (maxStride < 2 || lnG - g - a - logPeak > -kAliasExponent) return 1;
    // −L''(m) = ψ'(m+1) − 1/m² + 2a/m³ ≤ 1/(m + ½) + 2a/m³ (ψ'(m+1) < 1/(m + ½)): a spread no
    // larger than the true one.
    const double spread = 1.0 / (1.0 / (peak + 0.5) + 2.0 * a / (peak * peak * peak));
    static const std::array<double, kMaxStride + 1> minSpread = [] {
        std::array<double, kMaxStride + 1> s{};
        for (int h = 2; h <= kMaxStride; ++h)
            s[h] = kAliasExponent / (1.0 - std::cos(2.0 * kPi / h));
        return s;
    }();
    int h = 1;
    while (h < std::min(maxStride, kMaxStride) && spread >= minSpread[h + 1]) ++h;
    return h;
}

// For the terms m_k = m0 + dir·k·h (dir = ±1), k < n ≤ kStrideBlock: the ratio T_{m_k+h}/T_{m_k}
// without its exponential, m/(m+h) · Π_{j=1}^{h} g/(m+j), formed as m / ((m+h) · Π (m+j)/g) —
// the products along k vectorise; y_k = a·h/(m_k(m_k+h)), so that T_{m+h}/T_m = ratio · e^{y};
// and for k < n − 1 the step y_{k+1} − y_k in closed form (no cancellation):
//   up:   −2ah²/(m(m+h)(m+2h)),   down:   2ah²/((m−h)m(m+h)).
void strideBlock(double m0, int dir, int n, int h, double invG, double a, double* ratio, double* y,
                 double* step) {
    double mk[kStrideBlock], q[kStrideBlock];
    for (int k = 0; k < n; ++k) {
        mk[k] = m0 + dir * k * h;
        q[k] = mk[k] + h;
    }
    for (int j = 1; j <= h; ++j)
        for (int k = 0; k < n; ++k) q[k] *= (mk[k] + j) * invG;
    const double twoAh2 = 2.0 * a * h * h;
    for (int k = 0; k < n; ++k) {
        ratio[k] = mk[k] / q[k];
        y[k] = a * h / (mk[k] * (mk[k] + h));
    }
    for (int k = 0; k + 1 < n; ++k)
        step[k] = dir > 0 ? -twoAh2 / (mk[k] * (mk[k] + h) * (mk[k] + 2.0 * h))
                          : twoAh2 / ((mk[k] - h) * mk[k] * (mk[k] + h));
}

// The strided walk up from the peak (the peak's term included), terms relative to T_peak = 1,
// stopping where the unit walk's rule would (a term below 1e-12 of the sum, which is h times the
// strided sum). e^{y_k} follows k by the factors e^{y_{k+1} − y_k} (expSmall) where those are
// small, which they are from the block's first on since they shrink as m grows; a fresh exp
// starts each block. Returns the strided sum (without the factor h).
double sumUpStrided(double peak, double g, double a, int h) {
    const double invG = 1.0 / g, stop = kSeriesTolerance * h, last = peak + termCap(peak);
    double sum = 0.0, m = peak, t = 1.0;
    const auto count = [&](double mEnd, double s) {
        tTermsSummed += static_cast<std::uint64_t>((mEnd - peak) / h + 1.0);
        return s;
    };
    for (;;) {
        double ratio[kStrideBlock], y[kStrideBlock], step[kStrideBlock];
        strideBlock(m, +1, kStrideBlock, h, invG, a, ratio, y, step);
        const bool small = -step[0] <= kSmallStep;
        double e = std::exp(y[0]);
        for (int k = 0; k < kStrideBlock; ++k) {
            sum += t;
            if (m + k * h > g && t < stop * sum) return count(m + k * h, sum);
            t *= ratio[k] * e;
            if (k + 1 < kStrideBlock) e = small ? e * expSmall(step[k]) : std::exp(y[k + 1]);
        }
        m += kStrideBlock * h;
        if (m >= last) return count(m - h, sum);  // the cost bound (termCap)
    }
}

// The strided walk down from the peak, adding to the up walk's `sum`: T_m = T_{m+h} / (ratio ·
// e^{y}) for m = peak − h, peak − 2h, … ≥ 1. The factors grow as m falls: expSmall only when the
// block's last (largest) step is small. Returns the new strided sum.
double addDownStrided(double peak, double g, double a, int h, double sum) {
    const double invG = 1.0 / g, stop = kSeriesTolerance * h;
    const double first = std::max(1.0, peak - termCap(peak));  // the cost bound (termCap)
    double m = peak - h, t = 1.0;
    const auto count = [&](double mEnd, double s) {
        tTermsSummed += static_cast<std::uint64_t>((peak - mEnd) / h);
        return s;
    };
    while (m >= first) {
        const int n =
            static_cast<int>(std::min<double>(kStrideBlock, std::floor((m - first) / h) + 1.0));
        double ratio[kStrideBlock], y[kStrideBlock] = {}, step[kStrideBlock];
        strideBlock(m, -1, n, h, invG, a, ratio, y, step);
        const bool small = n < 2 || step[n - 2] <= kSmallStep;
        double e = std::exp(-y[0]);
        for (int k = 0; k < n; ++k) {
            t *= e / ratio[k];
            sum += t;
            if (t < stop * sum) return count(m - k * h, sum);
            if (k + 1 < n) e = small ? e * expSmall(-step[k]) : std::exp(-y[k + 1]);
        }
        m -= n * h;
    }
    return count(m + h, sum);
}

}  // namespace

double HeTorrance::distributionD(double g, double vxy2, double tau, int maxStride) {
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
    // std::exp where the step is not small, and every kResync terms).
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
    for (int k = 0;
         k < 2 &&
         g * peak / ((peak + 1.0) * (peak + 1.0)) * std::exp(a / (peak * (peak + 1.0))) > 1.0;
         ++k)
        peak += 1.0;
    const double logPeak = logSeriesTerm(peak, g, lnG, a);
    // Below e^{−746} the peak term's exp is 0 in double, and so is D (the sum of terms relative to
    // the peak is finite): nothing to sum. This is where g is denormal or a huge (extreme grazing
    // directions), and where the walks' ratios would meet 1/g = ∞ or e^{a/m} = ∞.
    if (logPeak < -746.0) return 0.0;

    // The two walks from the peak (terms relative to T_peak = 1), in the order the stopping rule
    // sees them: up first, then down relative to the whole sum; every h-th term where the terms
    // spread wide enough (strideFor).
    const int h = strideFor(peak, g, a, lnG, logPeak, maxStride);
    const double sum = h == 1 ? addDownFromPeak(peak, g, a, sumUpFromPeak(peak, g, a))
                              : h * addDownStrided(peak, g, a, h, sumUpStrided(peak, g, a, h));
    return kPi * kPi * tau * tau / 4.0 * std::exp(logPeak) * sum;
}

std::uint64_t HeTorrance::termsSummed() { return tTermsSummed; }

double HeTorrance::shadowingS(double cosTheta, double sigma0, double tau) {
    return directionTerms(cosTheta, sigma0, tau).s;
}

HeTorrance::ViewTerms HeTorrance::viewTerms(const Vec3& wo) const {
    // Per band, or copied from the band before when its σ0 and τ are the same (as eval shares
    // D·S·G between such bands).
    ViewTerms view;
    if (table) return view;  // the table's eval needs none
    for (int b = 0; b < kBandCount; ++b)
        view.out[b] = b > 0 && sigma0[b] == sigma0[b - 1] && tau[b] == tau[b - 1]
                          ? view.out[b - 1]
                          : directionTerms(wo.z, sigma0[b], tau[b]);
    return view;
}

Spectrum HeTorrance::eval(const Vec3& wi, const Vec3& wo) const {
    if (table) return table->eval(wi, wo);
    if (!aboveHorizon(wi, wo)) return Spectrum(0.0);
    return eval(wi, wo, viewTerms(wo));
}

Spectrum HeTorrance::eval(const Vec3& wi, const Vec3& wo, const ViewTerms& view) const {
    if (table) return table->eval(wi, wo);
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
    double lastEta = -1.0, lastKappa = -1.0, fresnel = 0.0;
    for (int b = 0; b < kBandCount; ++b) {
        if (sigma0[b] != lastSigma0 || tau[b] != lastTau) {
            lastSigma0 = sigma0[b];
            lastTau = tau[b];
            const double s0 = sigma0[b], t = tau[b];
            const DirectionTerms in = directionTerms(cosI, s0, t), out = view.out[b];
            const double kSum = in.k + out.k;
            // z0 ≤ A = (σ0/4)·kSum/sqrt(π/2) (solveZ0). When A/σ0 < 1e-9, (z0/σ0)² < 1e-18 is
            // lost in 1 + (z0/σ0)² and σ = σ0 exactly, so the solve is skipped (the common case:
            // away from grazing, erfc makes K tiny).
            const double z0 = kSum / (4.0 * std::sqrt(kPi / 2.0)) < 1e-9 ? 0.0 : solveZ0(s0, kSum);
            const double sigma = s0 / std::sqrt(1.0 + (z0 / s0) * (z0 / s0));
            const double root = kWaveNumber * sigma * (cosI + cosO);
            const double d = distributionD(root * root, vxy2, t);
            dsg = d * in.s * out.s * geometry;
        }
        if (eta[b] != lastEta || kappa[b] != lastKappa) {  // F, shared by equal bands
            lastEta = eta[b];
            lastKappa = kappa[b];
            fresnel = fresnelExact(eta[b], kappa[b], c);
        }
        const double value = ks[b] * fresnel * dsg / (kPi * cosI * cosO);
        f[b] = std::isfinite(value) ? value : 0.0;
    }
    return f;
}

}  // namespace lobe
