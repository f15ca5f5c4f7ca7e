// The display model's colour measures (analysis/colour.h) against values computed independently:
// ΔE_ITP (ITU-R BT.2124) from a plain-Python computation from first principles, and CIELAB of
// sRGB primaries against the widely tabulated values.
#include "analysis/colour.h"
#include "analysis/separation.h"
#include "core/error.h"

#include <gtest/gtest.h>

#include <cmath>

namespace lobe {
namespace {

// The expected values below come from this independent script (Python 3, no libraries). It does
// not use the BT.2087 matrix the code has typed in, but derives it from the primaries:
//   1. RGB→XYZ of BT.709 and of BT.2020 from their primaries and D65 (SMPTE RP 177):
//      P = [[x/y …], [1 …], [(1−x−y)/y …]], S = P⁻¹ · W, M_rgb→xyz = P · diag(S);
//      M = M2020⁻¹ · M709  (BT.709 (0.64,0.33) (0.30,0.60) (0.15,0.06); BT.2020 (0.708,0.292)
//      (0.170,0.797) (0.131,0.046); D65 (0.3127,0.3290)). It prints
//      [0.6274039 0.3292830 0.0433131; 0.0690973 0.9195404 0.0113623; 0.0163914 0.0880133
//      0.8955953].
//   2. rgb2020 × peak / 10000; LMS = [[1688,2146,262],[683,2951,462],[99,309,3688]] / 4096 · rgb.
//   3. PQ: ((c1 + c2·Y^m1)/(1 + c3·Y^m1))^m2, m1 = 2610/16384, m2 = 2523/4096·128,
//      c1 = 3424/4096, c2 = 2413/4096·32, c3 = 2392/4096·32.
//   4. I = (L'+M')/2, Ct = (6610 L' − 13613 M' + 7003 S')/4096, Cp = (17933 L' − 17390 M' − 543
//   S')/4096.
//   5. ΔE = 720·√(ΔI² + (ΔCt/2)² + ΔCp²).
// Output: I of white at 100 cd/m² 0.5080784215 (Ct = Cp = 0); ΔE for the pairs below.
struct ItpCase {
    Rgb3 a, b;
    double peak, expected;
};

TEST(Colour, DeltaEItpMatchesAnIndependentComputation) {
    const ItpCase cases[] = {
        {{1, 1, 1}, {0.9, 0.9, 0.9}, 100.0, 7.5860208255},
        {{0.5, 0.1, 0.1}, {0.5, 0.12, 0.1}, 100.0, 9.4601808588},
        {{0.2, 0.2, 0.2}, {0.2, 0.2, 0.25}, 100.0, 8.8637211163},
        {{0.01, 0.01, 0.01}, {0.011, 0.01, 0.01}, 100.0, 2.4080977820},
        {{1, 1, 1}, {0.9, 0.9, 0.9}, 200.0, 7.9031056665},
    };
    for (const ItpCase& c : cases) {
        const double d = deltaEItp(srgbToIctcp(c.a, c.peak), srgbToIctcp(c.b, c.peak));
        // The matrix is typed to 7 digits: relative agreement to 1e-6.
        EXPECT_NEAR(d, c.expected, 1e-6 * c.expected) << c.a[0] << "," << c.a[1] << "," << c.a[2];
    }
    const Rgb3 white = srgbToIctcp({1, 1, 1}, 100.0);
    EXPECT_NEAR(white[0], 0.5080784215, 1e-7);
    EXPECT_NEAR(white[1], 0.0, 1e-6);  // white is achromatic in ICtCp (LMS rows of BT.2100)
    EXPECT_NEAR(white[2], 0.0, 1e-6);
    EXPECT_EQ(deltaEItp(white, white), 0.0);
}

TEST(Colour, CielabOfSrgbPrimaries) {
    // CIELAB (D65) of sRGB white, red, green, blue: (100, 0, 0), (53.24, 80.09, 67.20),
    // (87.73, −86.18, 83.18), (32.30, 79.19, −107.86) as tabulated (e.g. Lindbloom's calculator,
    // IEC 61966-2-1 matrix, D65 white).
    const struct {
        Rgb3 rgb, lab;
    } cases[] = {{{1, 1, 1}, {100.0, 0.0, 0.0}},
                 {{1, 0, 0}, {53.24, 80.09, 67.20}},
                 {{0, 1, 0}, {87.73, -86.18, 83.18}},
                 {{0, 0, 1}, {32.30, 79.19, -107.86}}};
    for (const auto& c : cases) {
        const Rgb3 lab = srgbToLab(c.rgb);
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(lab[size_t(k)], c.lab[size_t(k)], 0.06) << k;
    }
}

TEST(Colour, DisplayClipsAndTones) {
    EXPECT_EQ(displayed(2.0, "clip"), 1.0);
    EXPECT_EQ(displayed(-1.0, "clip"), 0.0);
    EXPECT_EQ(displayed(0.5, "shoulder"), 0.5);  // below the knee 0.6
    EXPECT_LT(displayed(1.0, "shoulder"), 1.0);
    EXPECT_THROW(displayed(0.5, "filmic"), Error);
}

TEST(Colour, ItpMetricScoresHighlightsByTheirDetectionMaps) {
    // One grey object's highlight of 0.5 on 10 pixels over a backdrop of 0.2, another's 0.5 on 5
    // other pixels: each highlight's ΔE_ITP (pixel 0.7 against 0.2 displayed at 100 cd/m²) is far
    // above 1, disjoint → the pair's e is that ΔE, the same for both.
    SeparationLayers l;
    l.width = 40;
    l.height = 1;
    l.objects = {"a", "b"};
    l.backdrop.assign(120, 0.2f);
    l.lambert.assign(2, std::vector<float>(120, 0.0f));
    l.specular.assign(2, std::vector<float>(120, 0.0f));
    for (int i = 0; i < 10; ++i)
        for (int c = 0; c < 3; ++c) l.specular[0][size_t(3 * i + c)] = 0.5f;
    for (int i = 20; i < 25; ++i)
        for (int c = 0; c < 3; ++c) l.specular[1][size_t(3 * i + c)] = 0.5f;
    const SeparationReport r = measureSeparation(l, kItpThreshold, SeparationMetric::Itp);
    const double d =
        deltaEItp(srgbToIctcp({0.7f, 0.7f, 0.7f}, 100.0), srgbToIctcp({0.2f, 0.2f, 0.2f}, 100.0));
    EXPECT_GT(d, 10.0);
    EXPECT_NEAR(r.pairs[0].metric.eSum, d, 1e-6 * d);  // the layers are floats
    EXPECT_NEAR(r.score, d, 1e-6 * d);
    EXPECT_EQ(r.pairs[0].metric.areaA, 10);
    EXPECT_EQ(r.pairs[0].metric.areaB, 5);
    EXPECT_EQ(parseSeparationMetric("itp"), SeparationMetric::Itp);
    EXPECT_THROW(parseSeparationMetric("flip"), Error);
}

}  // namespace
}  // namespace lobe
