// Reconstruction filters and gradients against fields whose answers are known by hand: linear
// ramps (both filters and both gradient methods exact), a quadratic (B-spline adds the kernel's
// variance 1/3; trilinear adds t(1 − t); both gradients exact), a single spike (the B-spline
// approximates, trilinear interpolates), and world-space gradients under anisotropic spacing.
#include "dvr_test_grids.h"
#include "volume/reconstruction.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace lobe {
namespace {

using openvdb::Coord;

double ramp(int i, int j, int k) { return 0.3 * i - 0.2 * j + 0.1 * k + 2.0; }

TEST(Reconstruction, LinearFieldIsReproducedExactly) {
    auto grid = test::makeGrid(ramp, Coord(-2), Coord(12));
    GridReconstructor r(*grid);
    // Points well inside (the 4³ B-spline support stays within the filled box).
    const Vec3 pts[] = {{3.25, 4.5, 5.75}, {5, 5, 5}, {7.9, 2.1, 8.6}};
    for (const Vec3& p : pts) {
        const double f = 0.3 * p.x - 0.2 * p.y + 0.1 * p.z + 2.0;
        EXPECT_NEAR(r.trilinear(p), f, 1e-6);  // float voxels: ~1e-7 relative
        Vec3 g;
        EXPECT_NEAR(r.bsplineWithGradient(p, g), f, 1e-6);
        EXPECT_NEAR(g.x, 0.3, 1e-6);
        EXPECT_NEAR(g.y, -0.2, 1e-6);
        EXPECT_NEAR(g.z, 0.1, 1e-6);
        const Vec3 c = r.centralDifferences(p);
        EXPECT_NEAR(c.x, 0.3, 1e-6);
        EXPECT_NEAR(c.y, -0.2, 1e-6);
        EXPECT_NEAR(c.z, 0.1, 1e-6);
    }
}

TEST(Reconstruction, QuadraticShowsApproximationVsInterpolation) {
    // f = x² (voxel values i²). At x = i + t:
    //  trilinear  (1−t)i² + t(i+1)² = x² + t(1 − t);
    //  B-spline   Σ w_a (i−1+a)² = x² + 1/3 (the cubic B-spline's variance, 4 × 1/12);
    //  B-spline derivative 2x (the derivative of x² + 1/3);
    //  central differences of the trilinear field ((x+1)² − (x−1)²)/2 = 2x (the t(1−t) terms
    //  cancel).
    auto grid = test::makeGrid([](int i, int, int) { return double(i) * i; }, Coord(-3), Coord(12));
    GridReconstructor r(*grid);
    for (double x : {2.0, 3.3, 4.75, 6.5}) {
        const Vec3 p(x, 4.2, 5.9);
        const double t = x - std::floor(x);
        EXPECT_NEAR(r.trilinear(p), x * x + t * (1 - t), 1e-5);
        Vec3 g;
        EXPECT_NEAR(r.bsplineWithGradient(p, g), x * x + 1.0 / 3.0, 1e-5);
        EXPECT_NEAR(g.x, 2 * x, 1e-5);
        EXPECT_NEAR(g.y, 0.0, 1e-6);
        EXPECT_NEAR(r.centralDifferences(p).x, 2 * x, 1e-5);
    }
}

TEST(Reconstruction, SpikeBSplineApproximatesTrilinearInterpolates) {
    // One voxel of value 1 at (4,4,4). Trilinear at the voxel centre: 1. B-spline: the weight
    // product w1(0)³ = (4/6)³ = 8/27; at a neighbour centre (5,4,4): w0(0)·w1(0)² = (1/6)(4/6)².
    auto grid = test::makeGrid([](int i, int j, int k) { return i == 4 && j == 4 && k == 4; },
                               Coord(0), Coord(8));
    GridReconstructor r(*grid);
    EXPECT_DOUBLE_EQ(r.trilinear(Vec3(4, 4, 4)), 1.0);
    EXPECT_NEAR(r.bspline(Vec3(4, 4, 4)), 8.0 / 27.0, 1e-12);
    EXPECT_NEAR(r.bspline(Vec3(5, 4, 4)), (1.0 / 6.0) * (4.0 / 6.0) * (4.0 / 6.0), 1e-12);
    EXPECT_DOUBLE_EQ(r.trilinear(Vec3(5, 4, 4)), 0.0);
}

TEST(Reconstruction, WorldGradientUnderAnisotropicSpacing) {
    // Voxel size (2, 1, 4) and origin (10, −3, 7): world = diag(2,1,4)·index + origin. A field
    // 0.3 i − 0.2 j + 0.1 k has world gradient J⁻ᵀ g = (0.3/2, −0.2/1, 0.1/4).
    auto grid = test::makeGrid(ramp, Coord(-2), Coord(12), openvdb::Vec3d(2, 1, 4),
                               openvdb::Vec3d(10, -3, 7));
    const GridGeometry geo(grid->transform());
    EXPECT_NEAR(geo.referenceVoxelLength(), 2.0, 1e-12);  // cbrt(2·1·4)
    const Vec3 w = geo.indexToWorld(Vec3(1, 2, 3));
    EXPECT_NEAR(w.x, 12.0, 1e-12);
    EXPECT_NEAR(w.y, -1.0, 1e-12);
    EXPECT_NEAR(w.z, 19.0, 1e-12);
    const Vec3 back = geo.worldToIndex(w);
    EXPECT_NEAR((back - Vec3(1, 2, 3)).length(), 0.0, 1e-12);
    GridReconstructor r(*grid);
    Vec3 g;
    r.bsplineWithGradient(Vec3(4.3, 5.1, 6.8), g);
    const Vec3 gw = geo.gradientToWorld(g);
    EXPECT_NEAR(gw.x, 0.15, 1e-6);
    EXPECT_NEAR(gw.y, -0.2, 1e-6);
    EXPECT_NEAR(gw.z, 0.025, 1e-6);
    // Check against a finite difference taken in world space.
    const double h = 1e-3;
    const Vec3 p = Vec3(4.3, 5.1, 6.8);
    const Vec3 pw = geo.indexToWorld(p);
    const double fd = (r.trilinear(geo.worldToIndex(pw + Vec3(0, 0, h))) -
                       r.trilinear(geo.worldToIndex(pw - Vec3(0, 0, h)))) /
                      (2 * h);
    EXPECT_NEAR(fd, 0.025, 1e-4);
}

TEST(Reconstruction, DenseCopyGivesTheSameBits) {
    // A sparse grid (values on a ball, background 0.25 elsewhere, inactive tiles inside the box)
    // read through a dense copy of part of it and through the tree alone: every filter returns
    // the same bits (central differences the same values up to rounding), at points inside the
    // copy, on its edges and outside it.
    openvdb::initialize();
    auto grid = openvdb::FloatGrid::create(0.25f);
    auto acc = grid->getAccessor();
    for (int k = -20; k <= 20; ++k)
        for (int j = -20; j <= 20; ++j)
            for (int i = -20; i <= 20; ++i)
                if (i * i + j * j + k * k < 300)
                    acc.setValue(Coord(i, j, k), float(std::sin(0.3 * i) + 0.1 * j * k));
    const DenseField dense(*grid, openvdb::CoordBBox(Coord(-12, -9, -15), Coord(10, 13, 8)));
    EXPECT_EQ(dense.bytes(), size_t(23 * 23 * 24) * sizeof(float));
    GridReconstructor tree(*grid), copy(*grid, &dense);
    for (int n = 0; n < 4000; ++n) {
        // Points in [-24, 24]³: the copy, its edges and beyond, the ball and the background.
        const Vec3 p(-24.0 + 48.0 * std::fmod(n * 0.61803398875, 1.0),
                     -24.0 + 48.0 * std::fmod(n * 0.41421356237, 1.0),
                     -24.0 + 48.0 * std::fmod(n * 0.73205080757, 1.0));
        ASSERT_EQ(tree.trilinear(p), copy.trilinear(p)) << p;
        // The marcher's form with floor(p) given: the same bits, from the copy and the tree.
        const int i = int(std::floor(p.x)), j = int(std::floor(p.y)), k = int(std::floor(p.z));
        ASSERT_EQ(copy.trilinear(p, i, j, k), tree.trilinear(p)) << p;
        ASSERT_EQ(tree.trilinear(p, i, j, k), tree.trilinear(p)) << p;
        ASSERT_EQ(tree.bspline(p), copy.bspline(p)) << p;
        Vec3 ga, gb;
        ASSERT_EQ(tree.bsplineWithGradient(p, ga), copy.bsplineWithGradient(p, gb)) << p;
        ASSERT_EQ(ga, gb) << p;
        // Central differences read from the copy interpolate the corners' voxel differences
        // (one read of 32 voxels) where the tree's path differences six trilinear values: the
        // same field, equal up to rounding.
        ASSERT_LT((tree.centralDifferences(p) - copy.centralDifferences(p)).length(), 1e-12) << p;
    }
    // The copy holds what the tree holds, background included.
    EXPECT_EQ(*dense.at(0, 0, 0), grid->tree().getValue(Coord(0, 0, 0)));
    EXPECT_EQ(*dense.at(-12, 13, 8), 0.25f);
    EXPECT_TRUE(dense.holds(-12, -9, -15, 4));
    EXPECT_FALSE(dense.holds(8, 0, 0, 4));  // 8 … 11 passes x = 10
}

TEST(Reconstruction, CentralDifferencesFromTheCopyAreTheCornerFormulaBitForBit) {
    // The dense path of centralDifferences (two-lane vectors over z) against the formula written
    // out here one corner at a time: the trilinear interpolation of the voxel half-differences
    // at the cell's 8 corners, lerps along x, then y, then z. Same bits at every point.
    openvdb::initialize();
    auto grid = openvdb::FloatGrid::create(0.0f);
    auto acc = grid->getAccessor();
    for (int k = -2; k <= 12; ++k)
        for (int j = -2; j <= 12; ++j)
            for (int i = -2; i <= 12; ++i)
                acc.setValue(Coord(i, j, k), float(std::sin(0.7 * i + 0.3 * j * j) * std::cos(k)));
    const DenseField dense(*grid, openvdb::CoordBBox(Coord(-2), Coord(12)));
    GridReconstructor copy(*grid, &dense);
    auto lerp = [](double a, double b, double t) { return a + t * (b - a); };
    auto voxel = [&](int i, int j, int k) { return double(*dense.at(i, j, k)); };
    for (int n = 0; n < 3000; ++n) {
        const Vec3 p(std::fmod(n * 0.61803398875, 1.0) * 9.0,
                     std::fmod(n * 0.41421356237, 1.0) * 9.0,
                     std::fmod(n * 0.73205080757, 1.0) * 9.0);
        const int i = int(std::floor(p.x)), j = int(std::floor(p.y)), k = int(std::floor(p.z));
        const double tx = p.x - i, ty = p.y - j, tz = p.z - k;
        double d[3][8];
        for (int c = 0; c < 8; ++c) {
            const int x = i + (c & 1), y = j + ((c >> 1) & 1), z = k + ((c >> 2) & 1);
            d[0][c] = 0.5 * (voxel(x + 1, y, z) - voxel(x - 1, y, z));
            d[1][c] = 0.5 * (voxel(x, y + 1, z) - voxel(x, y - 1, z));
            d[2][c] = 0.5 * (voxel(x, y, z + 1) - voxel(x, y, z - 1));
        }
        const Vec3 g = copy.centralDifferences(p);
        for (int a = 0; a < 3; ++a) {
            const double* c = d[a];
            const double want = lerp(lerp(lerp(c[0], c[1], tx), lerp(c[2], c[3], tx), ty),
                                     lerp(lerp(c[4], c[5], tx), lerp(c[6], c[7], tx), ty), tz);
            ASSERT_EQ(g[a], want) << p << " axis " << a;
        }
    }
}

TEST(Reconstruction, BSplineAlongARayMatchesPointEvaluation) {
    // The ray's polynomial per cell (bsplineOnRay) against bspline() at the same points: dense
    // samples along rays in every direction (axis-aligned ones included) through a rough field,
    // two readers alternating between rays (the cache must follow the ray, not only the cell),
    // and t decreasing as well as increasing. Values are O(1); rounding of the degree-9
    // polynomial's coefficients is ~1e-15 of them.
    openvdb::initialize();
    auto grid = test::makeGrid(
        [](int i, int j, int k) { return std::sin(0.9 * i) * std::cos(0.7 * j) + 0.05 * k * k; },
        Coord(-4), Coord(20));
    GridReconstructor onRay(*grid), alternating(*grid), atPoint(*grid);
    const Vec3 dirs[] = {Vec3(1, 0, 0),        Vec3(0, -1, 0),          Vec3(0, 0, 0.5),
                         Vec3(0.3, 0.7, -0.2), Vec3(-0.61, 0.13, 0.77), Vec3(2.0, 1.5, 0.25)};
    double worst = 0.0;
    for (const Vec3& d : dirs)
        for (const Vec3& o : {Vec3(0.37, 0.81, 0.12), Vec3(8.0, 8.0, 8.0), Vec3(3.5, 12.25, 6.0)}) {
            for (int n = 0; n <= 400; ++n) {
                const double t = (n % 2 ? 400 - n : n) * 0.0173;  // forwards and backwards
                const double v = onRay.bsplineOnRay(o, d, t);
                const double w = atPoint.bspline(o + d * t);
                worst = std::max(worst, std::abs(v - w));
                ASSERT_NEAR(v, w, 1e-12) << "o " << o << " d " << d << " t " << t;
                // Another reader alternates between this ray and a parallel one: no call may
                // reuse the other ray's polynomial.
                const Vec3 o2 = o + Vec3(0.5, 0.25, 0.0);
                ASSERT_NEAR(alternating.bsplineOnRay(o, d, t), w, 1e-12);
                ASSERT_NEAR(alternating.bsplineOnRay(o2, d, t), atPoint.bspline(o2 + d * t), 1e-12);
            }
        }
    std::printf("largest difference from point evaluation: %.3g\n", worst);
}

}  // namespace
}  // namespace lobe
