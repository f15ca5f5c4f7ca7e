// The exact iso-surface's brick traversal (surface/iso_exact.cpp: integer 3-D DDA plus per-brick
// cell-class masks) against the straightforward per-cell code it replaced, kept here as the
// reference: cut the ray at every cell-face crossing, take each segment's cell as floor() of the
// segment's midpoint clamped into the brick, read the cell's 8 corners (here through an OpenVDB
// accessor on the grid itself, not the surface's brick copy), skip cells whose corners are all
// above or all below iso, else solve the trilinear cubic along the segment (trilinear_cell.h,
// Marmitt et al., VMV 2004). Both must give the same hits: same hit/miss per (ray, brick), t equal
// to rounding (1e-9 voxel), and through SurfaceScene the same first hit t and normal (the normal is
// −∇f of the same trilinear cell, carried to world space by A⁻ᵀ).
//
// Rays: random ones through a 20³ synthetic grid (a sum of sines, so most cells near the surface
// straddle iso and bricks meet in the middle of the grid), lattice-aligned ones (along voxel edges,
// faces and diagonals through lattice points, where several cell-face crossings coincide exactly),
// and random ones with random tMin through the CThead skull at iso 0.5 (assets/cthead, spacing
// 1,1,2, so a non-identity index → world map), where a ray crosses several bone walls.
#include "core/rng.h"
#include "surface/iso_exact.h"
#include "surface/surface_scene.h"
#include "surface/trilinear_cell.h"
#include "surface_test_grids.h"
#include "volume/volume.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <optional>
#include <vector>

namespace lobe {
namespace {

class OpenVdbInit : public ::testing::Environment {
public:
    void SetUp() override { openvdb::initialize(); }
};
const auto* const kOpenVdbEnv = ::testing::AddGlobalTestEnvironment(new OpenVdbInit);

constexpr int kB = IsoExactSurface::kBrickCells;
constexpr double kInf = std::numeric_limits<double>::infinity();

// ---------------------------------------------------------------------------------------------
// Reference: the previous IsoExactSurface::intersectBrick (midpoint cell, clamped), verbatim in
// its logic, reading corners from the grid.

struct ReferenceBricks {
    const openvdb::FloatGrid& grid;
    double iso;

    openvdb::Coord clampCell(const openvdb::Coord& org, const Vec3& u) const {
        openvdb::Coord cell;
        for (int a = 0; a < 3; ++a) {
            const double f = std::floor(u[a]);
            const double lo = org[a], hi = org[a] + kB - 1;
            cell[a] = static_cast<int>(std::min(hi, std::max(lo, std::isfinite(f) ? f : lo)));
        }
        return cell;
    }

    void corners(const openvdb::Coord& cell, double c[8]) const {
        auto acc = grid.getConstAccessor();
        for (int i = 0; i < 8; ++i)
            c[i] = acc.getValue(cell + openvdb::Coord(i & 1, (i >> 1) & 1, (i >> 2) & 1));
    }

