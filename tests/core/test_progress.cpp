// The progress display's estimate (core/progress.h): the cost schedule against hand-computed
// values, and the ETA on synthetic cost sequences — a poster whose first bands are sky, a batch
// whose scenes differ in cost per pixel — against the truth at 10 % of the way (issue 31: within
// ±30 %), with the pixel count's estimate beside it for contrast.
#include "core/progress.h"
#include "core/rng.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

namespace lobe {
namespace {

TEST(CostSchedule, CostDoneHandComputed) {
    CostSchedule s;
    s.addPart(100, 1.0);
    s.addPart(300, 9.0);
    EXPECT_EQ(s.totalUnits(), 400);
    EXPECT_DOUBLE_EQ(s.totalCost(), 10.0);
    EXPECT_DOUBLE_EQ(s.costDone(0), 0.0);
    EXPECT_DOUBLE_EQ(s.costDone(50), 0.5);               // half of part 0
    EXPECT_DOUBLE_EQ(s.costDone(100), 1.0);              // part 0 done
    EXPECT_DOUBLE_EQ(s.costDone(250), 1.0 + 9.0 * 0.5);  // half of part 1
    EXPECT_DOUBLE_EQ(s.costDone(400), 10.0);
    EXPECT_DOUBLE_EQ(s.costDone(1000), 10.0);
    EXPECT_DOUBLE_EQ(s.fractionDone(250), 0.55);  // where pixels alone say 0.625
}

TEST(CostSchedule, ZeroAndBadCostsFallBackToUnits) {
    CostSchedule s;
    s.addPart(100, 0.0);
    s.addPart(100, std::numeric_limits<double>::quiet_NaN());
    s.addPart(0, 5.0);  // adds nothing
    s.addPart(200, -1.0);
    EXPECT_EQ(s.totalUnits(), 400);
    EXPECT_DOUBLE_EQ(s.totalCost(), 0.0);
    EXPECT_DOUBLE_EQ(s.fractionDone(100), 0.25);
    // A skipped scene (cost 0) before a rendered one: done at once, counting nothing.
    CostSchedule t;
    t.addPart(100, 0.0);
    t.addPart(100, 2.0);
    EXPECT_DOUBLE_EQ(t.fractionDone(100), 0.0);
    EXPECT_DOUBLE_EQ(t.fractionDone(150), 0.5);
}

TEST(CostSchedule, UnknownPartsPricedByMeasuredOnes) {
    // Three scenes of 100 pixels: the first measured when it is assembled, the others later; the
    // third has twice the samples (weight 200).
    CostSchedule s;
    const int a = s.addUnknownPart(100, 100.0);
    const int b = s.addUnknownPart(100, 100.0);
    const int c = s.addUnknownPart(100, 200.0);
    EXPECT_DOUBLE_EQ(s.fractionDone(100), 0.25);  // by weight alone: 100 / 400
    s.setCost(a, 6.0);                            // 0.06 a weight unit
    EXPECT_DOUBLE_EQ(s.partCost(b), 6.0);
    EXPECT_DOUBLE_EQ(s.partCost(c), 12.0);
    EXPECT_DOUBLE_EQ(s.fractionDone(100), 0.25);
    s.setCost(b, 2.0);  // now (6 + 2) / 200 = 0.04 a weight unit
    EXPECT_DOUBLE_EQ(s.partCost(c), 8.0);
    EXPECT_DOUBLE_EQ(s.fractionDone(200), 8.0 / 16.0);
    EXPECT_DOUBLE_EQ(s.fractionDone(150), 7.0 / 16.0);
    s.setCost(c, 24.0);
    EXPECT_DOUBLE_EQ(s.totalCost(), 32.0);
    // A part added as measured (a skipped scene: 0) does not set the rate.
    CostSchedule t;
    t.addPart(100, 0.0);
    const int u = t.addUnknownPart(100, 50.0);
    EXPECT_DOUBLE_EQ(t.partCost(u), 50.0);
}

TEST(CostSchedule, RemainingSeconds) {
    EXPECT_DOUBLE_EQ(remainingSeconds(10.0, 0.25), 30.0);
    EXPECT_DOUBLE_EQ(remainingSeconds(10.0, 1.0), 0.0);
    EXPECT_TRUE(std::isinf(remainingSeconds(10.0, 0.0)));
}

TEST(CostSchedule, RemainingLoadSeconds) {
    // 3 of 24 scenes assembled in 0.9 s: 21 more at 0.3 s each.
    EXPECT_DOUBLE_EQ(remainingLoadSeconds(0.9, 3, 24), 21 * 0.3);
    EXPECT_DOUBLE_EQ(remainingLoadSeconds(0.9, 3, 3), 0.0);   // all done
    EXPECT_DOUBLE_EQ(remainingLoadSeconds(0.9, 3, 0), 0.0);   // none expected (no batch)
    EXPECT_DOUBLE_EQ(remainingLoadSeconds(0.0, 0, 24), 0.0);  // nothing measured yet
}

TEST(CostSchedule, ReporterUsesTheSchedule) {
    CostSchedule s;
    s.addPart(100, 1.0);
    s.addPart(100, 3.0);
    ProgressReporter progress("test", 200, false);
    progress.advance(100);
    EXPECT_DOUBLE_EQ(progress.fractionDone(), 0.5);  // by pixels
    progress.setSchedule(&s);
    EXPECT_DOUBLE_EQ(progress.fractionDone(), 0.25);  // by cost
    progress.advance(50);
    EXPECT_DOUBLE_EQ(progress.fractionDone(), 0.625);
}

// Each part's prediction within ±12 % of its true cost: then predicted left over predicted done
// is within 0.88/1.12 … 1.12/0.88 = 0.79 … 1.27 of the truth's ratio, inside ±30 % whatever the
// draws. (The pilot's own error per part: docs/performance.md, "Progress and ETA".)
constexpr double kPilotError = 0.12;

// A simulated run: parts with true costs (seconds) done in order, the pixels of the part under
// way done at a steady rate; the pilot's predictions are the true costs times a noise factor in
// [1 − noise, 1 + noise]. Returns ETA / truth when `share` of the true total time has passed,
// for the pilot's schedule and (in `byPixels`) for the pixel count.
double etaOverTruth(const std::vector<int64_t>& units, const std::vector<double>& trueCost,
                    double noise, double share, double* byPixels, uint64_t seed = 1) {
    Rng rng(seed);
    CostSchedule pilot, pixels;
    double total = 0.0;
    for (size_t k = 0; k < units.size(); ++k) {
        pilot.addPart(units[k], trueCost[k] * (1.0 + noise * (2.0 * rng.uniform() - 1.0)));
        pixels.addPart(units[k], double(units[k]));
        total += trueCost[k];
    }
    // Units done when `share` of the true time has passed.
    const double elapsed = share * total;
    double t = 0.0;
    int64_t done = 0;
    for (size_t k = 0; k < units.size(); ++k) {
        if (t + trueCost[k] >= elapsed) {
            done += int64_t(double(units[k]) * (elapsed - t) / trueCost[k]);
            break;
        }
        t += trueCost[k];
        done += units[k];
    }
    const double truth = total - elapsed;
    if (byPixels) *byPixels = remainingSeconds(elapsed, pixels.fractionDone(done)) / truth;
    return remainingSeconds(elapsed, pilot.fractionDone(done)) / truth;
}

TEST(CostSchedule, PosterEtaAtTenPercent) {
    // A 4096² poster in 16 bands of 256 rows: four bands of sky (cost 1 a pixel), then the head,
    // 25 to 60 times dearer, dearest in the middle — the shape of the poster.
    std::vector<int64_t> units(16, 4096 * 256);
    std::vector<double> cost;
    for (int b = 0; b < 16; ++b)
        cost.push_back(double(units[size_t(b)]) * 1e-6 *
                       (b < 4 ? 1.0 : 60.0 - 3.0 * std::abs(b - 9)));
    for (uint64_t seed = 1; seed <= 20; ++seed) {
        double byPixels = 0.0;
        const double ratio = etaOverTruth(units, cost, kPilotError, 0.1, &byPixels, seed);
        EXPECT_NEAR(ratio, 1.0, 0.3) << "seed " << seed;
        EXPECT_LT(byPixels, 0.3) << "seed " << seed;  // the pixel count's ETA: far too short
    }
}

TEST(CostSchedule, BatchEtaAtTenPercent) {
    // 24 scenes of one size, the first six dearer (an expensive BRDF), then cheaper ones and a
    // dear one now and then, as in the paper's renderings.
    std::vector<int64_t> units(24, 256 * 256);
    std::vector<double> cost;
    for (int k = 0; k < 24; ++k) cost.push_back(k < 6 ? 4.0 : (k % 7 == 0 ? 3.0 : 1.0));
    for (uint64_t seed = 1; seed <= 20; ++seed) {
        double byPixels = 0.0;
        for (double share : {0.1, 0.25, 0.5}) {
            const double ratio = etaOverTruth(units, cost, kPilotError, share, &byPixels, seed);
            EXPECT_NEAR(ratio, 1.0, 0.3) << "seed " << seed << " at " << share;
        }
        etaOverTruth(units, cost, kPilotError, 0.1, &byPixels, seed);
        EXPECT_GT(byPixels, 1.5) << "seed " << seed;  // by pixels: the dear first scenes mislead
    }
}

TEST(CostSchedule, EqualPartsNeedNoPilot) {
    // An orbit's frames of equal cost: pilot and pixels agree, and both are exact.
    std::vector<int64_t> units(12, 512 * 512);
    std::vector<double> cost(12, 2.0);
    double byPixels = 0.0;
    EXPECT_NEAR(etaOverTruth(units, cost, 0.0, 0.1, &byPixels), 1.0, 1e-3);
    EXPECT_NEAR(byPixels, 1.0, 1e-3);
}

}  // namespace
}  // namespace lobe
