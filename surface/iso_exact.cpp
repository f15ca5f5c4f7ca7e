// Exact iso-surface of a trilinear interpolant as an Embree user geometry; see iso_exact.h.
#include "surface/iso_exact.h"

#include "core/error.h"
#include "core/memory.h"
#include "surface/trilinear_cell.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace lobe {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// Bricks are entered this much early and left this much late (index units, voxels), so a root
// lying on a brick face is found by at least one of the two bricks despite rounding.
constexpr double kBrickOverlapVoxels = 1e-7;
// Root refinement stops when the bracket is this short (index units, voxels).
constexpr double kRootToleranceVoxels = 1e-10;
// Margin of the straddling-cell box test (index units): far above the walk's rounding (~1e-13
// voxel at CT coordinates) and the brick overlap (1e-7), far below a cell.
constexpr double kStraddleBoxMarginVoxels = 1e-5;

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
    : iso_(iso), map_(AffineMap::fromTransform(grid.transform(), name)) {
    if (!std::isfinite(iso)) throw Error(name + ": iso value must be finite");
    const openvdb::FloatTree& tree = grid.tree();
    if (!std::isfinite(tree.background()))
        throw Error(name + ": background value is not finite");
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
    // Pass 1 holds every candidate brick's values: refused by its size before allocating (a
    // foreign grid's two voxels 1e5 apart would need 1e13 bricks); the mesh method has no such
    // table.
    checkFits(double(nx) * ny * nz * (kBrickValues * sizeof(float) + 2),
              name + ": the exact iso-surface's table of " + std::to_string(int64_t(nx) * 8) +
                  " x " + std::to_string(int64_t(ny) * 8) + " x " + std::to_string(int64_t(nz) * 8) +
                  " cells (use \"method\": \"mesh\" for a grid this large)");
    const std::size_t nBricks = std::size_t(nx) * ny * nz;
    candidateBricks_ = nBricks;

    // Pass 1 (parallel): every candidate brick's 9³ values and range; keep those that straddle.
    std::vector<float> all(nBricks * kBrickValues);
    std::vector<char> keep(nBricks, 0);
    std::vector<char> nonFinite(nBricks, 0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nBricks, 16),
                      [&](const tbb::blocked_range<std::size_t>& range) {
        auto acc = grid.getConstUnsafeAccessor();
        for (std::size_t b = range.begin(); b != range.end(); ++b) {
            const int bx = int(b % nx), by = int((b / nx) % ny), bz = int(b / (std::size_t(nx) * ny));
            const openvdb::Coord o((bLo.x() + bx) * kBrickCells, (bLo.y() + by) * kBrickCells,
                                   (bLo.z() + bz) * kBrickCells);
            float* v = &all[b * kBrickValues];
            float lo = std::numeric_limits<float>::infinity(), hi = -lo;
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
            nonFinite[b] = !finite;
            // A brick whose 9³ values all equal iso is a solid region at the iso value, not a
            // surface: it is skipped (the only case where a root could go unreported).
            keep[b] = finite && lo <= iso && hi >= iso && lo < hi;
        }
    });
    if (std::find(nonFinite.begin(), nonFinite.end(), 1) != nonFinite.end())
        throw Error(name + ": the grid holds non-finite (NaN or Inf) values");

    // Pass 2: compact the kept bricks and their world bounds.
    for (std::size_t b = 0; b < nBricks; ++b) {
        if (!keep[b]) continue;
        const int bx = int(b % nx), by = int((b / nx) % ny), bz = int(b / (std::size_t(nx) * ny));
        const openvdb::Coord o((bLo.x() + bx) * kBrickCells, (bLo.y() + by) * kBrickCells,
                               (bLo.z() + bz) * kBrickCells);
        origins_.push_back(o);
        values_.insert(values_.end(), all.begin() + b * kBrickValues,
                       all.begin() + (b + 1) * kBrickValues);
        // Cell classes, compared in double exactly as the per-cell test they replace: straddling
        // (min ≤ iso ≤ max over the 8 corners), all above (min > iso), else all below.
        const float* v = &all[b * kBrickValues];
        std::uint64_t masks[kMaskWords] = {};
        std::array<std::uint8_t, 6> sbox{kBrickCells, kBrickCells, kBrickCells, 0, 0, 0};
        for (int z = 0; z < kBrickCells; ++z)
            for (int y = 0; y < kBrickCells; ++y)
                for (int x = 0; x < kBrickCells; ++x) {
                    const int base = x + kBrickPoints * (y + kBrickPoints * z);
                    double cMin = kInf, cMax = -kInf;
                    for (int c = 0; c < 8; ++c) {
                        const double w = v[base + ((c & 1) ? 1 : 0) + ((c & 2) ? kBrickPoints : 0) +
                                           ((c & 4) ? kBrickPoints * kBrickPoints : 0)];
                        cMin = std::min(cMin, w);
                        cMax = std::max(cMax, w);
                    }
                    const std::uint64_t bit = std::uint64_t(1) << (x + kBrickCells * y);
                    if (cMin > iso_)
                        masks[kBrickCells + z] |= bit;
                    else if (!(cMax < iso_)) {
                        masks[z] |= bit;
                        const int xyz[3] = {x, y, z};
                        for (int a = 0; a < 3; ++a) {
                            sbox[a] = static_cast<std::uint8_t>(std::min<int>(sbox[a], xyz[a]));
                            sbox[a + 3] = static_cast<std::uint8_t>(std::max<int>(sbox[a + 3], xyz[a] + 1));
                        }
                    }
                }
        cellMasks_.insert(cellMasks_.end(), masks, masks + kMaskWords);
        straddleBoxes_.push_back(sbox);
        // World AABB of the brick's 8 index-space corners, padded by the overlap and a relative
        // margin so float traversal never culls a grazing ray.
        std::array<float, 6> box{};
        double mn[3] = {kInf, kInf, kInf}, mx[3] = {-kInf, -kInf, -kInf};
        for (int c = 0; c < 8; ++c) {
            const Vec3 u(o.x() + ((c & 1) ? kBrickCells : 0) + ((c & 1) ? 1e-3 : -1e-3),
                         o.y() + ((c & 2) ? kBrickCells : 0) + ((c & 2) ? 1e-3 : -1e-3),
                         o.z() + ((c & 4) ? kBrickCells : 0) + ((c & 4) ? 1e-3 : -1e-3));
            const Vec3 w = map_.toWorld(u);
            for (int a = 0; a < 3; ++a) {
                mn[a] = std::min(mn[a], w[a]);
                mx[a] = std::max(mx[a], w[a]);
            }
        }
        for (int a = 0; a < 3; ++a) {
            const double pad = 1e-5 * (std::abs(mn[a]) + std::abs(mx[a]) + 1.0);
            box[a] = std::nextafter(static_cast<float>(mn[a] - pad), -std::numeric_limits<float>::infinity());
            box[a + 3] = std::nextafter(static_cast<float>(mx[a] + pad), std::numeric_limits<float>::infinity());
        }
        bounds_.push_back(box);
    }
}

