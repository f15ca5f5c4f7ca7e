// One voxel cell of a trilinear interpolant: its value, its analytic gradient, the cubic it
// becomes along a ray, and the first root of that cubic on an interval. The exact iso-surface
// (iso_exact.h) and the mesh method's shading normals (iso_mesh.h) both use it, so the two
// methods shade with the same gradient.
//
// Cell convention: corners c[i + 2j + 4k] are the lattice values at cell + (i, j, k); local
// coordinates u ∈ [0,1]³; f(u) = Σ c_ijk w_i(u_x) w_j(u_y) w_k(u_z) with w_0(s) = 1 − s, w_1(s) =
// s.
//
// Along a ray u(s) = u0 + s·du each weight is linear in s, so f is a cubic in s (Marmitt, Kleer,
// Wald, Friedrich, Slusallek, "Fast and Accurate Ray-Voxel Intersection Techniques for Iso-Surface
// Ray Tracing", VMV 2004, Sec. 3, eq. 3–5). The first root of f − iso on [0, L] is found as
// Marmitt et al. (Sec. 4.3) and Mitsuba 3's sdfgrid do: the roots of the derivative (a quadratic)
// split [0, L] into intervals on which the cubic is monotone; the first interval whose ends differ
// in sign holds the first root, which a safeguarded Newton/bisection then refines to ~1e-10 of
// the interval (no sign test is ever skipped, so a root is never jumped over).
#pragma once

#include "core/math.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace lobe {

struct Cubic {
    double c[4] = {0, 0, 0, 0};  // c[0] + c[1] s + c[2] s² + c[3] s³
    double operator()(double s) const { return ((c[3] * s + c[2]) * s + c[1]) * s + c[0]; }
    double derivative(double s) const { return (3.0 * c[3] * s + 2.0 * c[2]) * s + c[1]; }
};

inline double trilinearValue(const double c[8], const Vec3& u) {
    const double x00 = c[0] + (c[1] - c[0]) * u.x, x10 = c[2] + (c[3] - c[2]) * u.x;
    const double x01 = c[4] + (c[5] - c[4]) * u.x, x11 = c[6] + (c[7] - c[6]) * u.x;
    const double y0 = x00 + (x10 - x00) * u.y, y1 = x01 + (x11 - x01) * u.y;
    return y0 + (y1 - y0) * u.z;
}

// ∂f/∂u of the trilinear interpolant (differentiate each weight: w_0' = −1, w_1' = 1).
inline Vec3 trilinearGradient(const double c[8], const Vec3& u) {
    const double ux = u.x, uy = u.y, uz = u.z;
    // Differences along x at the four (j,k) edges, then bilinear in (y,z).
    const double dx00 = c[1] - c[0], dx10 = c[3] - c[2], dx01 = c[5] - c[4], dx11 = c[7] - c[6];
    const double gx = (dx00 * (1 - uy) + dx10 * uy) * (1 - uz) + (dx01 * (1 - uy) + dx11 * uy) * uz;
    const double dy00 = c[2] - c[0], dy10 = c[3] - c[1], dy01 = c[6] - c[4], dy11 = c[7] - c[5];
    const double gy = (dy00 * (1 - ux) + dy10 * ux) * (1 - uz) + (dy01 * (1 - ux) + dy11 * ux) * uz;
    const double dz00 = c[4] - c[0], dz10 = c[5] - c[1], dz01 = c[6] - c[2], dz11 = c[7] - c[3];
    const double gz = (dz00 * (1 - ux) + dz10 * ux) * (1 - uy) + (dz01 * (1 - ux) + dz11 * ux) * uy;
    return Vec3(gx, gy, gz);
}

// f(u0 + s·du) as a cubic in s, built by interpolating along x (linear in s), then y
// (quadratic), then z (cubic): the same nesting as trilinearValue, so both agree to rounding.
inline Cubic trilinearAlongRay(const double c[8], const Vec3& u0, const Vec3& du) {
    // Along x: e_jk(s) = c0jk + (c1jk − c0jk)(u0x + s dx) = a + b s.
    double ea[4], eb[4];
    for (int jk = 0; jk < 4; ++jk) {
        const double c0 = c[2 * jk], c1 = c[2 * jk + 1];
        ea[jk] = c0 + (c1 - c0) * u0.x;
        eb[jk] = (c1 - c0) * du.x;
    }
    // Along y: g_k(s) = e_0k + (e_1k − e_0k)(u0y + s dy), a quadratic q0 + q1 s + q2 s².
    double q[2][3];
    for (int k = 0; k < 2; ++k) {
        const double a0 = ea[2 * k], b0 = eb[2 * k];
        const double da = ea[2 * k + 1] - a0, db = eb[2 * k + 1] - b0;
        q[k][0] = a0 + da * u0.y;
        q[k][1] = b0 + da * du.y + db * u0.y;
        q[k][2] = db * du.y;
    }
    // Along z: f(s) = g_0 + (g_1 − g_0)(u0z + s dz).
    Cubic f;
    const double d0 = q[1][0] - q[0][0], d1 = q[1][1] - q[0][1], d2 = q[1][2] - q[0][2];
    f.c[0] = q[0][0] + d0 * u0.z;
    f.c[1] = q[0][1] + d1 * u0.z + d0 * du.z;
    f.c[2] = q[0][2] + d2 * u0.z + d1 * du.z;
    f.c[3] = d2 * du.z;
    return f;
}

