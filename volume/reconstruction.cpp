#include "volume/reconstruction.h"

#include "core/error.h"
#include "volume/dvr_simd.h"
#include "volume/grid_world.h"

#include <Imath/ImathMatrix.h>

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace lobe {

const char* reconstructionName(Reconstruction r) {
    return r == Reconstruction::kTrilinear ? "trilinear"
           : r == Reconstruction::kNearest ? "nearest"
                                           : "cubic-bspline";
}

const char* gradientMethodName(GradientMethod g) {
    return g == GradientMethod::kCentralDifferences ? "central-differences" : "bspline-derivative";
}

GridGeometry::GridGeometry(const openvdb::math::Transform& transform, const std::string& name) {
    if (!transform.isLinear())
        throw Error(name + ": the grid's index-to-world transform is not linear (" +
                    transform.mapType() + "); DVR needs an affine map");
    // Columns of J are the images of the index unit vectors; read them through the transform
    // itself so any linear map type (scale, translate, affine) is handled alike.
    const openvdb::Vec3d o = transform.indexToWorld(openvdb::Vec3d(0, 0, 0));
    origin_ = Vec3(o.x(), o.y(), o.z());
    Imath::M33d j;
    for (int c = 0; c < 3; ++c) {
        openvdb::Vec3d e(0, 0, 0);
        e[c] = 1.0;
        const openvdb::Vec3d w = transform.indexToWorld(e) - o;
        for (int r = 0; r < 3; ++r) j[r][c] = w[r];
    }
    const double det = j.determinant();
    if (!(std::abs(det) > 1e-300) || !std::isfinite(det))
        throw Error(name + ": the grid's index-to-world transform is singular");
    const Imath::M33d inv = j.inverse();
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) {
            j_[r][c] = j[r][c];
            jInv_[r][c] = inv[r][c];
        }
    refLength_ = std::cbrt(std::abs(det));
}

GridGeometry::GridGeometry(const openvdb::GridBase& grid, const std::string& name)
    : GridGeometry(grid.transform(), name) {
    const double s = gridWorldScale(grid);
    if (s == 1.0) return;
    // World = s · (J · index + origin): exact for a power of two s.
    origin_ = origin_ * s;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) {
            j_[r][c] *= s;
            jInv_[r][c] /= s;
        }
    refLength_ *= s;
}

Vec3 GridGeometry::worldToIndexDirection(const Vec3& d) const {
    return Vec3(jInv_[0][0] * d.x + jInv_[0][1] * d.y + jInv_[0][2] * d.z,
                jInv_[1][0] * d.x + jInv_[1][1] * d.y + jInv_[1][2] * d.z,
                jInv_[2][0] * d.x + jInv_[2][1] * d.y + jInv_[2][2] * d.z);
}

Vec3 GridGeometry::worldToIndex(const Vec3& p) const { return worldToIndexDirection(p - origin_); }

Vec3 GridGeometry::gradientToWorld(const Vec3& g) const {
    // J⁻ᵀ g: column r of J⁻¹ dotted with g.
    return Vec3(jInv_[0][0] * g.x + jInv_[1][0] * g.y + jInv_[2][0] * g.z,
                jInv_[0][1] * g.x + jInv_[1][1] * g.y + jInv_[2][1] * g.z,
                jInv_[0][2] * g.x + jInv_[1][2] * g.y + jInv_[2][2] * g.z);
}

namespace {

// Uniform cubic B-spline weights at fraction t (header, de Boor 1978), and their derivatives.
// Multiplied by 1/6 rather than divided by 6: twelve divisions were a third of a sample's cost
// (they differ from the divided weights by at most an ulp; the weights still sum to 1 within
// rounding).
constexpr double kSixth = 1.0 / 6.0;

inline double lerp(double a, double b, double t) { return a + t * (b - a); }

inline void bsplineWeights(double t, double w[4]) {
    const double s = 1.0 - t;
    const double t2 = t * t, t3 = t2 * t;
    w[0] = s * s * s * kSixth;
    w[1] = (3.0 * t3 - 6.0 * t2 + 4.0) * kSixth;
    w[2] = (-3.0 * t3 + 3.0 * t2 + 3.0 * t + 1.0) * kSixth;
    w[3] = t3 * kSixth;
}

inline void bsplineWeights(double t, double w[4], double dw[4]) {
    bsplineWeights(t, w);
    const double s = 1.0 - t;
    const double t2 = t * t;
    dw[0] = -0.5 * s * s;
    dw[1] = 0.5 * (3.0 * t2 - 4.0 * t);
    dw[2] = 0.5 * (-3.0 * t2 + 2.0 * t + 1.0);
    dw[3] = 0.5 * t2;
}

}  // namespace

