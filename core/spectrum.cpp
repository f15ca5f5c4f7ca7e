#include "core/spectrum.h"

#include <Imath/ImathMatrix.h>

#include <algorithm>

namespace lobe {
namespace {

using Imath::M33d;
using Imath::V3d;

// Row-vector convention of Imath (v * M) would invite mistakes: keep matrices as column
// transforms and multiply explicitly.
V3d apply(const M33d& m, const V3d& v) {
    return V3d(m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z,
               m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
               m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z);
}

M33d multiply(const M33d& a, const M33d& b) {
    M33d r;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            r[i][j] = 0.0;
            for (int k = 0; k < 3; ++k) r[i][j] += a[i][k] * b[k][j];
        }
    return r;
}

const M33d kCieRgbToXyz(0.49000, 0.31000, 0.20000,  //
                        0.17697, 0.81240, 0.01063,  //
                        0.00000, 0.01000, 0.99000);

const M33d kXyzToSrgb(3.2404542, -1.5371385, -0.4985314,  //
                      -0.9692660, 1.8760108, 0.0415560,   //
                      0.0556434, -0.2040259, 1.0572252);

// Bradford cone response matrix (Lam 1985; Lindbloom's tabulation).
const M33d kBradford(0.8951, 0.2664, -0.1614,  //
                     -0.7502, 1.7135, 0.0367,  //
                     0.0389, -0.0685, 1.0296);

M33d adaptationEToD65() {
    const V3d whiteE(1.0, 1.0, 1.0);
    const V3d whiteD65(0.95047, 1.0, 1.08883);
    const V3d coneE = apply(kBradford, whiteE);
    const V3d coneD65 = apply(kBradford, whiteD65);
    M33d scale(coneD65.x / coneE.x, 0, 0, 0, coneD65.y / coneE.y, 0, 0, 0, coneD65.z / coneE.z);
    return multiply(multiply(kBradford.inverse(), scale), kBradford);
}

const M33d& xyzToSrgbAdapted() {
    static const M33d m = multiply(kXyzToSrgb, adaptationEToD65());
    return m;
}

}  // namespace

std::array<double, 3> cieRgbToXyz(const Spectrum& bands) {
    const V3d xyz = apply(kCieRgbToXyz, V3d(bands[0], bands[1], bands[2]));
    return {xyz.x, xyz.y, xyz.z};
}

std::array<double, 3> xyzToLinearSrgb(const std::array<double, 3>& xyz) {
    const V3d rgb = apply(xyzToSrgbAdapted(), V3d(xyz[0], xyz[1], xyz[2]));
    return {rgb.x, rgb.y, rgb.z};
}

std::array<double, 3> bandsToLinearSrgb(const Spectrum& bands) {
    return xyzToLinearSrgb(cieRgbToXyz(bands));
}

double srgbEncode(double linear) {
    const double c = std::min(1.0, std::max(0.0, linear));
    return c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055;
}

double srgbDecode(double encoded) {
    return encoded <= 0.04045 ? encoded / 12.92 : std::pow((encoded + 0.055) / 1.055, 2.4);
}

Spectrum linearSrgbToBandsUnclamped(double r, double g, double b) {
    // bandsToLinearSrgb is linear (a 3×3 matrix, above); recover its columns from the
    // unit band triples and invert once.
    static const M33d kInverse = [] {
        M33d m;
        for (int j = 0; j < 3; ++j) {
            Spectrum unit(0.0);
            unit[j] = 1.0;
            const std::array<double, 3> c = bandsToLinearSrgb(unit);
            for (int i = 0; i < 3; ++i) m[i][j] = c[i];
        }
        return m.inverse();
    }();
    Spectrum out;
    const double rgb[3] = {r, g, b};
    for (int i = 0; i < 3; ++i) {
        double v = 0.0;
        for (int j = 0; j < 3; ++j) v += kInverse[i][j] * rgb[j];
        out[i] = v;
    }
    return out;
}

Spectrum linearSrgbToBands(double r, double g, double b) {
    Spectrum out = linearSrgbToBandsUnclamped(r, g, b);
    for (int i = 0; i < 3; ++i) out[i] = std::max(0.0, out[i]);
    return out;
}

}  // namespace lobe
