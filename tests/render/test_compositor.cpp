// render/compositor.h: the shading roulette's draws (ShadingRoulette) against the rule they
// implement, written here as the integrator had it — a running sum of w/w0 from the offset, a
// sample shaded when floor(sum after) > floor(sum before) — and FrontToBackCompositor::pass
// against add(alpha, 0), bit for bit.
#include "render/compositor.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

namespace lobe {
namespace {

// The decisions of the plain rule for weights `w` (each below w0) from `offset`.
std::vector<bool> floorRule(double offset, double w0, const std::vector<double>& w) {
    std::vector<bool> shaded;
    double sum = offset;
    for (double x : w) {
        const double before = sum;
        sum += x / w0;
        shaded.push_back(std::floor(sum) > std::floor(before));
    }
    return shaded;
}

std::vector<bool> drawn(double offset, double w0, const std::vector<double>& w) {
    ShadingRoulette roulette(offset, w0);
    std::vector<bool> shaded;
    for (double x : w) shaded.push_back(roulette.draw(x));
    return shaded;
}

// Rays as the integrator makes them: weights T·α below w0, T falling by (1 − α) per sample.
TEST(ShadingRoulette, DrawsAsTheFloorRuleOnRandomRays) {
    std::mt19937_64 gen(12345);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    long long shadedCount = 0, samples = 0;
    for (double w0 : {0.5, 0.03, 1e-3, 1e-6, 2e-12, 1e-13, 1e-200}) {
        for (int ray = 0; ray < 300; ++ray) {
            const double offset = uni(gen);
            std::vector<double> w;
            double T = 1.0;
            const double alphaMax = std::pow(10.0, -4.0 * uni(gen));
            while (T > 1e-3 && w.size() < 400) {
                const double alpha = alphaMax * uni(gen);
                const double weight = T * alpha;
                if (weight < w0) w.push_back(weight);
                T *= 1.0 - alpha;
            }
            const std::vector<bool> expected = floorRule(offset, w0, w);
            ASSERT_EQ(drawn(offset, w0, w), expected) << "w0 " << w0 << ", ray " << ray;
            for (bool b : expected) shadedCount += b ? 1 : 0;
            samples += static_cast<long long>(w.size());
        }
    }
    // The rule was exercised both ways.
    EXPECT_GT(shadedCount, 1000);
    EXPECT_GT(samples - shadedCount, 1000);
}

// A sum landing exactly on an integer has crossed it (floor(1) = 1 > floor(0.5) = 0).
TEST(ShadingRoulette, ASumReachingAnIntegerExactlyIsShaded) {
    ShadingRoulette roulette(0.5, 0.5);
    EXPECT_FALSE(roulette.draw(0.125));  // 0.75
    EXPECT_TRUE(roulette.draw(0.125));   // 1.0 exactly
    EXPECT_FALSE(roulette.draw(0.0));    // still 1.0: no new crossing
    EXPECT_FALSE(roulette.draw(0.25));   // 1.5
    EXPECT_TRUE(roulette.draw(0.25));    // 2.0 exactly
    EXPECT_EQ(roulette.sum(), 2.0);
}

// For w0 so small that the sum passes 2⁵³, floor(sum) + 1 rounds back to the sum; the rule is
// then applied with floors: a weight of 0 after a crossing crosses nothing.
TEST(ShadingRoulette, SumsBeyondTwoToThe53KeepTheFloorRule) {
    const double w0 = 1e-20;
    const std::vector<double> w = {0.5, 0.0, 1e-30, 0.25};
    // 5e19 (crossed), the same sum, 5e19 + 1e-10 (the same double), 7.5e19 (crossed).
    EXPECT_EQ(drawn(0.25, w0, w), (std::vector<bool>{true, false, false, true}));
    EXPECT_EQ(drawn(0.25, w0, w), floorRule(0.25, w0, w));
}

TEST(ShadingRoulette, NaNWeightsShadeNothingAfter) {
    const std::vector<double> w = {0.01, std::nan(""), 0.02, 0.5};
    EXPECT_EQ(drawn(0.9, 0.03, w), floorRule(0.9, 0.03, w));
    EXPECT_EQ(drawn(0.9, 0.03, w), (std::vector<bool>{true, false, false, false}));
}

TEST(FrontToBackCompositor, PassIsAddingZeroRadiance) {
    std::mt19937_64 gen(7);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    for (int ray = 0; ray < 200; ++ray) {
        FrontToBackCompositor a(1e-3), b(1e-3);
        while (!a.terminated()) {
            const double alpha = uni(gen) * uni(gen);
            if (uni(gen) < 0.3) {
                const Spectrum L(uni(gen), 0.0, 3.0 * uni(gen));
                a.add(alpha, L);
                b.add(alpha, L);
            } else {
                a.add(alpha, Spectrum(0.0));
                b.pass(alpha);
            }
            ASSERT_EQ(a.transmittance, b.transmittance);
            for (int k = 0; k < 3; ++k) {
                ASSERT_EQ(a.radiance[k], b.radiance[k]);
                ASSERT_EQ(std::signbit(a.radiance[k]), std::signbit(b.radiance[k]));
            }
            ASSERT_EQ(a.terminated(), b.terminated());
        }
    }
}

}  // namespace
}  // namespace lobe