    bool intersect(const openvdb::Coord& org, const Vec3& o, const Vec3& d, double tMin,
                   double tMax, double& tHit) const {
        const double dLen = d.length();
        if (!(dLen > 0.0) || !std::isfinite(dLen)) return false;
        const double overlap = 1e-7 / dLen;
        double t0 = tMin, t1 = tMax;
        for (int a = 0; a < 3; ++a) {
            const double lo = org[a], hi = org[a] + kB;
            if (d[a] == 0.0) {
                if (o[a] < lo - 1e-7 || o[a] > hi + 1e-7) return false;
                continue;
            }
            double ta = (lo - o[a]) / d[a], tb = (hi - o[a]) / d[a];
            if (ta > tb) std::swap(ta, tb);
            t0 = std::max(t0, ta - overlap);
            t1 = std::min(t1, tb + overlap);
        }
        if (!(t0 <= t1)) return false;
        int step[3];
        double k[3], tNext[3];
        for (int a = 0; a < 3; ++a) {
            const double p = o[a] + t0 * d[a];
            if (d[a] > 0.0) {
                step[a] = 1;
                k[a] = std::floor(p) + 1.0;
            } else if (d[a] < 0.0) {
                step[a] = -1;
                k[a] = std::ceil(p) - 1.0;
            } else {
                step[a] = 0;
                k[a] = 0.0;
            }
            tNext[a] = step[a] ? (k[a] - o[a]) / d[a] : kInf;
        }
        const double tol = 1e-10 / dLen;
        double t = t0, gPrevEnd = 0.0;
        for (int guard = 0; guard < 4 * 3 * (kB + 4) && t <= t1; ++guard) {
            const double tEnd = std::min(t1, std::min(tNext[0], std::min(tNext[1], tNext[2])));
            if (tEnd > t || (tEnd == t && t == t1)) {
                const openvdb::Coord cell = clampCell(org, o + d * (0.5 * (t + tEnd)));
                double c[8];
                corners(cell, c);
                const double cMin = *std::min_element(c, c + 8);
                const double cMax = *std::max_element(c, c + 8);
                if (cMin > iso) {
                    if (gPrevEnd < 0.0) { tHit = t; return true; }
                    gPrevEnd = 1.0;
                } else if (cMax < iso) {
                    if (gPrevEnd > 0.0) { tHit = t; return true; }
                    gPrevEnd = -1.0;
                } else {
                    const Vec3 p = o + d * t;
                    const Vec3 u0(p.x - cell.x(), p.y - cell.y(), p.z - cell.z());
                    Cubic g = trilinearAlongRay(c, u0, d);
                    g.c[0] -= iso;
                    const double g0 = g.c[0];
                    if ((g0 < 0.0 && gPrevEnd > 0.0) || (g0 > 0.0 && gPrevEnd < 0.0)) {
                        tHit = t;
                        return true;
                    }
                    double s = 0.0;
                    if (firstRootOnInterval(g, tEnd - t, tol, s)) {
                        tHit = std::min(t + s, t1);
                        return true;
                    }
                    gPrevEnd = g(tEnd - t);
                }
            }
            if (tEnd >= t1) break;
            for (int a = 0; a < 3; ++a) {
                if (tNext[a] <= tEnd) {
                    k[a] += step[a];
                    tNext[a] = (k[a] - o[a]) / d[a];
                }
            }
            t = std::max(t, tEnd);
        }
        return false;
    }

