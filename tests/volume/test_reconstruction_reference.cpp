// The optimised cubic B-spline path of GridReconstructor (volume/reconstruction.cpp: the 4³
// neighbourhood read leaf by leaf from the 8³ leaf buffers, tiles filled from one look-up)
// against the straightforward implementation it replaced, kept below as the reference: one
// accessor look-up per voxel, same weights, same summation order. The grid mixes leaves with
// random values, 8³ tiles of a constant value and background regions, at negative and positive
// coordinates, so the 4³ block crosses leaf boundaries on every axis and meets every kind of
// node; successive points often share a 4³ block, so the reconstructor's block cache is used
// too. The two must agree bit for bit: each sum is formed in the same order (at the project's
// flags; a build that lets the compiler contract a·b + c into FMAs differently in the two could
// differ by rounding).
#include <gtest/gtest.h>

#include <cmath>

#include "core/rng.h"
#include "volume/reconstruction.h"

namespace lobe {
namespace {

using openvdb::Coord;

// ---- Reference: the pre-optimisation GridReconstructor::bsplineWithGradient (commit f1d523a),
// ---- copied verbatim except for the accessor being a parameter.
void referenceWeights(double t, double w[4], double dw[4]) {
    const double s = 1.0 - t;
    const double t2 = t * t, t3 = t2 * t;
    w[0] = s * s * s / 6.0;
    w[1] = (3.0 * t3 - 6.0 * t2 + 4.0) / 6.0;
    w[2] = (-3.0 * t3 + 3.0 * t2 + 3.0 * t + 1.0) / 6.0;
    w[3] = t3 / 6.0;
    dw[0] = -0.5 * s * s;
    dw[1] = 0.5 * (3.0 * t2 - 4.0 * t);
    dw[2] = 0.5 * (-3.0 * t2 + 2.0 * t + 1.0);
    dw[3] = 0.5 * t2;
}

double referenceBSplineWithGradient(openvdb::FloatGrid::ConstAccessor& acc, const Vec3& p,
                                    Vec3& gradient) {
    const double fx = std::floor(p.x), fy = std::floor(p.y), fz = std::floor(p.z);
    const int i = int(fx) - 1, j = int(fy) - 1, k = int(fz) - 1;
    double wx[4], wy[4], wz[4], dx[4], dy[4], dz[4];
    referenceWeights(p.x - fx, wx, dx);
    referenceWeights(p.y - fy, wy, dy);
    referenceWeights(p.z - fz, wz, dz);
    double v = 0.0, gx = 0.0, gy = 0.0, gz = 0.0;
    for (int c = 0; c < 4; ++c) {
        double vz = 0.0, gxz = 0.0, gyz = 0.0;
        for (int b = 0; b < 4; ++b) {
            double vx = 0.0, dvx = 0.0;
            for (int a = 0; a < 4; ++a) {
                const double f = acc.getValue(openvdb::Coord(i + a, j + b, k + c));
                vx += wx[a] * f;
                dvx += dx[a] * f;
            }
            vz += wy[b] * vx;
            gxz += wy[b] * dvx;
            gyz += dy[b] * vx;
        }
        v += wz[c] * vz;
        gx += wz[c] * gxz;
        gy += wz[c] * gyz;
        gz += dz[c] * vz;
    }
    gradient = Vec3(gx, gy, gz);
    return v;
}
// ---- End of the reference.

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

TEST(ReconstructionReference, BSplineMatchesPerVoxelReferenceBitForBit) {
    const auto grid = mixedGrid();
    ASSERT_EQ(grid->tree().getValueDepth(Coord(3, 3, 3)), 2);  // tile, not leaf (depth 3)
    GridReconstructor fast(*grid);
    auto acc = grid->getConstAccessor();
    Rng rng(5, 9);
    // Random points over the whole grid and beyond its edge (background), plus points whose
    // 4³ block starts at every residue mod 8 on every axis.
    for (int n = 0; n < 20000; ++n) {
        Vec3 p(-16 + 40 * rng.uniform(), -16 + 40 * rng.uniform(), -16 + 40 * rng.uniform());
        if (n % 4 == 0) p = Vec3(std::floor(p.x) + (n % 8) * 0.125, std::floor(p.y) + 0.5,
                                 std::floor(p.z));  // exact integers and binary fractions
        // p, then a point a small step away (mostly the same 4³ block: the cached one), value
        // first and gradient second as the marcher asks.
        for (const Vec3& q : {p, p + Vec3(0.1, -0.07, 0.05)}) {
            Vec3 g, gRef;
            const double vRef = referenceBSplineWithGradient(acc, q, gRef);
            EXPECT_EQ(fast.bspline(q), vRef) << q;
            EXPECT_EQ(fast.bsplineWithGradient(q, g), vRef) << q;
            EXPECT_EQ(g.x, gRef.x) << q;
            EXPECT_EQ(g.y, gRef.y) << q;
            EXPECT_EQ(g.z, gRef.z) << q;
        }
    }
}

}  // namespace
}  // namespace lobe
