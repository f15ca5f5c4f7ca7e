#include "volume/volume_marcher.h"

#include "core/cpu_features.h"
#include "core/error.h"
#include "core/memory.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstring>

namespace lobe {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
// B-spline support around floor(p): voxels floor(p) − 1 … floor(p) + 2 (reconstruction.h).
constexpr int kSupportBelow = 1;
constexpr int kSupportAbove = 2;
// Margin on a brick's value range before asking the transfer function (guards the rounding of
// the reconstructed value; header, "Empty-space skipping").
constexpr double kRangeMargin = 1e-6;
// The range of the cubic B-spline over the cell whose 4³ control values start at footprint index
// (x, y, z) of `foot` (side fp, x fastest): the values of the uniform cubic B-spline on one cell
// are a tensor-product cubic whose Bézier coefficients follow from the control values along each
// axis by B0 = (P0 + 4P1 + P2)/6, B1 = (2P1 + P2)/3, B2 = (P1 + 2P2)/3, B3 = (P1 + 4P2 + P3)/6
// (Böhm's conversion; Farin, "Curves and Surfaces for CAGD", 5th ed., §8.5), and a Bézier patch
// lies within the range of its coefficients (convex hull property). Tighter than the range of the
// 64 control values, which spans three voxels of the data's variation rather than one.
void bsplineCellRange(const std::vector<float>& foot, int fp, int x, int y, int z, double& lo,
                      double& hi) {
    double q[4][4][4];  // [z][y][x]
    for (int c = 0; c < 4; ++c)
        for (int b = 0; b < 4; ++b)
            for (int a = 0; a < 4; ++a)
                q[c][b][a] = foot[(size_t(z + c) * fp + (y + b)) * fp + (x + a)];
    auto toBezier = [](double& p0, double& p1, double& p2, double& p3) {
        const double b0 = (p0 + 4.0 * p1 + p2) / 6.0, b1 = (2.0 * p1 + p2) / 3.0,
                     b2 = (p1 + 2.0 * p2) / 3.0, b3 = (p1 + 4.0 * p2 + p3) / 6.0;
        p0 = b0;
        p1 = b1;
        p2 = b2;
        p3 = b3;
    };
    for (int c = 0; c < 4; ++c)
        for (int b = 0; b < 4; ++b) toBezier(q[c][b][0], q[c][b][1], q[c][b][2], q[c][b][3]);
    for (int c = 0; c < 4; ++c)
        for (int a = 0; a < 4; ++a) toBezier(q[c][0][a], q[c][1][a], q[c][2][a], q[c][3][a]);
    for (int b = 0; b < 4; ++b)
        for (int a = 0; a < 4; ++a) toBezier(q[0][b][a], q[1][b][a], q[2][b][a], q[3][b][a]);
    lo = hi = q[0][0][0];
    for (int c = 0; c < 4; ++c)
        for (int b = 0; b < 4; ++b)
            for (int a = 0; a < 4; ++a) {
                lo = std::min(lo, q[c][b][a]);
                hi = std::max(hi, q[c][b][a]);
            }
}

// Below this step (voxels) the marcher jumps past a transparent cell; at and above it, it steps.
constexpr double kCellJumpStep = 0.3;
// Below this step (voxels) the cubic B-spline is read through the ray's polynomial in each cell
// (GridReconstructor::bsplineOnRay). Rendering 1 at 512² × 8 spp: step 0.05, 16.0 → 15.2 CPU s;
// at 0.1 it would cost 3 % more (6.7 samples a cell do not pay for building the polynomial).
constexpr double kRayPolynomialStep = 0.075;
// One row of an octant table (DvrVolume::computeCellDistances): c holds 0 (visible) or the cap
// for cells 1 … nx, r0/r1/r2 the finished rows at y + sy, z + sz and both, and r0s/r1s/r2s the
// same rows shifted by sx; rowA and rowB are scratch of nx + 2 cells. A free function with its
// arguments by value: stores through unsigned char may alias anything, and captured references
// reloaded in every iteration kept the loops scalar.
void octantRow(unsigned char* c, const unsigned char* r0, const unsigned char* r0s,
               const unsigned char* r1, const unsigned char* r1s, const unsigned char* r2,
               const unsigned char* r2s, int nx, int sx, unsigned char* rowA, unsigned char* rowB) {
    unsigned char* __restrict in = rowA;
    unsigned char* __restrict out = rowB;
    for (int x = 1; x <= nx; ++x) {
        unsigned char m = std::min(r0[x], r0s[x]);
        m = std::min(m, std::min(r1[x], r1s[x]));
        m = std::min(m, std::min(r2[x], r2s[x]));
        // m ≤ cap < 255: no overflow. Visible cells (0) stay 0.
        in[x] = std::min(c[x], (unsigned char)(m + 1));
    }
    // Along the row, against the sign: c(x) = min over k ≥ 0 of in(x + k·sx) + k, the serial
    // recurrence c(x) = min(in(x), c(x + sx) + 1) unrolled by doubling (after the round of
    // shift s, k runs over [0, 2s); shifts up to 128 cover the cap), each round a loop the
    // compiler vectorises. Cells past the row's end are the cap and change nothing.
    for (int sh = 1; sh <= 128 && sh < nx; sh *= 2) {
        if (sx > 0) {
            for (int x = 1; x <= nx - sh; ++x)
                out[x] = (unsigned char)std::min<int>(in[x], int(in[x + sh]) + sh);
            for (int x = std::max(1, nx - sh + 1); x <= nx; ++x) out[x] = in[x];
        } else {
            for (int x = 1; x <= sh; ++x) out[x] = in[x];
            for (int x = sh + 1; x <= nx; ++x)
                out[x] = (unsigned char)std::min<int>(in[x], int(in[x - sh]) + sh);
        }
        std::swap(in, out);
    }
    std::copy_n(in + 1, nx, c + 1);
}
}  // namespace

