// Pre-integrated classification (volume/pre_integration.h) against cases integrated by hand:
// a constant transfer function gives equation (1)'s opacity whatever the two values; a box of
// opacity crossed by a linear segment gives the box's share of the extinction, and the
// extinction-weighted colour; and through the marcher, a ramp field crossing a narrow box of
// opacity gives the exact transmittance at steps larger than the box, where point sampling
// depends on where its samples fall. Skipping changes a pre-integrated image by at most rounding
// here.
#include "core/rng.h"
#include "dvr_test_grids.h"
#include "render/compositor.h"
#include "volume/pre_integration.h"
#include "volume/volume_marcher.h"

#include <gtest/gtest.h>

#include <cmath>

namespace lobe {
namespace {

using openvdb::Coord;

TEST(PreIntegration, ConstantTransferFunctionGivesEquationOne) {
    const Spectrum c(0.2, 0.5, 0.9);
    const PreIntegratedTf pre(TransferFunction({{0.0, 0.3, c}, {1.0, 0.3, c}}));
    for (double sf : {-2.0, 0.0, 0.37, 1.5})
        for (double sb : {-1.0, 0.37, 0.370000001, 0.9, 3.0})
            for (double len : {0.05, 1.0, 2.5}) {
                double alpha;
                Spectrum colour;
                double where;
                pre.segment(sf, sb, len, alpha, colour, where);
                EXPECT_NEAR(alpha, correctOpacity(0.3, len), 1e-9) << sf << " " << sb;
                for (int b = 0; b < 3; ++b) EXPECT_NEAR(colour[b], c[b], 1e-9);
            }
}

TEST(PreIntegration, BoxOfOpacityByHand) {
    // Opacity a on [0.5, 1], colour c1 on [0.5, 0.75) and c2 on [0.75, 1]; 0 below 0.5.
    // τ = −ln(1 − a) on the box. A segment of length L running from 0 to 1 spends half of its
    // length in the box: α = 1 − exp(−τ L / 2) = 1 − (1 − a)^(L/2); colour (c1 + c2) / 2. From
    // 0.25 to 0.625 (a third inside): α = 1 − (1 − a)^(L/3), colour c1.
    const double a = 0.4;
    const Spectrum c0(1.0), c1(1.0, 0.0, 0.0), c2(0.0, 0.0, 1.0);
    const PreIntegratedTf pre(TransferFunction({{0.0, 0.0, c0},
                                                {0.5, 0.0, c0},
                                                {0.5, a, c1},
                                                {0.75, a, c1},
                                                {0.75, a, c2},
                                                {1.0, a, c2}}));
    double alpha, where;
    Spectrum colour;
    pre.segment(0.0, 1.0, 2.0, alpha, colour, where);
    EXPECT_NEAR(where, 0.75, 1e-9);  // the box's middle, three quarters of the way
    EXPECT_NEAR(alpha, 1.0 - std::pow(1.0 - a, 1.0), 1e-9);
    EXPECT_NEAR(colour[0], 0.5, 1e-9);
    EXPECT_NEAR(colour[2], 0.5, 1e-9);
    pre.segment(1.0, 0.0, 2.0, alpha, colour, where);
    EXPECT_NEAR(where, 0.25, 1e-9);  // the direction does not matter
    EXPECT_NEAR(alpha, 1.0 - std::pow(1.0 - a, 1.0), 1e-9);
    pre.segment(0.25, 0.625, 3.0, alpha, colour, where);
    EXPECT_NEAR(where, (0.5625 - 0.25) / 0.375, 1e-9);
    EXPECT_NEAR(alpha, 1.0 - std::pow(1.0 - a, 1.0), 1e-9);
    EXPECT_NEAR(colour[0], 1.0, 1e-9);
    EXPECT_NEAR(colour[2], 0.0, 1e-9);
    pre.segment(0.0, 0.45, 3.0, alpha, colour, where);  // wholly below the box: transparent
    EXPECT_EQ(alpha, 0.0);
    EXPECT_NEAR(pre.extinctionIntegral(1.0), -0.5 * std::log1p(-a), 1e-12);
    EXPECT_NEAR(pre.extinctionIntegral(2.0), -1.5 * std::log1p(-a), 1e-12);  // beyond: end value
}

// A ramp along x (value 0.01 per voxel) through a box of opacity 0.3 on [0.49, 0.51]: the ray
// along x from x = 20 to 80 spends 2 voxels in it, so its transmittance is exactly 0.7² = 0.49.
// (The ray stays off the grid's ends, where the field falls to the background 0 across the box
// again.)
double rampTransmittance(bool preIntegrated, double step, double jitter, bool skipping = true) {
    auto grid = test::makeGrid([](int i, int, int) { return 0.01 * i; }, Coord(0, 0, 0),
                               Coord(100, 15, 15));
    const Spectrum w(1.0);
    const TransferFunction box({{0.49, 0.0, w}, {0.49, 0.3, w}, {0.51, 0.3, w}, {0.51, 0.0, w}});
    DvrSettings set;
    set.stepVoxels = step;
    set.preIntegrated = preIntegrated;
    set.emptySpaceSkipping = skipping;
    const DvrVolume vol(grid, box, set);
    VolumeRaySampler s(vol);
    Ray ray;
    ray.o = Vec3(20.0, 7.3, 7.6);
    ray.d = Vec3(1.0, 0.0, 0.0);
    ray.tMax = 60.0;
    FrontToBackCompositor c(0.0);
    EXPECT_TRUE(s.begin(ray, jitter));
    s.marchSegment(1e30, [&](const VolumeSample& v) {
        c.add(v.alpha, v.colour);
        return true;
    });
    return c.transmittance;
}

TEST(PreIntegration, NarrowBoxIsExactAtLargeSteps) {
    for (double step : {0.3, 1.0, 2.0, 3.7})
        for (double jitter : {0.0, 0.25, 0.5, 0.9}) {
            EXPECT_NEAR(rampTransmittance(true, step, jitter), 0.49, 2e-3) << step << " " << jitter;
            EXPECT_NEAR(rampTransmittance(true, step, jitter, false), 0.49, 2e-3);
        }
    // Point sampling at a step of 3.7 voxels sees the box or not, depending on the jitter.
    double lo = 1.0, hi = 0.0;
    for (double jitter : {0.0, 0.25, 0.5, 0.75}) {
        const double t = rampTransmittance(false, 3.7, jitter);
        lo = std::min(lo, t);
        hi = std::max(hi, t);
    }
    EXPECT_GT(hi - lo, 0.2);
    EXPECT_NEAR(rampTransmittance(false, 0.01, 0.5), 0.49, 2e-3);  // and converges to it
}

TEST(PreIntegration, SkippingChangesAlmostNothing) {
    // A blob (Gaussian, peak 1) under a thin shell at 0.5: rays through it from every side,
    // composited with and without skipping. The transparent runs are skipped, the segments
    // entering and leaving them are kept.
    auto grid = test::makeGrid(
        [](int i, int j, int k) {
            const double r2 =
                (i - 20.0) * (i - 20.0) + (j - 20.0) * (j - 20.0) + (k - 20.0) * (k - 20.0);
            return std::exp(-r2 / 60.0);
        },
        Coord(0), Coord(40));
    const TransferFunction shell = TransferFunction::cortex(0.5, 0.04);
    for (double step : {0.05, 0.5, 1.5}) {
        DvrSettings on, off;
        on.preIntegrated = off.preIntegrated = true;
        on.stepVoxels = off.stepVoxels = step;
        off.emptySpaceSkipping = false;
        const DvrVolume vOn(grid, shell, on), vOff(grid, shell, off);
        double worst = 0.0, mean = 0.0;
        long long skipped = 0;
        for (int n = 0; n < 200; ++n) {
            Rng rng(5, n);
            const Vec3 dir =
                normalized(Vec3(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5));
            Ray ray;
            ray.o = Vec3(20) +
                    8.0 * Vec3(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5) -
                    40.0 * dir;
            ray.d = dir;
            const double jitter = rng.uniform();
            VolumeRaySampler a(vOn), b(vOff);
            FrontToBackCompositor ca(0.0), cb(0.0);
            a.begin(ray, jitter);
            b.begin(ray, jitter);
            a.marchSegment(1e30, [&](const VolumeSample& v) {
                ca.add(v.alpha, v.colour);
                return true;
            });
            b.marchSegment(1e30, [&](const VolumeSample& v) {
                cb.add(v.alpha, v.colour);
                return true;
            });
            worst = std::max(worst, std::abs(ca.transmittance - cb.transmittance));
            mean += 1.0 - cb.transmittance;
            skipped += a.samplesSkipped();
        }
        EXPECT_LT(worst, 1e-9) << step;
        EXPECT_GT(mean / 200, 0.1) << step;  // the shell is seen
        EXPECT_GT(skipped, 0) << step;
    }
}

}  // namespace
}  // namespace lobe
