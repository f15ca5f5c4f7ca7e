// Poulin–Fournier (docs/models.md model 6): values against an independent brute-force integration
// (Python and C++), the adaptive rule's accuracy, the fixed rule's error on a narrow lobe,
// reciprocity, finiteness and non-negativity at grazing, mirror and retro pairs, and the
// parameter table.
//
// Both brute-force references share no code with materials/poulin_fournier.cpp: they sample the
// whole period uniformly (midpoint rule; 3/4 of the points on the arc φ ∈ (−π, π), 1/4 on the floor
// y ∈ [0, D)), skip buried points, and decide lit/seen by casting the 2-D ray against every
// cylinder it can reach before rising above z = 1 (a quadratic per cylinder), instead of the
// model's closed-form intervals. Their error is O(h) at the shadow edges: ~1e-4 relative at 200k
// points, ~6e-5 at 1M (measured by comparing 200k, 1M and 4M points), hence the tolerances below.
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

// Direction with a given cos θ and azimuth (for grazing cases down to cos θ = 1e-7).
Vec3 directionCos(double cosTheta, double phiDeg) {
    const double s = std::sqrt(1.0 - cosTheta * cosTheta), p = phiDeg * kPi / 180.0;
    return Vec3(s * std::cos(p), s * std::sin(p), cosTheta);
}

PoulinFournier model(const std::vector<std::string>& settings = {}) {
    return std::get<PoulinFournier>(makeBrdf("poulin_fournier", settings));
}

// --- C++ brute force (see the file head) ---------------------------------------------------------
bool rayBlocked(double py, double pz, double uy, double uz, double period) {
    const double tMax = (1.0 - pz) / uz;
    const double yEnd = py + uy * tMax;
    const long k0 = long(std::floor((std::min(py, yEnd) - 1.0) / period));
    const long k1 = long(std::ceil((std::max(py, yEnd) + 1.0) / period));
    for (long k = k0; k <= k1; ++k) {
        const double dy = py - k * period, dz = pz;
        const double b = dy * uy + dz * uz;
        const double disc = b * b - (dy * dy + dz * dz - 1.0);
        if (disc > 0.0 && -b + std::sqrt(disc) > 1e-9) return true;
    }
    return false;
}

double bruteForce(const PoulinFournier& m, const Vec3& wi, const Vec3& wo, int samples,
                  int band = 0) {
    const double n = m.exponent[band], period = 2.0 + m.gap[band], depth = m.floorDepth[band];
    const double li = std::hypot(wi.y, wi.z), lo = std::hypot(wo.y, wo.z);
    const double uiy = wi.y / li, uiz = wi.z / li, uoy = wo.y / lo, uoz = wo.z / lo;
    const int arcSamples = samples / 4 * 3, floorSamples = samples - arcSamples;
    double sum = 0.0;
    for (int j = 0; j < arcSamples; ++j) {
        const double phi = -kPi + (j + 0.5) * 2.0 * kPi / arcSamples;
        const double s = std::sin(phi), c = std::cos(phi);
        if (c < -depth) continue;  // buried
        const double ni = s * wi.y + c * wi.z, no = s * wo.y + c * wo.z;
        if (ni <= 0.0 || no <= 0.0) continue;
        if (rayBlocked(s, c, uiy, uiz, period) || rayBlocked(s, c, uoy, uoz, period)) continue;
        sum += std::pow(std::max(0.0, 2.0 * ni * no - wi.dot(wo)), n) * ni * no * 2.0 * kPi /
               arcSamples;
    }
    for (int j = 0; j < floorSamples; ++j) {
        const double y = (j + 0.5) * period / floorSamples;
        const double d0 = y, d1 = y - period;
        if (d0 * d0 + depth * depth < 1.0 || d1 * d1 + depth * depth < 1.0) continue;  // buried
        if (rayBlocked(y, -depth, uiy, uiz, period) || rayBlocked(y, -depth, uoy, uoz, period))
            continue;
        const double cosAlpha = std::max(0.0, -wi.x * wo.x - wi.y * wo.y + wi.z * wo.z);
        sum += std::pow(cosAlpha, n) * wi.z * wo.z * period / floorSamples;
    }
    return m.ks[band] * sum / (period * wi.z * wo.z);
}

