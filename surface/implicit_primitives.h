// Implicit primitives of the flux-overlap standard test (docs/flux-overlap.md, "The standard
// test"; the paper's "BRDF flux overlap" section: "all geometric primitives were defined as
// implicit functions"). Each is a polynomial F(q) = 0 in object coordinates q, placed in the world
// by a rotation about the origin; F < 0 inside, so the normal ∇F/|∇F| points outwards.
//
// Rays are intersected with F itself, not with a mesh: march along the ray inside the bounding
// sphere with steps that provably cannot step over a root, then refine the bracketed root with a
// safeguarded Newton–bisection. The step bound is second order: with f(t) = F(o + t·d), |d| = 1,
// and M ≥ |dᵀ H_F d| on the bounding ball (H_F the Hessian of F),
//     f(t + s) ≥ f(t) + f'(t)·s − M·s²/2,
// which stays positive for s below the positive root of that parabola. Unlike a Lipschitz (first
// order) step, this step does not shrink to zero near a grazing silhouette where f' ≈ 0 and f is
// small: it is ≥ sqrt(2f/M), so thin silhouettes are found with O(log) steps and never skipped.
// No Embree, no OpenVDB: library lobe_implicit depends on lobe_core only.
#pragma once

#include "core/math.h"
#include "core/ray.h"

#include <array>
#include <string>

namespace lobe {

enum class ImplicitShape { Sphere, Torus, Superquadric };

struct ImplicitHit {
    double t = 0.0;   // ray parameter of the first root
    Vec3 p{0.0};      // world-space hit point
    Vec3 n{0, 0, 1};  // world-space unit normal ∇F/|∇F| (outwards)
    int steps = 0;    // march steps taken (for tests and benchmarks)
};

class ImplicitPrimitive {
public:
    // The three primitives of the standard test (docs/flux-overlap.md):
    // sphere x²+y²+z² = 1;
    // torus with major radius 0.7 and minor 0.3 around the object z axis (facing the camera at
    //   +z), tilted 30° about the world x axis so that its upper rim comes towards the camera;
    // superquadric x⁴+y⁴+z⁴ = 0.6, rotated 30° about y, then 20° about x.
    static ImplicitPrimitive sphere(double radius = 1.0);
    static ImplicitPrimitive torus(double majorRadius = 0.7, double minorRadius = 0.3,
                                   double tiltXDegrees = 30.0);
    static ImplicitPrimitive superquadric(double level = 0.6, double rotYDegrees = 30.0,
                                          double rotXDegrees = 20.0);
    // By name: "sphere", "torus", "superquadric"; throws lobe::Error otherwise.
    static ImplicitPrimitive byName(const std::string& name);

    ImplicitShape shape() const { return shape_; }
    const std::string& name() const { return name_; }
    double boundingRadius() const { return boundRadius_; }

    // F at a world point (object-space polynomial after the inverse rotation).
    double value(const Vec3& world) const { return valueLocal(toLocal(world)); }
    // ∇F at a world point, in world coordinates.
    Vec3 gradient(const Vec3& world) const { return toWorld(gradientLocal(toLocal(world))); }

    // First root of F along the ray within [ray.tMin, ray.tMax]; false when the ray misses.
    bool intersect(const Ray& ray, ImplicitHit& hit) const;

    // Object ↔ world (pure rotations: the inverse is the transpose).
    Vec3 toLocal(const Vec3& w) const;
    Vec3 toWorld(const Vec3& q) const;

private:
    double valueLocal(const Vec3& q) const;
    Vec3 gradientLocal(const Vec3& q) const;

    ImplicitShape shape_ = ImplicitShape::Sphere;
    std::string name_;
    std::array<double, 3> param_{1.0, 0.0, 0.0};  // sphere r; torus R, r; superquadric level
    std::array<Vec3, 3> rows_{Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};  // world→object rows
    double boundRadius_ = 1.0;  // sphere (centred at the origin) enclosing the surface, with margin
    double hessianBound_ = 2.0;  // M ≥ |dᵀ H d| for unit d inside the bounding sphere
};

}  // namespace lobe