DvrVolume::DvrVolume(openvdb::FloatGrid::ConstPtr grid, TransferFunction tf,
                     const DvrSettings& settings, const std::string& name)
    : grid_(std::move(grid)), tf_(std::move(tf)), settings_(settings) {
    if (!grid_) throw Error(name + ": no grid");
    if (!(settings_.stepVoxels > 0.0 && settings_.stepVoxels <= 16.0))
        throw Error(name + ": step must be in (0, 16] voxels, got " +
                    std::to_string(settings_.stepVoxels));
    const int bs = settings_.brickSize;
    if (bs < 1 || bs > 64 || (bs & (bs - 1)) != 0)
        throw Error(name + ": brick size must be a power of two in [1, 64] voxels, got " +
                    std::to_string(bs));
    while ((1 << brickShift_) < bs) ++brickShift_;
    if (!(settings_.minGradientPerVoxel >= 0.0))
        throw Error(name + ": the gradient threshold must be >= 0");
    geometry_ = GridGeometry(*grid_, name);

    const openvdb::CoordBBox active = grid_->evalActiveVoxelBoundingBox();
    empty_ = grid_->activeVoxelCount() == 0 || active.empty();
    if (empty_) return;
    // Domain: the active box grown by the B-spline support (2 voxels) on each side.
    const openvdb::Coord lo = active.min() - openvdb::Coord(2);
    const openvdb::Coord hi = active.max() + openvdb::Coord(2);
    domainLo_ = Vec3(lo.x(), lo.y(), lo.z());
    domainHi_ = Vec3(hi.x(), hi.y(), hi.z());
    const int b = settings_.brickSize;
    // The brick table is dense over the active box: a foreign grid whose active voxels lie far
    // apart (two voxels 1e5 apart: 1.6e13 bricks) is refused by its size before anything is
    // allocated — by the machine's memory, and at 2^28 bricks (an active box of 2580³ voxels
    // at 4³ a brick; larger ones take minutes just to build the table).
    double bricks = 1.0;
    for (int a = 0; a < 3; ++a) bricks *= double((int64_t(hi[a]) - lo[a]) / b + 1);
    const std::string span = std::to_string(int64_t(hi.x()) - lo.x() - 3) + " x " +
                             std::to_string(int64_t(hi.y()) - lo.y() - 3) + " x " +
                             std::to_string(int64_t(hi.z()) - lo.z() - 3) + " voxels";
    if (bricks > double(1 << 28))
        throw Error(name + ": the active voxels span " + span +
                    ", more than volume rendering "
                    "handles (2580³); crop the grid to the data, or prune stray active voxels");
    checkFits(bricks * double(1 + 8 * ((b * b * b + 63) / 64)),
              name + ": the empty-space table of an active box of " + span);
    // Every voxel a sample in the domain reads: floor(p) − 1 … floor(p) + 2 for the B-spline
    // and for central differences of the trilinear field, p ∈ [lo, hi].
    const openvdb::CoordBBox denseBox(lo - openvdb::Coord(1), hi + openvdb::Coord(2));
    const openvdb::Coord dd = denseBox.dim();
    // Only where it is cheap beside the machine's memory (an eighth at most): otherwise the
    // samplers read the tree, as fast as before the copy existed.
    const double memory = memoryBudget().bytes;
    const double budget =
        memory > 0.0 ? std::min(DenseField::kMaxBytes, memory / 8.0) : DenseField::kMaxBytes;
    if (4.0 * double(dd.x()) * double(dd.y()) * double(dd.z()) <= budget)
        dense_ = std::make_shared<const DenseField>(*grid_, denseBox);
    for (int a = 0; a < 3; ++a) {
        brickLo_[a] = lo[a];
        brickCount_[a] = (hi[a] - lo[a]) / b + 1;  // covers [lo, hi] (a point at hi included)
    }
    const size_t count = size_t(brickCount_[0]) * brickCount_[1] * brickCount_[2];
    brickTransparent_.assign(count, 0);
    cellWords_ = (b * b * b + 63) / 64;
    cellTransparent_.assign(count * size_t(cellWords_), 0);
    // A cell's support, as offsets from the cell: [c + lo, c + lo + n) per axis.
    const bool bspline = settings_.reconstruction == Reconstruction::kCubicBSpline;
    const int supportLo = bspline ? -1 : 0, supportN = bspline ? 4 : 2;
    const int fp = b + kSupportBelow + kSupportAbove;  // brick footprint side
    // Min/max over each brick's sample footprint, in parallel over z-slabs of bricks; one
    // accessor per task (accessors are not thread-safe).
    tbb::parallel_for(0, brickCount_[2], [&](int bz) {
        openvdb::FloatGrid::ConstAccessor acc = grid_->getConstAccessor();
        std::vector<float> foot(size_t(fp) * fp * fp);
        std::vector<float> rangeX(2 * size_t(fp) * fp * b), rangeY(2 * size_t(fp) * b * b);
        // Whether every value in [lo, hi] (widened by a rounding margin) is transparent.
        auto transparent = [&](double lo, double hi) {
            const double m =
                kRangeMargin * std::max(1.0, std::max(std::abs(double(lo)), std::abs(double(hi))));
            return tf_.isTransparent(lo - m, hi + m);
        };
        for (int by = 0; by < brickCount_[1]; ++by)
            for (int bx = 0; bx < brickCount_[0]; ++bx) {
                const int x0 = brickLo_[0] + bx * b, y0 = brickLo_[1] + by * b,
                          z0 = brickLo_[2] + bz * b;
                float vmin = std::numeric_limits<float>::infinity(), vmax = -vmin;
                for (int z = z0 - kSupportBelow; z < z0 + b + kSupportAbove; ++z)
                    for (int y = y0 - kSupportBelow; y < y0 + b + kSupportAbove; ++y)
                        for (int x = x0 - kSupportBelow; x < x0 + b + kSupportAbove; ++x) {
                            const float v = dense_ && dense_->holds(x, y, z, 1)
                                                ? *dense_->at(x, y, z)
                                                : acc.getValue(openvdb::Coord(x, y, z));
                            foot[(size_t(z - z0 + kSupportBelow) * fp + (y - y0 + kSupportBelow)) *
                                     fp +
                                 (x - x0 + kSupportBelow)] = v;
                            vmin = std::min(vmin, v);
                            vmax = std::max(vmax, v);
                        }
                const size_t i = (size_t(bz) * brickCount_[1] + by) * brickCount_[0] + bx;
                brickTransparent_[i] = transparent(vmin, vmax) ? 1 : 0;
                if (brickTransparent_[i]) continue;
                // Cell level: min/max over each cell's support window, separably (along x, then
                // y, then z) on the footprint: (min, max) pairs shrink fp³ → fp²·b → fp·b² → b³.
                const int o =
                    supportLo + kSupportBelow;  // first footprint index of cell 0's window
                auto window = [&](auto read, int c, float& lo, float& hi) {
                    lo = std::numeric_limits<float>::infinity();
                    hi = -lo;
                    for (int d = 0; d < supportN; ++d) {
                        float a, z;
                        read(o + c + d, a, z);
                        lo = std::min(lo, a);
                        hi = std::max(hi, z);
                    }
                };
                for (int z = 0; z < fp; ++z)
                    for (int y = 0; y < fp; ++y)
                        for (int cx = 0; cx < b; ++cx) {
                            const size_t row = (size_t(z) * fp + y) * fp;
                            auto read = [&](int x, float& a, float& zz) { a = zz = foot[row + x]; };
                            const size_t out = (size_t(z) * fp + y) * b + cx;
                            window(read, cx, rangeX[2 * out], rangeX[2 * out + 1]);
                        }
                for (int z = 0; z < fp; ++z)
                    for (int cy = 0; cy < b; ++cy)
                        for (int cx = 0; cx < b; ++cx) {
                            auto read = [&](int y, float& a, float& zz) {
                                const size_t in = (size_t(z) * fp + y) * b + cx;
                                a = rangeX[2 * in];
                                zz = rangeX[2 * in + 1];
                            };
                            const size_t out = (size_t(z) * b + cy) * b + cx;
                            window(read, cy, rangeY[2 * out], rangeY[2 * out + 1]);
                        }
                uint64_t* words = &cellTransparent_[i * size_t(cellWords_)];
                for (int cz = 0; cz < b; ++cz)
                    for (int cy = 0; cy < b; ++cy)
                        for (int cx = 0; cx < b; ++cx) {
                            auto read = [&](int z, float& a, float& zz) {
                                const size_t in = (size_t(z) * b + cy) * b + cx;
                                a = rangeY[2 * in];
                                zz = rangeY[2 * in + 1];
                            };
                            float lo, hi;
                            window(read, cz, lo, hi);
                            const int bit = (cz * b + cy) * b + cx;
                            double blo, bhi;
                            // A B-spline cell whose control values are not all transparent may
                            // still be: its Bézier range is tighter (bsplineCellRange).
                            if (transparent(lo, hi) ||
                                (bspline && (bsplineCellRange(foot, fp, cx, cy, cz, blo, bhi),
                                             transparent(blo, bhi))))
                                words[bit >> 6] |= uint64_t(1) << (bit & 63);
                        }
            }
    });
    // The octant tables (8 bytes a cell) within the dense copy's budget too, so both together
    // take at most a quarter of the machine's memory; beyond, the brick and cell tests.
    const double tableBytes =
        8.0 * double(brickCount_[0]) * brickCount_[1] * brickCount_[2] * double(b) * b * b;
    if (dense_ && settings_.emptySpaceSkipping && !settings_.preIntegrated && tableBytes <= budget)
        computeCellDistances();
    computeClearance();
    if (settings_.preIntegrated) pre_ = std::make_shared<const PreIntegratedTf>(tf_);
    tfArrays_ = std::make_shared<const TfArrays>(tf_);
    double alphaMax = 0.0;
    for (const TfPoint& q : tf_.points()) alphaMax = std::max(alphaMax, q.opacity);
    correction_ = OpacityCorrection(settings_.stepVoxels, alphaMax);
    // The values outside [visibleLo_, visibleHi_] are transparent (the first and last of the
    // TF's transparent ranges when they reach ±inf; at their finite end the opacity may already
    // be > 0, a step, so the comparisons there are strict).
    const auto ranges = tf_.transparentRanges();
    if (!ranges.empty() && ranges.front().first == -kInf) visibleLo_ = ranges.front().second;
    if (!ranges.empty() && ranges.back().second == kInf) visibleHi_ = ranges.back().first;
}