std::size_t IsoExactSurface::memoryBytes() const {
    return values_.size() * sizeof(float) + origins_.size() * sizeof(openvdb::Coord) +
           cellMasks_.size() * sizeof(std::uint64_t) +
           straddleBoxes_.size() * sizeof(straddleBoxes_[0]) + bounds_.size() * sizeof(bounds_[0]);
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

openvdb::Coord IsoExactSurface::clampCell(unsigned brick, const Vec3& u) const {
    const openvdb::Coord& o = origins_[brick];
    openvdb::Coord cell;
    for (int a = 0; a < 3; ++a) {
        const double f = std::floor(u[a]);
        const double lo = o[a], hi = o[a] + kBrickCells - 1;
        cell[a] = static_cast<int>(std::min(hi, std::max(lo, std::isfinite(f) ? f : lo)));
    }
    return cell;
}

Vec3 IsoExactSurface::worldGradient(unsigned brick, const Vec3& u) const {
    const openvdb::Coord cell = clampCell(brick, u);
    double c[8];
    cellCorners(brick, cell, c);
    const Vec3 local(u.x - cell.x(), u.y - cell.y(), u.z - cell.z());
    return map_.gradientToWorld(trilinearGradient(c, local));
}

bool IsoExactSurface::intersectBrick(unsigned brick, const Vec3& o, const Vec3& d, double tMin,
                                     double tMax, double& tHit) const {
    const double dLen = d.length();
    if (!(dLen > 0.0) || !std::isfinite(dLen)) return false;
    const openvdb::Coord& org = origins_[brick];
    // Slab clip against the brick's index box, widened by the overlap (in t units).
    const double overlap = kBrickOverlapVoxels / dLen;
    double t0 = tMin, t1 = tMax;
    for (int a = 0; a < 3; ++a) {
        const double lo = org[a], hi = org[a] + kBrickCells;
        if (d[a] == 0.0) {
            if (o[a] < lo - kBrickOverlapVoxels || o[a] > hi + kBrickOverlapVoxels) return false;
            continue;
        }
        double ta = (lo - o[a]) / d[a], tb = (hi - o[a]) / d[a];
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta - overlap);
        t1 = std::min(t1, tb + overlap);
    }
    if (!(t0 <= t1)) return false;
    {
        // Early out: [t0, t1] misses the box of the brick's straddling cells, widened by
        // kStraddleBoxMarginVoxels to cover the walk's rounding and the cells it clamps in from
        // the overlap. The walk itself still starts at t0, so a ray that passes is unchanged.
        const std::array<std::uint8_t, 6>& sb = straddleBoxes_[brick];
        double s0 = t0, s1 = t1;
        for (int a = 0; a < 3; ++a) {
            const double lo = org[a] + sb[a] - kStraddleBoxMarginVoxels;
            const double hi = org[a] + sb[a + 3] + kStraddleBoxMarginVoxels;
            if (d[a] == 0.0) {
                if (!(o[a] >= lo && o[a] <= hi)) return false;
                continue;
            }
            double ta = (lo - o[a]) / d[a], tb = (hi - o[a]) / d[a];
            if (ta > tb) std::swap(ta, tb);
            s0 = std::max(s0, ta);
            s1 = std::min(s1, tb);
        }
        if (!(s0 <= s1)) return false;
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
        tNext[a] = step[a] ? (k[a] - o[a]) / d[a] : kInf;
        c -= org[a];
        cell[a] = (c >= -1.0) ? (c <= kBrickCells ? static_cast<int>(c) : kBrickCells) : -1;
    }

    const float* values = &values_[std::size_t(brick) * kBrickValues];
    const std::uint64_t* masks = &cellMasks_[std::size_t(brick) * kMaskWords];
    constexpr int sy = kBrickPoints, sz = kBrickPoints * kBrickPoints;
    const double tol = kRootToleranceVoxels / dLen;
    double t = t0;
    double gPrevEnd = 0.0;  // g at the end of the previous segment; 0: none yet
    // Bounded: each pass moves at least one axis one plane (≤ ~3·(8+2) passes per brick).
    for (int guard = 0; guard < 4 * 3 * (kBrickCells + 4) && t <= t1; ++guard) {
        const double tEnd = std::min(t1, std::min(tNext[0], std::min(tNext[1], tNext[2])));
        if (tEnd > t || (tEnd == t && t == t1)) {
            const int lx = std::min(kBrickCells - 1, std::max(0, cell[0]));
            const int ly = std::min(kBrickCells - 1, std::max(0, cell[1]));
            const int lz = std::min(kBrickCells - 1, std::max(0, cell[2]));
            const std::uint64_t bit = std::uint64_t(1) << (lx + kBrickCells * ly);
            if (masks[lz] & bit) {
                // The 8 corners straddle iso: the cubic along the segment (trilinear_cell.h).
                const float* v = values + lx + sy * ly + sz * lz;
                const double c[8] = {v[0],      v[1],      v[sy],      v[sy + 1],
                                     v[sz],     v[sz + 1], v[sz + sy], v[sz + sy + 1]};
                const Vec3 p = o + d * t;
                const Vec3 u0(p.x - (org.x() + lx), p.y - (org.y() + ly), p.z - (org.z() + lz));
                Cubic g = trilinearAlongRay(c, u0, d);
                g.c[0] -= iso_;
                const double g0 = g.c[0];
                if ((g0 < 0.0 && gPrevEnd > 0.0) || (g0 > 0.0 && gPrevEnd < 0.0)) {
                    tHit = t;  // the sign changed exactly on the face between two cells
                    return true;
                }
                double s = 0.0;
                if (firstRootOnInterval(g, tEnd - t, tol, s)) {
                    tHit = std::min(t + s, t1);
                    return true;
                }
                gPrevEnd = g(tEnd - t);
            } else if (masks[kBrickCells + lz] & bit) {
                if (gPrevEnd < 0.0) { tHit = t; return true; }
                gPrevEnd = 1.0;  // the whole cell is above iso
            } else {
                if (gPrevEnd > 0.0) { tHit = t; return true; }
                gPrevEnd = -1.0;  // the whole cell is below iso
            }
        }
        if (tEnd >= t1) break;
        for (int a = 0; a < 3; ++a) {
            if (tNext[a] <= tEnd) {
                k[a] += step[a];
                cell[a] += step[a];
                tNext[a] = (k[a] - o[a]) / d[a];
            }
        }
        t = std::max(t, tEnd);
    }
    return false;
}

