// The cubic B-spline reconstruction of GridReconstructor (volume/reconstruction.cpp: the 4³
// neighbourhood read leaf by leaf from the 8³ leaf buffers, tiles filled from one look-up, a
// block cache) against the definition, written independently of that code: the tensor-product
// cubic B-spline
//     f(p) = Σ_q β(p.x − q.x) β(p.y − q.y) β(p.z − q.z) v(q)      over voxels q,
//     β(t) = 2/3 − t² + |t|³/2 for |t| < 1,   (2 − |t|)³/6 for 1 ≤ |t| < 2,   0 beyond
// (Unser 1999, "Splines: a perfect fit for signal and image processing", eq. 4 with n = 3), and
// its gradient with β'(t) = −2t + (3/2) t|t| for |t| < 1, −sign(t) (2 − |t|)²/2 for 1 ≤ |t| < 2.
// The voxel values come from OpenVDB's own accessor, one voxel at a time. The grid mixes leaves
// with random values, 8³ tiles of a constant value and background regions, at negative and
// positive coordinates, so the 4³ block crosses leaf boundaries on every axis and meets every
// kind of node; successive points often share a block, so the cache is used too. The sums are
// formed in another order, so they agree to rounding (1e-13 of the values' scale, 1).
#include "core/rng.h"
#include "volume/reconstruction.h"

#include <gtest/gtest.h>

#include <cmath>

namespace lobe {
namespace {

using openvdb::Coord;

double beta(double t) {
    const double a = std::abs(t);
    if (a < 1.0) return 2.0 / 3.0 - a * a + 0.5 * a * a * a;
    if (a < 2.0) return (2.0 - a) * (2.0 - a) * (2.0 - a) / 6.0;
    return 0.0;
}
double betaPrime(double t) {
    const double a = std::abs(t);
    if (a < 1.0) return -2.0 * t + 1.5 * t * a;
    if (a < 2.0) return -(t > 0 ? 1.0 : -1.0) * 0.5 * (2.0 - a) * (2.0 - a);
    return 0.0;
}

// The definition summed over every voxel whose kernel can reach p (a 5³ window: β vanishes
// outside).
double definitionBSpline(openvdb::FloatGrid::ConstAccessor& acc, const Vec3& p, Vec3& gradient) {
    const int i0 = int(std::floor(p.x)) - 2, j0 = int(std::floor(p.y)) - 2,
              k0 = int(std::floor(p.z)) - 2;
    double v = 0.0;
    gradient = Vec3(0.0);
    for (int k = k0; k <= k0 + 4; ++k)
        for (int j = j0; j <= j0 + 4; ++j)
            for (int i = i0; i <= i0 + 4; ++i) {
                const double f = acc.getValue(openvdb::Coord(i, j, k));
                const double bx = beta(p.x - i), by = beta(p.y - j), bz = beta(p.z - k);
                v += bx * by * bz * f;
                gradient += Vec3(betaPrime(p.x - i) * by * bz, bx * betaPrime(p.y - j) * bz,
                                 bx * by * betaPrime(p.z - k)) *
                            f;
            }
    return v;
}

// Random voxel values on [−12, 19]³ (a 4³ arrangement of 8³ leaves), then two leaf regions
// replaced by constant tiles and one emptied back to the background (−0.5).
openvdb::FloatGrid::Ptr mixedGrid() {
    openvdb::initialize();
    auto grid = openvdb::FloatGrid::create(-0.5f);
    auto acc = grid->getAccessor();
    Rng rng(77, 3);
    for (int k = -12; k <= 19; ++k)
        for (int j = -12; j <= 19; ++j)
            for (int i = -12; i <= 19; ++i)
                acc.setValue(Coord(i, j, k), float(2.0 * rng.uniform() - 1.0));
    auto& tree = grid->tree();
    tree.addTile(1, Coord(0, 0, 0), 0.75f, true);     // the 8³ region at the origin: a tile
    tree.addTile(1, Coord(-8, 8, 0), -0.25f, false);  // an inactive tile elsewhere
    tree.addTile(1, Coord(8, -8, 8), -0.5f, false);   // background again (no leaf)
    return grid;
}

TEST(ReconstructionReference, BSplineMatchesTheDefinition) {
    const auto grid = mixedGrid();
    ASSERT_EQ(grid->tree().getValueDepth(Coord(3, 3, 3)), 2);  // tile, not leaf (depth 3)
    GridReconstructor fast(*grid);
    auto acc = grid->getConstAccessor();
    Rng rng(5, 9);
    // Random points over the whole grid and beyond its edge (background), plus points whose
    // 4³ block starts at every residue mod 8 on every axis.
    for (int n = 0; n < 20000; ++n) {
        Vec3 p(-16 + 40 * rng.uniform(), -16 + 40 * rng.uniform(), -16 + 40 * rng.uniform());
        if (n % 4 == 0)
            p = Vec3(std::floor(p.x) + (n % 8) * 0.125, std::floor(p.y) + 0.5,
                     std::floor(p.z));  // exact integers and binary fractions
        // p, then a point a small step away (mostly the same 4³ block: the cached one), value
        // first and gradient second as the marcher asks.
        for (const Vec3& q : {p, p + Vec3(0.1, -0.07, 0.05)}) {
            Vec3 g, gRef;
            const double vRef = definitionBSpline(acc, q, gRef);
            EXPECT_NEAR(fast.bspline(q), vRef, 1e-13) << q;
            EXPECT_NEAR(fast.bsplineWithGradient(q, g), vRef, 1e-13) << q;
            EXPECT_NEAR(g.x, gRef.x, 1e-13) << q;
            EXPECT_NEAR(g.y, gRef.y, 1e-13) << q;
            EXPECT_NEAR(g.z, gRef.z, 1e-13) << q;
        }
    }
}

}  // namespace
}  // namespace lobe
