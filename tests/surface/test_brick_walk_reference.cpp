// The brick walk (surface/brick_walk.h) against the walk as it stood before its clip, DDA and
// Bernstein-skipped cells were rewritten for speed (main 8c78ded, docs/performance.md, round 4):
// that walk is kept here verbatim as the reference, and the two must return the same hit bit for
// bit on every ray: random rays through bumpy shells, rays along the axes (a direction component
// of 0 takes the general path), rays through lattice edges and corners (ties between axes), rays
// starting and ending inside the brick, and searches restarted beyond each root as the hit
// gathering does (user_geometry.h). The exact iso-surface's own walk (iso_exact.cpp: a copy
// compiled for AVX-512 where the CPU has it) must give the same hits as well.
#include "core/rng.h"
#include "surface/brick_walk.h"
#include "surface/iso_exact.h"
#include "surface/trilinear_cell.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace lobe {
namespace {

template <typename Corners>
bool referenceFirstRootInBrick(const openvdb::Coord& origin, const BrickCells& cells, double iso,
                               const WalkRay& ray, double tMin, double tMax, const Corners& corners,
                               double& tHit) {
    using namespace brick_walk_detail;
    constexpr int kCells = BrickCells::kCells;
    constexpr bool kSkipByBound = true;
    if (!ray.usable) return false;
    const Vec3& o = ray.o;
    const Vec3& d = ray.d;
    const Vec3& invD = ray.invD;
    // Slab clip against the brick's index box, widened by the overlap (in t units).
    const double overlap = ray.overlap;
    double t0 = tMin, t1 = tMax;
    for (int a = 0; a < 3; ++a) {
        const double lo = origin[a], hi = origin[a] + kCells;
        if (d[a] == 0.0) {
            if (o[a] < lo - kBrickOverlapVoxels || o[a] > hi + kBrickOverlapVoxels) return false;
            continue;
        }
        double ta = (lo - o[a]) * invD[a], tb = (hi - o[a]) * invD[a];
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta - overlap);
        t1 = std::min(t1, tb + overlap);
    }
    if (!(t0 <= t1)) return false;
    {
        // Early out: [t0, t1] misses the box of the brick's straddling cells, widened by
        // kStraddleBoxMarginVoxels to cover the walk's rounding and the cells it clamps in from
        // the overlap. Else the walk covers that box only: roots lie in straddling cells, and
        // the cells outside it cannot change sign between them (two cells a ray passes in turn
        // share at least a corner, so one all below iso and one all above never meet).
        const std::array<std::uint8_t, 6>& sb = cells.straddleBox;
        double s0 = t0, s1 = t1;
        for (int a = 0; a < 3; ++a) {
            const double lo = origin[a] + sb[a] - kStraddleBoxMarginVoxels;
            const double hi = origin[a] + sb[a + 3] + kStraddleBoxMarginVoxels;
            if (d[a] == 0.0) {
                if (!(o[a] >= lo && o[a] <= hi)) return false;
                continue;
            }
            double ta = (lo - o[a]) * invD[a], tb = (hi - o[a]) * invD[a];
            if (ta > tb) std::swap(ta, tb);
            s0 = std::max(s0, ta);
            s1 = std::min(s1, tb);
        }
        if (!(s0 <= s1)) return false;
        t0 = s0;
        t1 = s1;
    }

    // DDA state per axis (Amanatides & Woo 1987): the next integer plane k, reached at
    // tNext = (k − o)/d (computed from the integer k each time so nothing drifts), and the cell
    // the ray is in, relative to the brick's first cell. The cell lies just behind k: k − 1 going
    // up, k going down; an axis the ray does not move along keeps floor(o). The first cell is
    // clamped to one outside the brick (the overlap of kBrickOverlapVoxels can start there);
    // lookups clamp it into the brick, extending the boundary cell's interpolant over the overlap.
    int step[3], cell[3];
    double k[3], tNext[3];
    for (int a = 0; a < 3; ++a) {
        const double p = o[a] + t0 * d[a];
        double c;
        if (d[a] > 0.0) {
            step[a] = 1;
            k[a] = std::floor(p) + 1.0;
            c = k[a] - 1.0;
        } else if (d[a] < 0.0) {
            step[a] = -1;
            k[a] = std::ceil(p) - 1.0;
            c = k[a];
        } else {
            step[a] = 0;
            k[a] = 0.0;
            c = std::floor(p);
        }
        tNext[a] = step[a] ? (k[a] - o[a]) * invD[a] : kInf;
        c -= origin[a];
        cell[a] = (c >= -1.0) ? (c <= kCells ? static_cast<int>(c) : kCells) : -1;
    }