SurfaceHit IsoExactSurface::shade(const Ray& ray, double t, unsigned primId) const {
    SurfaceHit hit;
    hit.t = t;
    hit.position = ray.at(t);
    hit.primId = primId;
    const Vec3 u = map_.toIndex(hit.position);
    const Vec3 n = normalized(-worldGradient(primId, u));
    hit.normal = (n.length2() > 0.0 && isFinite(n)) ? n : normalized(-ray.d);
    return hit;
}

RTCGeometry IsoExactSurface::createGeometry(RTCDevice device) const {
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
    rtcSetGeometryUserPrimitiveCount(g, static_cast<unsigned>(origins_.size()));
    rtcSetGeometryUserData(g, const_cast<IsoExactSurface*>(this));
    rtcSetGeometryBoundsFunction(g, &IsoExactSurface::boundsCallback, nullptr);
    rtcSetGeometryIntersectFunction(g, &IsoExactSurface::intersectCallback);
    rtcSetGeometryOccludedFunction(g, &IsoExactSurface::occludedCallback);
    return g;
}

void IsoExactSurface::boundsCallback(const RTCBoundsFunctionArguments* args) {
    const auto* self = static_cast<const IsoExactSurface*>(args->geometryUserPtr);
    const std::array<float, 6>& b = self->bounds_[args->primID];
    args->bounds_o->lower_x = b[0];
    args->bounds_o->lower_y = b[1];
    args->bounds_o->lower_z = b[2];
    args->bounds_o->upper_x = b[3];
    args->bounds_o->upper_y = b[4];
    args->bounds_o->upper_z = b[5];
}

