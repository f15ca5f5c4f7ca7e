// Lattice packets with Google Highway: this file is compiled once per SIMD target
// (hwy/foreach_target.h) and the best target the CPU supports is chosen at run time
// (HWY_DYNAMIC_DISPATCH). See dvr_simd.h for the exactness argument; CMake compiles this file
// with -ffp-contract=off.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "volume/dvr_simd.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
// clang-format off: foreach_target.h must come before highway.h
#include <hwy/highway.h>
// clang-format on

#include "volume/dvr_simd.h"

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <cstring>

HWY_BEFORE_NAMESPACE();
namespace lobe {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using D = hn::ScalableTag<double>;
using V = hn::Vec<D>;
using M = hn::Mask<D>;

// a + t (b − a): GridReconstructor's lerp, operation by operation.
HWY_INLINE V Lerp(V a, V b, V t) { return hn::Add(a, hn::Mul(t, hn::Sub(b, a))); }

// t_k for lanes k0 + base + i: tEnter + (k + ξ) Δt, k a double (exact below 2⁵³).
HWY_INLINE V LatticeT(D d, const RayLattice& r, long long k) {
    const V kv = hn::Add(hn::Set(d, double(k)), hn::Iota(d, 0.0));
    return hn::Add(hn::Set(d, r.tEnter),
                   hn::Mul(hn::Add(kv, hn::Set(d, r.jitter)), hn::Set(d, r.dt)));
}

// TransferFunction::evaluate for a vector of values: the index of the first point strictly above
// the value (std::upper_bound: the count of points p with !(value < p)), then the same linear
// interpolation; below the first point or above the last, that point's values.
HWY_INLINE void TfLookup(D d, V v, const TfArrays& tf, double* alpha, double* c0, double* c1,
                         double* c2) {
    const int n = tf.size();
    if (n == 0) {
        hn::StoreU(hn::Zero(d), d, alpha);
        hn::StoreU(hn::Zero(d), d, c0);
        hn::StoreU(hn::Zero(d), d, c1);
        hn::StoreU(hn::Zero(d), d, c2);
        return;
    }
    const V one = hn::Set(d, 1.0);
    V count = hn::Zero(d);
    for (int j = 0; j < n; ++j)
        count =
            hn::Add(count, hn::IfThenElseZero(hn::Not(hn::Lt(v, hn::Set(d, tf.value[j]))), one));
    const V ia = hn::Max(hn::Sub(count, one), hn::Zero(d));
    const V ib = hn::Min(count, hn::Set(d, double(n - 1)));
    // Values vary slowly along a ray: usually every lane is on the same piece, whose end points
    // are then broadcast instead of gathered (the same numbers either way).
    const double firstCount = hn::GetLane(count);
    const bool onePiece = hn::AllTrue(d, hn::Eq(count, hn::Set(d, firstCount)));
    const hn::RebindToSigned<D> di;
    const auto ja = hn::ConvertTo(di, ia), jb = hn::ConvertTo(di, ib);
    const int sa = std::max(int(firstCount) - 1, 0), sb = std::min(int(firstCount), n - 1);
    auto at = [&](const std::vector<double>& x, bool isA) {
        return onePiece ? hn::Set(d, x[size_t(isA ? sa : sb)])
                        : hn::GatherIndex(d, x.data(), isA ? ja : jb);
    };
    const V av = at(tf.value, true), bv = at(tf.value, false);
    const V aa = at(tf.opacity, true), ba = at(tf.opacity, false);
    const M interior = hn::And(hn::Gt(count, hn::Zero(d)), hn::Lt(count, hn::Set(d, double(n))));
    const V s = hn::Div(hn::Sub(v, av), hn::Sub(bv, av));
    const V oneMinusS = hn::Sub(one, s);
    hn::StoreU(hn::IfThenElse(interior, hn::Add(aa, hn::Mul(s, hn::Sub(ba, aa))), ba), d, alpha);
    const std::vector<double>* bands[3] = {&tf.red, &tf.green, &tf.blue};
    double* outs[3] = {c0, c1, c2};
    for (int c = 0; c < 3; ++c) {
        const V ac = at(*bands[c], true), bc = at(*bands[c], false);
        const V mix = hn::Add(hn::Mul(ac, oneMinusS), hn::Mul(bc, s));
        hn::StoreU(hn::IfThenElse(interior, mix, bc), d, outs[c]);
    }
}

int PacketTrilinear(const RayLattice& r, long long k0, int n, const DenseField& field,
                    const TfArrays& tf, LatticePacket& out) {
    const D d;
    const hn::Rebind<float, D> df;
    const hn::Rebind<int32_t, D> di;
    const int N = int(hn::Lanes(d));
    const float* base = field.at(field.lo(0), field.lo(1), field.lo(2));
    const int32_t sx = int32_t(field.xStride()), sy = int32_t(field.yStride());
    const auto vsx = hn::Set(di, sx), vsy = hn::Set(di, sy);
    V first[3];  // the cell of the packet's first point
    out.sameCell = 0;
    bool sameSoFar = true;
    for (int b = 0; b < n; b += N) {
        const M valid = hn::FirstN(d, size_t(n - b));
        const V t = LatticeT(d, r, k0 + b);
        V f[3], frac[3], rel[3];
        M holds = valid;
        for (int a = 0; a < 3; ++a) {
            const V p = hn::Add(hn::Set(d, r.o[a]), hn::Mul(hn::Set(d, r.d[a]), t));
            f[a] = hn::Floor(p);
            frac[a] = hn::Sub(p, f[a]);
            // DenseField::holds(i, j, k, 2): i ≥ lo and i + 1 ≤ hi per axis.
            const V lo = hn::Set(d, double(field.lo(a))), hi = hn::Set(d, double(field.hi(a)));
            holds = hn::And(holds,
                            hn::And(hn::Ge(f[a], lo), hn::Le(hn::Add(f[a], hn::Set(d, 1.0)), hi)));
            rel[a] = hn::Sub(f[a], lo);
        }
        if (!hn::AllTrue(d, hn::Or(hn::Not(valid), holds))) return 0;
        if (b == 0)
            for (int a = 0; a < 3; ++a) first[a] = hn::Set(d, hn::GetLane(f[a]));
        if (sameSoFar) {
            M same = valid;
            for (int a = 0; a < 3; ++a) same = hn::And(same, hn::Eq(f[a], first[a]));
            const intptr_t firstOut = hn::FindFirstTrue(d, hn::Not(same));
            const int here = firstOut < 0 ? N : int(firstOut);
            out.sameCell += std::min(here, n - b);
            sameSoFar = here == N;
        }
        for (int a = 0; a < 3; ++a) rel[a] = hn::IfThenElseZero(holds, rel[a]);  // lanes past n
        const auto off = hn::Add(
            hn::Add(hn::Mul(hn::DemoteTo(di, rel[0]), vsx), hn::Mul(hn::DemoteTo(di, rel[1]), vsy)),
            hn::DemoteTo(di, rel[2]));
        V c[2][2][2];  // [dz][dy][dx], as GridReconstructor::trilinear
        // At fine steps the lanes often share one cell: its 8 voxels are then read once and
        // broadcast instead of gathered (the same numbers either way).
        M oneCell = holds;
        for (int a = 0; a < 3; ++a)
            oneCell = hn::And(oneCell, hn::Eq(f[a], hn::Set(d, hn::GetLane(f[a]))));
        if (hn::AllTrue(d, hn::Or(hn::Not(valid), oneCell))) {
            const float* q = base + hn::GetLane(off);
            for (int dz = 0; dz < 2; ++dz)
                for (int dy = 0; dy < 2; ++dy)
                    for (int dx = 0; dx < 2; ++dx)
                        c[dz][dy][dx] = hn::Set(d, double(q[dx * sx + dy * sy + dz]));
        } else {
            for (int dz = 0; dz < 2; ++dz)
                for (int dy = 0; dy < 2; ++dy)
                    for (int dx = 0; dx < 2; ++dx)
                        c[dz][dy][dx] = hn::PromoteTo(
                            d, hn::GatherIndex(df, base,
                                               hn::Add(off, hn::Set(di, dx * sx + dy * sy + dz))));
        }
        const V c00 = Lerp(c[0][0][0], c[0][0][1], frac[0]),
                c01 = Lerp(c[0][1][0], c[0][1][1], frac[0]);
        const V c10 = Lerp(c[1][0][0], c[1][0][1], frac[0]),
                c11 = Lerp(c[1][1][0], c[1][1][1], frac[0]);
        const V v = Lerp(Lerp(c00, c01, frac[1]), Lerp(c10, c11, frac[1]), frac[2]);
        // Whole vectors fit: kMaxPoints = 16 is a multiple of every x86 vector's lane count.
        hn::StoreU(v, d, out.value + b);
        TfLookup(d, v, tf, out.alpha + b, out.colour[0] + b, out.colour[1] + b, out.colour[2] + b);
    }
    return n;
}

int PacketPolynomial(const RayLattice& r, long long k0, int n, const double poly[10], double t0,
                     const int cell[3], const TfArrays& tf, LatticePacket& out) {
    const D d;
    const int N = int(hn::Lanes(d));
    int m = 0;
    for (int b = 0; b < n; b += N) {
        const V t = LatticeT(d, r, k0 + b);
        M inCell = hn::FirstN(d, size_t(n - b));
        for (int a = 0; a < 3; ++a) {
            const V p = hn::Add(hn::Set(d, r.o[a]), hn::Mul(hn::Set(d, r.d[a]), t));
            inCell = hn::And(inCell, hn::Eq(hn::Floor(p), hn::Set(d, double(cell[a]))));
        }
        const intptr_t firstOut = hn::FindFirstTrue(d, hn::Not(inCell));
        const int here = firstOut < 0 ? N : int(firstOut);
        // Estrin's scheme exactly as GridReconstructor::bsplineOnRay.
        const V s = hn::Sub(t, hn::Set(d, t0)), s2 = hn::Mul(s, s), s4 = hn::Mul(s2, s2);
        auto pair = [&](int j) {
            return hn::Add(hn::Set(d, poly[j]), hn::Mul(hn::Set(d, poly[j + 1]), s));
        };
        const V p01 = pair(0), p23 = pair(2), p45 = pair(4), p67 = pair(6), p89 = pair(8);
        const V v = hn::Add(
            hn::Add(hn::Add(p01, hn::Mul(p23, s2)), hn::Mul(hn::Add(p45, hn::Mul(p67, s2)), s4)),
            hn::Mul(p89, hn::Mul(s4, s4)));
        hn::StoreU(v, d, out.value + b);
        TfLookup(d, v, tf, out.alpha + b, out.colour[0] + b, out.colour[1] + b, out.colour[2] + b);
        m += std::min(here, n - b);
        if (here < N) break;
    }
    out.sameCell = m;
    return m;
}

// GridReconstructor::ensureRayCell's products: the same sums in the same order as its scalar loops
// (each element accumulated over the same index sequence, no contraction), so the same bits.
void RayCellPolynomial(const float* f, const double* wx, const double* wy, const double* wz,
                       double* poly) {
    const D d;
    const hn::Rebind<float, D> df;
    const int N = int(hn::Lanes(d));
    // Along x: px[k][row] = Σ_a f[a][row] · wx[a][k], a ascending (16 rows, whole vectors).
    alignas(64) double px[4][16];
    for (int r = 0; r < 16; r += N) {
        V acc[4] = {hn::Zero(d), hn::Zero(d), hn::Zero(d), hn::Zero(d)};
        for (int a = 0; a < 4; ++a) {
            const V fa = hn::PromoteTo(d, hn::LoadU(df, f + 16 * a + r));
            for (int k = 0; k < 4; ++k)
                acc[k] = hn::Add(acc[k], hn::Mul(fa, hn::Set(d, wx[4 * a + k])));
        }
        for (int k = 0; k < 4; ++k) hn::Store(acc[k], d, px[k] + r);
    }
    // Along y: py[k + l][c] = Σ_b Σ_k px[k][4b + c] · wy[b][l], b then k ascending, vectors over c.
    const hn::CappedTag<double, 4> d4;
    using V4 = hn::Vec<decltype(d4)>;
    const int N4 = int(hn::Lanes(d4));
    alignas(64) double py[7][4];
    for (int c0 = 0; c0 < 4; c0 += N4) {
        V4 acc[7];
        for (int m = 0; m < 7; ++m) acc[m] = hn::Zero(d4);
        for (int b = 0; b < 4; ++b)
            for (int k = 0; k < 4; ++k) {
                const V4 x = hn::LoadU(d4, px[k] + 4 * b + c0);
                for (int l = 0; l < 4; ++l)
                    acc[k + l] = hn::Add(acc[k + l], hn::Mul(x, hn::Set(d4, wy[4 * b + l])));
            }
        for (int m = 0; m < 7; ++m) hn::StoreU(acc[m], d4, py[m] + c0);
    }
    // Along z: the nonic, in ensureRayCell's order (k, c, l).
    // Scalar: vectors over the coefficient index would chain all 28 (k, c) steps; ten local
    // accumulators (registers, not stores through `poly`) chain at most 16.
    double acc[10] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
#pragma GCC unroll 7
    for (int k = 0; k < 7; ++k)
#pragma GCC unroll 4
        for (int c = 0; c < 4; ++c)
#pragma GCC unroll 4
            for (int l = 0; l < 4; ++l) acc[k + l] += py[k][c] * wz[4 * c + l];
    for (int m = 0; m < 10; ++m) poly[m] = acc[m];
}

// GridReconstructor::bspline / bsplineWithGradient's separable sums (reconstruction.cpp) with
// vectors over the 16 rows (x) and the 4 columns (y): the same operations in the same order per
// element, so the same bits. dw == nullptr: the value only.
void BSplineBlock(const float* f, const double* w, const double* dw, double* out) {
    const D d;
    const hn::Rebind<float, D> df;
    const int N = int(hn::Lanes(d));
    const double *wx = w, *wy = w + 4, *wz = w + 8;
    // Along x: vx[r] = Σ_a wx[a] f[a][r] (and dvx with the derivative weights), a ascending.
    alignas(64) double vx[16], dvx[16];
    for (int r = 0; r < 16; r += N) {
        V acc = hn::Zero(d), dacc = hn::Zero(d);
        for (int a = 0; a < 4; ++a) {
            const V fa = hn::PromoteTo(d, hn::LoadU(df, f + 16 * a + r));
            acc = hn::Add(acc, hn::Mul(hn::Set(d, wx[a]), fa));
            if (dw) dacc = hn::Add(dacc, hn::Mul(hn::Set(d, dw[a]), fa));
        }
        hn::Store(acc, d, vx + r);
        if (dw) hn::Store(dacc, d, dvx + r);
    }
    // Along y: vz[c] = Σ_b wy[b] vx[4b + c] (and the ∂x, ∂y partials), b ascending.
    const hn::CappedTag<double, 4> d4;
    using V4 = hn::Vec<decltype(d4)>;
    const int N4 = int(hn::Lanes(d4));
    alignas(32) double vz[4], gxz[4], gyz[4];
    for (int c0 = 0; c0 < 4; c0 += N4) {
        V4 v = hn::Zero(d4), gx = hn::Zero(d4), gy = hn::Zero(d4);
        for (int b = 0; b < 4; ++b) {
            const V4 row = hn::LoadU(d4, vx + 4 * b + c0);
            v = hn::Add(v, hn::Mul(hn::Set(d4, wy[b]), row));
            if (dw) {
                gx = hn::Add(gx, hn::Mul(hn::Set(d4, wy[b]), hn::LoadU(d4, dvx + 4 * b + c0)));
                gy = hn::Add(gy, hn::Mul(hn::Set(d4, dw[4 + b]), row));
            }
        }
        hn::StoreU(v, d4, vz + c0);
        if (dw) {
            hn::StoreU(gx, d4, gxz + c0);
            hn::StoreU(gy, d4, gyz + c0);
        }
    }
    // Along z: scalar sums, c ascending.
    double v = 0.0;
    for (int c = 0; c < 4; ++c) v += wz[c] * vz[c];
    out[0] = v;
    if (!dw) return;
    double gx = 0.0, gy = 0.0, gz = 0.0;
    for (int c = 0; c < 4; ++c) {
        gx += wz[c] * gxz[c];
        gy += wz[c] * gyz[c];
        gz += dw[8 + c] * vz[c];
    }
    out[1] = gx;
    out[2] = gy;
    out[3] = gz;
}

const char* Target() { return hwy::TargetName(HWY_TARGET); }

}  // namespace HWY_NAMESPACE
}  // namespace lobe
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace lobe {

HWY_EXPORT(PacketTrilinear);
HWY_EXPORT(PacketPolynomial);
HWY_EXPORT(RayCellPolynomial);
HWY_EXPORT(BSplineBlock);
HWY_EXPORT(Target);

TfArrays::TfArrays(const TransferFunction& tf) {
    for (const TfPoint& p : tf.points()) {
        value.push_back(p.value);
        opacity.push_back(p.opacity);
        red.push_back(p.colour[0]);
        green.push_back(p.colour[1]);
        blue.push_back(p.colour[2]);
    }
}

int latticePacketTrilinear(const RayLattice& ray, long long k0, int n, const DenseField& field,
                           const TfArrays& tf, LatticePacket& out) {
    if (n <= 0 || n > LatticePacket::kMaxPoints) return 0;
    return HWY_DYNAMIC_DISPATCH(PacketTrilinear)(ray, k0, n, field, tf, out);
}

int latticePacketPolynomial(const RayLattice& ray, long long k0, int n, const double poly[10],
                            double t0, const int cell[3], const TfArrays& tf, LatticePacket& out) {
    if (n <= 0 || n > LatticePacket::kMaxPoints) return 0;
    return HWY_DYNAMIC_DISPATCH(PacketPolynomial)(ray, k0, n, poly, t0, cell, tf, out);
}

void rayCellPolynomial(const float f[4][16], const double wx[4][4], const double wy[4][4],
                       const double wz[4][4], double poly[10]) {
    HWY_DYNAMIC_DISPATCH(RayCellPolynomial)(&f[0][0], &wx[0][0], &wy[0][0], &wz[0][0], poly);
}

void bsplineBlock(const float f[4][16], const double w[3][4], const double dw[3][4],
                  double out[4]) {
    HWY_DYNAMIC_DISPATCH(BSplineBlock)(&f[0][0], &w[0][0], dw ? &dw[0][0] : nullptr, out);
}

const char* latticePacketTarget() { return HWY_DYNAMIC_DISPATCH(Target)(); }

bool simdDisabledByEnvironment() {
    static const bool off = [] {
        const char* e = std::getenv("LOBE_SIMD");
        return e && (std::strcmp(e, "off") == 0 || std::strcmp(e, "0") == 0);
    }();
    return off;
}

}  // namespace lobe
#endif  // HWY_ONCE