void DvrVolume::computeClearance() {
    // Chessboard (L∞) distance, in bricks, from every transparent brick to the nearest brick that
    // is not: the two-pass chamfer transform with unit weights over the 26-neighbourhood, which
    // is exact for the chessboard metric (Rosenfeld & Pfaltz 1966, "Sequential operations in
    // digital picture processing", extended to 3-D; Borgefors 1984). Outside the table counts as
    // transparent: no sample lies there. Saturates at kMaxClearance (a smaller value is only a
    // shorter jump). Before: 1 = transparent, 0 = not. Jumping past the largest transparent
    // cube around the brick, not past the brick alone, cut the CThead's T2 render (step 0.25)
    // from 7.9 to 6.1 CPU s: a ray crossed ~60 air bricks one at a time.
    const int nx = brickCount_[0], ny = brickCount_[1], nz = brickCount_[2];
    auto at = [&](int x, int y, int z) -> unsigned char& {
        return brickTransparent_[(size_t(z) * ny + y) * nx + x];
    };
    for (unsigned char& c : brickTransparent_) c = c ? kMaxClearance : 0;
    // A pass visits bricks in one raster order and relaxes each from its 13 neighbours already
    // visited in that order (sign = +1: those before it, −1: those after it).
    auto pass = [&](int sign) {
        const int z0 = sign > 0 ? 0 : nz - 1, y0 = sign > 0 ? 0 : ny - 1,
                  x0 = sign > 0 ? 0 : nx - 1;
        for (int z = z0; z >= 0 && z < nz; z += sign)
            for (int y = y0; y >= 0 && y < ny; y += sign)
                for (int x = x0; x >= 0 && x < nx; x += sign) {
                    unsigned char& c = at(x, y, z);
                    if (c == 0) continue;
                    int best = c;
                    for (int dz = -1; dz <= 0; ++dz)
                        for (int dy = -1; dy <= 1; ++dy)
                            for (int dx = -1; dx <= 1; ++dx) {
                                // The 13 neighbours that precede (x, y, z) in this pass's order.
                                if (dz == 0 && (dy > 0 || (dy == 0 && dx >= 0))) continue;
                                const int qx = x + sign * dx, qy = y + sign * dy,
                                          qz = z + sign * dz;
                                if (qx < 0 || qy < 0 || qz < 0 || qx >= nx || qy >= ny || qz >= nz)
                                    continue;
                                best = std::min(best, at(qx, qy, qz) + 1);
                            }
                    c = (unsigned char)best;
                }
    };
    pass(+1);
    pass(-1);
}

