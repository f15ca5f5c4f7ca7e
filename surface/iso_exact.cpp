// Exact iso-surface of a trilinear interpolant as an Embree user geometry; see iso_exact.h.
#include "surface/iso_exact.h"

#include "core/cpu_features.h"
#include "core/error.h"
#include "core/memory.h"
#include "surface/brick_walk.h"
#include "surface/trilinear_cell.h"
#include "surface/user_geometry.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace lobe {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr int kBrickCells = BrickCells::kCells;
constexpr int kBrickPoints = BrickCells::kPoints;
constexpr int kBrickValues = BrickCells::kValues;

int floorDiv(int a, int b) { return (a >= 0) ? a / b : -((-a + b - 1) / b); }

// The index box of every stored value: leaf nodes (active and inactive voxels) and tiles whose
// value differs from the background (active or not). Everything outside reads as background.
bool storedIndexBox(const openvdb::FloatTree& tree, openvdb::CoordBBox& box) {
    box = openvdb::CoordBBox();
    bool any = tree.evalLeafBoundingBox(box);
    const float background = tree.background();
    auto it = tree.cbeginValueAll();
    it.setMaxDepth(openvdb::FloatTree::ValueAllCIter::LEAF_DEPTH - 1);  // tiles only
    for (; it; ++it) {
        if (it.isVoxelValue() || *it == background) continue;
        openvdb::CoordBBox tileBox;
        it.getBoundingBox(tileBox);
        if (any) {
            box.expand(tileBox);
        } else {
            box = tileBox;
            any = true;
        }
    }
    return any;
}

}  // namespace

IsoExactSurface::IsoExactSurface(const openvdb::FloatGrid& grid, double iso,
                                 const std::string& name)
    : iso_(iso), map_(AffineMap::fromGrid(grid, name)) {
    if (!std::isfinite(iso)) throw Error(name + ": iso value must be finite");
    const openvdb::FloatTree& tree = grid.tree();
    if (!std::isfinite(tree.background())) throw Error(name + ": background value is not finite");
    openvdb::CoordBBox stored;
    if (!storedIndexBox(tree, stored)) return;  // empty grid: constant background, no surface

    // Cells whose corners touch a stored value: from min − 1 to max (cell c spans c … c + 1).
    const openvdb::Coord cellLo = stored.min() - openvdb::Coord(1);
    const openvdb::Coord cellHi = stored.max();
    openvdb::Coord bLo, bHi;
    for (int a = 0; a < 3; ++a) {
        bLo[a] = floorDiv(cellLo[a], kBrickCells);
        bHi[a] = floorDiv(cellHi[a], kBrickCells);
    }
    const int nx = bHi.x() - bLo.x() + 1, ny = bHi.y() - bLo.y() + 1, nz = bHi.z() - bLo.z() + 1;
    // Pass 1 keeps two flags per candidate brick: refused by their size before allocating (a
    // foreign grid's two voxels 1e5 apart would need 1e13 bricks); the mesh and level-set
    // methods have no such table.
    checkFits(double(nx) * ny * nz * 2,
              name + ": the exact iso-surface's table of " + std::to_string(int64_t(nx) * 8) +
                  " x " + std::to_string(int64_t(ny) * 8) + " x " +
                  std::to_string(int64_t(nz) * 8) +
                  " cells (use \"method\": \"mesh\" or \"levelset\" for a grid this large)");
    const std::size_t nBricks = std::size_t(nx) * ny * nz;
    candidateBricks_ = nBricks;
    const auto brickOriginOf = [&](std::size_t b) {
        const int bx = int(b % nx), by = int((b / nx) % ny), bz = int(b / (std::size_t(nx) * ny));
        return openvdb::Coord((bLo.x() + bx) * kBrickCells, (bLo.y() + by) * kBrickCells,
                              (bLo.z() + bz) * kBrickCells);
    };
    // A brick's 9³ values, x fastest; false if one is not finite.
    const auto readBrick = [&](auto& acc, const openvdb::Coord& o, float* v, float& lo, float& hi) {
        lo = std::numeric_limits<float>::infinity();
        hi = -lo;
        bool finite = true;
        for (int k = 0; k < kBrickPoints; ++k)
            for (int j = 0; j < kBrickPoints; ++j)
                for (int i = 0; i < kBrickPoints; ++i) {
                    const float x = acc.getValue(o + openvdb::Coord(i, j, k));
                    finite = finite && std::isfinite(x);
                    *v++ = x;
                    lo = std::min(lo, x);
                    hi = std::max(hi, x);
                }
        return finite;
    };

    // Pass 1 (parallel): each candidate brick's range, read into a buffer of its own; keep the
    // bricks that straddle iso. Only flags are stored, so the build's memory grows with the
    // surface, not with the grid's box.
    std::vector<char> keep(nBricks, 0);
    std::vector<char> nonFinite(nBricks, 0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nBricks, 16),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                          auto acc = grid.getConstUnsafeAccessor();
                          float v[kBrickValues];
                          for (std::size_t b = range.begin(); b != range.end(); ++b) {
                              float lo, hi;
                              const bool finite = readBrick(acc, brickOriginOf(b), v, lo, hi);
                              nonFinite[b] = !finite;
                              // A brick whose 9³ values all equal iso is a solid region at the iso
                              // value, not a surface: it is skipped (the only case where a root
                              // could go unreported).
                              keep[b] = finite && lo <= iso && hi >= iso && lo < hi;
                          }
                      });
    if (std::find(nonFinite.begin(), nonFinite.end(), 1) != nonFinite.end())
        throw Error(name + ": the grid holds non-finite (NaN or Inf) values");

    // Pass 2: the kept bricks in order, their values read again, their cell classes and bounds.
    for (std::size_t b = 0; b < nBricks; ++b)
        if (keep[b]) origins_.push_back(brickOriginOf(b));
    const std::size_t kept = origins_.size();
    checkFits(double(kept) * (kBrickValues * sizeof(float) + sizeof(BrickCells) + 40),
              name + ": the exact iso-surface's " + std::to_string(kept) + " bricks");
    values_.resize(kept * kBrickValues);
    cells_.resize(kept);
    bounds_.resize(kept);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, kept, 16),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                          auto acc = grid.getConstUnsafeAccessor();
                          for (std::size_t k = range.begin(); k != range.end(); ++k) {
                              float* v = &values_[k * kBrickValues];
                              float lo, hi;
                              readBrick(acc, origins_[k], v, lo, hi);
                              cells_[k] = BrickCells::classify(v, iso_);
                              bounds_[k] = brickWorldBounds(map_, origins_[k], cells_[k]);
                          }
                      });
}