    const std::uint64_t* masks = cells.masks;
    const double tol = ray.tol;
    double t = t0;
    double gPrevEnd = 0.0;  // g at the end of the previous segment; 0: none yet
    // Bounded: each pass moves at least one axis one plane (≤ ~3·(8+2) passes per brick).
    for (int guard = 0; guard < 4 * 3 * (kCells + 4) && t <= t1; ++guard) {
        const double tEnd = std::min(t1, std::min(tNext[0], std::min(tNext[1], tNext[2])));
        if (tEnd > t || (tEnd == t && t == t1)) {
            const int lx = std::min(kCells - 1, std::max(0, cell[0]));
            const int ly = std::min(kCells - 1, std::max(0, cell[1]));
            const int lz = std::min(kCells - 1, std::max(0, cell[2]));
            const std::uint64_t bit = std::uint64_t(1) << (lx + kCells * ly);
            if (masks[lz] & bit) {
                // The 8 corners straddle iso: the cubic along the segment (trilinear_cell.h).
                double c[8];
                corners(lx, ly, lz, c);
                const Vec3 p = o + d * t;
                const Vec3 u0(p.x - (origin.x() + lx), p.y - (origin.y() + ly),
                              p.z - (origin.z() + lz));
                Cubic g = trilinearAlongRay(c, u0, d);
                g.c[0] -= iso;
                const double g0 = g.c[0];
                if ((g0 < 0.0 && gPrevEnd > 0.0) || (g0 > 0.0 && gPrevEnd < 0.0)) {
                    tHit = t;  // the sign changed exactly on the face between two cells
                    return true;
                }
                double s = 0.0;
                // Most straddling cells a ray crosses hold no root on its segment: the Bernstein
                // bound proves that for most of them without the derivative's roots, and
                // firstRootOnInterval would then return false (trilinear_cell.h).
                if (!(kSkipByBound && cubicHasNoRootOn(g, tEnd - t)) &&
                    firstRootOnInterval(g, tEnd - t, tol, s)) {
                    tHit = std::min(t + s, t1);
                    return true;
                }
                gPrevEnd = g(tEnd - t);
            } else if (masks[kCells + lz] & bit) {
                if (gPrevEnd < 0.0) {
                    tHit = t;
                    return true;
                }
                gPrevEnd = 1.0;  // the whole cell is above iso
            } else {
                if (gPrevEnd > 0.0) {
                    tHit = t;
                    return true;
                }
                gPrevEnd = -1.0;  // the whole cell is below iso
            }
        }
        if (tEnd >= t1) break;
        for (int a = 0; a < 3; ++a) {
            if (tNext[a] <= tEnd) {
                k[a] += step[a];
                cell[a] += step[a];
                tNext[a] = (k[a] - o[a]) * invD[a];
            }
        }
        t = std::max(t, tEnd);
    }
    return false;
}

struct Shell {
    std::vector<float> v;
    BrickCells cells;
    openvdb::Coord origin;
    double iso = 0.0;
};

// A bumpy shell (|x − centre| − radius plus noise) in one brick; thin ones give two walls.
Shell randomShell(Rng& rng, const openvdb::Coord& origin) {
    constexpr int P = BrickCells::kPoints;
    Shell s;
    s.origin = origin;
    s.v.resize(BrickCells::kValues);
    const Vec3 centre(rng.uniform() * 8, rng.uniform() * 8, rng.uniform() * 8);
    const double radius = 1.0 + 5.0 * rng.uniform();
    const double thickness = rng.uniform() < 0.5 ? 0.6 + 1.5 * rng.uniform() : 1e9;
    for (int z = 0; z < P; ++z)
        for (int y = 0; y < P; ++y)
            for (int x = 0; x < P; ++x) {
                const double r = (Vec3(x, y, z) - centre).length() - radius;
                const double f = thickness < 1e8 ? std::abs(r) - thickness : r;
                s.v[size_t(x + P * (y + P * z))] = float(f + 0.4 * (rng.uniform() - 0.5));
            }
    s.iso = 0.1 * (rng.uniform() - 0.5);
    s.cells = BrickCells::classify(s.v.data(), s.iso);
    return s;
}