double GridReconstructor::trilinear(const Vec3& p) {
    const double fx = std::floor(p.x), fy = std::floor(p.y), fz = std::floor(p.z);
    const int i = int(fx), j = int(fy), k = int(fz);
    const double tx = p.x - fx, ty = p.y - fy, tz = p.z - fz;
    if (dense_ && dense_->holds(i, j, k, 2))
        return trilinearDense(dense_->at(i, j, k), std::ptrdiff_t(dense_->xStride()),
                              std::ptrdiff_t(dense_->yStride()), tx, ty, tz);
    // The same lerps on the tree's values, x-major as in the dense copy.
    float c[8];
    for (int dx = 0; dx < 2; ++dx)
        for (int dy = 0; dy < 2; ++dy)
            for (int dz = 0; dz < 2; ++dz)
                c[4 * dx + 2 * dy + dz] = acc_.getValue(openvdb::Coord(i + dx, j + dy, k + dz));
    return trilinearDense(c, 4, 2, tx, ty, tz);
}

const GridReconstructor::Block& GridReconstructor::block(int i, int j, int k) {
    // Successive samples along a ray (steps of a fraction of a voxel) and the value-then-gradient
    // pair the marcher asks for at one position mostly fall in the same 4³ block: keep the last.
    const openvdb::Coord origin(i, j, k);
    if (!(hasBlock_ && origin == blockOrigin_)) {
        gather4(i, j, k, block_);
        blockOrigin_ = origin;
        hasBlock_ = true;
    }
    return block_;
}

void GridReconstructor::gather4(int i, int j, int k, Block& f) {
    // The 4³ block [i, i+3] × [j, j+3] × [k, k+3] meets at most two 8³ leaves per axis. For each
    // of those (≤ 8) pieces, read the leaf's value buffer directly, or, where no leaf exists, the
    // one value of the tile that covers the whole 8³ region — the values getValue would return
    // voxel by voxel, for ≤ 8 tree look-ups instead of 64 (perf: the 64 accessor look-ups were
    // most of the cost of a cortex sample). Leaf buffers are z-fastest (offset x·64 + y·8 + z),
    // hence the (a, 4b + c) layout of f: runs along z are contiguous in both.
    if (dense_ && dense_->holds(i, j, k, 4)) {
        const float* q = dense_->at(i, j, k);
        const size_t sx = dense_->xStride(), sy = dense_->yStride();
        for (int a = 0; a < 4; ++a)
            for (int b = 0; b < 4; ++b)
                for (int c = 0; c < 4; ++c) f[a][4 * b + c] = q[a * sx + b * sy + c];
        return;
    }
    using Leaf = openvdb::FloatGrid::TreeType::LeafNodeType;
    static_assert(Leaf::DIM == 8, "the split below assumes 8³ leaves");
    const int ri = i & 7, rj = j & 7, rk = k & 7;
    if (ri <= 4 && rj <= 4 && rk <= 4) {
        // The whole block in one leaf region (the common case for (5/8)³ of positions).
        const openvdb::Coord origin(i, j, k);
        if (const Leaf* leaf = acc_.probeConstLeaf(origin)) {
            const float* data = leaf->buffer().data() + Leaf::coordToOffset(origin);
            for (int a = 0; a < 4; ++a)
                for (int b = 0; b < 4; ++b)
                    for (int c = 0; c < 4; ++c) f[a][4 * b + c] = data[a * 64 + b * 8 + c];
        } else {
            const float v = acc_.getValue(origin);
            for (int a = 0; a < 4; ++a)
                for (int r = 0; r < 16; ++r) f[a][r] = v;
        }
        return;
    }
    const int x0[2] = {i, i - ri + 8}, y0[2] = {j, j - rj + 8}, z0[2] = {k, k - rk + 8};
    const int nx0 = std::min(4, 8 - ri), ny0 = std::min(4, 8 - rj), nz0 = std::min(4, 8 - rk);
    const int nx[2] = {nx0, 4 - nx0}, ny[2] = {ny0, 4 - ny0}, nz[2] = {nz0, 4 - nz0};
    for (int pa = 0, ca = 0; pa < 2 && nx[pa] > 0; ca += nx[pa], ++pa)
        for (int pb = 0, cb = 0; pb < 2 && ny[pb] > 0; cb += ny[pb], ++pb)
            for (int pc = 0, cc = 0; pc < 2 && nz[pc] > 0; cc += nz[pc], ++pc) {
                const openvdb::Coord origin(x0[pa], y0[pb], z0[pc]);
                if (const Leaf* leaf = acc_.probeConstLeaf(origin)) {
                    const float* data = leaf->buffer().data() + Leaf::coordToOffset(origin);
                    for (int a = 0; a < nx[pa]; ++a)
                        for (int b = 0; b < ny[pb]; ++b)
                            for (int c = 0; c < nz[pc]; ++c)
                                f[ca + a][4 * (cb + b) + cc + c] = data[a * 64 + b * 8 + c];
                } else {
                    const float v = acc_.getValue(origin);
                    for (int a = 0; a < nx[pa]; ++a)
                        for (int b = 0; b < ny[pb]; ++b)
                            for (int c = 0; c < nz[pc]; ++c) f[ca + a][4 * (cb + b) + cc + c] = v;
                }
            }
}