// --- (a) values from an independent Python script ---------------------------------------------
// python3 (standard library only), the brute force above typed again in Python, 1M points:
//
//   import math
//   def d3(th, ph):
//       th, ph = math.radians(th), math.radians(ph)
//       return (math.sin(th)*math.cos(ph), math.sin(th)*math.sin(ph), math.cos(th))
//   def blocked(py, pz, uy, uz, D):
//       tmax = (1.0 - pz) / uz                     # above z = 1 no cylinder can be hit
//       y1 = py + uy * tmax
//       for k in range(math.floor((min(py, y1) - 1) / D), math.ceil((max(py, y1) + 1) / D) + 1):
//           dy, dz = py - k * D, pz
//           b = dy * uy + dz * uz
//           disc = b * b - (dy * dy + dz * dz - 1.0)
//           if disc > 0 and -b + math.sqrt(disc) > 1e-9:
//               return True
//       return False
//   def pf(ks, n, gap, depth, wi, wo, M):
//       D = 2.0 + gap
//       Li, Lo = math.hypot(wi[1], wi[2]), math.hypot(wo[1], wo[2])
//       ui, uo = (wi[1]/Li, wi[2]/Li), (wo[1]/Lo, wo[2]/Lo)
//       dot = sum(a*b for a, b in zip(wi, wo))
//       Ma = 3 * M // 4; Mf = M - Ma; total = 0.0
//       for j in range(Ma):
//           phi = -math.pi + (j + 0.5) * 2 * math.pi / Ma
//           s, c = math.sin(phi), math.cos(phi)
//           if c < -depth: continue                # buried
//           ni, no = s*wi[1] + c*wi[2], s*wo[1] + c*wo[2]
//           if ni <= 0 or no <= 0: continue
//           if blocked(s, c, *ui, D) or blocked(s, c, *uo, D): continue
//           total += max(0.0, 2*ni*no - dot)**n * ni * no * (2*math.pi/Ma)
//       for j in range(Mf):
//           y = (j + 0.5) * D / Mf
//           if any((y - k*D)**2 + depth**2 < 1 for k in (0, 1)): continue   # buried
//           if blocked(y, -depth, *ui, D) or blocked(y, -depth, *uo, D): continue
//           total += max(0.0, -wi[0]*wo[0] - wi[1]*wo[1] + wi[2]*wo[2])**n * wi[2]*wo[2] * (D/Mf)
//       return ks * total / (D * wi[2] * wo[2])
//   cases = [((30, 90), (35, 265), 0.8, [100], 2.0, 4.0),
//            ((60, 45), (55, 230), 0.8, [100], 2.0, 4.0),
//            ((80, 100), (70, 280), 0.8, [20], 0.5, 0.5),
//            ((45, 70), (45, 250), 0.5, [20, 100, 400], 2.0, 4.0)]
//   for (ti, pi_), (to, po), ks, ns, gap, depth in cases:
//       wi, wo = d3(ti, pi_), d3(to, po)
//       vals = [pf(ks, n, gap, depth, wi, wo, 1000000) for n in ns]
//       print((ti, pi_), (to, po), ks, ns, gap, depth, [repr(v) for v in vals])
//
// Output:
//   (30, 90) (35, 265) 0.8 [100] 2.0 4.0 ['0.08649465487896293']
//   (60, 45) (55, 230) 0.8 [100] 2.0 4.0 ['0.0174867892831525']
//   (80, 100) (70, 280) 0.8 [20] 0.5 0.5 ['0.08387968286524726']
//   (45, 70) (45, 250) 0.5 [20, 100, 400] 2.0 4.0 ['0.13146461854874503', '0.11266309478309741',
//                                                  '0.1046939150354753']
TEST(PoulinFournier, MatchesIndependentPythonBruteForce) {
    struct Case {
        double ti, pi, to, po;
        std::vector<std::string> settings;
        Spectrum expected;
    };
    // clang-format off
    const std::vector<Case> cases = {
        {30, 90, 35, 265, {}, Spectrum(0.08649465487896293)},
        {60, 45, 55, 230, {}, Spectrum(0.0174867892831525)},
        {80, 100, 70, 280, {"exponent=20", "gap=0.5", "floor_depth=0.5"},
         Spectrum(0.08387968286524726)},
        {45, 70, 45, 250, {"ks=0.5", "exponent=20,100,400"},
         Spectrum(0.13146461854874503, 0.11266309478309741, 0.1046939150354753)},
    };
    // clang-format on
    for (const Case& c : cases) {
        const Spectrum f = model(c.settings).eval(direction(c.ti, c.pi), direction(c.to, c.po));
        for (int b = 0; b < kBandCount; ++b)
            EXPECT_NEAR(f[b], c.expected[b], 2e-4 * c.expected[b])
                << c.ti << "," << c.pi << " -> " << c.to << "," << c.po << " band " << b;
    }
}

