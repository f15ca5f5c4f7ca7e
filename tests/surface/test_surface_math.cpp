// Unit tests of the pieces under the exact iso-surface: the trilinear cell (value, gradient, cubic
// along a ray), the quadratic and first-root solvers, the affine index ↔ world map, and the Embree
// device's error reporting.
#include "core/error.h"
#include "core/rng.h"
#include "surface/affine_map.h"
#include "surface/brick_walk.h"
#include "surface/embree_device.h"
#include "surface/trilinear_cell.h"

#include <gtest/gtest.h>

#include <cmath>

namespace lobe {
namespace {

TEST(TrilinearCell, ValueAtCornersAndCentre) {
    const double c[8] = {1, 2, 3, 4, 5, 6, 7, 8};
    // Corner (i,j,k) holds c[i + 2j + 4k].
    EXPECT_DOUBLE_EQ(trilinearValue(c, Vec3(0, 0, 0)), 1.0);
    EXPECT_DOUBLE_EQ(trilinearValue(c, Vec3(1, 0, 0)), 2.0);
    EXPECT_DOUBLE_EQ(trilinearValue(c, Vec3(0, 1, 0)), 3.0);
    EXPECT_DOUBLE_EQ(trilinearValue(c, Vec3(0, 0, 1)), 5.0);
    EXPECT_DOUBLE_EQ(trilinearValue(c, Vec3(1, 1, 1)), 8.0);
    // Centre: the mean of the corners, (1+…+8)/8 = 4.5.
    EXPECT_DOUBLE_EQ(trilinearValue(c, Vec3(0.5, 0.5, 0.5)), 4.5);
    // These corners are the linear function 1 + x + 2y + 4z, reproduced exactly, gradient (1,2,4).
    const Vec3 g = trilinearGradient(c, Vec3(0.3, 0.7, 0.1));
    EXPECT_DOUBLE_EQ(g.x, 1.0);
    EXPECT_DOUBLE_EQ(g.y, 2.0);
    EXPECT_DOUBLE_EQ(g.z, 4.0);
}

TEST(TrilinearCell, GradientMatchesFiniteDifferences) {
    Rng rng(7, 1);
    for (int n = 0; n < 200; ++n) {
        double c[8];
        for (double& v : c) v = rng.uniform() * 4.0 - 2.0;
        const Vec3 u(rng.uniform(), rng.uniform(), rng.uniform());
        const Vec3 g = trilinearGradient(c, u);
        const double h = 1e-6;
        for (int a = 0; a < 3; ++a) {
            Vec3 up = u, um = u;
            up[a] += h;
            um[a] -= h;
            // The interpolant is linear along each axis, so the central difference along one
            // axis is exact up to rounding.
            const double fd = (trilinearValue(c, up) - trilinearValue(c, um)) / (2 * h);
            EXPECT_NEAR(g[a], fd, 1e-8);
        }
    }
}

TEST(TrilinearCell, CubicAlongRayReproducesTheInterpolant) {
    Rng rng(11, 3);
    for (int n = 0; n < 200; ++n) {
        double c[8];
        for (double& v : c) v = rng.uniform() * 4.0 - 2.0;
        const Vec3 u0(rng.uniform(), rng.uniform(), rng.uniform());
        const Vec3 du(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5);
        const Cubic f = trilinearAlongRay(c, u0, du);
        for (double s : {0.0, 0.25, 0.5, 1.0, 1.7}) {
            EXPECT_NEAR(f(s), trilinearValue(c, u0 + du * s), 1e-12);
            const double h = 1e-6;
            EXPECT_NEAR(f.derivative(s), (f(s + h) - f(s - h)) / (2 * h), 1e-7);
        }
    }
}

TEST(TrilinearCell, QuadraticRoots) {
    double r[2];
    // x² − 3x + 2 = (x − 1)(x − 2).
    ASSERT_EQ(solveQuadratic(1, -3, 2, r), 2);
    EXPECT_DOUBLE_EQ(r[0], 1.0);
    EXPECT_DOUBLE_EQ(r[1], 2.0);
    // Cancellation case: x² − 1e8 x + 1 has roots ≈ 1e-8 and 1e8; the naive formula loses the small
    // one.
    ASSERT_EQ(solveQuadratic(1, -1e8, 1, r), 2);
    EXPECT_NEAR(r[0], 1e-8, 1e-20);
    EXPECT_EQ(solveQuadratic(1, 0, 1, r), 0);   // x² + 1: none
    ASSERT_EQ(solveQuadratic(0, 2, -1, r), 1);  // linear 2x − 1
    EXPECT_DOUBLE_EQ(r[0], 0.5);
    EXPECT_EQ(solveQuadratic(0, 0, 3, r), 0);  // constant
}

TEST(TrilinearCell, FirstRootOfACubicWithThreeRoots) {
    // g(s) = (s − 0.2)(s − 0.5)(s − 0.9) = s³ − 1.6 s² + 0.73 s − 0.09.
    Cubic g;
    g.c[0] = -0.09;
    g.c[1] = 0.73;
    g.c[2] = -1.6;
    g.c[3] = 1.0;
    double root = -1;
    ASSERT_TRUE(firstRootOnInterval(g, 1.0, 1e-14, root));
    EXPECT_NEAR(root, 0.2, 1e-12);
    // Shift the start past the first root: g(s + 0.3) has roots −0.1, 0.2, 0.6 → first in [0,1] is
    // 0.2.
    Cubic h;  // coefficients of g(s + 0.3), expanded by hand:
    // (s + 0.1)(s − 0.2)(s − 0.6) = s³ − 0.7 s² + 0.04 s + 0.012.
    h.c[0] = 0.012;
    h.c[1] = 0.04;
    h.c[2] = -0.7;
    h.c[3] = 1.0;
    ASSERT_TRUE(firstRootOnInterval(h, 1.0, 1e-14, root));
    EXPECT_NEAR(root, 0.2, 1e-12);
    // Between 0.25 and 0.45 g has no root: g(s + 0.25) on [0, 0.2].
    Cubic k;  // (s + 0.05)(s − 0.25)(s − 0.65) = s³ − 0.85 s² + 0.1225 s + 0.008125
    k.c[0] = 0.008125;
    k.c[1] = 0.1225;
    k.c[2] = -0.85;
    k.c[3] = 1.0;
    EXPECT_FALSE(firstRootOnInterval(k, 0.2, 1e-14, root));
    // Tangent touch that stays on one side: (s − 0.5)² + 1e-9 has no root.
    Cubic t;
    t.c[0] = 0.25 + 1e-9;
    t.c[1] = -1.0;
    t.c[2] = 1.0;
    EXPECT_FALSE(firstRootOnInterval(t, 1.0, 1e-14, root));
    // Two roots 1e-4 apart near a derivative root: (s − 0.5)² − 2.5e-9 → 0.5 ∓ 5e-5.
    t.c[0] = 0.25 - 2.5e-9;
    ASSERT_TRUE(firstRootOnInterval(t, 1.0, 1e-14, root));
    EXPECT_NEAR(root, 0.5 - 5e-5, 1e-10);
}

TEST(TrilinearCell, BernsteinBoundSkipsOnlyCubicsWithoutARoot) {
    // No root on [0, 0.2]: (s + 0.05)(s − 0.25)(s − 0.65), all Bernstein coefficients positive.
    Cubic k;
    k.c[0] = 0.008125;
    k.c[1] = 0.1225;
    k.c[2] = -0.85;
    k.c[3] = 1.0;
    EXPECT_TRUE(cubicHasNoRootOn(k, 0.2));
    double root = -1;
    EXPECT_FALSE(firstRootOnInterval(k, 0.2, 1e-14, root));
    // The same cubic on [0, 0.3] has its root at 0.25: never skipped.
    EXPECT_FALSE(cubicHasNoRootOn(k, 0.3));
    // A positive cubic the bound cannot prove ((s − 0.5)² + 1e-9: b1 < 0) is left to the solve.
    Cubic t;
    t.c[0] = 0.25 + 1e-9;
    t.c[1] = -1.0;
    t.c[2] = 1.0;
    EXPECT_FALSE(cubicHasNoRootOn(t, 1.0));
    t.c[0] = std::nan("");
    EXPECT_FALSE(cubicHasNoRootOn(t, 1.0));
    // Random cubics along random segments of random cells, many of them grazing the iso value:
    // wherever the bound skips, the solve finds no root either.
    Rng rng(2026);
    int skipped = 0, rooted = 0;
    for (int i = 0; i < 200000; ++i) {
        double c[8];
        for (double& v : c) v = rng.uniform() - 0.5;
        const Vec3 u0(rng.uniform(), rng.uniform(), rng.uniform());
        const Vec3 du =
            normalized(Vec3(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5));
        Cubic g = trilinearAlongRay(c, u0, du);
        // Shift so that g touches or nearly touches 0 somewhere: iso = g(s*) ± tiny.
        const double sStar = rng.uniform();
        g.c[0] -= g(sStar) + (rng.uniform() - 0.5) * std::ldexp(1.0, -int(rng.uniform() * 60));
        const double length = rng.uniform();
        const bool skip = cubicHasNoRootOn(g, length);
        const bool found = firstRootOnInterval(g, length, 1e-10, root);
        if (skip) {
            ++skipped;
            ASSERT_FALSE(found) << "case " << i;
        }
        rooted += found;
    }
    EXPECT_GT(skipped, 20000);  // the bound does skip
    EXPECT_GT(rooted, 20000);
}

// The brick walk with the Bernstein skip returns the same hit, bit for bit, as the walk that
// solves every straddling cell, over random rays through bricks of a bumpy sphere.
TEST(BrickWalk, BernsteinSkipLeavesEveryHitBitIdentical) {
    constexpr int P = BrickCells::kPoints;
    std::vector<float> v(BrickCells::kValues);
    Rng rng(31);
    const double iso = 0.0;
    int hits = 0, rays = 0;
    for (int brick = 0; brick < 20; ++brick) {
        const Vec3 centre(rng.uniform() * 8, rng.uniform() * 8, rng.uniform() * 8);
        const double radius = 2.0 + 4.0 * rng.uniform();
        for (int z = 0; z < P; ++z)
            for (int y = 0; y < P; ++y)
                for (int x = 0; x < P; ++x)
                    v[size_t(x + P * (y + P * z))] = float((Vec3(x, y, z) - centre).length() -
                                                           radius + 0.3 * (rng.uniform() - 0.5));
        const BrickCells cells = BrickCells::classify(v.data(), iso);
        const openvdb::Coord origin(8, -16, 0);
        const auto corners = [&](int lx, int ly, int lz, double c[8]) {
            for (int k = 0; k < 8; ++k)
                c[k] =
                    v[size_t((lx + (k & 1)) + P * ((ly + ((k >> 1) & 1)) + P * (lz + (k >> 2))))];
        };
        for (int r = 0; r < 5000; ++r) {
            const Vec3 target = Vec3(origin.x(), origin.y(), origin.z()) +
                                Vec3(rng.uniform(), rng.uniform(), rng.uniform()) * 8.0;
            const Vec3 d =
                normalized(Vec3(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5));
            const Vec3 o = target - d * 20.0;
            double tA = -1, tB = -1;
            const bool a = firstRootInBrick(origin, cells, iso, o, d, 0.0, 40.0, corners, tA);
            const bool b = firstRootInBrick<decltype(corners), false>(origin, cells, iso, o, d, 0.0,
                                                                      40.0, corners, tB);
            ASSERT_EQ(a, b) << "brick " << brick << " ray " << r;
            if (a) {
                ASSERT_EQ(tA, tB) << "brick " << brick << " ray " << r;
            }
            hits += a;
            ++rays;
        }
    }
    EXPECT_GT(hits, rays / 10);
}

TEST(AffineMap, AnisotropicSpacingAndFlip) {
    // x = diag(1, 1, 2)·u + (10, 0, −4), then flip x: A = diag(−1, 1, 2).
    openvdb::Mat4d m = openvdb::Mat4d::identity();
    m[0][0] = -1.0;
    m[2][2] = 2.0;
    m[3][0] = 10.0;
    m[3][2] = -4.0;
    const auto xform = openvdb::math::Transform::createLinearTransform(m);
    const AffineMap map = AffineMap::fromTransform(*xform);
    const Vec3 w = map.toWorld(Vec3(1, 2, 3));
    EXPECT_DOUBLE_EQ(w.x, 9.0);  // −1 + 10
    EXPECT_DOUBLE_EQ(w.y, 2.0);
    EXPECT_DOUBLE_EQ(w.z, 2.0);  // 6 − 4
    const Vec3 u = map.toIndex(w);
    EXPECT_NEAR(u.x, 1.0, 1e-15);
    EXPECT_NEAR(u.y, 2.0, 1e-15);
    EXPECT_NEAR(u.z, 3.0, 1e-15);
    // f(u) = u_z ⇒ f(x) = (x_z + 4)/2 ⇒ ∇f_world = (0, 0, 1/2); f(u) = u_x ⇒ ∇f_world = (−1, 0, 0).
    const Vec3 gz = map.gradientToWorld(Vec3(0, 0, 1));
    EXPECT_DOUBLE_EQ(gz.z, 0.5);
    EXPECT_DOUBLE_EQ(gz.x, 0.0);
    const Vec3 gx = map.gradientToWorld(Vec3(1, 0, 0));
    EXPECT_DOUBLE_EQ(gx.x, -1.0);
}

TEST(AffineMap, SingularMatrixIsAnError) {
    Mat3 singular;
    singular.m[2][2] = 0.0;
    EXPECT_THROW(AffineMap::fromMatrix(singular, Vec3(0.0)), Error);
}

TEST(EmbreeDevice, BadCallsBecomeErrorsOnTheCallingThread) {
    EmbreeDevice device("threads=1");
    EXPECT_NO_THROW(device.check("nothing wrong yet"));
    // An unknown geometry type is an invalid argument: Embree records it, check() throws once.
    RTCGeometry bad = rtcNewGeometry(device.get(), static_cast<RTCGeometryType>(999));
    EXPECT_EQ(bad, nullptr);
    try {
        device.check("making a geometry");
        ADD_FAILURE() << "no error reported";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("making a geometry"), std::string::npos) << e.what();
    }
    EXPECT_NO_THROW(device.check("after the error was reported"));
    // A user-primitive count on a triangle mesh is an invalid operation.
    RTCGeometry g = rtcNewGeometry(device.get(), RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcSetGeometryUserPrimitiveCount(g, 3);
    EXPECT_THROW(device.check("setting a primitive count"), Error);
    rtcReleaseGeometry(g);
}

}  // namespace
}  // namespace lobe