double GridReconstructor::bsplineWithGradient(const Vec3& p, Vec3& gradient) {
    const double fx = std::floor(p.x), fy = std::floor(p.y), fz = std::floor(p.z);
    double w[3][4], dw[3][4];
    bsplineWeights(p.x - fx, w[0], dw[0]);
    bsplineWeights(p.y - fy, w[1], dw[1]);
    bsplineWeights(p.z - fz, w[2], dw[2]);
    const Block& f = block(int(fx) - 1, int(fy) - 1, int(fz) - 1);
    // Separable sums: reduce along x (16 rows at once, value and x-derivative weights), then
    // along y (value, ∂x and ∂y partials), then along z — 16 × 2 × 4 + 4 × 3 × 4 + 4 × 4
    // products instead of 64 × 4 weight products. Each quantity is summed in the same order as
    // a plain triple loop over (c, b, a), with SIMD vectors over rows and columns (bsplineBlock,
    // volume/dvr_simd.h), so the result does not depend on the vectorisation.
    double out[4];
    bsplineBlock(f, w, dw, out);
    gradient = Vec3(out[1], out[2], out[3]);
    return out[0];
}

double GridReconstructor::bspline(const Vec3& p) {
    // The value part of bsplineWithGradient alone, with the same operations in the same order
    // (so the two return the same bits); the marcher asks for the value at every sample and the
    // gradient only where the transfer function is not transparent.
    const double fx = std::floor(p.x), fy = std::floor(p.y), fz = std::floor(p.z);
    double w[3][4];
    bsplineWeights(p.x - fx, w[0]);
    bsplineWeights(p.y - fy, w[1]);
    bsplineWeights(p.z - fz, w[2]);
    const Block& f = block(int(fx) - 1, int(fy) - 1, int(fz) - 1);
    double out[4];
    bsplineBlock(f, w, nullptr, out);
    return out[0];
}

const double* GridReconstructor::rayPolynomial(const Vec3& o, const Vec3& d, double t, double& t0,
                                               int cell[3]) {
    ensureRayCell(o, d, t);
    t0 = ray_.t0;
    for (int a = 0; a < 3; ++a) cell[a] = ray_.cell[a];
    return ray_.poly;
}

double GridReconstructor::bsplineOnRay(const Vec3& o, const Vec3& d, double t) {
    ensureRayCell(o, d, t);
    const RayCell& r = ray_;
    // Estrin's scheme: a tree of depth 4 instead of Horner's chain of 9 multiply-adds (the
    // chain's latency, not its arithmetic, was the cost of a sample). volume/dvr_simd.cpp does
    // the same operations for a packet of lattice points.
    const double s = t - r.t0, s2 = s * s, s4 = s2 * s2;
    const double* c = r.poly;
    const double p01 = c[0] + c[1] * s, p23 = c[2] + c[3] * s, p45 = c[4] + c[5] * s,
                 p67 = c[6] + c[7] * s, p89 = c[8] + c[9] * s;
    return (p01 + p23 * s2) + (p45 + p67 * s2) * s4 + p89 * (s4 * s4);
}