void DvrVolume::computeCellDistances() {
    // Header, "Cell distances": per octant of directions (signs sx, sy, sz), the side of the
    // largest transparent cube of cells that starts at a cell and extends towards that octant,
    // F(c) = 0 on a visible cell, else min(cap, 1 + min over the 7 neighbours c + δ, δ ∈
    // {0,1}³ \ {0} scaled by the signs): the cube of side m at c is c and the seven cubes of side
    // m − 1 at those neighbours (each offset o ∈ [0, m)³ \ {0} is δ + o' with δ_a = [o_a ≥ 1]
    // and o' ∈ [0, m − 1)³). One raster pass in the order opposite to the octant's signs reaches
    // every neighbour first — the forward half of the two-pass chamfer transform (Rosenfeld &
    // Pfaltz 1966; Borgefors 1984), exact for this one-sided chessboard metric. Each row: the
    // six neighbours in the next row and slab at once (a loop the compiler vectorises), then the
    // one along the row, in order. The tables are padded by one cell of `cap` on every side
    // (outside counts as transparent) so no neighbour needs a bounds test; each is copied out
    // without the padding, brick by brick.
    const int b = settings_.brickSize, shift = brickShift_;
    for (int a = 0; a < 3; ++a) cellCount_[a] = brickCount_[a] * b;
    const int nx = cellCount_[0], ny = cellCount_[1], nz = cellCount_[2];
    const int px = nx + 2, py = ny + 2, pz = nz + 2;
    const size_t row = size_t(px), slab = size_t(px) * py;
    constexpr unsigned char cap = kOctantDistanceCap;
    std::vector<unsigned char> init(slab * pz, cap);
    // Brick by brick: transparent bricks keep `cap`; the others take their cell bits.
    auto forEachBrick = [&](auto&& fn) {
        tbb::parallel_for(0, brickCount_[2], [&](int bz) {
            for (int by = 0; by < brickCount_[1]; ++by)
                for (int bx = 0; bx < brickCount_[0]; ++bx)
                    fn(bx, by, bz,
                       (size_t(bz) * brickCount_[1] + by) * size_t(brickCount_[0]) + bx);
        });
    };
    forEachBrick([&](int bx, int by, int bz, size_t brick) {
        if (brickTransparent_[brick]) return;
        const uint64_t* words = &cellTransparent_[brick * size_t(cellWords_)];
        for (int cz = 0; cz < b; ++cz)
            for (int cy = 0; cy < b; ++cy) {
                unsigned char* out = &init[size_t(bz * b + cz + 1) * slab +
                                           size_t(by * b + cy + 1) * row + size_t(bx * b + 1)];
                for (int cx = 0; cx < b; ++cx) {
                    const int bit = (cz * b + cy) * b + cx;
                    out[cx] = (words[bit >> 6] >> (bit & 63) & 1) ? cap : 0;
                }
            }
    });
    tbb::parallel_for(0, 8, [&](int octant) {
        const int sx = octant & 1 ? -1 : 1, sy = octant & 2 ? -1 : 1, sz = octant & 4 ? -1 : 1;
        std::vector<unsigned char> d(init);
        // Default-initialised (each task its own, in parallel): the copy below writes every cell.
        octantDistance_[size_t(octant)].reset(new unsigned char[size_t(nx) * ny * nz]);
        std::vector<unsigned char> rowA(static_cast<size_t>(px)), rowB(rowA);
        const std::ptrdiff_t dy = sy * std::ptrdiff_t(row), dz = sz * std::ptrdiff_t(slab);
        for (int zi = 0; zi < nz; ++zi) {
            const int z = sz > 0 ? nz - zi : zi + 1;  // the neighbour at z + sz first
            for (int yi = 0; yi < ny; ++yi) {
                const int y = sy > 0 ? ny - yi : yi + 1;
                unsigned char* c = &d[size_t(z) * slab + size_t(y) * row];
                const unsigned char *r0 = c + dy, *r0s = r0 + sx, *r1 = c + dz, *r1s = r1 + sx,
                                    *r2 = c + dz + dy, *r2s = r2 + sx;
                octantRow(c, r0, r0s, r1, r1s, r2, r2s, nx, sx, rowA.data(), rowB.data());
            }
        }
        // Stored brick by brick (the B³ cells of a brick together, x fastest: one 64-byte cache
        // line at B = 4), so the rays of a tile that look up nearby cells share lines.
        unsigned char* table = octantDistance_[size_t(octant)].get();
        for (size_t brick = 0, n = size_t(brickCount_[0]) * brickCount_[1] * brickCount_[2];
             brick < n; ++brick) {
            const int bx = int(brick % size_t(brickCount_[0]));
            const int by = int(brick / size_t(brickCount_[0]) % size_t(brickCount_[1]));
            const int bz = int(brick / (size_t(brickCount_[0]) * brickCount_[1]));
            unsigned char* out = &table[brick << (3 * shift)];
            for (int cz = 0; cz < b; ++cz)
                for (int cy = 0; cy < b; ++cy, out += b) {
                    const unsigned char* in =
                        &d[size_t(bz * b + cz + 1) * slab + size_t(by * b + cy + 1) * row +
                           size_t(bx * b + 1)];
                    if (b == 4)
                        std::memcpy(out, in, 4);  // one move, not a call
                    else
                        std::copy_n(in, b, out);
                }
        }
    });
}

int DvrVolume::cellDistance(int i, int j, int k) const {
    const int q[3] = {i - brickLo_[0], j - brickLo_[1], k - brickLo_[2]};
    for (int a = 0; a < 3; ++a)
        if (q[a] < 0 || q[a] >= cellCount_[a]) return -1;
    // The nearest visible cell lies in one octant's forward region (header, "Cell distances").
    int d = kCellDistanceCap;
    for (const auto& t : octantDistance_) d = std::min<int>(d, t[cellSlot(q[0], q[1], q[2])]);
    return d;
}

bool DvrVolume::cellTransparent(int i, int j, int k) const {
    if (brickTransparent_.empty()) return false;
    const int q[3] = {i - brickLo_[0], j - brickLo_[1], k - brickLo_[2]};
    const int b = settings_.brickSize;
    int bi[3], bit = 0;
    for (int a = 2; a >= 0; --a) {
        if (q[a] < 0 || q[a] >= brickCount_[a] * b) return false;
        bi[a] = q[a] >> brickShift_;
        bit = bit * b + (q[a] & (b - 1));
    }
    const size_t brick = (size_t(bi[2]) * brickCount_[1] + bi[1]) * brickCount_[0] + bi[0];
    return brickTransparent_[brick] != 0 ||
           (cellTransparent_[brick * size_t(cellWords_) + (bit >> 6)] >> (bit & 63) & 1);
}

double DvrVolume::transparentBrickFraction() const {
    if (brickTransparent_.empty()) return 1.0;
    size_t n = 0;
    for (unsigned char c : brickTransparent_) n += c ? 1 : 0;
    return double(n) / double(brickTransparent_.size());
}

VolumeRaySampler::VolumeRaySampler(const DvrVolume& volume)
    : vol_(&volume), recon_(volume.grid(), volume.dense()) {}

