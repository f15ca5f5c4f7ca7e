// He–Torrance (docs/models.md model 7): values against an independent Python implementation, the
// D series' early stop against a sum with many more terms (small and large g), the Newton z0
// against its equation, S against a hand value, reciprocity, finiteness and non-negativity at
// grazing, mirror and retro pairs and at the ends of the parameter ranges.
#include "core/error.h"
#include "core/rng.h"
#include "materials/registry.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

namespace lobe {
namespace {

Vec3 direction(double thetaDeg, double phiDeg) {
    const double t = thetaDeg * kPi / 180.0, p = phiDeg * kPi / 180.0;
    return Vec3(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t));
}

Vec3 directionCos(double cosTheta, double phiDeg) {
    const double s = std::sqrt(1.0 - cosTheta * cosTheta), p = phiDeg * kPi / 180.0;
    return Vec3(s * std::cos(p), s * std::sin(p), cosTheta);
}

HeTorrance model(const std::vector<std::string>& settings = {}) {
    return std::get<HeTorrance>(makeBrdf("he_torrance", settings));
}

// --- (a) values from an independent Python script ---------------------------------------------
// python3 (standard library only). It shares no code or method with he_torrance.cpp where the
// C++ has a choice: z0 by bisection instead of Newton, D as the plain series m = 1..M summed with
// math.fsum far past the peak (no early stop, lnΓ per term instead of a recurrence), Fresnel with
// cmath.
//
//   import math, cmath
//   def d3(th, ph):
//       th, ph = math.radians(th), math.radians(ph)
//       return (math.sin(th)*math.cos(ph), math.sin(th)*math.sin(ph), math.cos(th))
//   def fresnel(eta, kappa, c):
//       n = complex(eta, kappa); g = cmath.sqrt(n*n + c*c - 1)
//       return 0.5 * abs(g-c)**2/abs(g+c)**2 * (1 + abs(c*(g+c)-1)**2/abs(c*(g-c)+1)**2)
//   def K(ct, s0, tau):
//       t = math.sqrt(1 - ct*ct) / ct
//       return 0.0 if t == 0 else t * math.erfc(tau / (2*s0*t))
//   def S1(ct, s0, tau):
//       st = math.sqrt(1 - ct*ct)
//       if st == 0: return 1.0
//       c = tau * ct / (2*s0*st)
//       lam = 0.5 * (math.exp(-c*c)/(math.sqrt(math.pi)*c) - math.erfc(c))
//       return (1 - 0.5*math.erfc(c)) / (lam + 1)
//   def ht(ks, s0, tau, eta, kappa, wi, wo):
//       k = 2*math.pi
//       H = [a+b for a, b in zip(wi, wo)]; Hn = math.sqrt(sum(x*x for x in H))
//       h = [x/Hn for x in H]
//       A = s0/4 * (K(wi[2], s0, tau) + K(wo[2], s0, tau))
//       lo, hi = 0.0, max(A, 1e-300) / math.sqrt(math.pi/2)  # sqrt(pi/2) z = A exp(-z^2/2s0^2)
//       for _ in range(200):
//           mid = 0.5*(lo+hi)
//           if math.sqrt(math.pi/2)*mid - A*math.exp(-mid*mid/(2*s0*s0)) > 0: hi = mid
//           else: lo = mid
//       z0 = 0.5*(lo+hi)
//       sigma = s0 / math.sqrt(1 + z0*z0/(s0*s0))
//       g = (k*sigma*(wi[2]+wo[2]))**2
//       vxy2 = k*k*(H[0]**2 + H[1]**2)
//       M = int(g + 60*math.sqrt(g) + 3*math.sqrt(vxy2*tau*tau/4) + 500)
//       D = math.pi**2*tau**2/4 * math.fsum(
//           math.exp(m*math.log(g) - g - math.lgamma(m+1) - math.log(m) - vxy2*tau*tau/(4*m))
//           for m in range(1, M+1))
//       G = (Hn*Hn / H[2])**2
//       S = S1(wi[2], s0, tau) * S1(wo[2], s0, tau)
//       F = fresnel(eta, kappa, sum(a*b for a, b in zip(wi, h)))
//       return ks * F * S * G * D / (math.pi * wi[2] * wo[2])
//   cases = [((30, 10), (35, 185), {}),
//            ((60, -40), (50, 150), {}),
//            ((30, 0), (30, 178), {}),
//            ((85, 0), (84, 181), {}),
//            ((45, 20), (40, 205), {'sigma0': 0.2}),
//            ((45, 20), (40, 190), {'sigma0': 3.0, 'tau': 30.0}),
//            ((20, 0), (25, 170), {'eta': (0.16, 0.37, 1.59), 'kappa': (3.9, 2.8, 1.9)})]
//   for (ti, pi_), (to, po), p in cases:
//       wi, wo = d3(ti, pi_), d3(to, po)
//       etas = p.get('eta', (1.6,)*3); kappas = p.get('kappa', (0.2,)*3)
//       vals = [ht(0.8, p.get('sigma0', 1.0), p.get('tau', 10.0), etas[b], kappas[b], wi, wo)
//               for b in range(3)]
//       print((ti, pi_), (to, po), p, [repr(v) for v in vals])
//
// Output (bands equal unless eta/kappa differ):
//   (30, 10) (35, 185) {} ['0.1305645380548555', ...]
//   (60, -40) (50, 150) {} ['0.26552094252839037', ...]
//   (30, 0) (30, 178) {} ['0.12948532944466665', ...]
//   (85, 0) (84, 181) {} ['17.899944272887975', ...]
//   (45, 20) (40, 205) {'sigma0': 0.2} ['0.47340588715132637', ...]
//   (45, 20) (40, 190) {'sigma0': 3.0, 'tau': 30.0} ['0.16435573644494378', ...]
//   (20, 0) (25, 170) {'eta': (0.16, 0.37, 1.59), 'kappa': (3.9, 2.8, 1.9)}
//       ['1.6796638480134158', '1.4808784469430551', '0.6708581013974428']
TEST(HeTorrance, MatchesIndependentPythonValues) {
    struct Case {
        double ti, pi, to, po;
        std::vector<std::string> settings;
        Spectrum expected;
    };
    // clang-format off
    const std::vector<Case> cases = {
        {30, 10, 35, 185, {}, Spectrum(0.1305645380548555)},
        {60, -40, 50, 150, {}, Spectrum(0.26552094252839037)},
        {30, 0, 30, 178, {}, Spectrum(0.12948532944466665)},
        {85, 0, 84, 181, {}, Spectrum(17.899944272887975)},
        {45, 20, 40, 205, {"sigma0_over_lambda=0.2"}, Spectrum(0.47340588715132637)},
        {45, 20, 40, 190, {"sigma0_over_lambda=3", "tau_over_lambda=30"},
         Spectrum(0.16435573644494378)},
        {20, 0, 25, 170, {"eta=0.16,0.37,1.59", "kappa=3.9,2.8,1.9"},
         Spectrum(1.6796638480134158, 1.4808784469430551, 0.6708581013974428)},
    };
    // clang-format on
    for (const Case& c : cases) {
        const Spectrum f = model(c.settings).eval(direction(c.ti, c.pi), direction(c.to, c.po));
        for (int b = 0; b < kBandCount; ++b)
            EXPECT_NEAR(f[b], c.expected[b], 1e-9 * c.expected[b])
                << c.ti << "," << c.pi << " -> " << c.to << "," << c.po << " band " << b;
    }
}

// --- (b) the D series: early stop vs many more terms -------------------------------------------
// Reference: Σ_{m=1}^{M} with M = g + 60√g + 3√a + 2000 (the Poisson weight g^m e^{−g}/m! is below
// e^{−1800} there), each term from lnΓ directly, summed with Kahan compensation.
double manyTermD(double g, double vxy2, double tau) {
    const double a = vxy2 * tau * tau / 4.0;
    const long terms = long(g + 60.0 * std::sqrt(g) + 3.0 * std::sqrt(a) + 2000.0);
    double sum = 0.0, carry = 0.0;
    for (long m = 1; m <= terms; ++m) {
        const double x =
            std::exp(m * std::log(g) - g - std::lgamma(m + 1.0) - std::log(double(m)) - a / m) -
            carry;
        const double t = sum + x;
        carry = (t - sum) - x;
        sum = t;
    }
    return kPi * kPi * tau * tau / 4.0 * sum;
}

TEST(HeTorrance, SeriesStopsOnlyWhenTheRestIsNegligible) {
    for (const double g : {1e-12, 1e-3, 0.3, 2.0, 20.0, 158.0, 1500.0, 20000.0})
        for (const double a : {0.0, 3.0, 400.0, 3948.0}) {  // a = vxy2 τ²/4; 3948 = k²·4·10²/4
            const double tau = 10.0, vxy2 = 4.0 * a / (tau * tau);
            const double reference = manyTermD(g, vxy2, tau);
            const double d = HeTorrance::distributionD(g, vxy2, tau);
            if (reference == 0.0) {
                EXPECT_EQ(d, 0.0);
            } else {
                EXPECT_NEAR(d, reference, 1e-10 * reference) << "g " << g << " a " << a;
            }
        }
}

// --- z0, S, K --------------------------------------------------------------------------------
TEST(HeTorrance, NewtonZ0SolvesItsEquation) {
    for (const double sigma0 : {0.01, 1.0, 100.0})
        for (const double kSum : {0.0, 1e-6, 0.3, 5.0, 2e7}) {
            const double z0 = HeTorrance::solveZ0(sigma0, kSum);
            const double lhs = std::sqrt(kPi / 2.0) * z0;
            const double rhs = sigma0 / 4.0 * kSum * std::exp(-z0 * z0 / (2.0 * sigma0 * sigma0));
            EXPECT_GE(z0, 0.0);
            EXPECT_NEAR(lhs, rhs, 1e-12 * std::max(lhs, 1e-300)) << sigma0 << " " << kSum;
        }
    EXPECT_EQ(HeTorrance::effectiveRoughnessK(1.0, 1.0, 10.0), 0.0);  // K(0) = 0
}

// S at c = τ cot θ/(2σ0) = 1 (τ = 10, σ0 = 1: cot θ = 0.2, cos θ = 0.2/√1.04 =
// 0.19611613513818402):
// erfc(1) = 0.15729920705028513, Λ(1) = ½[e^{−1}/√π − erfc(1)] = ½[0.20755374871029736 −
// 0.15729920705028513] = 0.025127270830006126, S = (1 − 0.078649603525142565)/1.025127270830006126
// = 0.8987668387056715.
TEST(HeTorrance, ShadowingHandValueAndLimits) {
    EXPECT_NEAR(HeTorrance::shadowingS(0.19611613513818402, 1.0, 10.0), 0.8987668387056715, 1e-13);
    EXPECT_EQ(HeTorrance::shadowingS(1.0, 1.0, 10.0), 1.0);  // S(0) = 1
    EXPECT_LT(HeTorrance::shadowingS(1e-7, 1.0, 10.0), 1e-5);
    double previous = 0.0;
    for (double c = 1e-7; c <= 1.0; c *= 1.5) {  // S grows as θ decreases
        const double s = HeTorrance::shadowingS(c, 1.0, 10.0);
        EXPECT_GE(s, previous);
        EXPECT_LE(s, 1.0);
        previous = s;
    }
}

// --- (d) invariants ----------------------------------------------------------------------------
// Reciprocal by construction (docs/models.md model 7): K(θi) + K(θo), g ∝ (cos θi + cos θo)², D
// and G of H = wi + wo, S(θi)S(θo), F(wi·h) with wi·h = wo·h.
TEST(HeTorrance, ReciprocalForRandomPairs) {
    for (const auto& settings : std::vector<std::vector<std::string>>{
             {}, {"sigma0_over_lambda=0.2"}, {"sigma0_over_lambda=3", "tau_over_lambda=2"}}) {
        const HeTorrance m = model(settings);
        Rng rng(21, 4);
        for (int i = 0; i < 2000; ++i) {
            const Vec3 wi = directionCos(rng.uniform(), 360.0 * rng.uniform());
            const Vec3 wo = directionCos(rng.uniform(), 360.0 * rng.uniform());
            const double a = m.eval(wi, wo)[0], b = m.eval(wo, wi)[0];
            EXPECT_NEAR(a, b, 1e-9 * std::max(a, b)) << wi << " " << wo;
        }
    }
}

TEST(HeTorrance, FiniteAndNonNegativeAtGrazingMirrorAndRetroPairs) {
    for (const auto& settings :
         std::vector<std::vector<std::string>>{{},
                                               {"sigma0_over_lambda=0.01", "tau_over_lambda=1000"},
                                               {"sigma0_over_lambda=0.01", "tau_over_lambda=0.01"},
                                               {"sigma0_over_lambda=100", "tau_over_lambda=0.01"},
                                               {"sigma0_over_lambda=100", "tau_over_lambda=1000"},
                                               {"eta=0.01", "kappa=20"}}) {
        const HeTorrance m = model(settings);
        for (const double ci : {1e-7, 1e-4, 0.3, 1.0})
            for (const double co : {1e-7, 1e-3, 0.7, 1.0})
                for (const double phi : {0.0, 90.0, 211.0}) {
                    const Vec3 wi = directionCos(ci, phi);
                    for (const Vec3& wo : {directionCos(co, phi + 180.0), directionCos(co, phi),
                                           directionCos(co, phi + 77.0), wi, mirrorLocal(wi)}) {
                        const Spectrum f = m.eval(wi, wo);
                        for (int b = 0; b < kBandCount; ++b) {
                            ASSERT_TRUE(std::isfinite(f[b])) << wi << " " << wo;
                            ASSERT_GE(f[b], 0.0) << wi << " " << wo;
                        }
                    }
                }
        EXPECT_EQ(m.eval(directionCos(0.5, 0), directionCos(-0.5, 180))[0], 0.0);
        EXPECT_EQ(m.eval(directionCos(0.0, 0), directionCos(0.5, 180))[0], 0.0);
    }
}

TEST(HeTorrance, ParameterTable) {
    const HeTorrance m = model();
    EXPECT_EQ(m.ks[0], 0.8);
    EXPECT_EQ(m.sigma0[0], 1.0);
    EXPECT_EQ(m.tau[0], 10.0);
    EXPECT_EQ(m.eta[0], 1.6);
    EXPECT_EQ(m.kappa[0], 0.2);
    EXPECT_THROW(model({"sigma0_over_lambda=0"}), Error);
    EXPECT_THROW(model({"tau_over_lambda=-1"}), Error);
    EXPECT_THROW(model({"kappa=-0.2"}), Error);
}

}  // namespace
}  // namespace lobe