std::size_t IsoExactSurface::memoryBytes() const {
    return values_.size() * sizeof(float) + origins_.size() * sizeof(openvdb::Coord) +
           cells_.size() * sizeof(BrickCells) + bounds_.size() * sizeof(bounds_[0]);
}

void IsoExactSurface::cellCorners(unsigned brick, const openvdb::Coord& cell, double c[8]) const {
    const openvdb::Coord l = cell - origins_[brick];
    const float* v = &values_[std::size_t(brick) * kBrickValues];
    const int base = l.x() + kBrickPoints * (l.y() + kBrickPoints * l.z());
    constexpr int sy = kBrickPoints, sz = kBrickPoints * kBrickPoints;
    c[0] = v[base];
    c[1] = v[base + 1];
    c[2] = v[base + sy];
    c[3] = v[base + sy + 1];
    c[4] = v[base + sz];
    c[5] = v[base + sz + 1];
    c[6] = v[base + sz + sy];
    c[7] = v[base + sz + sy + 1];
}

Vec3 IsoExactSurface::worldGradient(unsigned brick, const Vec3& u) const {
    const openvdb::Coord cell = cellInBrick(origins_[brick], u);
    double c[8];
    cellCorners(brick, cell, c);
    const Vec3 local(u.x - cell.x(), u.y - cell.y(), u.z - cell.z());
    return map_.gradientToWorld(trilinearGradient(c, local));
}

bool IsoExactSurface::intersectBrick(unsigned brick, const Vec3& o, const Vec3& d, double tMin,
                                     double tMax, double& tHit) const {
    return intersectPrimitive(brick, WalkRay(o, d), tMin, tMax, tHit);
}

namespace {

// The corners of cell (lx, ly, lz) of a brick's 9³ values (trilinear_cell.h order).
struct BrickCorners {
    const float* values;
    void operator()(int lx, int ly, int lz, double c[8]) const {
        constexpr int sy = kBrickPoints, sz = kBrickPoints * kBrickPoints;
        const float* v = values + lx + sy * ly + sz * lz;
        c[0] = v[0];
        c[1] = v[1];
        c[2] = v[sy];
        c[3] = v[sy + 1];
        c[4] = v[sz];
        c[5] = v[sz + 1];
        c[6] = v[sz + sy];
        c[7] = v[sz + sy + 1];
    }
};

// The walk compiled for AVX-512 (F, VL, DQ, BW, CD: Skylake-SP and later), called where the
// CPU has it: its scalar code in the VEX/EVEX forms (rounding in one instruction, three-operand
// arithmetic). The same hits as the baseline copy bit for bit: the same operations on the same
// doubles, and this file is compiled with -ffp-contract=off (surface/CMakeLists.txt), so no
// product and sum fuse into an FMA. flatten puts the corner reads and the cubic's tests into
// this copy too. Rendering 1's walk: 0.91-0.93x the baseline's CPU (docs/performance.md, round 5;
// AVX2 alone 0.96x, -march-style tuning for Ice Lake 1.02x).
[[gnu::target("avx512f,avx512vl,avx512dq,avx512bw,avx512cd"), gnu::flatten]] bool walkAvx512(
    const openvdb::Coord& origin, const BrickCells& cells, double iso, const WalkRay& ray,
    double tMin, double tMax, const BrickCorners& corners, double& tHit) {
    return firstRootInBrick(origin, cells, iso, ray, tMin, tMax, corners, tHit);
}

const bool kAvx512 = cpuHasAvx512();

}  // namespace

bool IsoExactSurface::intersectPrimitive(unsigned brick, const WalkRay& ray, double tMin,
                                         double tMax, double& tHit) const {
    const BrickCorners corners{&values_[std::size_t(brick) * kBrickValues]};
    if (kAvx512)
        return walkAvx512(origins_[brick], cells_[brick], iso_, ray, tMin, tMax, corners, tHit);
    return firstRootInBrick(origins_[brick], cells_[brick], iso_, ray, tMin, tMax, corners, tHit);
}

// flatten: the hit's position, its index point, the cell's corners, the gradient and its
// world form in one function (the preview's 0.52 M hits: these calls 1.66 → 1.20 % of the
// process' perf samples); the same operations, so the same normal.
[[gnu::flatten]] SurfaceHit IsoExactSurface::shade(const Ray& ray, double t,
                                                   unsigned primId) const {
    return user_geometry::shadeByGradient(
        ray, t, primId, [&](const Vec3& x) { return worldGradient(primId, map_.toIndex(x)); });
}

RTCGeometry IsoExactSurface::createGeometry(RTCDevice device) const {
    return user_geometry::create(device, this, origins_.size());
}

}  // namespace lobe