bool VolumeRaySampler::begin(const Ray& ray, double jitter, double stepScale) {
    active_ = false;
    k_ = 0;
    tEnter_ = 0.0;
    tExit_ = -1.0;
    if (vol_->empty_) return false;
    const GridGeometry& g = vol_->geometry_;
    oIdx_ = g.worldToIndex(ray.o);
    dIdx_ = g.worldToIndexDirection(ray.d);
    const double idxSpeed = dIdx_.length();  // index-space length per unit t
    if (!(idxSpeed > 0.0) || !std::isfinite(idxSpeed)) return false;
    // Slab clipping against the domain box (Kay & Kajiya 1986) in index space; t is shared with
    // world space because the map is affine.
    double t0 = ray.tMin, t1 = ray.tMax;
    for (int a = 0; a < 3; ++a) {
        if (dIdx_[a] == 0.0) {
            if (oIdx_[a] < vol_->domainLo_[a] || oIdx_[a] > vol_->domainHi_[a]) return false;
            continue;
        }
        double ta = (vol_->domainLo_[a] - oIdx_[a]) / dIdx_[a];
        double tb = (vol_->domainHi_[a] - oIdx_[a]) / dIdx_[a];
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
    }
    // Clipping (core/clip.h): the kept intervals of the ray, exactly; the lattice starts at the
    // first kept point and jumps over the gaps (next()).
    clip_.count = 0;
    clipIndex_ = 0;
    if (!vol_->settings_.clip.empty()) {
        Ray r = ray;
        r.tMin = t0;
        r.tMax = t1;
        if (!(t0 <= t1)) return false;
        clip_ = clipRay(r, vol_->settings_.clip);
        if (clip_.empty()) return false;
        t0 = clip_.v[0].lo.t;
        t1 = clip_.v[clip_.count - 1].hi.t;
    }
    if (!(t0 <= t1) || !std::isfinite(t0) || !std::isfinite(t1)) return false;
    tEnter_ = t0;
    tExit_ = t1;
    stepVoxels_ = vol_->settings_.stepVoxels * (stepScale >= 1.0 ? stepScale : 1.0);
    dt_ = stepVoxels_ / idxSpeed;
    jitter_ = std::min(std::max(jitter, 0.0), std::nextafter(1.0, 0.0));
    // Opacity exponent: the world length of one step in reference voxel lengths (header).
    stepRefLengths_ = dt_ * ray.d.length() / g.referenceVoxelLength();
    lastAlphaVoxel_ = -1.0;
    // A polynomial from an earlier march of the same ray (built at another jitter) would give
    // the same values up to rounding only: each march builds its own, so an image does not
    // depend on what a thread rendered before.
    recon_.forgetRay();
    prevK_ = -2;
    prevSkippable_ = false;
    visibleCellEnd_ = -kInf;
    octantTable_ = nullptr;
    if (vol_->hasCellDistances()) {
        const int octant =
            (dIdx_[0] < 0.0 ? 1 : 0) | (dIdx_[1] < 0.0 ? 2 : 0) | (dIdx_[2] < 0.0 ? 4 : 0);
        octantTable_ = vol_->octantDistance_[size_t(octant)].get();
    }
    for (int a = 0; a < 3; ++a) invDIdx_[a] = dIdx_[a] != 0.0 ? 1.0 / dIdx_[a] : 0.0;
    invDt_ = 1.0 / dt_;
    rayPolynomial_ = vol_->settings_.reconstruction == Reconstruction::kCubicBSpline &&
                     stepVoxels_ < kRayPolynomialStep;
    kLast_ = std::floor((tExit_ - tEnter_) / dt_ - jitter_);
    boundRayCells_ = rayPolynomial_ && !vol_->pre_ && vol_->settings_.emptySpaceSkipping;
    boundCell_[0] = boundCell_[1] = boundCell_[2] = std::numeric_limits<int>::min();
    // Lattice packets: about one voxel of the ray at a time, at most LatticePacket::kMaxPoints;
    // trilinear from the dense copy or the B-spline's ray polynomial, without pre-integration.
    packetN_ = 0;
    packetSameCell_ = 0;
    packetSize_ = 0;
    const DvrSettings& set = vol_->settings_;
    const bool packetFilter =
        (set.reconstruction == Reconstruction::kTrilinear && vol_->dense_) || rayPolynomial_;
    if (set.simd && !simdDisabledByEnvironment() && !vol_->pre_ && packetFilter) {
        const double perVoxel = std::floor(1.0 / stepVoxels_);
        if (perVoxel >= LatticePacket::kMinPoints)
            packetSize_ = int(std::min<double>(perVoxel, LatticePacket::kMaxPoints));
        for (int a = 0; a < 3; ++a) {
            lattice_.o[a] = oIdx_[a];
            lattice_.d[a] = dIdx_[a];
        }
        lattice_.tEnter = tEnter_;
        lattice_.jitter = jitter_;
        lattice_.dt = dt_;
    }
    coarseTrilinear_ = octantTable_ && stepVoxels_ >= kCellJumpStep && packetSize_ == 0 &&
                       set.reconstruction == Reconstruction::kTrilinear && !vol_->pre_ &&
                       clip_.count <= 1;
    // The AVX2 copy of the coarse path where the CPU has it; DvrSettings::simd = false or
    // LOBE_SIMD=off keeps the baseline copy (the same samples; tests compare the two).
    coarseAvx2_ = coarseTrilinear_ && set.simd && !simdDisabledByEnvironment() && cpuHasAvx2();
    active_ = true;
    return true;
}

double VolumeRaySampler::peekT() const {
    if (!active_) return kInf;
    const double t = tEnter_ + (double(k_) + jitter_) * dt_;
    return t > tExit_ ? kInf : t;
}

