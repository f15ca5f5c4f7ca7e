// The three wavelength bands every BRDF is evaluated at: 700.0, 546.1 and 435.8 nm, the CIE 1931
// RGB primaries (docs/models.md, "Conventions"). Because the bands *are* the CIE RGB
// primaries, a band triple is a CIE RGB colour and converts to display colour through
// CIE RGB → XYZ → linear sRGB.
#pragma once

#include <array>
#include <cmath>

namespace lobe {

constexpr int kBandCount = 3;
constexpr std::array<double, kBandCount> kBandWavelengthsNm = {700.0, 546.1, 435.8};
// Channel names used in EXR files and CSV headers.
constexpr std::array<const char*, kBandCount> kBandNames = {"700", "546.1", "435.8"};

struct Spectrum {
    std::array<double, kBandCount> v{0.0, 0.0, 0.0};

    Spectrum() = default;
    explicit Spectrum(double x) : v{x, x, x} {}
    Spectrum(double a, double b, double c) : v{a, b, c} {}

    double& operator[](int i) { return v[i]; }
    double operator[](int i) const { return v[i]; }

    Spectrum& operator+=(const Spectrum& o) {
        for (int i = 0; i < kBandCount; ++i) v[i] += o.v[i];
        return *this;
    }
    Spectrum& operator*=(double s) {
        for (double& x : v) x *= s;
        return *this;
    }
    friend Spectrum operator+(Spectrum a, const Spectrum& b) { return a += b; }
    friend Spectrum operator*(Spectrum a, double s) { return a *= s; }
    friend Spectrum operator*(double s, Spectrum a) { return a *= s; }
    friend Spectrum operator*(const Spectrum& a, const Spectrum& b) {
        return {a.v[0] * b.v[0], a.v[1] * b.v[1], a.v[2] * b.v[2]};
    }
    double maxValue() const { return std::max(v[0], std::max(v[1], v[2])); }
    double average() const { return (v[0] + v[1] + v[2]) / 3.0; }
    bool operator==(const Spectrum& o) const {
        return v[0] == o.v[0] && v[1] == o.v[1] && v[2] == o.v[2];
    }
    bool operator!=(const Spectrum& o) const { return !(*this == o); }
    bool isFinite() const {
        return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
    }
};

// CIE 1931 RGB (the band triple) → CIE XYZ, normalised so that the equal-energy triple (1,1,1)
// maps to the equal-energy white X = Y = Z = 1 (CIE 1931 standard observer definition; Wyszecki &
// Stiles, "Color Science", 2nd ed., table 3.3 without its 1/0.17697 luminance factor).
std::array<double, 3> cieRgbToXyz(const Spectrum& bands);

// CIE XYZ → linear sRGB (IEC 61966-2-1), after a Bradford chromatic adaptation from the
// equal-energy white E to sRGB's D65, so that a band-flat (grey) surface lit by band-flat light
// is displayed grey rather than pink.
std::array<double, 3> xyzToLinearSrgb(const std::array<double, 3>& xyz);

// Both steps at once: the conversion every image uses.
std::array<double, 3> bandsToLinearSrgb(const Spectrum& bands);

// Inverse of bandsToLinearSrgb, each band clamped to ≥ 0: sRGB colour names and label colours
// (transfer functions, segmentations) to bands. sRGB colours outside the CIE RGB gamut (pure
// blue) lose their negative band.
Spectrum linearSrgbToBands(double r, double g, double b);
// The same without the clamp: a colour outside the CIE RGB gamut keeps negative bands, so that
// it displays exactly (a solid image background, render/background.cpp).
Spectrum linearSrgbToBandsUnclamped(double r, double g, double b);

// sRGB transfer function (IEC 61966-2-1) of a linear value clamped to [0, 1].
double srgbEncode(double linear);
// Its inverse (IEC 61966-2-1): the linear value of an encoded value in [0, 1].
double srgbDecode(double encoded);

}  // namespace lobe
