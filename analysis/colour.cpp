#include "analysis/colour.h"

#include "core/error.h"
#include "core/rgb_image.h"

#include <algorithm>
#include <cmath>

namespace lobe {

bool toneIsShoulder(const std::string& tone) {
    if (tone == "clip") return false;
    if (tone == "shoulder") return true;
    throw Error("unknown tone curve '" + tone + "' (expected clip or shoulder)");
}

double displayedShoulder(double x, bool shoulder) {
    if (!(x > 0.0)) return 0.0;  // also NaN
    return std::min(1.0, shoulder ? shoulderTone(x) : x);
}

double displayed(double x, const std::string& tone) {
    return displayedShoulder(x, toneIsShoulder(tone));
}

Rgb3 srgbToLab(const Rgb3& c) {
    // IEC 61966-2-1 linear sRGB → XYZ (D65); the white (1,1,1) → the matrix's row sums.
    const double X = 0.4124 * c[0] + 0.3576 * c[1] + 0.1805 * c[2];
    const double Y = 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
    const double Z = 0.0193 * c[0] + 0.1192 * c[1] + 0.9505 * c[2];
    constexpr double Xn = 0.4124 + 0.3576 + 0.1805, Yn = 1.0, Zn = 0.0193 + 0.1192 + 0.9505;
    // CIE 15:2004 eq. 8.2: f(t) = t^(1/3) above (6/29)³, else t/(3 (6/29)²) + 4/29.
    const auto f = [](double t) {
        constexpr double d = 6.0 / 29.0;
        return t > d * d * d ? std::cbrt(t) : t / (3.0 * d * d) + 4.0 / 29.0;
    };
    const double fx = f(X / Xn), fy = f(Y / Yn), fz = f(Z / Zn);
    return {116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz)};
}

Rgb3 srgbToIctcp(const Rgb3& c, double peak) {
    // ITU-R BT.2087-0, §2 (M = RGB→XYZ of BT.2020, inverted, times RGB→XYZ of BT.709).
    const double r = 0.6274039 * c[0] + 0.3292830 * c[1] + 0.0433131 * c[2];
    const double g = 0.0690973 * c[0] + 0.9195404 * c[1] + 0.0113623 * c[2];
    const double b = 0.0163914 * c[0] + 0.0880133 * c[1] + 0.8955953 * c[2];
    // ITU-R BT.2100-2, Table 6 (ICtCp), on absolute light normalised to 10000 cd/m².
    const double s = peak / 10000.0;
    const double L = (1688.0 * r + 2146.0 * g + 262.0 * b) / 4096.0 * s;
    const double M = (683.0 * r + 2951.0 * g + 462.0 * b) / 4096.0 * s;
    const double S = (99.0 * r + 309.0 * g + 3688.0 * b) / 4096.0 * s;
    // SMPTE ST 2084 inverse EOTF.
    const auto pq = [](double y) {
        constexpr double m1 = 2610.0 / 16384.0, m2 = 2523.0 / 4096.0 * 128.0;
        constexpr double c1 = 3424.0 / 4096.0, c2 = 2413.0 / 4096.0 * 32.0,
                         c3 = 2392.0 / 4096.0 * 32.0;
        const double ym = std::pow(std::max(y, 0.0), m1);
        return std::pow((c1 + c2 * ym) / (1.0 + c3 * ym), m2);
    };
    const double Lp = pq(L), Mp = pq(M), Sp = pq(S);
    return {0.5 * Lp + 0.5 * Mp, (6610.0 * Lp - 13613.0 * Mp + 7003.0 * Sp) / 4096.0,
            (17933.0 * Lp - 17390.0 * Mp - 543.0 * Sp) / 4096.0};
}

double deltaEItp(const Rgb3& a, const Rgb3& b) {
    const double dI = a[0] - b[0], dT = 0.5 * (a[1] - b[1]), dP = a[2] - b[2];
    return 720.0 * std::sqrt(dI * dI + dT * dT + dP * dP);
}

}  // namespace lobe
