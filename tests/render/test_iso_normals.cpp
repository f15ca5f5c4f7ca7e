// Smooth shading normals on iso-surfaces ("normals": "bspline", render/scene.h smoothIsoNormal):
// the trilinear interpolant's gradient turns at every cell face, so a coarse iso-surface shows
// one facet per cell; the cubic B-spline's gradient is continuous there. On a ball field
// f = 1 − r/12 (radial, so the true normal is the radial direction) sampled on integer voxels.
#include "render/scene.h"

#include <gtest/gtest.h>
#include <openvdb/openvdb.h>

#include <cmath>

namespace lobe {
namespace {

const Vec3 kCentre(15.3, 15.6, 15.45);  // off the lattice, so no symmetry helps

double ball(const Vec3& p) { return std::max(0.0, 1.0 - (p - kCentre).length() / 12.0); }

openvdb::FloatGrid::Ptr ballGrid() {
    openvdb::initialize();
    openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(0.0f);
    auto acc = grid->getAccessor();
    for (int z = 0; z < 32; ++z)
        for (int y = 0; y < 32; ++y)
            for (int x = 0; x < 32; ++x)
                acc.setValue(openvdb::Coord(x, y, z), float(ball(Vec3(x, y, z))));
    return grid;
}

// The gradient of the trilinear interpolant of the voxel values at p (the iso-surface methods'
// own normal), by hand: cell corners at integer coordinates.
Vec3 trilinearGradient(const Vec3& p) {
    const int x0 = int(std::floor(p.x)), y0 = int(std::floor(p.y)), z0 = int(std::floor(p.z));
    const double fx = p.x - x0, fy = p.y - y0, fz = p.z - z0;
    auto v = [&](int dx, int dy, int dz) { return ball(Vec3(x0 + dx, y0 + dy, z0 + dz)); };
    Vec3 g(0.0);
    for (int dz = 0; dz < 2; ++dz)
        for (int dy = 0; dy < 2; ++dy)
            for (int dx = 0; dx < 2; ++dx) {
                const double wx = dx ? fx : 1 - fx, wy = dy ? fy : 1 - fy, wz = dz ? fz : 1 - fz;
                const double sx = dx ? 1 : -1, sy = dy ? 1 : -1, sz = dz ? 1 : -1;
                const double val = v(dx, dy, dz);
                g += Vec3(sx * wy * wz, wx * sy * wz, wx * wy * sz) * val;
            }
    return g;
}

double angle(const Vec3& a, const Vec3& b) {
    return std::acos(std::clamp(a.dot(b) / (a.length() * b.length()), -1.0, 1.0));
}

TEST(IsoNormals, BSplineNormalsAreContinuousAcrossCellFacesAndTrilinearOnesAreNot) {
    const openvdb::FloatGrid::Ptr grid = ballGrid();
    const GridGeometry geometry(grid->transform());
    // Points on the iso-surface f = 0.5 (radius 6) that lie on a cell face x = integer, and the
    // normals just either side of that face.
    double bsplineJump = 0.0, trilinearJump = 0.0, bsplineError = 0.0;
    int n = 0;
    for (int k = 0; k < 40; ++k) {
        const double theta = 0.3 + 2.5 * k / 40.0, phi = 0.7 * k;
        const Vec3 dir(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                       std::cos(theta));
        Vec3 p = kCentre + dir * 6.0;
        p.x = std::round(
            p.x);  // onto the nearest face x = const (still within a cell of the surface)
        const Vec3 e(1e-7, 0, 0);
        const Vec3 out = (p - kCentre) * (1.0 / (p - kCentre).length());
        const Vec3 b0 = smoothIsoNormal(*grid, geometry, p - e, out);
        const Vec3 b1 = smoothIsoNormal(*grid, geometry, p + e, out);
        bsplineJump = std::max(bsplineJump, angle(b0, b1));
        trilinearJump =
            std::max(trilinearJump, angle(trilinearGradient(p - e), trilinearGradient(p + e)));
        bsplineError += angle(b0, out);
        EXPECT_GT(b0.dot(out), 0.0);  // turned to the fallback's side
        EXPECT_NEAR(b0.length(), 1.0, 1e-12);
        ++n;
    }
    EXPECT_LT(bsplineJump, 1e-5);
    EXPECT_GT(trilinearJump, 0.02);     // a visible facet edge (> 1°)
    EXPECT_LT(bsplineError / n, 0.05);  // and close to the true (radial) normal on average
    std::printf(
        "largest jump across a face: bspline %.2e rad, trilinear %.3f rad; bspline mean "
        "error %.4f rad\n",
        bsplineJump, trilinearJump, bsplineError / n);
    // Where the field is flat the hit's own normal is kept.
    const Vec3 fallback(0, 0, 1);
    EXPECT_EQ(smoothIsoNormal(*grid, geometry, Vec3(1, 1, 1), fallback).z, 1.0);
}

}  // namespace
}  // namespace lobe
