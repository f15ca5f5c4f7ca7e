// Small math vocabulary shared by every module: Imath vectors in double precision and a few
// numerically careful helpers. Double precision because `lobe brdf eval` promises 9 significant
// digits and the flux-overlap test sums millions of small values.
#pragma once

#include <Imath/ImathVec.h>

#include <algorithm>
#include <cmath>

namespace lobe {

using Vec3 = Imath::V3d;
using Vec2 = Imath::V2d;

constexpr double kPi = 3.14159265358979323846;
constexpr double kInvPi = 1.0 / kPi;

inline double clamp01(double x) { return std::min(1.0, std::max(0.0, x)); }

// sqrt that treats tiny negative round-off as zero instead of returning NaN.
inline double safeSqrt(double x) { return std::sqrt(std::max(0.0, x)); }

inline double radians(double degrees) { return degrees * kPi / 180.0; }

// Vector normalised in place; a zero vector stays zero (callers check for that case explicitly).
inline Vec3 normalized(const Vec3& v) {
    const double len = v.length();
    return len > 0.0 ? v / len : Vec3(0.0);
}

// (x, y, z) as a unit vector, divided by its largest component first so that neither 1e308 nor
// 1e-300 components overflow or vanish in the length; false for the zero vector. How `lobe brdf
// eval` and the Python module's lobe.brdf.eval take their directions.
inline bool unitDirection(double x, double y, double z, Vec3& out) {
    const double m = std::max({std::abs(x), std::abs(y), std::abs(z)});
    if (!(m > 0.0)) return false;
    out = Vec3(x / m, y / m, z / m).normalized();
    return true;
}

inline bool isFinite(const Vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// A value as an image stores it: NaN becomes 0 and anything beyond the float range (±inf
// included) the largest float of its sign — an overflowing highlight is white, not a black hole
// and not an Inf in the EXR.
inline float imageFloat(double v) {
    if (std::isnan(v)) return 0.0f;
    constexpr double kMax = 3.4028234663852886e38;  // FLT_MAX
    return float(std::clamp(v, -kMax, kMax));
}

// Whether a 3×3 linear map (rows m[r][c]) is singular or so nearly that its inverse means
// nothing: |det| ≤ 1e-9 · |column 0| · |column 1| · |column 2|. Scale-free — a 1e-5 mm voxel is
// fine — and by Hadamard's inequality the ratio is 1 for orthogonal columns and falls to 0 as
// they become parallel (a shear of 1e12 gives 1e-12; marching such a grid never advanced).
template <class Matrix>
bool nearlySingular(const Matrix& m) {
    double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                 m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                 m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    double bound = 1.0;
    for (int c = 0; c < 3; ++c)
        bound *= std::sqrt(m[0][c] * m[0][c] + m[1][c] * m[1][c] + m[2][c] * m[2][c]);
    return !std::isfinite(det) || !std::isfinite(bound) || !(std::abs(det) > 1e-9 * bound);
}

}  // namespace lobe
