#include "core/error.h"
#include "core/math.h"
#include "core/rgb_image.h"
#include "core/spectrum.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace lobe {
namespace {

std::array<double, 2> chromaticity(const std::array<double, 3>& xyz) {
    const double s = xyz[0] + xyz[1] + xyz[2];
    return {xyz[0] / s, xyz[1] / s};
}

}  // namespace

// Each band is a CIE RGB primary, so its XYZ chromaticity must be the spectral locus at that
// wavelength (CIE 1931 2° observer; Wyszecki & Stiles table I(3.3.1)):
// 700 nm (0.73469, 0.26531), 546.1 nm (0.27368, 0.71743), 435.8 nm (0.16654, 0.00888).
TEST(Spectrum, PrimariesLieOnTheSpectralLocus) {
    const double expected[3][2] = {{0.73469, 0.26531}, {0.27368, 0.71743}, {0.16654, 0.00888}};
    for (int band = 0; band < 3; ++band) {
        Spectrum s;
        s[band] = 1.0;
        const auto xy = chromaticity(cieRgbToXyz(s));
        EXPECT_NEAR(xy[0], expected[band][0], 2e-4) << kBandNames[band];
        EXPECT_NEAR(xy[1], expected[band][1], 2e-4) << kBandNames[band];
    }
}

TEST(Spectrum, EqualEnergyIsWhiteEAndDisplaysGrey) {
    const auto xyz = cieRgbToXyz(Spectrum(1.0));
    EXPECT_NEAR(xyz[0], 1.0, 1e-9);
    EXPECT_NEAR(xyz[1], 1.0, 1e-9);
    EXPECT_NEAR(xyz[2], 1.0, 1e-9);
    const auto rgb = bandsToLinearSrgb(Spectrum(0.5));
    // Bradford E → D65 then the sRGB matrix: grey to within the 4-digit precision of the
    // published matrices.
    EXPECT_NEAR(rgb[0], 0.5, 2e-3);
    EXPECT_NEAR(rgb[1], 0.5, 2e-3);
    EXPECT_NEAR(rgb[2], 0.5, 2e-3);
}

TEST(Spectrum, RedBandDisplaysRed) {
    const auto rgb = bandsToLinearSrgb(Spectrum(1.0, 0.0, 0.0));
    EXPECT_GT(rgb[0], 0.5);
    EXPECT_GT(rgb[0], 5 * std::abs(rgb[1]));
    EXPECT_GT(rgb[0], 5 * std::abs(rgb[2]));
}

TEST(Spectrum, SrgbEncodingKnownValues) {
    EXPECT_DOUBLE_EQ(srgbEncode(0.0), 0.0);
    EXPECT_DOUBLE_EQ(srgbEncode(1.0), 1.0);
    EXPECT_NEAR(srgbEncode(0.0031308), 0.0404500, 1e-6);  // the two branches meet here
    EXPECT_NEAR(srgbEncode(0.5), 0.7353569, 1e-6);        // 1.055·0.5^(1/2.4) − 0.055
    EXPECT_DOUBLE_EQ(srgbEncode(2.0), 1.0);               // clamped
    EXPECT_DOUBLE_EQ(srgbEncode(-1.0), 0.0);
}

TEST(Spectrum, SrgbDecodingKnownValues) {
    EXPECT_DOUBLE_EQ(srgbDecode(0.0), 0.0);
    EXPECT_DOUBLE_EQ(srgbDecode(1.0), 1.0);
    EXPECT_NEAR(srgbDecode(0.04045), 0.0031308, 1e-7);  // the two branches meet here
    EXPECT_NEAR(srgbDecode(0.5), 0.2140411, 1e-6);      // ((0.5 + 0.055)/1.055)^2.4
    for (double v : {0.01, 0.2, 0.7353569}) EXPECT_NEAR(srgbEncode(srgbDecode(v)), v, 1e-12);
}

}  // namespace lobe

namespace lobe {
namespace {

TEST(ToneCurve, ShoulderIsIdentityBelowTheKneeSmoothAboveAndNeverWhite) {
    EXPECT_EQ(shoulderTone(0.3), 0.3);
    EXPECT_EQ(shoulderTone(0.6), 0.6);
    // Slope 1 at the knee from above: (f(k + h) − f(k)) / h → 1.
    EXPECT_NEAR((shoulderTone(0.6 + 1e-7) - 0.6) / 1e-7, 1.0, 1e-6);
    double last = 0.6;
    for (double x = 0.7; x < 12.0; x *= 1.3) {  // (in doubles the curve reaches 1 near x = 15)
        const double y = shoulderTone(x);
        EXPECT_GT(y, last);
        EXPECT_LT(y, 1.0);
        last = y;
    }
    // At x = k + (1 − k) ln 2 the curve is halfway from k to 1.
    EXPECT_NEAR(shoulderTone(0.6 + 0.4 * std::log(2.0)), 0.8, 1e-12);
    RgbImage img(1, 1);
    img.set(0, 0, {0.5, 2.0, 3.0});
    EXPECT_THROW(applyTone(img, "s-curve"), Error);
    applyTone(img, "shoulder");
    EXPECT_FLOAT_EQ(img.pixel(0, 0)[0], 0.5f);
    EXPECT_LT(img.pixel(0, 0)[2], 1.0f);
}

}  // namespace
}  // namespace lobe

namespace lobe {
namespace {

// What an image stores (core/math.h): NaN is 0, beyond the float range is the largest float of
// that sign (infinities included), everything else the nearest float.
TEST(ImageFloat, NonFiniteAndHugeValuesBecomeFiniteFloats) {
    constexpr float kMax = std::numeric_limits<float>::max();
    EXPECT_EQ(imageFloat(std::nan("")), 0.0f);
    EXPECT_EQ(imageFloat(HUGE_VAL), kMax);
    EXPECT_EQ(imageFloat(-HUGE_VAL), -kMax);
    EXPECT_EQ(imageFloat(2.1e236), kMax);
    EXPECT_EQ(imageFloat(-1e39), -kMax);
    EXPECT_EQ(imageFloat(0.25), 0.25f);
    EXPECT_EQ(imageFloat(1e30), float(1e30));
}

TEST(Spectrum, SrgbToBandsInvertsBandsToSrgb) {
    const Spectrum bands = linearSrgbToBands(0.2, 0.5, 0.7);
    ASSERT_GE(bands[0], 0.0);  // inside the CIE RGB gamut: no clamping, exact inverse
    const auto rgb = bandsToLinearSrgb(bands);
    EXPECT_NEAR(rgb[0], 0.2, 1e-12);
    EXPECT_NEAR(rgb[1], 0.5, 1e-12);
    EXPECT_NEAR(rgb[2], 0.7, 1e-12);
    // Pure sRGB blue lies outside the CIE RGB triangle: a band is clamped to 0, never negative.
    const Spectrum b = linearSrgbToBands(0, 0, 1);
    for (int i = 0; i < 3; ++i) EXPECT_GE(b[i], 0.0);
}

}  // namespace
}  // namespace lobe
