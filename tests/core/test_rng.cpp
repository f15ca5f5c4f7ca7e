#include "core/rng.h"
#include "core/sampling.h"

#include <gtest/gtest.h>

#include <set>

namespace lobe {

TEST(Rng, SameSeedGivesSameSequence) {
    Rng a = pixelSampleRng(42, 10, 20, 3), b = pixelSampleRng(42, 10, 20, 3);
    for (int i = 0; i < 1000; ++i) ASSERT_EQ(a.nextUint(), b.nextUint());
}

TEST(Rng, NeighbouringPixelsAndSamplesDiffer) {
    std::set<uint32_t> firsts;
    for (uint32_t x = 0; x < 16; ++x)
        for (uint32_t s = 0; s < 16; ++s) firsts.insert(pixelSampleRng(7, x, 0, s).nextUint());
    EXPECT_EQ(firsts.size(), 256u);  // no two streams start alike
}

TEST(Rng, UniformIsInUnitIntervalWithMeanHalf) {
    Rng rng(1, 2);
    double sum = 0.0;
    const int n = 200000;
    for (int i = 0; i < n; ++i) {
        const double u = rng.uniform();
        ASSERT_GE(u, 0.0);
        ASSERT_LT(u, 1.0);
        sum += u;
    }
    EXPECT_NEAR(sum / n, 0.5, 0.005);  // 0.5 ± ~8σ (σ = 1/sqrt(12 n))
}

TEST(Sampling, StrataFactorisation) {
    EXPECT_EQ(strataFor(16).rows, 4);
    EXPECT_EQ(strataFor(16).cols, 4);
    EXPECT_EQ(strataFor(8).rows, 2);
    EXPECT_EQ(strataFor(8).cols, 4);
    EXPECT_EQ(strataFor(7).rows * strataFor(7).cols, 7);
    EXPECT_EQ(strataFor(1).rows * strataFor(1).cols, 1);
}

TEST(Sampling, EachSampleStaysInItsStratum) {
    const StrataGrid grid = strataFor(8);
    Rng rng(3, 4);
    for (int i = 0; i < 8; ++i) {
        const Vec2 p = jitteredSample(grid, i, rng);
        EXPECT_GE(p.x, double(i % grid.cols) / grid.cols);
        EXPECT_LT(p.x, double(i % grid.cols + 1) / grid.cols);
        EXPECT_GE(p.y, double(i / grid.cols) / grid.rows);
        EXPECT_LT(p.y, double(i / grid.cols + 1) / grid.rows);
    }
}

}  // namespace lobe