// Real roots of a x² + b x + c = 0 written to r (0, 1 or 2, ascending), by the cancellation-free
// form q = −(b + sign(b)√(b² − 4ac))/2, x = q/a, c/q (Press et al., Numerical Recipes 3rd ed.,
// eq. 5.6.4–5.6.5). a = 0 falls back to the linear root.
inline int solveQuadratic(double a, double b, double c, double r[2]) {
    const double scale = std::max({std::abs(a), std::abs(b), std::abs(c)});
    if (scale == 0.0) return 0;
    if (std::abs(a) <= 1e-14 * scale) {
        if (b == 0.0) return 0;
        r[0] = -c / b;
        return 1;
    }
    const double disc = b * b - 4.0 * a * c;
    if (disc < 0.0) return 0;
    const double q = -0.5 * (b + std::copysign(std::sqrt(disc), b));
    if (q == 0.0) {  // b = 0 and c = 0: double root at 0
        r[0] = 0.0;
        return 1;
    }
    double x0 = q / a, x1 = c / q;
    if (x0 > x1) std::swap(x0, x1);
    r[0] = x0;
    r[1] = x1;
    return 2;
}

// Refines the single root of a function monotone on [lo, hi] whose end values gLo, gHi have
// opposite signs: Newton steps, replaced by bisection whenever Newton leaves the bracket
// (Numerical Recipes 3rd ed., Sec. 9.4, "rtsafe"). Stops when the bracket is narrower than tol.
inline double refineMonotoneRoot(const Cubic& g, double lo, double hi, double gLo, double tol) {
    double s = 0.5 * (lo + hi);
    for (int iter = 0; iter < 100 && hi - lo > tol; ++iter) {
        const double gs = g(s);
        if (gs == 0.0) return s;
        if ((gs < 0.0) == (gLo < 0.0)) {
            lo = s;
            gLo = gs;
        } else {
            hi = s;
        }
        const double dg = g.derivative(s);
        double next = dg != 0.0 ? s - gs / dg : lo - 1.0;
        if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
        s = next;
    }
    return s;
}

// True when the cubic g has one strict sign on [0, L] by a margin that rounding cannot cross, so
// that firstRootOnInterval(g, L, …) is certain to return false (no evaluation of g at a point of
// [0, L] can round to 0 or to the other sign) and its quadratic solve can be skipped. The test is
// the convex-hull property of the Bernstein form (Farouki & Rajan, "On the numerical condition
// of polynomials in Bernstein form", CAGD 4, 1987): with a_k = c_k L^k, g on [0, L] lies between
// the least and the greatest of b0 = a0, b1 = a0 + a1/3, b2 = a0 + 2a1/3 + a2/3,
// b3 = a0 + a1 + a2 + a3. The margin, 64 ε Σ|a_k|, exceeds the rounding of these sums and of a
// Horner evaluation of g at any s ∈ [0, L] (at most 6 ε Σ|c_k| s^k: Higham, "Accuracy and
// Stability of Numerical Algorithms", 2nd ed., §5.1) with room to spare. NaN gives false.
inline bool cubicHasNoRootOn(const Cubic& g, double length) {
    const double a0 = g.c[0], a1 = g.c[1] * length, a2 = g.c[2] * (length * length),
                 a3 = g.c[3] * (length * length * length);
    const double margin = 64.0 * std::numeric_limits<double>::epsilon() *
                          (std::abs(a0) + std::abs(a1) + std::abs(a2) + std::abs(a3));
    const double b1 = a0 + a1 * (1.0 / 3.0), b2 = a0 + a1 * (2.0 / 3.0) + a2 * (1.0 / 3.0),
                 b3 = a0 + a1 + a2 + a3;
    if (a0 > margin) return b1 > margin && b2 > margin && b3 > margin;
    if (a0 < -margin) return b1 < -margin && b2 < -margin && b3 < -margin;
    return false;
}

// First s ∈ [0, L] with g(s) = 0, where g is the cubic f − iso; false when there is none. A
// tangential touch (an even-multiplicity root strictly inside an interval) is not a crossing and
// is reported only if g is exactly 0 at a derivative root. tol: bracket width at which
// refinement stops, in s units.
inline bool firstRootOnInterval(const Cubic& g, double length, double tol, double& root) {
    double pts[4];
    int n = 0;
    pts[n++] = 0.0;
    double r[2];
    const int nr = solveQuadratic(3.0 * g.c[3], 2.0 * g.c[2], g.c[1], r);
    for (int i = 0; i < nr; ++i)
        if (r[i] > 0.0 && r[i] < length) pts[n++] = r[i];
    pts[n++] = length;
    double gPrev = g(pts[0]);
    if (gPrev == 0.0) {
        root = pts[0];
        return true;
    }
    for (int i = 1; i < n; ++i) {
        const double gi = g(pts[i]);
        if (gi == 0.0) {
            root = pts[i];
            return true;
        }
        if ((gi < 0.0) != (gPrev < 0.0)) {
            root = refineMonotoneRoot(g, pts[i - 1], pts[i], gPrev, tol);
            return true;
        }
        gPrev = gi;
    }
    return false;
}

}  // namespace lobe