// --- (c) adaptive Simpson against the C++ brute force ------------------------------------------
TEST(PoulinFournier, AdaptiveSimpsonMatchesBruteForceIncludingGrazing) {
    struct Case {
        Vec3 wi, wo;
        std::vector<std::string> settings;
    };
    const std::vector<Case> cases = {
        {direction(30, 80), direction(35, 265), {}},
        {direction(70, 100), direction(20, 300), {}},
        {direction(45, 10), direction(50, 200), {}},            // across the cylinders' axis
        {direction(85, 60), direction(84, 250), {}},            // grazing
        {directionCos(0.02, 95), directionCos(0.05, 272), {}},  // grazing: far occluders
        {directionCos(0.03, 80), direction(40, 250), {"gap=0.5"}},
        {direction(75, 85), direction(70, 260), {"floor_depth=0.3"}},        // buried cylinders
        {direction(60, 100), direction(65, 275), {"gap=0", "exponent=20"}},  // touching
    };
    for (const Case& c : cases) {
        const PoulinFournier m = model(c.settings);
        const double f = m.eval(c.wi, c.wo)[0];
        const double reference = bruteForce(m, c.wi, c.wo, 400000);
        ASSERT_GT(reference, 1e-4);
        EXPECT_NEAR(f, reference, 3e-4 * reference) << c.wi << " " << c.wo;
    }
}

// The adaptive rule's own accuracy: started from 64 sub-intervals it must agree to 1e-6 with the
// fixed rule on 4096 sub-intervals (h⁴ smaller by 2²⁴, so effectively exact), over many pairs.
TEST(PoulinFournier, AdaptiveRuleIsAccurateToOnePartInAMillion) {
    const PoulinFournier m = model();
    Rng rng(11, 3);
    double worst = 0.0;
    for (int i = 0; i < 300; ++i) {
        const Vec3 wi = directionCos(0.02 + 0.98 * rng.uniform(), 360.0 * rng.uniform());
        const Vec3 r = mirrorLocal(wi);
        const Vec3 wo =
            directionCos(std::max(0.02, r.z + 0.2 * (rng.uniform() - 0.5)),
                         std::atan2(r.y, r.x) * 180.0 / kPi + 20.0 * (rng.uniform() - 0.5));
        const double a = m.eval(wi, wo)[0], exact = m.evalFixedRule(wi, wo, 4096)[0];
        if (exact > 1e-6) worst = std::max(worst, std::abs(a - exact) / exact);
    }
    EXPECT_LT(worst, 1e-6);
}

// The fixed 64-interval rule vs the adaptive one. With the interval ends exact, the integrand
// is smooth on the interval and at exponent 100 the two agree to ~2e-6 (measured; the doc's "off
// by up to 0.5 %" is not reproduced). The difference shows on a narrow lobe: at exponent 1e4 the
// lobe is ~0.005 rad wide against a node spacing of ~0.02 rad, and the fixed rule is off by
// percents while the adaptive rule still matches the brute force.
TEST(PoulinFournier, FixedRuleMissesANarrowLobeAdaptiveDoesNot) {
    const PoulinFournier m = model({"exponent=10000"});
    double worstFixed = 0.0;
    for (const auto& [wi, wo] : {std::pair{direction(30, 80), direction(30, 260)},
                                 std::pair{direction(50, 100), direction(50.5, 280)},
                                 std::pair{direction(45, 95), direction(45.3, 275)}}) {
        const double reference = bruteForce(m, wi, wo, 400000);
        ASSERT_GT(reference, 1e-3);
        EXPECT_NEAR(m.eval(wi, wo)[0], reference, 2e-4 * reference);
        worstFixed =
            std::max(worstFixed, std::abs(m.evalFixedRule(wi, wo)[0] - reference) / reference);
    }
    EXPECT_GT(worstFixed, 1e-2);
}

// --- (d) invariants -----------------------------------------------------------------------------
// The definition is symmetric in wi and wo (docs/models.md model 6), and so is the evaluation
// (same nodes, products in commutative order), up to the order of the floor's breakpoints.
TEST(PoulinFournier, ReciprocalForRandomPairs) {
    for (const auto& settings : std::vector<std::vector<std::string>>{
             {}, {"gap=0.5", "floor_depth=0.5"}, {"exponent=20", "gap=0"}, {"floor_depth=0"}}) {
        const PoulinFournier m = model(settings);
        Rng rng(5, 9);
        for (int i = 0; i < 400; ++i) {
            const Vec3 wi = directionCos(rng.uniform(), 360.0 * rng.uniform());
            Vec3 wo = directionCos(rng.uniform(), 360.0 * rng.uniform());
            if (i % 2) {  // near-mirror: where the value is large
                const Vec3 r = mirrorLocal(wi);
                wo =
                    directionCos(std::max(1e-3, r.z + 0.1 * (rng.uniform() - 0.5)),
                                 std::atan2(r.y, r.x) * 180.0 / kPi + 10.0 * (rng.uniform() - 0.5));
            }
            const double a = m.eval(wi, wo)[0], b = m.eval(wo, wi)[0];
            EXPECT_NEAR(a, b, 1e-9 * std::max(a, b)) << wi << " " << wo;
        }
    }
}

