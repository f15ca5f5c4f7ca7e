// Implicit primitives: hit points against closed forms (sphere: quadratic; torus: rays in its
// plane and parallel to its axis; superquadric: rays along an axis and the diagonal), thin grazing
// silhouettes, and random camera rays against a dense sampling of F along the ray.
#include "core/error.h"
#include "core/rng.h"
#include "surface/implicit_primitives.h"

#include <gtest/gtest.h>

#include <cmath>

namespace lobe {
namespace {

Ray makeRay(const Vec3& o, const Vec3& d) {
    Ray r;
    r.o = o;
    r.d = normalized(d);
    return r;
}

// A ray given in object coordinates, moved to the world by the primitive's rotation: its hit
// parameter must not change.
Ray objectRay(const ImplicitPrimitive& prim, const Vec3& o, const Vec3& d) {
    return makeRay(prim.toWorld(o), prim.toWorld(d));
}

TEST(ImplicitPrimitives, SphereMatchesQuadraticOnRandomCameraRays) {
    const ImplicitPrimitive sphere = ImplicitPrimitive::sphere();
    Rng rng(7);
    int hits = 0;
    for (int i = 0; i < 20000; ++i) {
        const Vec3 o(0, 0, 4);
        const Vec3 d = normalized(Vec3(2.0 * rng.uniform() - 1.0, 2.0 * rng.uniform() - 1.0, -3.0) *
                                  Vec3(0.5, 0.5, 1.0));
        // |o + t d|² = 1: t² + 2(o·d)t + |o|² − 1 = 0, first root t = −b − sqrt(b² − c).
        const double b = o.dot(d), c = o.length2() - 1.0, disc = b * b - c;
        ImplicitHit hit;
        const bool got = sphere.intersect(makeRay(o, d), hit);
        if (std::abs(disc) < 1e-12) continue;  // numerically tangent: either answer is right
        ASSERT_EQ(got, disc > 0.0) << "ray " << i << " disc " << disc;
        if (!got) continue;
        ++hits;
        const double tRef = -b - std::sqrt(disc);
        EXPECT_NEAR(hit.t, tRef, 1e-9);
        EXPECT_NEAR((hit.n - hit.p / hit.p.length()).length(), 0.0, 1e-9);  // n = p/|p|
        EXPECT_GT(hit.n.dot(-d), 0.0);  // outward, facing the camera
    }
    EXPECT_GT(hits, 5000);
}

TEST(ImplicitPrimitives, SphereThinGrazingSilhouettes) {
    const ImplicitPrimitive sphere = ImplicitPrimitive::sphere();
    // Ray parallel to z at distance x from the axis: hit at z = sqrt(1 − x²), t = 4 − z. At
    // x = 1 − 1e-12 the chord inside the sphere is 2·sqrt(2e-12) ≈ 2.8e-6 long.
    for (const double eps : {1e-3, 1e-6, 1e-9, 1e-12}) {
        const double x = 1.0 - eps;
        ImplicitHit hit;
        ASSERT_TRUE(sphere.intersect(makeRay(Vec3(x, 0, 4), Vec3(0, 0, -1)), hit)) << eps;
        EXPECT_NEAR(hit.t, 4.0 - std::sqrt(1.0 - x * x), 1e-9) << eps;
        EXPECT_FALSE(sphere.intersect(makeRay(Vec3(1.0 + eps, 0, 4), Vec3(0, 0, -1)), hit)) << eps;
    }
}

TEST(ImplicitPrimitives, TorusRaysInItsPlaneAndAlongItsAxis) {
    const double R = 0.7, r = 0.3;
    // Untilted and the test's 30° tilt: rays given in object coordinates hit at the same t.
    for (const double tilt : {0.0, 30.0}) {
        const ImplicitPrimitive torus = ImplicitPrimitive::torus(R, r, tilt);
        ImplicitHit hit;
        // In the plane z = 0 along −x from x = 4: roots at x = ±(R ± r); the first is R + r.
        ASSERT_TRUE(torus.intersect(objectRay(torus, Vec3(4, 0, 0), Vec3(-1, 0, 0)), hit));
        EXPECT_NEAR(hit.t, 4.0 - (R + r), 1e-9);
        // Normal at (R + r, 0, 0) is +x in object coordinates.
        EXPECT_NEAR((torus.toLocal(hit.n) - Vec3(1, 0, 0)).length(), 0.0, 1e-9);
        // Parallel to the axis at distance ρ from it: hit at z = sqrt(r² − (ρ − R)²), t = 4 − z;
        // ρ near R ± r are the outer and inner grazing silhouettes.
        for (const double rho : {R, R + 0.5 * r, R + r - 1e-9, R - r + 1e-9, R - 0.9 * r}) {
            ASSERT_TRUE(torus.intersect(objectRay(torus, Vec3(rho, 0, 4), Vec3(0, 0, -1)), hit))
                << "tilt " << tilt << " rho " << rho;
            const double z = std::sqrt(r * r - (rho - R) * (rho - R));
            EXPECT_NEAR(hit.t, 4.0 - z, 1e-8) << "tilt " << tilt << " rho " << rho;
        }
        // Through the hole and just outside the rims: misses.
        for (const double rho : {0.0, 0.2, R - r - 1e-9, R + r + 1e-9})
            EXPECT_FALSE(torus.intersect(objectRay(torus, Vec3(rho, 0, 4), Vec3(0, 0, -1)), hit))
                << "tilt " << tilt << " rho " << rho;
    }
}

TEST(ImplicitPrimitives, SuperquadricAxisAndDiagonalRays) {
    const double level = 0.6;
    for (const auto& [ry, rx] : {std::pair{0.0, 0.0}, std::pair{30.0, 20.0}}) {
        const ImplicitPrimitive sq = ImplicitPrimitive::superquadric(level, ry, rx);
        ImplicitHit hit;
        // Along −x: x⁴ = level → x = level^(1/4); normal +x.
        ASSERT_TRUE(sq.intersect(objectRay(sq, Vec3(4, 0, 0), Vec3(-1, 0, 0)), hit));
        EXPECT_NEAR(hit.t, 4.0 - std::pow(level, 0.25), 1e-9);
        EXPECT_NEAR((sq.toLocal(hit.n) - Vec3(1, 0, 0)).length(), 0.0, 1e-9);
        // Along the diagonal towards the origin: 3x⁴ = level → |q| = √3 (level/3)^(1/4); normal
        // ∝ (x³, x³, x³), i.e. the diagonal itself.
        const Vec3 diag = normalized(Vec3(1, 1, 1));
        ASSERT_TRUE(sq.intersect(objectRay(sq, diag * 4.0, -diag), hit));
        EXPECT_NEAR(hit.t, 4.0 - std::sqrt(3.0) * std::pow(level / 3.0, 0.25), 1e-9);
        EXPECT_NEAR((sq.toLocal(hit.n) - diag).length(), 0.0, 1e-9);
    }
}

TEST(ImplicitPrimitives, TorusRayGrazingOneTubeThenHittingTheOther) {
    // In the object plane y = 0 the torus is two circles of radius r centred at (±R, 0) in (x, z).
    // A line through the centre (−R, 0) of the far circle whose distance from the near centre
    // (R, 0) is r + δ just misses the near tube (f' ≈ 0 there, f small) and must still find the
    // far tube, at t = 4 − r from a start 4 before the far centre. Distance from (R,0) of the line
    // through (−R,0) with direction (−1, −s)/N: 2R·s/N = r + δ → s/N = k, s = k/sqrt(1 − k²).
    const double R = 0.7, r = 0.3;
    for (const double tilt : {0.0, 30.0}) {
        const ImplicitPrimitive torus = ImplicitPrimitive::torus(R, r, tilt);
        for (const double delta : {1e-2, 1e-4, 1e-7}) {
            const double k = (r + delta) / (2.0 * R), s = k / std::sqrt(1.0 - k * k);
            const Vec3 d = normalized(Vec3(-1.0, 0.0, -s));
            const Vec3 o = Vec3(-R, 0, 0) - d * 4.0;
            ImplicitHit hit;
            ASSERT_TRUE(torus.intersect(objectRay(torus, o, d), hit)) << tilt << " " << delta;
            EXPECT_NEAR(hit.t, 4.0 - r, 1e-9) << "tilt " << tilt << " delta " << delta;
        }
    }
}

// Dense reference: F sampled at n points along the ray's chord through the bounding sphere.
// Returns the first sample index with F ≤ 0, or -1.
struct Dense {
    double t0 = 0, dt = 0;
    int first = -1;
};
Dense denseFirstRoot(const ImplicitPrimitive& prim, const Ray& ray, int n) {
    const double rho = prim.boundingRadius();
    const double b = ray.o.dot(ray.d), c = ray.o.length2() - rho * rho, disc = b * b - c;
    Dense out;
    if (disc <= 0.0) return out;
    out.t0 = -b - std::sqrt(disc);
    out.dt = 2.0 * std::sqrt(disc) / n;
    for (int i = 0; i <= n; ++i)
        if (prim.value(ray.at(out.t0 + i * out.dt)) <= 0.0) {
            out.first = i;
            break;
        }
    return out;
}

TEST(ImplicitPrimitives, RandomCameraRaysAgreeWithDenseSampling) {
    for (const char* name : {"sphere", "torus", "superquadric"}) {
        const ImplicitPrimitive prim = ImplicitPrimitive::byName(name);
        Rng rng(11);
        int hits = 0, misses = 0;
        for (int i = 0; i < 400; ++i) {
            // Camera of the standard test: (0,0,4), 40° field of view (tan 20° ≈ 0.364).
            const Vec3 d(0.364 * (2.0 * rng.uniform() - 1.0), 0.364 * (2.0 * rng.uniform() - 1.0),
                         -1.0);
            const Ray ray = makeRay(Vec3(0, 0, 4), d);
            ImplicitHit hit;
            const bool got = prim.intersect(ray, hit);
            const Dense dense = denseFirstRoot(prim, ray, 20000);
            if (got) {
                ++hits;
                // On the surface: |F| small relative to |∇F|·(tolerance in t).
                EXPECT_LT(std::abs(prim.value(hit.p)), 1e-9 * prim.gradient(hit.p).length())
                    << name << " ray " << i;
                EXPECT_GT(hit.n.dot(-ray.d), -1e-9) << name;
                // Never behind the first root the dense sampling found.
                if (dense.first >= 0) {
                    EXPECT_LE(hit.t, dense.t0 + dense.first * dense.dt + 1e-9) << name << " " << i;
                }
            } else {
                ++misses;
                EXPECT_EQ(dense.first, -1) << name << " ray " << i << " missed a root";
            }
        }
        EXPECT_GT(hits, 50) << name;
        EXPECT_GT(misses, 50) << name;
    }
}

TEST(ImplicitPrimitives, SilhouettesFoundByBisectionAreConsistent) {
    // Walk outwards from the image centre in several directions, find the hit/miss boundary of
    // the intersector by bisection, and check the rays 1e-7 (in image-plane units) either side:
    // the inner one hits a point on the surface, the outer one has no root even under dense
    // sampling, so no thin silhouette is lost.
    for (const char* name : {"sphere", "torus", "superquadric"}) {
        const ImplicitPrimitive prim = ImplicitPrimitive::byName(name);
        for (int k = 0; k < 12; ++k) {
            const double phi = 2.0 * kPi * (k + 0.37) / 12.0;
            const Vec3 dir(std::cos(phi), std::sin(phi), 0.0);
            const auto rayAt = [&](double s) {
                return makeRay(Vec3(0, 0, 4), dir * s + Vec3(0, 0, -1));
            };
            ImplicitHit hit;
            double lo = 0.0, hi = 0.364;  // the outer silhouette: last hit going outwards
            if (!prim.intersect(rayAt(hi), hit)) {
                // find the outermost hit by stepping in from the edge
                double s = hi;
                while (s > 0.0 && !prim.intersect(rayAt(s), hit)) s -= 1e-3;
                ASSERT_GT(s, 0.0) << name;
                lo = s;
            }
            for (int i = 0; i < 60; ++i) {
                const double mid = 0.5 * (lo + hi);
                (prim.intersect(rayAt(mid), hit) ? lo : hi) = mid;
            }
            ASSERT_TRUE(prim.intersect(rayAt(lo - 1e-7), hit)) << name << " k " << k;
            EXPECT_LT(std::abs(prim.value(hit.p)), 1e-9 * prim.gradient(hit.p).length());
            EXPECT_FALSE(prim.intersect(rayAt(hi + 1e-7), hit));
            EXPECT_EQ(denseFirstRoot(prim, rayAt(hi + 1e-7), 200000).first, -1)
                << name << " k " << k;
        }
    }
}

TEST(ImplicitPrimitives, UnknownNameIsAnError) {
    EXPECT_THROW(ImplicitPrimitive::byName("cube"), Error);
}

}  // namespace
}  // namespace lobe
