// The walk through one 8³ block of trilinear cells that finds the first root of f − iso along a
// ray, shared by the exact iso-surface (iso_exact.h: values copied into bricks) and the level set
// (iso_levelset.h: values read from the OpenVDB tree). The method and its guarantees are those
// described in iso_exact.h (Marmitt et al., VMV 2004; Amanatides & Woo 1987); the cell values
// come from a Corners callback, so both methods run the very same arithmetic.
//
// A brick is the 8³ cells whose first corner lies in [origin, origin + 8)³ (origin a multiple of
// 8, OpenVDB's leaf alignment); it reads the 9³ lattice points origin … origin + 8.
#pragma once

#include "core/math.h"
#include "surface/trilinear_cell.h"

#include <openvdb/openvdb.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

namespace lobe {

struct BrickCells {
    static constexpr int kCells = 8;            // cells per brick side
    static constexpr int kPoints = kCells + 1;  // lattice points per brick side
    static constexpr int kValues = kPoints * kPoints * kPoints;
    // Cell-class masks: word z (0…7) holds bit x + 8y of the cells (x, y, z) that straddle iso,
    // word kCells + z those whose corners are all above iso; the cells in neither are all below.
    static constexpr int kMaskWords = 2 * kCells;
    static_assert(kCells * kCells == 64, "one 64-bit word per z layer of cells");

    std::uint64_t masks[kMaskWords] = {};
    // The box of the straddling cells in cells relative to the origin (lo xyz, hi xyz, hi
    // exclusive, 0 … 8); empty (lo > hi) when none straddles.
    std::array<std::uint8_t, 6> straddleBox{kCells, kCells, kCells, 0, 0, 0};

    bool anyStraddles() const { return straddleBox[0] < straddleBox[3]; }

    // Classifies the 8³ cells from the brick's 9³ lattice values (x fastest), compared in double
    // exactly as the per-cell test they replace: straddling (min ≤ iso ≤ max over the 8 corners),
    // all above (min > iso), else all below.
    static BrickCells classify(const float* v, double iso);
};

namespace brick_walk_detail {
constexpr double kInf = std::numeric_limits<double>::infinity();
// Bricks are entered this much early and left this much late (index units, voxels), so a root
// lying on a brick face is found by at least one of the two bricks despite rounding.
constexpr double kBrickOverlapVoxels = 1e-7;
// Root refinement stops when the bracket is this short (index units, voxels).
constexpr double kRootToleranceVoxels = 1e-10;
// Margin of the straddling-cell box test (index units): far above the walk's rounding (~1e-13
// voxel at CT coordinates) and the brick overlap (1e-7), far below a cell.
constexpr double kStraddleBoxMarginVoxels = 1e-5;
}  // namespace brick_walk_detail

inline BrickCells BrickCells::classify(const float* v, double iso) {
    BrickCells b;
    for (int z = 0; z < kCells; ++z)
        for (int y = 0; y < kCells; ++y)
            for (int x = 0; x < kCells; ++x) {
                const int base = x + kPoints * (y + kPoints * z);
                double cMin = brick_walk_detail::kInf, cMax = -brick_walk_detail::kInf;
                for (int c = 0; c < 8; ++c) {
                    const double w = v[base + ((c & 1) ? 1 : 0) + ((c & 2) ? kPoints : 0) +
                                       ((c & 4) ? kPoints * kPoints : 0)];
                    cMin = std::min(cMin, w);
                    cMax = std::max(cMax, w);
                }
                const std::uint64_t bit = std::uint64_t(1) << (x + kCells * y);
                if (cMin > iso) {
                    b.masks[kCells + z] |= bit;
                } else if (!(cMax < iso)) {
                    b.masks[z] |= bit;
                    const int xyz[3] = {x, y, z};
                    for (int a = 0; a < 3; ++a) {
                        b.straddleBox[a] =
                            static_cast<std::uint8_t>(std::min<int>(b.straddleBox[a], xyz[a]));
                        b.straddleBox[a + 3] = static_cast<std::uint8_t>(
                            std::max<int>(b.straddleBox[a + 3], xyz[a] + 1));
                    }
                }
            }
    return b;
}

// An index-space ray o + t·d with what every brick's walk derives from it alone: |d|, 1/d per
// axis, and the brick overlap and root tolerance in t units. A ray crosses about 2.5 bricks'
// boxes (T1), so the user geometry makes this once per ray (user_geometry.h) instead of once
// per brick: a square root, five divisions and the index transform fewer per brick, the same
// numbers bit for bit.
struct WalkRay {
    Vec3 o, d;
    Vec3 invD;            // 1/d per axis (0 where d is 0)
    double dLen = 0.0;    // |d|
    double overlap = 0;   // brick_walk_detail::kBrickOverlapVoxels / |d|
    double tol = 0.0;     // brick_walk_detail::kRootToleranceVoxels / |d|
    bool usable = false;  // |d| finite and non-zero: otherwise no brick is searched
    // o finite, and every d[a] and 1/d[a] finite and non-zero: firstRootInBrick's clip may then
    // skip the tests for an axis the ray does not move along (same numbers either way).
    bool regular = false;