TEST(PoulinFournier, FiniteAndNonNegativeAtGrazingMirrorAndRetroPairs) {
    for (const auto& settings :
         std::vector<std::vector<std::string>>{{},
                                               {"gap=0", "floor_depth=0"},
                                               {"gap=100", "floor_depth=100"},
                                               {"exponent=0"},
                                               {"exponent=100000"},
                                               {"floor_depth=1"}}) {
        const PoulinFournier m = model(settings);
        std::vector<std::pair<Vec3, Vec3>> pairs;
        for (const double ci : {1e-7, 1e-4, 0.3, 1.0})
            for (const double co : {1e-7, 1e-3, 0.7})
                for (const double phi : {0.0, 37.0, 90.0, 180.0, 270.0}) {
                    const Vec3 wi = directionCos(ci, phi);
                    pairs.push_back({wi, directionCos(co, phi + 180.0)});  // mirror azimuth
                    pairs.push_back({wi, directionCos(co, phi)});          // retro azimuth
                    pairs.push_back({wi, directionCos(co, phi + 77.0)});
                    pairs.push_back({wi, wi});
                    pairs.push_back({wi, mirrorLocal(wi)});
                }
        for (const auto& [wi, wo] : pairs) {
            const Spectrum f = m.eval(wi, wo);
            for (int b = 0; b < kBandCount; ++b) {
                ASSERT_TRUE(std::isfinite(f[b])) << wi << " " << wo;
                ASSERT_GE(f[b], 0.0) << wi << " " << wo;
            }
        }
        EXPECT_EQ(m.eval(directionCos(0.5, 0), directionCos(-0.5, 0))[0], 0.0);
        EXPECT_EQ(m.eval(directionCos(0.0, 90), directionCos(0.5, 270))[0], 0.0);
    }
}

// Bands with different geometry are integrated separately: each band equals the single-valued
// model with that band's parameters.
TEST(PoulinFournier, PerBandGeometry) {
    const PoulinFournier m = model({"gap=0.5,2,8", "floor_depth=0.2,4,1", "ks=0.3,0.8,1"});
    const Vec3 wi = direction(60, 95), wo = direction(55, 265);
    const Spectrum f = m.eval(wi, wo);
    EXPECT_DOUBLE_EQ(f[0], model({"gap=0.5", "floor_depth=0.2", "ks=0.3"}).eval(wi, wo)[0]);
    EXPECT_DOUBLE_EQ(f[1], model({"gap=2", "floor_depth=4", "ks=0.8"}).eval(wi, wo)[0]);
    EXPECT_DOUBLE_EQ(f[2], model({"gap=8", "floor_depth=1", "ks=1"}).eval(wi, wo)[0]);
    EXPECT_NE(f[0], f[2]);
}

// A flat surface is the limit of a deep floor far from the cylinders seen straight down: at wi = wo
// = n every floor point is lit and seen except under the cylinders, the arc contributes
// ∫ cos^n(2φ)·cos²φ dφ, so f = ks·[gap + ∫_{−π/2}^{π/2} cos^n(2φ) cos²φ dφ]/D. At exponent 0:
// f = ks·(gap + π/2)/(2 + gap) = 0.8·(2 + π/2)/4 = 0.714159265… — derived by hand.
TEST(PoulinFournier, NormalIncidenceHandValue) {
    const Vec3 n(0, 0, 1);
    EXPECT_NEAR(model({"exponent=0"}).eval(n, n)[0], 0.8 * (2.0 + kPi / 2.0) / 4.0, 1e-9);
}

TEST(PoulinFournier, ParameterTable) {
    const PoulinFournier m = model();
    EXPECT_EQ(m.ks[0], 0.8);
    EXPECT_EQ(m.exponent[0], 100.0);
    EXPECT_EQ(m.gap[0], 2.0);
    EXPECT_EQ(m.floorDepth[0], 4.0);
    // `intervals` changed nothing in a render (only the fixed rule read it): no longer settable.
    EXPECT_THROW(model({"intervals=64"}), Error);
    EXPECT_THROW(model({"gap=-1"}), Error);
    EXPECT_THROW(model({"floor_depth=-0.1"}), Error);
}

}  // namespace
}  // namespace lobe
