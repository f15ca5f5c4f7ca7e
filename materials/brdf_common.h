// Shared conventions of every BRDF (docs/models.md, "Conventions"):
// local frame x = tangent t, y = bitangent b, z = normal n; wi towards the light, wo towards the
// viewer, both unit and leaving the surface; every model returns the specular value f_s in sr⁻¹
// *without* the cosine, and 0 whenever either direction is at or below the horizon.
#pragma once

#include "core/math.h"
#include "core/spectrum.h"

#include <algorithm>
#include <cmath>

namespace lobe {

// Both directions strictly above the surface: the precondition for every non-zero f_s.
inline bool aboveHorizon(const Vec3& wi, const Vec3& wo) { return wi.z > 0.0 && wo.z > 0.0; }

// Mirror direction r(w) = 2(n·w)n − w, written out in the local frame where n = (0,0,1).
inline Vec3 mirrorLocal(const Vec3& w) { return Vec3(-w.x, -w.y, w.z); }

// cos α = max(0, r(wi)·wo): the angle between the viewer and the mirror direction (Phong's α).
inline double cosAlpha(const Vec3& wi, const Vec3& wo) {
    return std::max(0.0, mirrorLocal(wi).dot(wo));
}

// x^n for a whole n by repeated squaring (≤ 20 products for n ≤ 1024).
inline double powerOfWhole(double x, unsigned n) {
    double result = 1.0, square = x;
    while (n) {
        if (n & 1u) result *= square;
        n >>= 1;
        if (n) square *= square;
    }
    return result;
}

// The exponents powerOf takes by repeated squaring: whole, 0 … 1024.
inline bool isWholeExponent(double e) { return e >= 0.0 && e <= 1024.0 && e == std::floor(e); }

// x^e for x ≥ 0. A whole exponent up to 1024 (Phong's usual shininess) by repeated squaring,
// ≤ 20 products, within ~10 ulps of std::pow and about 5× cheaper; any other by std::pow.
inline double powerOf(double x, double e) {
    if (!isWholeExponent(e)) return std::pow(x, e);
    return powerOfWhole(x, static_cast<unsigned>(e));
}

// Unit half vector h = (wi + wo)/|wi + wo|; returns false when wi = −wo (h undefined).
inline bool halfVector(const Vec3& wi, const Vec3& wo, Vec3& h) {
    const Vec3 sum = wi + wo;
    const double len = sum.length();
    if (!(len > 1e-300)) return false;
    h = sum / len;
    return true;
}

// Schlick's Fresnel approximation, F(c) = F0 + (1 − F0)(1 − c)⁵ (Schlick 1994, eq. 24).
inline double fresnelSchlick(double f0, double c) {
    const double m = 1.0 - std::min(1.0, std::max(0.0, c));
    const double m2 = m * m;
    return f0 + (1.0 - f0) * m2 * m2 * m;
}

// Exact Fresnel reflectance of unpolarised light at a boundary with complex relative index of
// refraction eta + i·kappa (kappa ≥ 0) for cos of the incidence angle c ∈ [0,1]: the paper's
// eq. 1.6 (Cook & Torrance 1982, eq. 7) with the sign typo fixed, g² = η² + c² − 1, g complex.
// At c = 1 it equals ((eta−1)² + kappa²)/((eta+1)² + kappa²).
double fresnelExact(double eta, double kappa, double c);

}  // namespace lobe