    WalkRay() = default;
    WalkRay(const Vec3& origin, const Vec3& direction)
        : o(origin), d(direction), dLen(direction.length()) {
        usable = dLen > 0.0 && std::isfinite(dLen);
        if (!usable) return;
        overlap = brick_walk_detail::kBrickOverlapVoxels / dLen;
        // 1/d per axis, so that the ~15 plane crossings of a brick cost a product each, not a
        // division (~1 ulp more per crossing: far below the overlap and the root tolerance).
        invD = Vec3(d.x != 0.0 ? 1.0 / d.x : 0.0, d.y != 0.0 ? 1.0 / d.y : 0.0,
                    d.z != 0.0 ? 1.0 / d.z : 0.0);
        tol = brick_walk_detail::kRootToleranceVoxels / dLen;
        regular = std::isfinite(o.x) && std::isfinite(o.y) && std::isfinite(o.z);
        for (int a = 0; a < 3; ++a)
            regular = regular && d[a] != 0.0 && invD[a] != 0.0 && std::isfinite(invD[a]);
    }
};

// The first root of f − iso along the index-space ray o + t·d, t ∈ [tMin, tMax], inside the
// brick at `origin`. corners(lx, ly, lz, c) fills c[8] (trilinear_cell.h order) for the cell at
// origin + (lx, ly, lz), 0 ≤ l < 8; it is called for straddling cells only.
// kSkipByBound = false solves every straddling cell's cubic (no Bernstein skip): the reference
// the tests compare the walk against, bit for bit.
template <typename Corners, bool kSkipByBound = true>
bool firstRootInBrick(const openvdb::Coord& origin, const BrickCells& cells, double iso,
                      const WalkRay& ray, double tMin, double tMax, const Corners& corners,
                      double& tHit) {
    using namespace brick_walk_detail;
    constexpr int kCells = BrickCells::kCells;
    if (!ray.usable) return false;
    const Vec3& o = ray.o;
    const Vec3& d = ray.d;
    const Vec3& invD = ray.invD;
    double t0 = tMin, t1 = tMax;
    if (ray.regular) {
        // The two clips below in one pass, without branches: for d > 0 the plane at the box's
        // low side is entered and the high one left (the products are monotone in the plane),
        // for d < 0 the other way round, which is the swap below made in advance; max and min
        // are exact, so their order does not matter, and an empty brick clip leaves an empty
        // straddle clip.
        const std::array<std::uint8_t, 6>& sb = cells.straddleBox;
        double e0 = t0, e1 = t1;
        double s0 = -kInf, s1 = kInf;
        for (int a = 0; a < 3; ++a) {
            const bool up = d[a] > 0.0;
            const double lo = origin[a], hi = origin[a] + kCells;
            const double slo = origin[a] + sb[a] - kStraddleBoxMarginVoxels;
            const double shi = origin[a] + sb[a + 3] + kStraddleBoxMarginVoxels;
            const double ta = ((up ? lo : hi) - o[a]) * invD[a];
            const double tb = ((up ? hi : lo) - o[a]) * invD[a];
            const double sa = ((up ? slo : shi) - o[a]) * invD[a];
            const double sbb = ((up ? shi : slo) - o[a]) * invD[a];
            e0 = std::max(e0, ta - ray.overlap);
            e1 = std::min(e1, tb + ray.overlap);
            s0 = std::max(s0, sa);
            s1 = std::min(s1, sbb);
        }
        t0 = std::max(e0, s0);
        t1 = std::min(e1, s1);
        if (!(t0 <= t1)) return false;
    } else {
        // Slab clip against the brick's index box, widened by the overlap (in t units).
        const double overlap = ray.overlap;
        for (int a = 0; a < 3; ++a) {
            const double lo = origin[a], hi = origin[a] + kCells;
            if (d[a] == 0.0) {
                if (o[a] < lo - kBrickOverlapVoxels || o[a] > hi + kBrickOverlapVoxels)
                    return false;
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
        if (ray.regular) {
            // d[a] ≠ 0: the two branches below without the test of the third.
            const bool up = d[a] > 0.0;
            step[a] = up ? 1 : -1;
            k[a] = up ? std::floor(p) + 1.0 : std::ceil(p) - 1.0;
            c = up ? k[a] - 1.0 : k[a];
        } else if (d[a] > 0.0) {
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
    const int sx = step[0], sy = step[1], sz = step[2];
    const double fx = sx, fy = sy, fz = sz;
    const double ox = o.x, oy = o.y, oz = o.z, ix = invD.x, iy = invD.y, iz = invD.z;
    double kx = k[0], ky = k[1], kz = k[2];
    double nx = tNext[0], ny = tNext[1], nz = tNext[2];
    int cx = cell[0], cy = cell[1], cz = cell[2];

    const std::uint64_t* masks = cells.masks;
    const double tol = ray.tol;
    double t = t0;
    double gPrevEnd = 0.0;  // g at the end of the previous segment; 0: none yet
    // Bounded: each pass moves at least one axis one plane (≤ ~3·(8+2) passes per brick).
    for (int guard = 0; guard < 4 * 3 * (kCells + 4) && t <= t1; ++guard) {
        const double tEnd = std::min(t1, std::min(nx, std::min(ny, nz)));
        if (tEnd > t || (tEnd == t && t == t1)) {
            const int lx = std::min(kCells - 1, std::max(0, cx));
            const int ly = std::min(kCells - 1, std::max(0, cy));
            const int lz = std::min(kCells - 1, std::max(0, cz));
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
                // Most straddling cells a ray crosses hold no root on its segment: the Bernstein
                // bound proves that for most of them without the derivative's roots, and
                // firstRootOnInterval would then return false (trilinear_cell.h). It also proves
                // that g(L) has g0's sign (no evaluation on [0, L] rounds across 0), and only the
                // sign of gPrevEnd is ever read.
                if (kSkipByBound && cubicHasNoRootOn(g, tEnd - t)) {
                    gPrevEnd = g0;
                } else {
                    double s = 0.0;
                    if (firstRootOnInterval(g, tEnd - t, tol, s)) {
                        tHit = std::min(t + s, t1);
                        return true;
                    }
                    gPrevEnd = g(tEnd - t);
                }
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
        if (nx <= tEnd) {
            kx += fx;
            cx += sx;
            nx = (kx - ox) * ix;
        }
        if (ny <= tEnd) {
            ky += fy;
            cy += sy;
            ny = (ky - oy) * iy;
        }
        if (nz <= tEnd) {
            kz += fz;
            cz += sz;
            nz = (kz - oz) * iz;
        }
        t = std::max(t, tEnd);
    }
    return false;
}

// The same for a ray given by its origin and direction alone.
template <typename Corners, bool kSkipByBound = true>
bool firstRootInBrick(const openvdb::Coord& origin, const BrickCells& cells, double iso,
                      const Vec3& o, const Vec3& d, double tMin, double tMax,
                      const Corners& corners, double& tHit) {
    return firstRootInBrick<Corners, kSkipByBound>(origin, cells, iso, WalkRay(o, d), tMin, tMax,
                                                   corners, tHit);
}

// The cell of the brick at `origin` that holds index point u, clamped into the brick (a hit in
// the overlap just outside it uses the boundary cell's interpolant).
inline openvdb::Coord cellInBrick(const openvdb::Coord& origin, const Vec3& u) {
    openvdb::Coord cell;
    for (int a = 0; a < 3; ++a) {
        const double f = std::floor(u[a]);
        const double lo = origin[a], hi = origin[a] + BrickCells::kCells - 1;
        cell[a] = static_cast<int>(std::min(hi, std::max(lo, std::isfinite(f) ? f : lo)));
    }
    return cell;
}

// World AABB of the box of a brick's straddling cells (the whole brick when none straddles): its
// 8 index-space corners widened by 1e-3 voxel, padded by a relative margin and rounded outwards
// to float so float traversal never culls a grazing ray. A ray that misses it misses every
// straddling cell, which firstRootInBrick's early out tests with a margin of 1e-5 voxel: so
// Embree culls those rays instead of calling the brick (the preview of rendering 1: surfaces
// 0.51 → 0.48 CPU s, same image).
template <typename Map>
std::array<float, 6> brickWorldBounds(const Map& map, const openvdb::Coord& o,
                                      const BrickCells& cells) {
    constexpr int kCells = BrickCells::kCells;
    const std::array<std::uint8_t, 6>& sb = cells.straddleBox;
    int lo[3] = {0, 0, 0}, hi[3] = {kCells, kCells, kCells};
    if (cells.anyStraddles())
        for (int a = 0; a < 3; ++a) {
            lo[a] = sb[a];
            hi[a] = sb[a + 3];
        }
    double mn[3] = {brick_walk_detail::kInf, brick_walk_detail::kInf, brick_walk_detail::kInf};
    double mx[3] = {-mn[0], -mn[0], -mn[0]};
    for (int c = 0; c < 8; ++c) {
        const Vec3 u(o.x() + ((c & 1) ? hi[0] : lo[0]) + ((c & 1) ? 1e-3 : -1e-3),
                     o.y() + ((c & 2) ? hi[1] : lo[1]) + ((c & 2) ? 1e-3 : -1e-3),
                     o.z() + ((c & 4) ? hi[2] : lo[2]) + ((c & 4) ? 1e-3 : -1e-3));
        const Vec3 w = map.toWorld(u);
        for (int a = 0; a < 3; ++a) {
            mn[a] = std::min(mn[a], w[a]);
            mx[a] = std::max(mx[a], w[a]);
        }
    }
    std::array<float, 6> box{};
    for (int a = 0; a < 3; ++a) {
        const double pad = 1e-5 * (std::abs(mn[a]) + std::abs(mx[a]) + 1.0);
        box[a] = std::nextafter(static_cast<float>(mn[a] - pad),
                                -std::numeric_limits<float>::infinity());
        box[a + 3] =
            std::nextafter(static_cast<float>(mx[a] + pad), std::numeric_limits<float>::infinity());
    }
    return box;
}

}  // namespace lobe
