// The total flux overlap metric (docs/flux-overlap.md) on small hand-made lattices that
// exercise every branch: A only, B only, both with Φa > Φb and Φb > Φa, both equal, below the
// threshold, and an empty area.
#include "analysis/flux_overlap.h"
#include "core/error.h"

#include <gtest/gtest.h>

#include <vector>

namespace lobe {
namespace {

// One pixel per branch, threshold t = 0.1:
//   px  a     b     branch                c     d
//   0   0.5   0     A only               0.5   0
//   1   0     0.4   B only               0     0.4
//   2   0.8   0.2   both, a > b          0.6   0
//   3   0.3   0.6   both, b > a          0     0.3
//   4   0.05  0.05  both below t         0     0
//   5   0     0     empty                0     0
//   6   0.7   0.7   both, equal          0     0
// areaA = #{a > t} = {0,2,3,6} = 4, areaB = {1,2,3,6} = 4
// OA = 0.5 + 0.6 = 1.1, OB = 0.4 + 0.3 = 0.7
// e_sum = min(1.1/4, 0.7/4) = 0.175
// Σc² = 0.25 + 0.36 = 0.61, Σd² = 0.16 + 0.09 = 0.25, mn = 7
// e_mse = min(0.61/16/7, 0.25/16/7) = 0.25/112
const std::vector<float> kA = {0.5f, 0.0f, 0.8f, 0.3f, 0.05f, 0.0f, 0.7f};
const std::vector<float> kB = {0.0f, 0.4f, 0.2f, 0.6f, 0.05f, 0.0f, 0.7f};

TEST(FluxOverlap, EveryBranchOnAHandMadeLattice) {
    const FluxOverlap r = fluxOverlap(kA.data(), kB.data(), kA.size(), 0.1);
    EXPECT_EQ(r.areaA, 4);
    EXPECT_EQ(r.areaB, 4);
    EXPECT_NEAR(r.OA, 1.1, 1e-6);
    EXPECT_NEAR(r.OB, 0.7, 1e-6);
    EXPECT_NEAR(r.eSum, 0.175, 1e-6);
    EXPECT_NEAR(r.eMse, 0.25 / 112.0, 1e-8);
    EXPECT_DOUBLE_EQ(r.value(OverlapVariant::Sum), r.eSum);
    EXPECT_DOUBLE_EQ(r.value(OverlapVariant::Mse), r.eMse);
}

TEST(FluxOverlap, PerPixelContributionsFollowEquations124And125) {
    const double t = 0.1;
    const double expectedC[] = {0.5, 0.0, 0.6, 0.0, 0.0, 0.0, 0.0};
    const double expectedD[] = {0.0, 0.4, 0.0, 0.3, 0.0, 0.0, 0.0};
    for (size_t i = 0; i < kA.size(); ++i) {
        const OverlapContribution cd = overlapContribution(kA[i], kB[i], t);
        EXPECT_NEAR(cd.c, expectedC[i], 1e-6) << "pixel " << i;
        EXPECT_NEAR(cd.d, expectedD[i], 1e-6) << "pixel " << i;
        EXPECT_TRUE(cd.c == 0.0 || cd.d == 0.0) << "at most one of c, d per pixel";
    }
}

TEST(FluxOverlap, CommutativeUpToSwappingAAndB) {
    const FluxOverlap ab = fluxOverlap(kA.data(), kB.data(), kA.size(), 0.1);
    const FluxOverlap ba = fluxOverlap(kB.data(), kA.data(), kA.size(), 0.1);
    EXPECT_DOUBLE_EQ(ab.eSum, ba.eSum);
    EXPECT_DOUBLE_EQ(ab.eMse, ba.eMse);
    EXPECT_DOUBLE_EQ(ab.OA, ba.OB);
    EXPECT_EQ(ab.areaA, ba.areaB);
}

TEST(FluxOverlap, EmptyAreaGivesZero) {
    const std::vector<float> zeros(kA.size(), 0.0f);
    const FluxOverlap r = fluxOverlap(kA.data(), zeros.data(), kA.size(), 0.1);
    EXPECT_EQ(r.areaB, 0);
    EXPECT_NEAR(r.OA, 0.5 + 0.8 + 0.3 + 0.7, 1e-6);  // all of A's lobe is uncovered ...
    EXPECT_EQ(r.eSum, 0.0);                          // ... but there is no B to compare with
    EXPECT_EQ(r.eMse, 0.0);
}

TEST(FluxOverlap, BelowThresholdIsNoLobe) {
    // Every value ≤ t: both areas empty. A value equal to t is not above it.
    const std::vector<float> a = {0.1f, 0.05f}, b = {0.0f, 0.1f};
    const FluxOverlap r = fluxOverlap(a.data(), b.data(), a.size(), double(0.1f));
    EXPECT_EQ(r.areaA, 0);
    EXPECT_EQ(r.areaB, 0);
    EXPECT_EQ(r.OA + r.OB, 0.0);
    EXPECT_EQ(r.eSum, 0.0);
}

TEST(FluxOverlap, IdenticalLatticesOverlapCompletely) {
    const FluxOverlap r = fluxOverlap(kA.data(), kA.data(), kA.size(), 0.1);
    EXPECT_EQ(r.eSum, 0.0);
    EXPECT_EQ(r.eMse, 0.0);
}

TEST(FluxOverlap, DisjointLobesScoreTheirMeanFlux) {
    // A: one pixel of 1, B: one pixel of 2, apart. OA/areaA = 1, OB/areaB = 2 → e_sum = 1.
    // mse: min(1²/1/4, 2²/1/4) = 0.25 (mn = 4).
    const std::vector<float> a = {1.0f, 0.0f, 0.0f, 0.0f}, b = {0.0f, 0.0f, 2.0f, 0.0f};
    const FluxOverlap r = fluxOverlap(a.data(), b.data(), a.size());
    EXPECT_DOUBLE_EQ(r.eSum, 1.0);
    EXPECT_DOUBLE_EQ(r.eMse, 0.25);
}

TEST(FluxOverlap, ContainedLobeScoresZero) {
    // B lies inside A and is dimmer everywhere: OB = 0, so e = min(…, 0) = 0 (Figure 4A: a lobe
    // that never rises above the other is invisible).
    const std::vector<float> a = {1.0f, 1.0f, 1.0f}, b = {0.5f, 0.0f, 0.9f};
    const FluxOverlap r = fluxOverlap(a.data(), b.data(), a.size());
    EXPECT_GT(r.OA, 0.0);
    EXPECT_EQ(r.OB, 0.0);
    EXPECT_EQ(r.eSum, 0.0);
}

TEST(FluxOverlap, VariantNames) {
    EXPECT_EQ(parseOverlapVariant("sum"), OverlapVariant::Sum);
    EXPECT_EQ(parseOverlapVariant("mse"), OverlapVariant::Mse);
    EXPECT_THROW(parseOverlapVariant("rms"), Error);
    EXPECT_STREQ(overlapVariantName(OverlapVariant::Mse), "mse");
}

}  // namespace
}  // namespace lobe