    // World-space normal at index point u of brick org: −A⁻ᵀ∇f, normalised (iso_exact.cpp).
    Vec3 normal(const IsoExactSurface& s, const openvdb::Coord& org, const Vec3& u) const {
        const openvdb::Coord cell = clampCell(org, u);
        double c[8];
        corners(cell, c);
        const Vec3 local(u.x - cell.x(), u.y - cell.y(), u.z - cell.z());
        return normalized(-s.map().gradientToWorld(trilinearGradient(c, local)));
    }
};

// Does the index ray o + t·d, t ∈ [tMin, tMax], touch brick org's box (widened by 1e-3)?
bool touchesBrick(const openvdb::Coord& org, const Vec3& o, const Vec3& d, double tMin,
                  double tMax) {
    double t0 = tMin, t1 = tMax;
    for (int a = 0; a < 3; ++a) {
        const double lo = org[a] - 1e-3, hi = org[a] + kB + 1e-3;
        if (d[a] == 0.0) {
            if (o[a] < lo || o[a] > hi) return false;
            continue;
        }
        double ta = (lo - o[a]) / d[a], tb = (hi - o[a]) / d[a];
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
    }
    return t0 <= t1;
}

struct Comparison {
    long pairs = 0, hits = 0, hitMismatches = 0, bitIdentical = 0;
    double maxDtVoxels = 0.0;  // |Δt|·|d|, index units
};

// Every (ray, brick) pair the ray touches: hit/miss and t of the surface against the reference.
void compareBricks(const IsoExactSurface& s, const ReferenceBricks& ref, const Vec3& o,
                   const Vec3& d, double tMin, double tMax, Comparison& cmp) {
    for (unsigned b = 0; b < s.brickCount(); ++b) {
        const openvdb::Coord& org = s.brickOrigin(b);
        if (!touchesBrick(org, o, d, tMin, tMax)) continue;
        ++cmp.pairs;
        double tNew = 0.0, tRef = 0.0;
        const bool hNew = s.intersectBrick(b, o, d, tMin, tMax, tNew);
        const bool hRef = ref.intersect(org, o, d, tMin, tMax, tRef);
        if (hNew != hRef) {
            ++cmp.hitMismatches;
            ADD_FAILURE() << "brick " << org << " ray o=" << o << " d=" << d << " tMin=" << tMin
                          << ": hit " << hNew << " (t " << tNew << "), reference " << hRef
                          << " (t " << tRef << ")";
            continue;
        }
        if (!hNew) continue;
        ++cmp.hits;
        if (tNew == tRef) ++cmp.bitIdentical;
        cmp.maxDtVoxels = std::max(cmp.maxDtVoxels, std::abs(tNew - tRef) * d.length());
    }
}

void report(const char* what, const Comparison& c) {
    std::printf("%s: %ld (ray, brick) pairs, %ld hits, %ld bit-identical t, max |dt| %.3g voxel, "
                "%ld hit/miss mismatches\n",
                what, c.pairs, c.hits, c.bitIdentical, c.maxDtVoxels, c.hitMismatches);
}

Vec3 randomUnit(Rng& rng) {
    // Uniform on the sphere: z uniform in [−1,1], azimuth uniform (Archimedes).
    const double z = 2.0 * rng.uniform() - 1.0, phi = 2.0 * kPi * rng.uniform();
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    return Vec3(r * std::cos(phi), r * std::sin(phi), z);
}

// A 20³ grid (indices 0…19, so bricks start at −8, 0, 8, 16 along each axis) of a smooth
// oscillating field with many iso crossings; identity transform so index = world.
openvdb::FloatGrid::Ptr wavyGrid() {
    const int dims[3] = {20, 20, 20};
    const double identity[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    return test::makeGrid(dims, identity, Vec3(0.0), -1.0f, [](const Vec3& p) {
        return std::sin(0.45 * p.x) * std::cos(0.37 * p.y) + 0.6 * std::sin(0.29 * p.z + 0.3 * p.x) +
               0.05 * std::cos(1.7 * p.x * p.y * 0.1);
    });
}

TEST(IsoExactTraversal, RandomRaysMatchThePerCellReference) {
    const auto grid = wavyGrid();
    const double iso = 0.1;
    const IsoExactSurface s(*grid, iso, "wavy");
    ASSERT_GT(s.brickCount(), 8u);
    const ReferenceBricks ref{*grid, iso};
    Rng rng(12345);
    Comparison cmp;
    for (int i = 0; i < 3000; ++i) {
        // Through a random point of the grid from a random direction and origin distance;
        // directions of random length (t is in the caller's units, so |d| ≠ 1 must work too);
        // tMin sometimes inside the grid, tMax sometimes finite.
        const Vec3 target(19.0 * rng.uniform(), 19.0 * rng.uniform(), 19.0 * rng.uniform());
        const Vec3 d = randomUnit(rng) * (0.25 + 3.0 * rng.uniform());
        const Vec3 o = target - d * ((2.0 + 30.0 * rng.uniform()) / d.length());
        const double tMin = (i % 3 == 0) ? 20.0 * rng.uniform() / d.length() : 0.0;
        const double tMax = (i % 5 == 0) ? tMin + 10.0 * rng.uniform() / d.length() : kInf;
        compareBricks(s, ref, o, d, tMin, tMax, cmp);
    }
    report("random rays, 20^3 grid", cmp);
    EXPECT_EQ(cmp.hitMismatches, 0);
    EXPECT_GT(cmp.hits, 1000);
    EXPECT_LE(cmp.maxDtVoxels, 1e-9);
}

TEST(IsoExactTraversal, LatticeAlignedRaysMatchThePerCellReference) {
    // Rays along the axes on a quarter-voxel lattice of offsets (so exactly along voxel edges and
    // faces, and on brick faces at multiples of 8), and along face and space diagonals through
    // lattice points (crossing voxel edges and corners, where 2 or 3 face crossings tie), both
    // directions. These are the cases where a DDA and the midpoint rule could pick different cells.
    const auto grid = wavyGrid();
    const double iso = 0.1;
    const IsoExactSurface s(*grid, iso, "wavy");
    const ReferenceBricks ref{*grid, iso};
    Comparison cmp;
    for (int axis = 0; axis < 3; ++axis)
        for (int sign : {1, -1})
            for (int i = -2; i <= 80; i += 3)
                for (int j = -2; j <= 80; j += 5) {
                    Vec3 o(0.0), d(0.0);
                    o[axis] = sign > 0 ? -3.0 : 23.0;
                    o[(axis + 1) % 3] = 0.25 * i;
                    o[(axis + 2) % 3] = 0.25 * j;
                    d[axis] = sign;
                    compareBricks(s, ref, o, d, 0.0, kInf, cmp);
                }
    const int diagonals[][3] = {{1, 1, 0}, {1, 0, 1}, {0, 1, 1}, {1, 1, 1}, {1, -1, 1},
                                {-1, 1, 1}, {1, 1, -1}, {2, 1, 0}, {1, 2, 2}};
    for (const auto& dg : diagonals)
        for (int sign : {1, -1})
            for (int i = 0; i <= 20; i += 1)
                for (int j = 0; j <= 20; j += 2) {
                    const Vec3 d(sign * dg[0], sign * dg[1], sign * dg[2]);
                    // A lattice point inside the grid, backed off 30 steps.
                    const Vec3 through(i, j, (i + 2 * j) % 20);
                    compareBricks(s, ref, through - d * 30.0, d, 0.0, kInf, cmp);
                }
    report("lattice-aligned rays, 20^3 grid", cmp);
    EXPECT_EQ(cmp.hitMismatches, 0);
    EXPECT_GT(cmp.hits, 1000);
    EXPECT_LE(cmp.maxDtVoxels, 1e-9);
}

// Through SurfaceScene (Embree, world space): first hit t and normal against the reference's
// first hit over all bricks the ray touches.
struct SceneComparison {
    long rays = 0, hits = 0, mismatches = 0;
    double maxDtVoxels = 0.0, maxNormalDiff = 0.0;
};

void compareScene(const IsoExactSurface& s, const SurfaceScene& scene, const ReferenceBricks& ref,
                  const Ray& ray, SceneComparison& cmp) {
    ++cmp.rays;
    const Vec3 o = s.map().toIndex(ray.o), d = s.map().directionToIndex(ray.d);
    double tRef = kInf;
    unsigned bestBrick = 0;
    for (unsigned b = 0; b < s.brickCount(); ++b) {
        const openvdb::Coord& org = s.brickOrigin(b);
        if (!touchesBrick(org, o, d, ray.tMin, std::min(ray.tMax, tRef))) continue;
        double t = 0.0;
        if (ref.intersect(org, o, d, ray.tMin, std::min(ray.tMax, tRef), t) && t < tRef) {
            tRef = t;
            bestBrick = b;
        }
    }
    const auto hit = scene.intersect(ray);
    if (hit.has_value() != (tRef < kInf)) {
        ++cmp.mismatches;
        ADD_FAILURE() << "ray o=" << ray.o << " d=" << ray.d << " tMin=" << ray.tMin << ": scene "
                      << (hit ? "hits" : "misses") << ", reference t " << tRef;
        return;
    }
    if (!hit) return;
    ++cmp.hits;
    cmp.maxDtVoxels = std::max(cmp.maxDtVoxels, std::abs(hit->t - tRef) * d.length());
    const Vec3 nRef = ref.normal(s, s.brickOrigin(bestBrick), o + d * tRef);
    cmp.maxNormalDiff = std::max(cmp.maxNormalDiff, (hit->normal - nRef).length());
}

TEST(IsoExactTraversal, SceneFirstHitsAndNormalsMatchTheReference) {
    const auto grid = wavyGrid();
    const double iso = 0.1;
    auto s = std::make_shared<IsoExactSurface>(*grid, iso, "wavy");
    SurfaceScene scene("threads=1");
    scene.add(s);
    scene.commit();
    const ReferenceBricks ref{*grid, iso};
    Rng rng(777);
    SceneComparison cmp;
    for (int i = 0; i < 2000; ++i) {
        Ray ray;
        const Vec3 target(19.0 * rng.uniform(), 19.0 * rng.uniform(), 19.0 * rng.uniform());
        ray.d = randomUnit(rng);
        ray.o = target - ray.d * (2.0 + 30.0 * rng.uniform());
        ray.tMin = (i % 2) ? 15.0 * rng.uniform() : 0.0;
        compareScene(*s, scene, ref, ray, cmp);
    }
    std::printf("scene, 20^3 grid: %ld rays, %ld hits, max |dt| %.3g voxel, max |dn| %.3g\n",
                cmp.rays, cmp.hits, cmp.maxDtVoxels, cmp.maxNormalDiff);
    EXPECT_EQ(cmp.mismatches, 0);
    EXPECT_GT(cmp.hits, 1000);
    EXPECT_LE(cmp.maxDtVoxels, 1e-9);
    EXPECT_LE(cmp.maxNormalDiff, 1e-9);
}

TEST(IsoExactTraversal, CtheadSkullMatchesTheReference) {
    // The paper's skull: CThead / 3272 at iso 0.5 (shared/docs/paper-scene.md), spacing 1,1,2.
    LoadOptions opts;
    opts.normalize = 3272.0;
    const Volume vol = loadVolume(LOBE_SOURCE_DIR "/assets/cthead/cthead.nhdr", opts);
    const double iso = 0.5;
    auto s = std::make_shared<IsoExactSurface>(*vol.grid, iso, "CThead");
    SurfaceScene scene("threads=1");
    scene.add(s);
    scene.commit();
    const ReferenceBricks ref{*vol.grid, iso};
    Rng rng(2003);
    SceneComparison cmp;
    Comparison bricks;
    // World box of the volume: index 0…255 × 0…255 × 0…112, z spacing 2.
    const Vec3 centre = s->map().toWorld(Vec3(127.5, 127.5, 56.0));
    for (int i = 0; i < 400; ++i) {
        // Rays through a random point of the central region from a random direction, starting
        // outside the head; half of them start at a random depth (as the compositing renderer's
        // repeated queries do), so hits inside and behind bone walls are compared too.
        const Vec3 target = centre + Vec3(rng.uniform() - 0.5, rng.uniform() - 0.5,
                                          rng.uniform() - 0.5) * 180.0;
        Ray ray;
        ray.d = randomUnit(rng);
        ray.o = target - ray.d * 300.0;
        ray.tMin = (i % 2) ? 200.0 + 200.0 * rng.uniform() : 0.0;
        compareScene(*s, scene, ref, ray, cmp);
        if (i % 4 == 0)
            compareBricks(*s, ref, s->map().toIndex(ray.o), s->map().directionToIndex(ray.d),
                          ray.tMin, kInf, bricks);
    }
    std::printf("scene, CThead: %ld rays, %ld hits, max |dt| %.3g voxel, max |dn| %.3g\n",
                cmp.rays, cmp.hits, cmp.maxDtVoxels, cmp.maxNormalDiff);
    report("bricks, CThead", bricks);
    EXPECT_EQ(cmp.mismatches, 0);
    EXPECT_GT(cmp.hits, 200);
    EXPECT_LE(cmp.maxDtVoxels, 1e-9);
    EXPECT_LE(cmp.maxNormalDiff, 1e-9);
    EXPECT_EQ(bricks.hitMismatches, 0);
    EXPECT_GT(bricks.hits, 100);
    EXPECT_LE(bricks.maxDtVoxels, 1e-9);
}

}  // namespace
}  // namespace lobe