bool VolumeRaySampler::next(double tEnd, VolumeSample& s, bool withNormal) {
    if (!active_) return false;
    if (coarseTrilinear_)
        return coarseAvx2_ ? nextCoarseTrilinearAvx2(tEnd, s, withNormal)
                           : nextCoarseTrilinear(tEnd, s, withNormal);
    const DvrVolume& v = *vol_;
    const DvrSettings& set = v.settings_;
    const int b = set.brickSize;
    const bool pre = v.pre_ != nullptr;
    while (true) {
        const double t = tEnter_ + (double(k_) + jitter_) * dt_;
        if (t > tExit_) {
            active_ = false;
            return false;
        }
        if (t >= tEnd) return false;
        if (clip_.count > 1) {
            // Between kept intervals: on to the first lattice point of the next one.
            while (clipIndex_ < clip_.count && t > clip_.v[clipIndex_].hi.t) ++clipIndex_;
            if (clipIndex_ == clip_.count) {
                active_ = false;
                return false;
            }
            const double lo = clip_.v[clipIndex_].lo.t;
            if (t < lo) {
                const double kf = std::ceil((lo - tEnter_) * invDt_ - jitter_);
                k_ = std::max(k_ + 1, kf > 9e18 ? (long long)9e18 : (long long)kf);
                continue;
            }
        }
        const Vec3 p = oIdx_ + dIdx_ * t;
        bool skippable = false;  // this point lies in a transparent brick or cell
        // A packet starts at a point found visible; the points after it in the same cell
        // (floor(p) equal) get the same answer from the tables below, so they skip the test.
        const bool sameCell = k_ > packetK0_ && k_ - packetK0_ < packetSameCell_;
        if (octantTable_) {
            // One table read per point (header, "Cell distances").
            int cell[3];
            if (!sameCell && t >= visibleCellEnd_ && skipByCellDistance(p, cell)) continue;
        } else if (set.emptySpaceSkipping && !sameCell) {
            // Brick and cell of floor(p), in integers (this runs for every lattice point, so no
            // std::floor or division: a truncation corrected downwards, and a shift by log2 B).
            // Points of an edge brick's clamp may lie outside it: their cell is not tested.
            int bi[3], cell[3], bit = 0;
            bool inside = true;
            for (int a = 2; a >= 0; --a) {
                int f = int(p[a]);
                f -= p[a] < double(f) ? 1 : 0;  // floor, |p| < 2³¹ inside the domain
                cell[a] = f;
                const int q = f - v.brickLo_[a];
                bi[a] = q < 0 ? 0 : std::min(v.brickCount_[a] - 1, q >> v.brickShift_);
                const int c = q - (bi[a] << v.brickShift_);
                inside = inside && c >= 0 && c < b;
                bit = bit * b + c;
            }
            const size_t idx =
                (size_t(bi[2]) * v.brickCount_[1] + bi[1]) * v.brickCount_[0] + bi[0];
            // With pre-integration the segment that ends at the first point of a transparent
            // run still starts at a visible one: that point is evaluated ("closing"), the next
            // ones are skipped.
            const bool closing = pre && prevK_ == k_ - 1 && !prevSkippable_;
            if (const int clearance = v.brickTransparent_[idx]) {
                if (!closing) {
                    // Past the cube of (2·clearance − 1)³ transparent bricks centred on this one.
                    int lo[3];
                    for (int a = 0; a < 3; ++a) lo[a] = v.brickLo_[a] + (bi[a] - clearance + 1) * b;
                    jumpPastBox(lo, (2 * clearance - 1) * b);
                    continue;
                }
                skippable = true;
            } else if (inside &&
                       (v.cellTransparent_[idx * size_t(v.cellWords_) + (bit >> 6)] >> (bit & 63) &
                        1)) {
                // Cell level, inside the brick: past the cell's box (a cell holds ~1 / step
                // lattice points along a ray: 20 at the paper's step). At coarse steps a cell
                // holds one or two points, and one step is cheaper than computing the jump.
                if (!closing) {
                    if (stepVoxels_ < kCellJumpStep) {
                        jumpPastBox(cell, 1);
                    } else {
                        ++skipped_;
                        ++k_;
                    }
                    continue;
                }
                skippable = true;
            }
        }
        if (boundRayCells_ && !(packetSize_ > 0 && k_ >= packetK0_ && k_ - packetK0_ < packetN_)) {
            int cell[3];
            if (rayCellTransparent(t, cell)) {
                jumpPastBox(cell, 1);
                continue;
            }
        }
        ++evaluated_;
        const bool fromPacket =
            packetSize_ > 0 && (k_ - packetK0_ < packetN_ && k_ >= packetK0_ ? true : fillPacket());
        const double value = fromPacket       ? packet_.value[k_ - packetK0_]
                             : rayPolynomial_ ? recon_.bsplineOnRay(oIdx_, dIdx_, t)
                                              : recon_.value(set.reconstruction, p);
        double alpha;
        Spectrum colour;
        if (pre) {
            // The segment from the previous lattice point to this one (its value reconstructed
            // here when that point was skipped; such values are not counted as evaluated).
            const double front =
                prevK_ == k_ - 1
                    ? prevValue_
                    : recon_.value(set.reconstruction,
                                   oIdx_ + dIdx_ * (tEnter_ + (double(k_ - 1) + jitter_) * dt_));
            prevK_ = k_;
            prevValue_ = value;
            prevSkippable_ = skippable;
            double where;
            v.pre_->segment(front, value, stepRefLengths_, alpha, colour, where);
            ++k_;
            if (!(alpha > 0.0)) continue;
            if (set.mask && !set.mask->keeps(v.geometry_.indexToWorld(oIdx_ + dIdx_ * t))) continue;
            // The sample sits at the segment's centre of extinction (pre_integration.h).
            const double tc = t - (1.0 - where) * dt_;
            return emit(s, tc, oIdx_ + dIdx_ * tc, value, alpha, colour, withNormal);
        } else {
            double alphaVoxel;
            if (fromPacket) {
                const int i = int(k_ - packetK0_);
                alphaVoxel = packet_.alpha[i];
                colour = Spectrum(packet_.colour[0][i], packet_.colour[1][i], packet_.colour[2][i]);
            } else {
                v.tf_.evaluate(value, alphaVoxel, colour);
            }
            ++k_;
            if (!(alphaVoxel > 0.0)) {
                if (fromPacket && clip_.count <= 1) skipTransparentPacketRun(tEnd);
                continue;
            }
            if (set.mask && !set.mask->keeps(v.geometry_.indexToWorld(p))) continue;
            alpha = correctedOpacity(alphaVoxel);
        }
        return emit(s, t, p, value, alpha, colour, withNormal);
    }
}

// The coarse path (nextCoarseTrilinear) in two copies: for the baseline x86-64 and for AVX2
// (coarseAvx2_, chosen in begin()). Both are the one loop below with everything it calls in the
// file inlined ([[gnu::flatten]]: the cell test, the jump and addNormal, which GCC had left as
// calls; T2 at step 1, --threads 1, render CPU 2.23 → 2.15 s when it was first flattened). The
// AVX2 copy performs the same operations on the same doubles — one-instruction floor(p) and
// the jump's ceil, three-operand arithmetic — and the file is compiled with -ffp-contract=off, so
// no multiply-add is fused and both give the same samples bit for bit (volume/CMakeLists.txt;
// docs/performance.md, round 6).
[[gnu::flatten]] bool VolumeRaySampler::nextCoarseTrilinear(double tEnd, VolumeSample& s,
                                                            bool withNormal) {
    return coarseTrilinearLoop<false>(tEnd, s, withNormal);
}

