#include "core/spectrum.h"

#include <gtest/gtest.h>

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

}  // namespace lobe
