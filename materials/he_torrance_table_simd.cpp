// HeTorranceTable::evalLanes with Google Highway: the table's coordinates of up to four
// direction pairs at once, the lanes being the lights of one shaded point (he_torrance_table.h).
// This file is compiled once per SIMD target (hwy/foreach_target.h) and the best target the CPU
// supports is chosen at run time (HWY_DYNAMIC_DISPATCH); CMake compiles it with
// -ffp-contract=off, so that no product and sum fuse into an FMA.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "materials/he_torrance_table_simd.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
// clang-format off: foreach_target.h must come before highway.h
#include <hwy/contrib/math/math-inl.h>
#include <hwy/highway.h>
// clang-format on

#include "materials/brdf_common.h"
#include "materials/he_torrance_table.h"

#include <algorithm>
#include <limits>

HWY_BEFORE_NAMESPACE();
namespace lobe {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using D = hn::CappedTag<double, HeTorranceTable::kLanes>;
using V = hn::Vec<D>;

// std::max(a, b), std::min(a, b) and std::clamp(v, lo, hi) lane by lane with the standard's
// choices ((a < b) ? b : a; (b < a) ? b : a; (v < lo) ? lo : (hi < v) ? hi : v), so that NaN
// and signed zeros come out as in the scalar code.
HWY_INLINE V StdMax(V a, V b) { return hn::IfThenElse(hn::Lt(a, b), b, a); }
HWY_INLINE V StdMin(V a, V b) { return hn::IfThenElse(hn::Lt(b, a), b, a); }
HWY_INLINE V StdClamp(V v, V lo, V hi) {
    return hn::IfThenElse(hn::Lt(v, lo), lo, hn::IfThenElse(hn::Lt(hi, v), hi, v));
}

// HeTorranceTable::coordinates and eval's cell position, lane by lane, the same IEEE operations
// in the same order (Imath's Vec3 length, division and dot product written out), except acos:
// Highway's Acos (within a few ulp of libm's). Out: the cell's first node and the fractions per
// axis, and whether the lane's sum wi + wo was too short for Imath's plain length (the caller
// evaluates those lanes with eval itself).
void TableCoordinatesImpl(int n, const double* wx, const double* wy, const double* wz,
                          const double* wo, const int* nodes, int* cell, double* frac, int* tiny) {
    const D d;
    constexpr int L = HeTorranceTable::kLanes;
    alignas(32) double bx[L] = {}, by[L] = {}, bz[L] = {};
    for (int k = 0; k < n; ++k) {
        bx[k] = wx[k];
        by[k] = wy[k];
        bz[k] = wz[k];
    }
    for (int k = n; k < L; ++k) bz[k] = 1.0;  // unused lanes: the pole, finite throughout
    // Vectors of 2 (SSE) or 4 lanes: as many passes as that takes.
    alignas(32) double xs[L], ys[L], zs[L], tinyLanes[L];
    for (int k0 = 0; k0 < n; k0 += int(hn::Lanes(d))) {
        const V ix = hn::LoadU(d, bx + k0), iy = hn::LoadU(d, by + k0), iz = hn::LoadU(d, bz + k0);
        const V zero = hn::Zero(d), one = hn::Set(d, 1.0), minusOne = hn::Set(d, -1.0);
        const V halfPi = hn::Set(d, 0.5 * kPi);  // kHalfPi of he_torrance_table.cpp
        // sum = wi + wo, its length (Imath: dot = x·x + y·y + z·z, then sqrt), h = sum / len.
        const V sx = hn::Add(ix, hn::Set(d, wo[0])), sy = hn::Add(iy, hn::Set(d, wo[1])),
                sz = hn::Add(iz, hn::Set(d, wo[2]));
        const V len2 = hn::Add(hn::Add(hn::Mul(sx, sx), hn::Mul(sy, sy)), hn::Mul(sz, sz));
        const auto isTiny = hn::Lt(len2, hn::Set(d, 2.0 * std::numeric_limits<double>::min()));
        const V len = hn::Sqrt(len2);
        const V hx = hn::Div(sx, len), hy = hn::Div(sy, len), hz = hn::Div(sz, len);
        const V cosH = StdClamp(hz, minusOne, one);
        const V cosD = StdClamp(hn::Add(hn::Add(hn::Mul(ix, hx), hn::Mul(iy, hy)), hn::Mul(iz, hz)),
                                minusOne, one);
        const V u = hn::Sqrt(hn::Div(hn::Acos(d, cosH), halfPi));
        const V thetaD = hn::Acos(d, cosD);
        const V sinH = hn::Sqrt(StdMax(zero, hn::Sub(one, hn::Mul(cosH, cosH))));
        const V sinD = hn::Sqrt(StdMax(zero, hn::Sub(one, hn::Mul(cosD, cosD))));
        const V denom = hn::Mul(sinH, sinD);
        // φd = acos(min(1, |wi.z − cos θd·h.z| / denom)) where denom > 1e-12, else 0 (the
        // division's lanes with a small denominator are not used).
        const auto wide = hn::Gt(denom, hn::Set(d, 1e-12));
        const V ratio = StdMin(one, hn::Div(hn::Abs(hn::Sub(iz, hn::Mul(cosD, hz))),
                                            hn::IfThenElse(wide, denom, one)));
        const V phiD = hn::IfThenElseZero(wide, hn::Acos(d, ratio));
        // eval's node coordinates: x along u, y along v = 1 − √(max(0, 1 − θd/(π/2))), z along φd.
        const V v = hn::Sub(one, hn::Sqrt(StdMax(zero, hn::Sub(one, hn::Div(thetaD, halfPi)))));
        const V x = hn::Mul(StdClamp(u, zero, one), hn::Set(d, double(nodes[0] - 1)));
        const V y = hn::Mul(StdClamp(v, zero, one), hn::Set(d, double(nodes[1] - 1)));
        const V z =
            hn::Mul(StdClamp(hn::Div(phiD, halfPi), zero, one), hn::Set(d, double(nodes[2] - 1)));
        hn::StoreU(x, d, xs + k0);
        hn::StoreU(y, d, ys + k0);
        hn::StoreU(z, d, zs + k0);
        hn::StoreU(hn::IfThenElseZero(isTiny, one), d, tinyLanes + k0);
    }
    for (int k = 0; k < n; ++k) {
        // int(x) truncates the non-negative x (std::min(int(x), nodes − 2) as eval).
        const int cx = std::min(int(xs[k]), nodes[0] - 2), cy = std::min(int(ys[k]), nodes[1] - 2),
                  cz = std::min(int(zs[k]), nodes[2] - 2);
        cell[3 * k] = cx;
        cell[3 * k + 1] = cy;
        cell[3 * k + 2] = cz;
        frac[3 * k] = xs[k] - cx;
        frac[3 * k + 1] = ys[k] - cy;
        frac[3 * k + 2] = zs[k] - cz;
        tiny[k] = tinyLanes[k] != 0.0;
    }
}

}  // namespace HWY_NAMESPACE
}  // namespace lobe
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace lobe {

HWY_EXPORT(TableCoordinatesImpl);

void HeTorranceTable::evalLanes(int n, const double* wx, const double* wy, const double* wz,
                                const Vec3& wo, Spectrum* f) const {
    const int nodes[3] = {res_.half, res_.diff, res_.phi};
    const double woArr[3] = {wo.x, wo.y, wo.z};
    int cell[3 * kLanes], tiny[kLanes];
    double frac[3 * kLanes];
    HWY_DYNAMIC_DISPATCH(TableCoordinatesImpl)(n, wx, wy, wz, woArr, nodes, cell, frac, tiny);
    for (int k = 0; k < n; ++k) {
        const Vec3 wi(wx[k], wy[k], wz[k]);
        if (!aboveHorizon(wi, wo)) {
            f[k] = Spectrum(0.0);
        } else if (tiny[k]) {
            f[k] = eval(wi, wo);
        } else {
            f[k] = interpolate(cell + 3 * k, frac + 3 * k);
        }
    }
}

}  // namespace lobe
#endif  // HWY_ONCE