[[gnu::flatten, gnu::target("avx2")]] bool VolumeRaySampler::nextCoarseTrilinearAvx2(
    double tEnd, VolumeSample& s, bool withNormal) {
    return coarseTrilinearLoop<true>(tEnd, s, withNormal);
}

template <bool kFloorInstruction>
bool VolumeRaySampler::coarseTrilinearLoop(double tEnd, VolumeSample& s, bool withNormal) {
    // next() for its most common case at coarse steps (begin(), coarseTrilinear_), step for
    // step the same operations, hence the same samples: one table read per point
    // (skipByCellDistance's, at a coarse step), the value from the cell that read found, the
    // opacity without interpolation between transparent control points. The lattice index and
    // the counters live in locals (registers) and are written back when the loop ends.
    const DvrVolume& v = *vol_;
    long long k = k_, evaluated = 0, skipped = 0;
    const long long kEnd = (long long)kLast_ + 1;  // the first lattice index past the domain
    const unsigned char* const table = octantTable_;
    while (true) {
        const double t = tEnter_ + (double(k) + jitter_) * dt_;
        if (t > tExit_) {
            active_ = false;
            break;
        }
        if (t >= tEnd) break;
        const Vec3 p = oIdx_ + dIdx_ * t;
        int cell[3], q[3];
        bool inside = true;
        for (int a = 0; a < 3; ++a) {
            int f;
            if constexpr (kFloorInstruction) {
                f = int(std::floor(p[a]));  // one instruction (SSE4.1 and later)
            } else {
                f = int(p[a]);
                f -= p[a] < double(f) ? 1 : 0;  // floor, |p| < 2³¹ inside the domain
            }
            cell[a] = f;
            q[a] = f - v.brickLo_[a];
            inside = inside && unsigned(q[a]) < unsigned(v.cellCount_[a]);
        }
        // A point that rounding puts just outside the table is evaluated, never skipped.
        if (inside) {
            const int d = table[v.cellSlot(q[0], q[1], q[2])];
            if (d == 1) {
                // A lone transparent cell at a coarse step holds one or two points: a step is
                // cheaper than the jump.
                ++skipped;
                ++k;
                continue;
            }
            if (d != 0) {
                const long long kNext = pastTransparentCells(q, cell, d, k);
                skipped += std::max(0LL, std::min(kNext, kEnd) - k);
                k = kNext;
                continue;
            }
        }
        ++evaluated;
        const double value = recon_.trilinear(p, cell[0], cell[1], cell[2]);
        Spectrum colour;
        const double alphaVoxel = v.tf_.opacityIfVisible(value, colour);
        ++k;
        if (!(alphaVoxel > 0.0)) continue;
        if (v.settings_.mask && !v.settings_.mask->keeps(v.geometry_.indexToWorld(p))) continue;
        k_ = k;
        evaluated_ += evaluated;
        skipped_ += skipped;
        return emit(s, t, p, value, correctedOpacity(alphaVoxel), colour, withNormal);
    }
    k_ = k;
    evaluated_ += evaluated;
    skipped_ += skipped;
    return false;
}

bool VolumeRaySampler::rayCellTransparent(double t, int cell[3]) {
    double t0;
    const double* c = recon_.rayPolynomial(oIdx_, dIdx_, t, t0, cell);
    if (cell[0] == boundCell_[0] && cell[1] == boundCell_[1] && cell[2] == boundCell_[2])
        return false;  // bounded at the first point of this cell: not transparent
    for (int a = 0; a < 3; ++a) boundCell_[a] = cell[a];
    // The ray's exit from the cell, a hair late (a longer stretch only widens the bound).
    double tOut = kInf;
    for (int a = 0; a < 3; ++a) {
        if (dIdx_[a] == 0.0) continue;
        const double bound = dIdx_[a] > 0.0 ? double(cell[a]) + 1.0 : double(cell[a]);
        tOut = std::min(tOut, (bound - oIdx_[a]) * invDIdx_[a]);
    }
    const double len = tOut - t0 + 1e-9 * dt_;
    if (!(len >= 0.0) || !std::isfinite(len)) return false;
    // Bernstein coefficients of f(t0 + s) = Σ c_k s^k on s in [0, len]:
    // b_i = Σ_{k ≤ i} C(i, k) / C(9, k) · c_k len^k; f lies between their min and max (the
    // convex-hull property; Farouki & Rajan, CAGD 4, 1987). Stops as soon as the range so far
    // reaches the visible values.
    static const std::array<std::array<double, 10>, 10> w = [] {
        std::array<std::array<double, 10>, 10> m{};
        double binom[10][10] = {};
        for (int n = 0; n < 10; ++n) {
            binom[n][0] = 1.0;
            for (int k = 1; k <= n; ++k)
                binom[n][k] = binom[n - 1][k - 1] + (k < n ? binom[n - 1][k] : 0.0);
        }
        for (int i = 0; i < 10; ++i)
            for (int k = 0; k <= i; ++k) m[size_t(i)][size_t(k)] = binom[i][k] / binom[9][k];
        return m;
    }();
    double a[10];
    double pw = 1.0;
    for (int k = 0; k < 10; ++k, pw *= len) a[k] = c[k] * pw;
    const double lo = vol_->visibleLo_, hi = vol_->visibleHi_;
    double bMin = kInf, bMax = -kInf;
    for (int i = 0; i < 10; ++i) {
        double b = 0.0;
        for (int k = 0; k <= i; ++k) b += w[size_t(i)][size_t(k)] * a[k];
        bMin = std::min(bMin, b);
        bMax = std::max(bMax, b);
        // The same margin as the brick and cell tables (kRangeMargin), for the rounding of the
        // polynomial's evaluations (~1e-13 of the values) and of these sums.
        const double m = kRangeMargin * std::max(1.0, std::max(std::abs(bMin), std::abs(bMax)));
        if (bMax + m >= lo && bMin - m <= hi) return false;
    }
    return true;
}

bool VolumeRaySampler::fillPacket() {
    // Points k_ … on to the last one inside the domain, at most packetSize_ of them.
    const int n =
        int(std::min<long long>(packetSize_, std::max<long long>(1, (long long)kLast_ + 1 - k_)));
    packetK0_ = k_;
    packetN_ = 0;
    packetSameCell_ = 0;
    if (rayPolynomial_) {
        const double t = tEnter_ + (double(k_) + jitter_) * dt_;
        double t0;
        int cell[3];
        const double* poly = recon_.rayPolynomial(oIdx_, dIdx_, t, t0, cell);
        packetN_ =
            latticePacketPolynomial(lattice_, k_, n, poly, t0, cell, *vol_->tfArrays_, packet_);
    } else {
        packetN_ =
            latticePacketTrilinear(lattice_, k_, n, *vol_->dense_, *vol_->tfArrays_, packet_);
    }
    packetSameCell_ = packetN_ > 0 ? packet_.sameCell : 0;
    packets_ += packetN_ > 0 ? 1 : 0;
    return packetN_ > 0;
}