// Every root along the ray (each search from just beyond the last, as the hit gathering does)
// by both walks; counts the roots.
int compareWalks(const Shell& s, const Vec3& o, const Vec3& d, double tMin, double tMax) {
    constexpr int P = BrickCells::kPoints;
    const float* v = s.v.data();
    const auto corners = [v](int lx, int ly, int lz, double c[8]) {
        for (int k = 0; k < 8; ++k)
            c[k] = v[size_t((lx + (k & 1)) + P * ((ly + ((k >> 1) & 1)) + P * (lz + (k >> 2))))];
    };
    const WalkRay ray(o, d);
    int roots = 0;
    double a = tMin;
    for (int guard = 0; guard < 64 && a <= tMax; ++guard) {
        double tNew = -1.0, tRef = -1.0;
        const bool hitNew = firstRootInBrick(s.origin, s.cells, s.iso, ray, a, tMax, corners, tNew);
        const bool hitRef =
            referenceFirstRootInBrick(s.origin, s.cells, s.iso, ray, a, tMax, corners, tRef);
        EXPECT_EQ(hitNew, hitRef);
        if (hitNew != hitRef || !hitNew) break;
        EXPECT_EQ(tNew, tRef);
        if (tNew != tRef) break;
        ++roots;
        a = tNew + 1e-6 * (1.0 + std::abs(tNew));
    }
    return roots;
}

TEST(BrickWalkReference, RandomRaysGiveTheReferenceHitsBitForBit) {
    Rng rng(4031);
    const openvdb::Coord origin(-8, 16, 24);
    const Vec3 lo(origin.x(), origin.y(), origin.z());
    int roots = 0, rays = 0;
    for (int brick = 0; brick < 40; ++brick) {
        const Shell s = randomShell(rng, origin);
        for (int r = 0; r < 2000; ++r) {
            const Vec3 target = lo + Vec3(rng.uniform(), rng.uniform(), rng.uniform()) * 8.0;
            Vec3 d(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5);
            // Index-space directions are not unit (anisotropic voxels, world units per voxel).
            d = d * std::exp(4.0 * (rng.uniform() - 0.5));
            const double back = 12.0 / d.length();
            const Vec3 o = target - d * back;
            // Whole crossings, and segments that start or end inside the brick.
            const double tMin = r % 3 == 1 ? back * rng.uniform() * 1.5 : 0.0;
            const double tMax = r % 3 == 2 ? back * (0.5 + rng.uniform()) : 3.0 * back;
            roots += compareWalks(s, o, d, tMin, tMax);
            ++rays;
        }
    }
    EXPECT_GT(roots, rays / 4);
}

TEST(BrickWalkReference, AxisRaysAndLatticeTiesGiveTheReferenceHitsBitForBit) {
    Rng rng(77);
    const openvdb::Coord origin(0, 0, -8);
    const Vec3 lo(origin.x(), origin.y(), origin.z());
    // Directions with zero components (the general path) and with equal components (the DDA
    // steps two or three axes at once through lattice edges and corners).
    const Vec3 dirs[] = {Vec3(1, 0, 0),  Vec3(0, -1, 0),       Vec3(0, 0, 1),     Vec3(1, 1, 0),
                         Vec3(0, 1, -1), Vec3(-1, 0, 1),       Vec3(1, 1, 1),     Vec3(-1, 1, -1),
                         Vec3(2, 1, 0),  Vec3(1e-300, 1, 0.5), Vec3(0.25, 0.5, 1)};
    int roots = 0;
    for (int brick = 0; brick < 40; ++brick) {
        const Shell s = randomShell(rng, origin);
        for (const Vec3& dir : dirs)
            for (int r = 0; r < 200; ++r) {
                // Origins on lattice points, edges and faces, or anywhere.
                Vec3 target = lo + Vec3(rng.uniform(), rng.uniform(), rng.uniform()) * 8.0;
                const int snap = r % 4;
                for (int a = 0; a < snap; ++a) target[a] = std::floor(target[a]);
                const Vec3 o = target - dir * 16.0;
                roots += compareWalks(s, o, dir, 0.0, 40.0);
                roots += compareWalks(s, target, dir, 0.0, 40.0);
            }
    }
    EXPECT_GT(roots, 1000);
}

