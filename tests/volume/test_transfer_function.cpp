// Transfer functions: piecewise-linear evaluation, steps, exact maximum over a range, transparent
// ranges, opacity correction, the paper's presets and the sRGB → band conversion.
#include "core/error.h"
#include "volume/transfer_function.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace lobe {
namespace {

TEST(TransferFunction, InterpolatesLinearlyAndClampsAtEnds) {
    const TransferFunction tf({{0.2, 0.0, Spectrum(0, 0, 1)}, {0.6, 0.4, Spectrum(1, 0, 0)}});
    // At 0.3: s = (0.3 − 0.2)/0.4 = 0.25 → opacity 0.25·0.4 = 0.1, colour (0.25, 0, 0.75).
    EXPECT_NEAR(tf.opacity(0.3), 0.1, 1e-15);
    const Spectrum c = tf.colour(0.3);
    EXPECT_NEAR(c[0], 0.25, 1e-15);
    EXPECT_NEAR(c[1], 0.0, 1e-15);
    EXPECT_NEAR(c[2], 0.75, 1e-15);
    EXPECT_EQ(tf.opacity(-5.0), 0.0);  // below the first point: its value
    EXPECT_EQ(tf.opacity(7.0), 0.4);   // above the last point: its value
    EXPECT_EQ(TransferFunction().opacity(0.5), 0.0);
}

TEST(TransferFunction, StepTakesRightLimitAtItsValue) {
    const TransferFunction tf({{0.5, 0.0, Spectrum(1)}, {0.5, 0.3, Spectrum(1)}});
    EXPECT_EQ(tf.opacity(0.5 - 1e-12), 0.0);
    EXPECT_EQ(tf.opacity(0.5), 0.3);
    EXPECT_EQ(tf.opacity(0.9), 0.3);
}

TEST(TransferFunction, OpacityIfVisibleIsEvaluateWhereVisible) {
    // The marcher's shortcut: between two control points of opacity 0 it returns 0 without
    // touching the colour; elsewhere evaluate()'s opacity and colour, bit for bit. Hand case:
    // the T3 tents 0.69 → 0.70 → 0.71 (opacity 0 → 0.3 → 0), a plateau 0.8 … 0.9 and a step.
    const Spectrum red(1, 0, 0), blue(0, 0, 1);
    const TransferFunction tf({{0.69, 0.0, red},
                               {0.70, 0.3, blue},
                               {0.71, 0.0, red},
                               {0.74, 0.0, blue},
                               {0.8, 0.0, red},
                               {0.8, 0.25, blue},
                               {0.9, 0.25, red}});
    const Spectrum sentinel(-7.0);
    Spectrum c = sentinel;
    EXPECT_EQ(tf.opacityIfVisible(0.72, c), 0.0);  // inside the transparent piece 0.71 … 0.74
    EXPECT_EQ(c, sentinel);
    // At 0.695: s = 0.5 → opacity 0.15, colour halfway between red and blue.
    EXPECT_NEAR(tf.opacityIfVisible(0.695, c), 0.15, 1e-12);
    EXPECT_NEAR(c[0], 0.5, 1e-12);
    EXPECT_NEAR(c[2], 0.5, 1e-12);
    // On the plateau the opacity is exactly the control points' (0.25 + s · 0).
    EXPECT_EQ(tf.opacityIfVisible(0.83, c), 0.25);
    EXPECT_EQ(tf.opacityIfVisible(0.8, c), 0.25);  // the step's right limit, as evaluate()
    EXPECT_EQ(c, blue);
    // Everywhere, on a fine grid of values through every piece, the ends and the points: the
    // same opacity as evaluate() and, where it is > 0, the same colour.
    int visible = 0, transparent = 0;
    for (int i = -50; i <= 1300; ++i) {
        const double v = 0.6 + 0.00025 * i + (i % 7 == 0 ? 1e-13 : 0.0);
        for (double x : {v, std::nextafter(0.71, 0.0), 0.71, 0.74, 0.9, 0.69}) {
            double a;
            Spectrum ce, cv = sentinel;
            tf.evaluate(x, a, ce);
            const double b = tf.opacityIfVisible(x, cv);
            ASSERT_EQ(a, b) << x;
            if (b > 0.0) {
                ASSERT_EQ(ce, cv) << x;
                ++visible;
            } else {
                ++transparent;
            }
        }
    }
    EXPECT_GT(visible, 1000);
    EXPECT_GT(transparent, 1000);
    Spectrum e = sentinel;
    EXPECT_EQ(TransferFunction().opacityIfVisible(0.5, e), 0.0);
}

TEST(TransferFunction, MaxOpacityIsExact) {
    // Tent 0 → 0.5 → 0 on [0.4, 0.6]: inside [0.45, 0.7] the peak 0.5 at 0.6 is a control point,
    // inside [0.41, 0.42] the maximum is at the right end: (0.42 − 0.4)/0.1 · 0.5 = 0.1.
    const TransferFunction tf(
        {{0.4, 0.0, Spectrum(1)}, {0.5, 0.5, Spectrum(1)}, {0.6, 0.0, Spectrum(1)}});
    EXPECT_EQ(tf.maxOpacity(0.45, 0.7), 0.5);
    EXPECT_NEAR(tf.maxOpacity(0.41, 0.42), 0.1, 1e-15);
    EXPECT_TRUE(tf.isTransparent(0.0, 0.4));
    EXPECT_TRUE(tf.isTransparent(0.6, 3.0));
    EXPECT_FALSE(tf.isTransparent(0.0, 0.400001));
}

TEST(TransferFunction, TransparentRangesOfADensityMap) {
    // Map 0: 0 below 0.69, up to 0.3 at 0.71, flat to 0.74, down to 0 at 0.76.
    const auto r = TransferFunction::densityMap(0).transparentRanges();
    ASSERT_EQ(r.size(), 2u);
    EXPECT_EQ(r[0].first, -std::numeric_limits<double>::infinity());
    EXPECT_NEAR(r[0].second, 0.69, 1e-15);
    EXPECT_NEAR(r[1].first, 0.76, 1e-15);
    EXPECT_EQ(r[1].second, std::numeric_limits<double>::infinity());
}

TEST(TransferFunction, OpacityCorrection) {
    // 1 − (1 − 0.5)² = 0.75; 1 − 0.5^0.5 = 0.292893…; Δ = 1 leaves α unchanged; 20 steps of
    // 0.05 compose back to the per-voxel opacity: 1 − ((1 − α)^0.05)^20 = α.
    EXPECT_NEAR(correctOpacity(0.5, 2.0), 0.75, 1e-15);
    EXPECT_NEAR(correctOpacity(0.5, 0.5), 1.0 - std::sqrt(0.5), 1e-15);
    EXPECT_NEAR(correctOpacity(0.3, 1.0), 0.3, 1e-15);
    double t = 1.0;
    for (int i = 0; i < 20; ++i) t *= 1.0 - correctOpacity(0.3, 0.05);
    EXPECT_NEAR(1.0 - t, 0.3, 1e-14);
    EXPECT_EQ(correctOpacity(0.0, 0.05), 0.0);
}

TEST(TransferFunction, OpacityCorrectionTableMatchesTheFormula) {
    // The table (transfer_function.h: within 2e-15 of correctOpacity on [0, top], the formula
    // itself elsewhere) against correctOpacity for α from 1e-6 to 0.999 (log-spaced and
    // uniform) and exponents from 0.01 to 16, with top 0.2 (the cortex shell) and 0.75 (the
    // limit). Hand values: 1 − (1 − 0.5)² = 0.75, 1 − 0.5^0.5 = 1 − √½.
    const OpacityCorrection square(2.0, 0.75), root(0.5, 0.75);
    EXPECT_NEAR(square.correct(0.5, 2.0), 0.75, 4e-15 * 0.75);
    EXPECT_NEAR(root.correct(0.5, 0.5), 1.0 - std::sqrt(0.5), 4e-15 * (1.0 - std::sqrt(0.5)));
    const double exponents[] = {0.01, 0.02, 0.05, 0.1, 0.3, 0.5, 0.79,
                                1.0,  1.26, 1.59, 2.0, 3.5, 4.0, 16.0};
    for (double top : {0.2, 0.75})
        for (double r : exponents) {
            const OpacityCorrection table(r, top);
            ASSERT_TRUE(table.tabulated());
            EXPECT_EQ(table.top(), top);
            double worst = 0.0;
            for (int k = 0; k <= 20000; ++k) {
                const double a =
                    k % 2 ? 1e-6 * std::pow(0.999 / 1e-6, k / 20000.0) : 0.999 * k / 20000.0;
                const double exact = correctOpacity(a, r);
                const double got = table.correct(a, r);
                if (a > top || a <= 0.0) {
                    EXPECT_EQ(got, exact) << "alpha " << a << ", r " << r;
                    continue;
                }
                worst = std::max(worst, std::abs(got - exact) / exact);
            }
            EXPECT_LE(worst, 4e-15) << "r " << r << ", top " << top;
            // The interval ends and top itself (the last interval takes α = top).
            for (double a : {1.0 / 256, 2.0 / 256, 0.5 * top, top})
                EXPECT_NEAR(table.correct(a, r), correctOpacity(a, r),
                            4e-15 * correctOpacity(a, r));
        }
}

TEST(TransferFunction, OpacityCorrectionTableOnlyForItsExponent) {
    const OpacityCorrection table(0.05, 0.2);
    // A ray's exponent a few ulps from the table's takes the table (within 2e-14 of the
    // formula); one 1e-12 away, and any α above top or ≤ 0, takes the formula bit for bit.
    const double near = 0.05 * (1.0 + 4e-16), far = 0.05 * (1.0 + 1e-12);
    for (double a : {1e-6, 0.001, 0.05, 0.1999}) {
        EXPECT_NEAR(table.correct(a, near), correctOpacity(a, near),
                    2e-14 * correctOpacity(a, near));
        EXPECT_EQ(table.correct(a, near), table.correct(a, 0.05));
        EXPECT_EQ(table.correct(a, far), correctOpacity(a, far));
    }
    EXPECT_EQ(table.correct(0.3, 0.05), correctOpacity(0.3, 0.05));
    EXPECT_EQ(table.correct(0.0, 0.05), 0.0);
    EXPECT_EQ(table.correct(-0.1, 0.05), 0.0);
    // No visible opacity: no table; the default object has none either.
    EXPECT_FALSE(OpacityCorrection(0.05, 0.0).tabulated());
    EXPECT_FALSE(OpacityCorrection().tabulated());
    EXPECT_EQ(OpacityCorrection().correct(0.3, 0.5), correctOpacity(0.3, 0.5));
    EXPECT_THROW(OpacityCorrection(0.0, 0.2), Error);
    EXPECT_THROW(OpacityCorrection(std::nan(""), 0.2), Error);
}

TEST(TransferFunction, PaperPresets) {
    const double iso[4] = {0.70, 0.75, 0.80, 0.85};
    const double alpha[4] = {0.3, 0.4, 0.5, 0.6};
    for (int i = 0; i < 4; ++i) {
        const TransferFunction tf = TransferFunction::densityMap(i, 0.02);
        EXPECT_NEAR(tf.opacity(iso[i]), 0.5 * alpha[i], 1e-12) << "half opacity at the iso value";
        EXPECT_NEAR(tf.opacity(iso[i] + 0.01), alpha[i], 1e-12);
        EXPECT_EQ(tf.opacity(iso[i] - 0.011), 0.0);
        if (i < 3) {
            EXPECT_EQ(tf.opacity(iso[i + 1] + 0.011), 0.0);
        }
    }
    const TransferFunction all = TransferFunction::densityMaps();
    EXPECT_NEAR(all.opacity(0.9), 0.6, 1e-15);
    EXPECT_NEAR(all.opacity(0.775), 0.4, 1e-15);
    // Red: the 700 nm band dominates; blue: the 435.8 nm band.
    const Spectrum red = all.colour(0.9), blue = all.colour(0.72);
    EXPECT_GT(red[0], 5 * red[2]);
    EXPECT_GT(blue[2], 5 * blue[0]);

    const TransferFunction cortex = TransferFunction::cortex(0.47, 0.1);
    EXPECT_EQ(cortex.opacity(0.419), 0.0);
    EXPECT_NEAR(cortex.opacity(0.4200001), 0.001, 1e-6);
    EXPECT_NEAR(cortex.opacity(0.47), 0.5 * (0.001 + 0.2), 1e-12);
    EXPECT_NEAR(cortex.opacity(0.9), 0.2, 1e-15);
}

// The cortex shell at the paper scenes' numbers (boundary 0.47, width 0.14, peak 0.2): the tent
// 0.40 -> 0.47 -> 0.54, values by hand from its five points.
TEST(TransferFunction, CortexShellIsATentAroundTheBoundary) {
    const TransferFunction shell = TransferFunction::cortexShell();
    EXPECT_EQ(shell.opacity(0.1), 0.0);
    EXPECT_EQ(shell.opacity(0.3999), 0.0);
    EXPECT_NEAR(shell.opacity(0.40), 0.001, 1e-15);  // the step's right limit
    // Halfway up the rising side: 0.001 + (0.2 - 0.001) / 2.
    EXPECT_NEAR(shell.opacity(0.435), 0.1005, 1e-12);
    EXPECT_NEAR(shell.opacity(0.47), 0.2, 1e-15);
    // 3/7 of the way down the falling side: 0.2 - 3/7 * 0.199 = 0.114714285714...
    EXPECT_NEAR(shell.opacity(0.50), 0.2 - 3.0 / 7.0 * 0.199, 1e-12);
    EXPECT_NEAR(shell.opacity(0.5399999), 0.001, 1e-6);
    EXPECT_EQ(shell.opacity(0.54), 0.0);  // the closing step: the tissue inside stays clear
    EXPECT_EQ(shell.opacity(0.9), 0.0);
    const Spectrum c = shell.colour(0.47);
    EXPECT_EQ(c[0], 0.85);
    EXPECT_EQ(c[1], 0.72);
    EXPECT_EQ(c[2], 0.62);
    const auto clear = shell.transparentRanges();
    ASSERT_EQ(clear.size(), 2u);
    EXPECT_NEAR(clear[0].second, 0.40, 1e-15);
    EXPECT_NEAR(clear[1].first, 0.54, 1e-15);
    EXPECT_TRUE(std::isinf(clear[1].second));

    // Other numbers: boundary 0.3, width 0.2, peak 0.5: edges at 0.2 and 0.4, and halfway up
    // 0.001 + 0.499 / 2 = 0.2505.
    const TransferFunction own = TransferFunction::cortexShell(0.3, 0.2, 0.5, Spectrum(1));
    EXPECT_NEAR(own.opacity(0.25), 0.2505, 1e-12);
    EXPECT_NEAR(own.opacity(0.3), 0.5, 1e-15);
    EXPECT_EQ(own.opacity(0.19), 0.0);
    EXPECT_EQ(own.opacity(0.41), 0.0);

    EXPECT_THROW(TransferFunction::cortexShell(0.47, 0.0), Error);
    EXPECT_THROW(TransferFunction::cortexShell(0.47, 0.1, 0.0005), Error);  // below the edges
    EXPECT_THROW(TransferFunction::cortexShell(0.47, 0.1, 1.0), Error);
}

TEST(TransferFunction, BadInputThrows) {
    EXPECT_THROW(TransferFunction({{0.5, 0.1, Spectrum(1)}, {0.4, 0.1, Spectrum(1)}}), Error);
    EXPECT_THROW(TransferFunction({{0.5, 1.0, Spectrum(1)}}), Error);
    EXPECT_THROW(TransferFunction({{0.5, -0.1, Spectrum(1)}}), Error);
    EXPECT_THROW(TransferFunction({{0.5, 0.1, Spectrum(-1)}}), Error);
    EXPECT_THROW(TransferFunction({{std::nan(""), 0.1, Spectrum(1)}}), Error);
    EXPECT_THROW(TransferFunction::densityMap(4), Error);
    EXPECT_THROW(TransferFunction::densityMap(0, 0.06), Error);
    try {
        TransferFunction({{0.5, 0.1, Spectrum(1)}, {0.4, 0.1, Spectrum(1)}}, "scene.json: tf");
        FAIL();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("scene.json: tf, control point 1"), std::string::npos);
    }
}

}  // namespace
}  // namespace lobe