void VolumeRaySampler::skipTransparentPacketRun(double tEnd) {
    // Points of the packet's first cell after its first point take no table test in next()
    // (`sameCell`), so a transparent one only counts as evaluated and moves k_ on.
    const long long i0 = k_ - packetK0_;
    const int limit = std::min(packetN_, packetSameCell_);
    if (i0 < 1 || i0 >= limit) return;
    int i = int(i0);
    while (i < limit && !(packet_.alpha[i] > 0.0)) ++i;
    if (i == i0) return;
    // next()'s t for the last of them, the same expression.
    const double tLast = tEnter_ + (double(packetK0_ + i - 1) + jitter_) * dt_;
    if (tLast > tExit_ || tLast >= tEnd) return;
    evaluated_ += i - i0;
    k_ = packetK0_ + i;
}

bool VolumeRaySampler::skipByCellDistance(const Vec3& p, int cell[3]) {
    const DvrVolume& v = *vol_;
    int q[3];
    bool inside = true;
    for (int a = 0; a < 3; ++a) {
        int f = int(p[a]);
        f -= p[a] < double(f) ? 1 : 0;  // floor, |p| < 2³¹ inside the domain
        cell[a] = f;
        q[a] = f - v.brickLo_[a];
        inside = inside && unsigned(q[a]) < unsigned(v.cellCount_[a]);
    }
    // A point that rounding puts just outside the table is evaluated, never skipped.
    if (!inside) return false;
    const int d = octantTable_[v.cellSlot(q[0], q[1], q[2])];
    if (d == 0) {
        // A visible cell at a fine step holds ~1 / step points: those before the ray's exit
        // from it need no table read (header, "Cell distances"). Rounding can only put a point
        // before this exit into the next cell, which is then evaluated instead of tested —
        // evaluating a transparent point changes nothing but the work done.
        if (stepVoxels_ < kCellJumpStep) {
            double tOut = kInf;
            for (int a = 0; a < 3; ++a) {
                if (dIdx_[a] == 0.0) continue;
                const double bound = dIdx_[a] > 0.0 ? double(cell[a]) + 1.0 : double(cell[a]);
                tOut = std::min(tOut, (bound - oIdx_[a]) * invDIdx_[a]);
            }
            visibleCellEnd_ = tOut;
        }
        return false;
    }
    if (d == 1 && stepVoxels_ >= kCellJumpStep) {
        // A lone transparent cell at a coarse step holds one or two points: a step is cheaper
        // than the jump.
        ++skipped_;
        ++k_;
        return true;
    }
    const long long kNext = pastTransparentCells(q, cell, d, k_);
    // Count only lattice points inside the domain (t ≤ tExit) as skipped.
    skipped_ += std::max(0LL, std::min(kNext, (long long)kLast_ + 1) - k_);
    k_ = kNext;
    return true;
}

long long VolumeRaySampler::pastTransparentCells(const int q[3], const int cell[3], int d,
                                                 long long k) const {
    const DvrVolume& v = *vol_;
    if (d == DvrVolume::kOctantDistanceCap) {
        // Far from anything visible: the cube of bricks around the cell's brick when it reaches
        // further (its half-side is at least (c − 1)·B; the octant cube's reach is d − 1).
        const int shift = v.brickShift_, b = 1 << shift;
        int bi[3];
        for (int a = 0; a < 3; ++a) bi[a] = q[a] >> shift;
        const int c =
            v.brickTransparent_[(size_t(bi[2]) * v.brickCount_[1] + bi[1]) * v.brickCount_[0] +
                                bi[0]];
        if ((c - 1) * b > d - 1) {
            int lo[3];
            for (int a = 0; a < 3; ++a) lo[a] = v.brickLo_[a] + (bi[a] - c + 1) * b;
            return pastBox(lo, (2 * c - 1) * b, k);
        }
    }
    // Past the cube of side d that starts at the cell and extends along the ray's direction.
    int lo[3];
    for (int a = 0; a < 3; ++a) lo[a] = dIdx_[a] < 0.0 ? cell[a] - d + 1 : cell[a];
    return pastBox(lo, d, k);
}

void VolumeRaySampler::jumpPastBox(const int lo[3], int size) {
    const long long kNext = pastBox(lo, size, k_);
    // Count only lattice points inside the domain (t ≤ tExit) as skipped.
    skipped_ += std::max(0LL, std::min(kNext, (long long)kLast_ + 1) - k_);
    k_ = kNext;
}

long long VolumeRaySampler::pastBox(const int lo[3], int size, long long k) const {
    // Exit of the box [lo, lo + size)³ along the ray, then the first lattice point past it. The
    // jump is conservative: a point that rounding puts on the exit plane, or a hair before it,
    // is visited (tested again, at the cost of one more step), never passed over — so skipping
    // passes only points inside the transparent box.
    double tOut = kInf;
    for (int a = 0; a < 3; ++a) {
        if (dIdx_[a] == 0.0) continue;
        const double bound = dIdx_[a] > 0.0 ? double(lo[a]) + size : double(lo[a]);
        tOut = std::min(tOut, (bound - oIdx_[a]) * invDIdx_[a]);
    }
    long long kNext = k + 1;
    if (std::isfinite(tOut)) {
        const double x = (tOut - tEnter_) * invDt_ - jitter_;
        const double kf = std::ceil(x - 1e-9 * std::max(1.0, std::abs(x)));
        if (kf > double(kNext)) kNext = kf > 9e18 ? (long long)9e18 : (long long)kf;
    }
    return kNext;
}

void VolumeRaySampler::addNormal(VolumeSample& s) {
    const DvrSettings& set = vol_->settings_;
    Vec3 gIdx;
    if (set.gradient == GradientMethod::kBSplineDerivative)
        recon_.bsplineWithGradient(s.indexPosition, gIdx);
    else
        gIdx = recon_.centralDifferences(s.indexPosition);
    const GridGeometry& geo = vol_->geometry_;
    s.gradient = geo.gradientToWorld(gIdx);
    const double gLen = s.gradient.length();
    s.hasNormal = gLen * geo.referenceVoxelLength() >= set.minGradientPerVoxel && gLen > 0.0;
    s.normal = s.hasNormal ? -s.gradient / gLen : Vec3(0, 0, 1);
}

}  // namespace lobe