// IsoExactSurface::intersectPrimitive runs the walk compiled for AVX-512 on a CPU that has it
// (iso_exact.cpp): it must return the reference walk's hits bit for bit, on the surface's own
// bricks, for every root along random rays (each search from just beyond the last). Fails when
// that copy is compiled with floating-point contraction (fused multiply-adds).
TEST(BrickWalkReference, TheExactSurfacesWalkGivesTheReferenceHitsBitForBit) {
    Rng rng(2611);
    openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(1.0f);
    auto acc = grid->getAccessor();
    // Two bumpy shells over 3 × 2 × 2 bricks, one thin (two walls), values on 25 × 17 × 17 points.
    const Vec3 c0(7.3, 8.1, 6.6), c1(15.2, 7.7, 9.4);
    for (int z = 0; z <= 16; ++z)
        for (int y = 0; y <= 16; ++y)
            for (int x = 0; x <= 24; ++x) {
                const Vec3 p(x, y, z);
                const double a = (p - c0).length() - 5.5;
                const double b = std::abs((p - c1).length() - 4.0) - 0.8;
                acc.setValue(openvdb::Coord(x, y, z),
                             float(std::min(a, b) + 0.4 * (rng.uniform() - 0.5)));
            }
    const double iso = 0.05;
    const IsoExactSurface surface(*grid, iso, "shells");
    ASSERT_GT(surface.brickCount(), 4u);
    constexpr int P = BrickCells::kPoints;
    int roots = 0;
    for (unsigned brick = 0; brick < surface.brickCount(); ++brick) {
        const openvdb::Coord origin = surface.brickOrigin(brick);
        std::vector<float> v(BrickCells::kValues);
        for (int z = 0; z < P; ++z)
            for (int y = 0; y < P; ++y)
                for (int x = 0; x < P; ++x)
                    v[size_t(x + P * (y + P * z))] = acc.getValue(origin + openvdb::Coord(x, y, z));
        const BrickCells cells = BrickCells::classify(v.data(), iso);
        const auto corners = [&v](int lx, int ly, int lz, double c[8]) {
            for (int k = 0; k < 8; ++k)
                c[k] =
                    v[size_t((lx + (k & 1)) + P * ((ly + ((k >> 1) & 1)) + P * (lz + (k >> 2))))];
        };
        const Vec3 lo(origin.x(), origin.y(), origin.z());
        for (int r = 0; r < 3000; ++r) {
            const Vec3 target = lo + Vec3(rng.uniform(), rng.uniform(), rng.uniform()) * 8.0;
            Vec3 d(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5);
            d = d * std::exp(4.0 * (rng.uniform() - 0.5));
            if (r % 10 == 0) d[r / 10 % 3] = 0.0;  // the general path too
            const double back = 12.0 / d.length();
            const WalkRay ray(target - d * back, d);
            const double tMax = r % 2 ? back * (0.5 + rng.uniform()) : 3.0 * back;
            double a = r % 3 == 1 ? back * rng.uniform() : 0.0;
            for (int guard = 0; guard < 64 && a <= tMax; ++guard) {
                double tNew = -1.0, tRef = -1.0;
                const bool hitNew = surface.intersectPrimitive(brick, ray, a, tMax, tNew);
                const bool hitRef =
                    referenceFirstRootInBrick(origin, cells, iso, ray, a, tMax, corners, tRef);
                ASSERT_EQ(hitNew, hitRef);
                if (!hitNew) break;
                ASSERT_EQ(tNew, tRef);
                ++roots;
                a = tNew + 1e-6 * (1.0 + std::abs(tNew));
            }
        }
    }
    EXPECT_GT(roots, 5000);
}

}  // namespace
}  // namespace lobe
