// Implicit primitives of the flux-overlap standard test: polynomials, their gradients, a bound on
// their second directional derivative, and the robust first-root search described in the header.
#include "surface/implicit_primitives.h"

#include "core/error.h"

#include <cmath>

namespace lobe {
namespace {

// Rotation matrices as rows (object → world): R_x(a) maps (x, y, z) to
// (x, y cos a − z sin a, y sin a + z cos a), so +a moves +y towards +z (the camera).
using Rows = std::array<Vec3, 3>;

Rows rotX(double deg) {
    const double c = std::cos(radians(deg)), s = std::sin(radians(deg));
    return {Vec3(1, 0, 0), Vec3(0, c, -s), Vec3(0, s, c)};
}
Rows rotY(double deg) {
    const double c = std::cos(radians(deg)), s = std::sin(radians(deg));
    return {Vec3(c, 0, s), Vec3(0, 1, 0), Vec3(-s, 0, c)};
}
Rows multiply(const Rows& a, const Rows& b) {
    Rows out;
    for (int i = 0; i < 3; ++i)
        out[i] =
            Vec3(a[i].dot(Vec3(b[0].x, b[1].x, b[2].x)), a[i].dot(Vec3(b[0].y, b[1].y, b[2].y)),
                 a[i].dot(Vec3(b[0].z, b[1].z, b[2].z)));
    return out;
}
// The world→object map is the transpose of object→world; its rows are the columns of R.
Rows transpose(const Rows& r) {
    return {Vec3(r[0].x, r[1].x, r[2].x), Vec3(r[0].y, r[1].y, r[2].y),
            Vec3(r[0].z, r[1].z, r[2].z)};
}

// Relative margin of the bounding sphere: the march starts where F > 0 strictly.
constexpr double kBoundMargin = 1.05;
// Smallest march step (object units, the primitives are ~1 across). Only a dip of F below zero
// narrower than this along the ray (a ray tangent to within ~1e-18) could be stepped over.
constexpr double kMinStep = 1e-9;
constexpr int kMaxMarchSteps = 100000;
constexpr int kMaxRefineSteps = 100;

}  // namespace

ImplicitPrimitive ImplicitPrimitive::sphere(double radius) {
    ImplicitPrimitive p;
    p.shape_ = ImplicitShape::Sphere;
    p.name_ = "sphere";
    p.param_ = {radius, 0.0, 0.0};
    p.boundRadius_ = kBoundMargin * radius;
    // F = |q|² − r²: H = 2I, so dᵀHd = 2 for unit d.
    p.hessianBound_ = 2.0;
    return p;
}

ImplicitPrimitive ImplicitPrimitive::torus(double majorRadius, double minorRadius,
                                           double tiltXDegrees) {
    ImplicitPrimitive p;
    p.shape_ = ImplicitShape::Torus;
    p.name_ = "torus";
    p.param_ = {majorRadius, minorRadius, 0.0};
    p.rows_ = transpose(rotX(tiltXDegrees));
    const double rho = kBoundMargin * (majorRadius + minorRadius);
    p.boundRadius_ = rho;
    // F = s² − 4R²(x²+y²), s = |q|² + R² − r². H = 4s·I + 8 q qᵀ − 8R²·diag(1,1,0), so for unit d
    // |dᵀHd| ≤ 4|s| + 8|q|² + 8R² ≤ 4(ρ² + R² + r²) + 8ρ² + 8R² on the ball |q| ≤ ρ.
    const double R2 = majorRadius * majorRadius, r2 = minorRadius * minorRadius;
    p.hessianBound_ = 4.0 * (rho * rho + R2 + r2) + 8.0 * rho * rho + 8.0 * R2;
    return p;
}

ImplicitPrimitive ImplicitPrimitive::superquadric(double level, double rotYDegrees,
                                                  double rotXDegrees) {
    ImplicitPrimitive p;
    p.shape_ = ImplicitShape::Superquadric;
    p.name_ = "superquadric";
    p.param_ = {level, 0.0, 0.0};
    // "Rotated 30° about y, then 20° about x": world = R_x · R_y · q.
    p.rows_ = transpose(multiply(rotX(rotXDegrees), rotY(rotYDegrees)));
    // Farthest surface points are the corners x = y = z = (level/3)^(1/4): |q| = √3 (level/3)^¼.
    const double rho = kBoundMargin * std::sqrt(3.0) * std::pow(level / 3.0, 0.25);
    p.boundRadius_ = rho;
    // F = x⁴ + y⁴ + z⁴ − level: H = diag(12x², 12y², 12z²), |dᵀHd| ≤ 12·max(x², y², z²) ≤ 12ρ².
    p.hessianBound_ = 12.0 * rho * rho;
    return p;
}

ImplicitPrimitive ImplicitPrimitive::byName(const std::string& name) {
    if (name == "sphere") return sphere();
    if (name == "torus") return torus();
    if (name == "superquadric") return superquadric();
    throw Error("unknown implicit primitive '" + name + "' (known: sphere, torus, superquadric)");
}

Vec3 ImplicitPrimitive::toLocal(const Vec3& w) const {
    return Vec3(rows_[0].dot(w), rows_[1].dot(w), rows_[2].dot(w));
}

Vec3 ImplicitPrimitive::toWorld(const Vec3& q) const {
    return rows_[0] * q.x + rows_[1] * q.y + rows_[2] * q.z;
}

double ImplicitPrimitive::valueLocal(const Vec3& q) const {
    switch (shape_) {
        case ImplicitShape::Sphere:
            return q.length2() - param_[0] * param_[0];
        case ImplicitShape::Torus: {
            const double R2 = param_[0] * param_[0], r2 = param_[1] * param_[1];
            const double s = q.length2() + R2 - r2;
            return s * s - 4.0 * R2 * (q.x * q.x + q.y * q.y);
        }
        case ImplicitShape::Superquadric: {
            const double x2 = q.x * q.x, y2 = q.y * q.y, z2 = q.z * q.z;
            return x2 * x2 + y2 * y2 + z2 * z2 - param_[0];
        }
    }
    return 0.0;
}

Vec3 ImplicitPrimitive::gradientLocal(const Vec3& q) const {
    switch (shape_) {
        case ImplicitShape::Sphere:
            return q * 2.0;
        case ImplicitShape::Torus: {
            const double R2 = param_[0] * param_[0], r2 = param_[1] * param_[1];
            const double s = q.length2() + R2 - r2;
            // ∇F = 4s·q − 8R²·(x, y, 0)
            return Vec3(4.0 * s * q.x - 8.0 * R2 * q.x, 4.0 * s * q.y - 8.0 * R2 * q.y,
                        4.0 * s * q.z);
        }
        case ImplicitShape::Superquadric:
            return Vec3(4.0 * q.x * q.x * q.x, 4.0 * q.y * q.y * q.y, 4.0 * q.z * q.z * q.z);
    }
    return Vec3(0.0);
}

bool ImplicitPrimitive::intersect(const Ray& ray, ImplicitHit& hit) const {
    // Work in object coordinates: a rotation keeps t and |d| = 1.
    const Vec3 o = toLocal(ray.o);
    const Vec3 d = normalized(toLocal(ray.d));
    const double dScale = ray.d.length();  // t in the caller's units if d was not unit
    if (!(dScale > 0.0)) return false;

    // Chord of the bounding sphere |o + t d|² = ρ².
    const double b = o.dot(d);
    const double c = o.length2() - boundRadius_ * boundRadius_;
    const double disc = b * b - c;
    if (disc < 0.0) return false;
    const double sq = std::sqrt(disc);
    double t = std::max(ray.tMin * dScale, -b - sq);
    const double tEnd = std::min(ray.tMax * dScale, -b + sq);
    if (!(t <= tEnd)) return false;

    const double M = hessianBound_;
    double f = valueLocal(o + d * t);
    int steps = 0;
    double lo = t, hi = t;
    bool bracketed = f <= 0.0;  // a ray starting inside reports its start
    while (!bracketed) {
        if (++steps > kMaxMarchSteps || t >= tEnd) return false;
        const double g = gradientLocal(o + d * t).dot(d);  // f'(t)
        // Positive root of f + g s − M s²/2 = 0, in the form without cancellation.
        const double root = std::sqrt(g * g + 2.0 * M * f);
        double s = g >= 0.0 ? (g + root) / M : 2.0 * f / (root - g);
        s = std::max(s, kMinStep);
        const double tNext = std::min(t + s, tEnd);
        const double fNext = valueLocal(o + d * tNext);
        if (fNext <= 0.0) {
            lo = t;
            hi = tNext;
            bracketed = true;
        } else {
            t = tNext;
            f = fNext;
        }
    }

    // Safeguarded Newton–bisection on [lo, hi], f(lo) > 0 ≥ f(hi). Newton converges from one
    // side, so stop on a small step as well as on a small bracket.
    double tHit = hi;
    if (hi > lo) {
        const double tol = 1e-13 * (1.0 + std::abs(hi));
        double x = 0.5 * (lo + hi);
        for (int i = 0; i < kMaxRefineSteps; ++i) {
            const Vec3 q = o + d * x;
            const double fx = valueLocal(q);
            tHit = x;
            if (fx == 0.0) break;
            if (fx > 0.0)
                lo = x;
            else
                hi = x;
            if (hi - lo <= tol) break;
            const double gx = gradientLocal(q).dot(d);
            const double newton = gx != 0.0 ? x - fx / gx : lo - 1.0;
            const double next = (newton > lo && newton < hi) ? newton : 0.5 * (lo + hi);
            ++steps;
            if (std::abs(next - x) <= tol) {
                tHit = next;
                break;
            }
            x = next;
        }
    }
    const Vec3 q = o + d * tHit;
    const Vec3 grad = gradientLocal(q);
    hit.t = tHit / dScale;
    hit.p = ray.o + ray.d * hit.t;
    hit.n = toWorld(normalized(grad));
    hit.steps = steps;
    return grad.length2() > 0.0;
}

}  // namespace lobe