namespace {

// The ray of lane i: the caller's double ray when SurfaceScene passed one (single rays), else
// Embree's float copy. tMax also respects the best double hit recorded so far.
void laneRay(RTCRayN* ray, unsigned N, unsigned i, const RayContext* ctx, Vec3& o, Vec3& d,
             double& tMin, double& tMax) {
    const double tfar = RTCRayN_tfar(ray, N, i);
    if (N == 1 && ctx && ctx->ray) {
        o = ctx->ray->o;
        d = ctx->ray->d;
        tMin = std::max(0.0, ctx->ray->tMin);
        tMax = std::min(tfar, ctx->ray->tMax);
        if (ctx->geomId != RTC_INVALID_GEOMETRY_ID) tMax = std::min(tMax, ctx->tHit);
    } else {
        o = Vec3(RTCRayN_org_x(ray, N, i), RTCRayN_org_y(ray, N, i), RTCRayN_org_z(ray, N, i));
        d = Vec3(RTCRayN_dir_x(ray, N, i), RTCRayN_dir_y(ray, N, i), RTCRayN_dir_z(ray, N, i));
        tMin = RTCRayN_tnear(ray, N, i);
        tMax = tfar;
    }
}

}  // namespace

void IsoExactSurface::intersectCallback(const RTCIntersectFunctionNArguments* args) {
    const auto* self = static_cast<const IsoExactSurface*>(args->geometryUserPtr);
    auto* ctx = reinterpret_cast<RayContext*>(args->context);
    RTCRayN* ray = RTCRayHitN_RayN(args->rayhit, args->N);
    RTCHitN* hit = RTCRayHitN_HitN(args->rayhit, args->N);
    for (unsigned i = 0; i < args->N; ++i) {
        if (args->valid[i] != -1) continue;
        Vec3 o, d;
        double tMin, tMax;
        laneRay(ray, args->N, i, ctx, o, d, tMin, tMax);
        const Vec3 oi = self->map_.toIndex(o), di = self->map_.directionToIndex(d);
        double t;
        if (!self->intersectBrick(args->primID, oi, di, tMin, tMax, t)) continue;
        const Vec3 ng = -self->worldGradient(args->primID, oi + di * t);
        RTCRayN_tfar(ray, args->N, i) = static_cast<float>(t);
        RTCHitN_Ng_x(hit, args->N, i) = static_cast<float>(ng.x);
        RTCHitN_Ng_y(hit, args->N, i) = static_cast<float>(ng.y);
        RTCHitN_Ng_z(hit, args->N, i) = static_cast<float>(ng.z);
        RTCHitN_u(hit, args->N, i) = 0.0f;
        RTCHitN_v(hit, args->N, i) = 0.0f;
        RTCHitN_primID(hit, args->N, i) = args->primID;
        RTCHitN_geomID(hit, args->N, i) = args->geomID;
        RTCHitN_instID(hit, args->N, i, 0) = args->context->instID[0];
        if (args->N == 1 && ctx && ctx->ray) {
            ctx->tHit = t;
            ctx->geomId = args->geomID;
            ctx->primId = args->primID;
        }
    }
}

void IsoExactSurface::occludedCallback(const RTCOccludedFunctionNArguments* args) {
    const auto* self = static_cast<const IsoExactSurface*>(args->geometryUserPtr);
    const auto* ctx = reinterpret_cast<const RayContext*>(args->context);
    for (unsigned i = 0; i < args->N; ++i) {
        if (args->valid[i] != -1) continue;
        Vec3 o, d;
        double tMin, tMax;
        laneRay(args->ray, args->N, i, ctx, o, d, tMin, tMax);
        double t;
        if (self->intersectBrick(args->primID, self->map_.toIndex(o),
                                 self->map_.directionToIndex(d), tMin, tMax, t))
            RTCRayN_tfar(args->ray, args->N, i) = -std::numeric_limits<float>::infinity();
    }
}

}  // namespace lobe