void GridReconstructor::ensureRayCell(const Vec3& o, const Vec3& d, double t) {
    const Vec3 p = o + d * t;
    const double fx = std::floor(p.x), fy = std::floor(p.y), fz = std::floor(p.z);
    const openvdb::Coord cell{int(fx), int(fy), int(fz)};
    RayCell& r = ray_;
    if (!(r.valid && cell == r.cell && o == r.o && d == r.d)) {
        // Each weight w_a(u + e·s), u the local coordinate at t0 = t and e the axis' speed, as a
        // cubic in s by its Taylor expansion at u (the derivatives of the weights in the file's
        // head): W[a][k] = w_a^(k)(u) e^k / k!.
        auto weights = [](double u, double e, double W[4][4]) {
            const double e2 = e * e, e3 = e2 * e;
            double w[4], d1[4];
            bsplineWeights(u, w, d1);  // the weights and their first derivatives
            const double d2[4] = {1.0 - u, 3.0 * u - 2.0, 1.0 - 3.0 * u, u};
            const double d3[4] = {-1.0, 3.0, -3.0, 1.0};
            for (int a = 0; a < 4; ++a) {
                W[a][0] = w[a];
                W[a][1] = d1[a] * e;
                W[a][2] = 0.5 * d2[a] * e2;
                W[a][3] = kSixth * d3[a] * e3;
            }
        };
        double wx[4][4], wy[4][4], wz[4][4];
        weights(p.x - fx, d.x, wx);
        weights(p.y - fy, d.y, wy);
        weights(p.z - fz, d.z, wz);
        const Block& f = block(cell.x() - 1, cell.y() - 1, cell.z() - 1);
        // Along x: 16 rows (y, z) of cubics; along y: 4 sextics; along z: the nonic (~600
        // products), with SIMD vectors over rows (volume/dvr_simd.h; the same bits as scalar
        // loops, tests/volume/test_dvr_simd.cpp).
        rayCellPolynomial(f, wx, wy, wz, r.poly);
        r.o = o;
        r.d = d;
        r.cell = cell;
        r.t0 = t;
        r.valid = true;
    }
}

Vec3 GridReconstructor::centralDifferences(const Vec3& p) {
    // From the dense copy: the trilinear interpolation of the voxel central differences at the
    // cell's 8 corners (the same field, head of reconstruction.h), read once from the 32 voxels
    // they use, instead of six trilinear look-ups of 8 voxels each. Equal up to rounding.
    const double fx = std::floor(p.x), fy = std::floor(p.y), fz = std::floor(p.z);
    const int i = int(fx), j = int(fy), k = int(fz);
    if (dense_ && dense_->holds(i - 1, j - 1, k - 1, 4)) {
        const float* q = dense_->at(i, j, k);
        const std::ptrdiff_t sx = std::ptrdiff_t(dense_->xStride()),
                             sy = std::ptrdiff_t(dense_->yStride());
        const double tx = p.x - fx, ty = p.y - fy, tz = p.z - fz;
        // The corners at z = k and k + 1 are neighbours in memory: both in one two-lane vector
        // (GCC/Clang vector extensions), each lane doing the scalar operations — the same bits.
        // d[a][c]: half the difference along axis a at the corners c = dx + 2dy, (dz = 0, 1).
        using V2 = double __attribute__((vector_size(16)));
        auto pair = [](const float* v) { return V2{double(v[0]), double(v[1])}; };
        auto lerp2 = [](V2 a, V2 b, V2 t) { return a + t * (b - a); };
        const V2 half = {0.5, 0.5};
        V2 d[3][4];
        for (int c = 0; c < 4; ++c) {
            const float* v = q + (c & 1) * sx + (c >> 1) * sy;
            d[0][c] = half * (pair(v + sx) - pair(v - sx));
            d[1][c] = half * (pair(v + sy) - pair(v - sy));
            d[2][c] = half * (pair(v + 1) - pair(v - 1));
        }
        const V2 vx = {tx, tx}, vy = {ty, ty};
        double g[3];
        for (int a = 0; a < 3; ++a) {
            // Along x for both z, then y for both z, then z: lerp(lerp(lerp(c0, c1, tx),
            // lerp(c2, c3, tx), ty), lerp(lerp(c4, c5, tx), lerp(c6, c7, tx), ty), tz).
            const V2 y = lerp2(lerp2(d[a][0], d[a][1], vx), lerp2(d[a][2], d[a][3], vx), vy);
            g[a] = lerp(y[0], y[1], tz);
        }
        return Vec3(g[0], g[1], g[2]);
    }
    return Vec3(0.5 * (trilinear(p + Vec3(1, 0, 0)) - trilinear(p - Vec3(1, 0, 0))),
                0.5 * (trilinear(p + Vec3(0, 1, 0)) - trilinear(p - Vec3(0, 1, 0))),
                0.5 * (trilinear(p + Vec3(0, 0, 1)) - trilinear(p - Vec3(0, 0, 1))));
}

double GridReconstructor::valueAndGradient(Reconstruction r, GradientMethod g, const Vec3& p,
                                           Vec3& gradient) {
    if (r == Reconstruction::kCubicBSpline) {
        const double v = bsplineWithGradient(p, gradient);
        if (g == GradientMethod::kCentralDifferences) gradient = centralDifferences(p);
        return v;
    }
    const double v = r == Reconstruction::kNearest ? nearest(p) : trilinear(p);
    if (g == GradientMethod::kBSplineDerivative)
        bsplineWithGradient(p, gradient);
    else
        gradient = centralDifferences(p);
    return v;
}

}  // namespace lobe
