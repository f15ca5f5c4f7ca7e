// The flux-overlap standard test: a hand-computed pixel, determinism over thread counts, the
// ranking with ties, Kendall's tau, input validation, and the report files.
#include "analysis/overlap_ranking.h"
#include "analysis/overlap_report.h"
#include "core/error.h"
#include "materials/registry.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace lobe {
namespace {

namespace fs = std::filesystem;

StandardTestOptions smallOptions() {
    StandardTestOptions o;
    o.size = 16;
    o.samplesPerPixel = 4;
    return o;
}

TEST(StandardTest, CentrePixelOfTheSphereUnderLambertMatchesHandComputation) {
    // Lambert (kd = 0.2, f = kd/π) on the sphere, centre pixel of an odd lattice: the point seen
    // is p ≈ (0,0,1) with n ≈ (0,0,1). Per light, I/d² · cos θi with toLight = L − p:
    //   (−3,3,3): toLight (−3,3,2),  d² = 22,    cos θi = 2/√22    → 2/22^1.5
    //   (3,2,3):  toLight (3,2,2),   d² = 17,    cos θi = 2/√17    → 2/17^1.5
    //   (0,−3,2.5): toLight (0,−3,1.5), d² = 11.25, cos θi = 1.5/√11.25 → 1.5/11.25^1.5
    // flux = 0.2/π · (0.019382 + 0.028534 + 0.039752) = 0.0055811.
    // The pixel spans ±0.017 on the sphere; the flux varies linearly across it to first order,
    // which the 4×4 jittered mean cancels up to the jitter noise, hence 0.5 %.
    StandardTestOptions o;
    o.size = 63;
    o.samplesPerPixel = 16;
    o.models = {"lambert", "phong"};
    const LatticeSet set = renderStandardLattices(o);
    const double expected =
        0.2 / kPi *
        (2.0 / std::pow(22.0, 1.5) + 2.0 / std::pow(17.0, 1.5) + 1.5 / std::pow(11.25, 1.5));
    const size_t centre = size_t(31) * 63 + 31;
    for (int band = 0; band < 3; ++band)
        EXPECT_NEAR(set.lattice(0, 0, band)[centre], expected, 0.005 * expected);
    // Corner pixels miss every primitive: 0.
    for (int p = 0; p < kStandardPrimitiveCount; ++p) EXPECT_EQ(set.lattice(1, p, 0)[0], 0.0f);
}

TEST(StandardTest, LatticesAreFiniteNonNegativeAndIndependentOfThreadCount) {
    StandardTestOptions o = smallOptions();
    o.threads = 1;
    const LatticeSet one = renderStandardLattices(o);
    o.threads = 2;
    const LatticeSet two = renderStandardLattices(o);
    EXPECT_EQ(one.models, specularModelNames());
    ASSERT_EQ(one.data.size(), two.data.size());
    EXPECT_TRUE(one.data == two.data);
    double total = 0.0;
    for (float v : one.data) {
        ASSERT_TRUE(std::isfinite(v));
        ASSERT_GE(v, 0.0f);
        total += v;
    }
    EXPECT_GT(total, 0.0);
    const auto p1 = scoreAllPairs(one, kFluxThreshold, OverlapVariant::Sum, 1);
    const auto p2 = scoreAllPairs(two, kFluxThreshold, OverlapVariant::Sum, 2);
    const size_t n = one.models.size();
    ASSERT_EQ(p1.size(), n * (n - 1) / 2);
    for (size_t i = 0; i < p1.size(); ++i) {
        EXPECT_EQ(p1[i].modelA, p2[i].modelA);
        EXPECT_EQ(p1[i].score, p2[i].score);
        EXPECT_GE(p1[i].score, 0.0);
        if (i > 0) {
            EXPECT_LE(p1[i].score, p1[i - 1].score);  // descending
        }
        // The score is the mean of the per-primitive scores (each a mean over bands).
        EXPECT_NEAR(p1[i].score,
                    (p1[i].perPrimitive[0] + p1[i].perPrimitive[1] + p1[i].perPrimitive[2]) / 3.0,
                    1e-12 + 1e-9 * p1[i].score);
    }
}

TEST(StandardTest, ParameterOverridesChangeOnlyTheirModel) {
    StandardTestOptions o = smallOptions();
    o.models = {"phong", "ward"};
    const LatticeSet base = renderStandardLattices(o);
    o.settings["phong"] = {"exponent=50"};
    const LatticeSet changed = renderStandardLattices(o);
    const size_t perModel = base.data.size() / 2;
    EXPECT_FALSE(std::equal(base.data.begin(), base.data.begin() + perModel, changed.data.begin()));
    EXPECT_TRUE(
        std::equal(base.data.begin() + perModel, base.data.end(), changed.data.begin() + perModel));
}

TEST(StandardTest, RankingSharesRanksOnTies) {
    std::vector<PairScore> pairs(5);
    const double scores[] = {0.3, 0.5, 0.5, 0.1, 0.1};
    for (int i = 0; i < 5; ++i) {
        pairs[i].a = i;
        pairs[i].b = i + 1;
        pairs[i].score = scores[i];
    }
    rankPairs(pairs);
    // Sorted: 0.5, 0.5, 0.3, 0.1, 0.1 → ranks 1, 1, 3, 4, 4 (competition ranking).
    const int expected[] = {1, 1, 3, 4, 4};
    for (int i = 0; i < 5; ++i) EXPECT_EQ(pairs[i].rank, expected[i]) << i;
    EXPECT_EQ(pairs[0].a, 1);  // ties in model order
    EXPECT_EQ(pairs[1].a, 2);
}

TEST(StandardTest, KendallTauOnHandMadeLists) {
    // y swaps the 2nd and 3rd of four: 6 pairs, 1 discordant → tau = (5 − 1)/6.
    const RankAgreement r = compareRankings({1, 2, 3, 4}, {1, 3, 2, 4});
    EXPECT_EQ(r.discordant, 1);
    EXPECT_EQ(r.comparable, 6);
    EXPECT_NEAR(r.kendallTau, 4.0 / 6.0, 1e-12);
    EXPECT_NEAR(compareRankings({1, 2, 3}, {3, 2, 1}).kendallTau, -1.0, 1e-12);
    // Ties (tau-b): x = (1,1,2), y = (1,2,3): n0 = 3, x ties 1, C = 2, D = 0 →
    // tau = 2 / sqrt(2·3).
    EXPECT_NEAR(compareRankings({1, 1, 2}, {1, 2, 3}).kendallTau, 2.0 / std::sqrt(6.0), 1e-12);
}

TEST(StandardTest, BadOptionsAreErrorsBeforeAnyWork) {
    StandardTestOptions o = smallOptions();
    o.size = 0;
    EXPECT_THROW(validateStandardTestOptions(o), Error);
    o = smallOptions();
    o.samplesPerPixel = 0;
    EXPECT_THROW(validateStandardTestOptions(o), Error);
    o = smallOptions();
    o.settings["nosuchmodel"] = {"ks=1"};
    EXPECT_THROW(validateStandardTestOptions(o), Error);
    o = smallOptions();
    o.settings["phong"] = {"nosuchkey=1"};
    EXPECT_THROW(validateStandardTestOptions(o), Error);
    o = smallOptions();
    o.settings["phong"] = {"ks=-5"};  // out of range
    EXPECT_THROW(renderStandardLattices(o), Error);
    o = smallOptions();
    o.models = {"phong"};
    EXPECT_THROW(validateStandardTestOptions(o), Error);
}

TEST(OverlapReport, WritesAllFilesOrNone) {
    StandardTestOptions o = smallOptions();
    o.models = {"phong", "ward", "ashikhmin_shirley"};
    const LatticeSet set = renderStandardLattices(o);
    const auto pairs = scoreAllPairs(set, kFluxThreshold, OverlapVariant::Sum);
    const fs::path dir = fs::path(LOBE_BINARY_DIR) / "test-output" / "overlap_report";
    fs::remove_all(dir);

    // A bad --pair fails before anything is written.
    EXPECT_THROW(writeOverlapReport(dir.string(), set, pairs, {{"phong", "lafortune"}},
                                    kFluxThreshold, OverlapVariant::Sum, "test"),
                 Error);
    EXPECT_FALSE(fs::exists(dir / "overlap.csv"));

    const OverlapReportFiles files = writeOverlapReport(
        dir.string(), set, pairs, {{"ward", "phong"}}, kFluxThreshold, OverlapVariant::Sum, "test");
    std::ifstream csv(files.csv);
    std::string line;
    std::getline(csv, line);
    EXPECT_EQ(line, "rank,score,model_a,model_b,score_mse,sphere,torus,superquadric");
    int rows = 0;
    while (std::getline(csv, line)) ++rows;
    EXPECT_EQ(rows, 3);
    EXPECT_TRUE(fs::exists(files.markdown));
    EXPECT_TRUE(fs::exists(files.heatmap));
    EXPECT_TRUE(fs::exists(dir / "lobes" / "ward_vs_phong.png"));
    EXPECT_GE(files.lobeImages.size(), 2u);
    for (const auto& entry : fs::directory_iterator(dir))
        EXPECT_EQ(entry.path().filename().string().find(".partial"), std::string::npos);
}

}  // namespace
}  // namespace lobe
