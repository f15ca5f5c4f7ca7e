// Phong's light loop with Google Highway: this file is compiled once per SIMD target
// (hwy/foreach_target.h) and the best target the CPU supports is chosen at run time
// (HWY_DYNAMIC_DISPATCH). See shading_simd.h for the exactness argument; CMake compiles this file
// with -ffp-contract=off.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "render/shading_simd.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
// clang-format off: foreach_target.h must come before highway.h
#include <hwy/highway.h>
// clang-format on

#include "materials/brdf.h"
#include "render/shading_simd.h"

#include <algorithm>

HWY_BEFORE_NAMESPACE();
namespace lobe {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// At most four lanes: four lights (or the three bands) at a time.
using D = hn::CappedTag<double, 4>;
using V = hn::Vec<D>;

constexpr int kChunk = 8;  // lights per pass

void PhongLightSumsImpl(const PhongPointInput& point, const LightTable& table, bool combined,
                        PhongSums& sums) {
    const D d;
    const int lanes = int(hn::Lanes(d));
    const Frame& frame = point.frame;
    const V px = hn::Set(d, point.position.x), py = hn::Set(d, point.position.y),
            pz = hn::Set(d, point.position.z);
    const V tx = hn::Set(d, frame.t.x), ty = hn::Set(d, frame.t.y), tz = hn::Set(d, frame.t.z);
    const V bx = hn::Set(d, frame.b.x), by = hn::Set(d, frame.b.y), bz = hn::Set(d, frame.b.z);
    const V nx = hn::Set(d, frame.n.x), ny = hn::Set(d, frame.n.y), nz = hn::Set(d, frame.n.z);
    // Mirror of wi about n in the local frame, (−wi.x, −wi.y, wi.z) (brdf_common.h, cosAlpha).
    const V wox = hn::Set(d, point.wo.x), woy = hn::Set(d, point.wo.y),
            woz = hn::Set(d, point.wo.z);
    const V vx = hn::Set(d, point.toViewer.x), vy = hn::Set(d, point.toViewer.y),
            vz = hn::Set(d, point.toViewer.z);
    const V zero = hn::Zero(d), one = hn::Set(d, 1.0), big = hn::Set(d, kMaxBrdfValue);
    const V scale = hn::Set(d, point.specularScale);

    const int n = table.count;
    for (int start = 0; start < n; start += kChunk) {
        const int count = std::min(n - start, kChunk);
        const double* lx = table.px + start;
        const double* ly = table.py + start;
        const double* lz = table.pz + start;
        const double* sh = point.shadow ? point.shadow + start : nullptr;
        HWY_ALIGN double shTail[kChunk] = {};
        if (sh && count % lanes != 0) {  // the last vector would read past the caller's array
            std::copy(sh, sh + count, shTail);
            sh = shTail;
        }
        HWY_ALIGN double g[kChunk], power[kChunk], lit[kChunk];
        // Lights as lanes: core/light_directions.cpp's operations, then Phong's power.
        for (int i = 0; i < count; i += lanes) {
            // toLight = light − position; d² = (x·x + y·y) + z·z; u = toLight / √d².
            const V dx = hn::Sub(hn::LoadU(d, lx + i), px);
            const V dy = hn::Sub(hn::LoadU(d, ly + i), py);
            const V dz = hn::Sub(hn::LoadU(d, lz + i), pz);
            const V d2 = hn::Add(hn::Add(hn::Mul(dx, dx), hn::Mul(dy, dy)), hn::Mul(dz, dz));
            const V s = hn::Sqrt(d2);
            const V ux = hn::Div(dx, s), uy = hn::Div(dy, s), uz = hn::Div(dz, s);
            // wi.z = u·n (frame.toLocal's third term); g = wi.z / d².
            const V wz = hn::Add(hn::Add(hn::Mul(ux, nx), hn::Mul(uy, ny)), hn::Mul(uz, nz));
            V gi = hn::Div(wz, d2);
            auto ok = hn::And(hn::Lt(zero, d2), hn::Lt(zero, wz));
            if (sh) {
                gi = hn::Mul(gi, hn::LoadU(d, sh + i));
                ok = hn::And(ok, hn::Lt(zero, gi));
            }
            // cos α = max(0, r(wi)·wo); std::max(0, c) = 0 < c ? c : 0.
            V c;
            if (point.frameFree) {
                // 2 (n·u)(n·v) − u·v
                const V uv = hn::Add(hn::Add(hn::Mul(ux, vx), hn::Mul(uy, vy)), hn::Mul(uz, vz));
                c = hn::Sub(hn::Mul(hn::Add(wz, wz), woz), uv);
            } else {
                // wi = frame.toLocal(u); r(wi) = (−wi.x, −wi.y, wi.z); Imath's dot order.
                const V wx = hn::Add(hn::Add(hn::Mul(ux, tx), hn::Mul(uy, ty)), hn::Mul(uz, tz));
                const V wy = hn::Add(hn::Add(hn::Mul(ux, bx), hn::Mul(uy, by)), hn::Mul(uz, bz));
                c = hn::Add(hn::Add(hn::Mul(hn::Neg(wx), wox), hn::Mul(hn::Neg(wy), woy)),
                            hn::Mul(wz, woz));
            }
            const V cos = hn::IfThenElse(hn::Lt(zero, c), c, zero);
            // powerOfWhole (brdf_common.h): repeated squaring, the same products in the same order.
            V result = one, square = cos;
            for (unsigned e = point.exponent; e;) {
                if (e & 1u) result = hn::Mul(result, square);
                e >>= 1;
                if (e) square = hn::Mul(square, square);
            }
            hn::Store(gi, d, g + i);
            hn::Store(result, d, power + i);
            hn::Store(hn::IfThenElseZero(ok, one), d, lit + i);
        }
        for (int k = 0; k < count; ++k) sums.evaluations += lit[k] != 0.0;
        // Bands as lanes, the lights in the scene's order.
        for (int b = 0; b < 4; b += lanes) {
            const V diffuse = hn::LoadU(d, point.diffuse + b), ks = hn::LoadU(d, point.ks + b);
            V lambert = hn::LoadU(d, sums.lambert + b), spec = hn::LoadU(d, sums.specular + b);
            for (int k = 0; k < count; ++k) {
                if (lit[k] == 0.0) continue;
                const V I = hn::LoadU(d, table.intensity + 4 * (start + k) + b);
                const V gk = hn::Set(d, g[k]);
                V f = zero;
                if (point.specularOn) {
                    // clampBrdfValue (materials/brdf.h): NaN → 0, then std::clamp(v, 0, max).
                    const V v = hn::Mul(ks, hn::Set(d, power[k]));
                    f = hn::IfThenElse(hn::Lt(v, zero), zero,
                                       hn::IfThenElse(hn::Lt(big, v), big, v));
                    f = hn::IfThenElse(hn::IsNaN(v), zero, f);
                }
                if (combined) {
                    // (kd/π + f_s · s) · I · g
                    const V sum = point.specularOn ? hn::Add(diffuse, hn::Mul(f, scale)) : diffuse;
                    lambert = hn::Add(lambert, hn::Mul(hn::Mul(sum, I), gk));
                } else {
                    lambert = hn::Add(lambert, hn::Mul(hn::Mul(diffuse, I), gk));
                    if (point.specularOn)
                        spec = hn::Add(spec, hn::Mul(hn::Mul(hn::Mul(f, scale), I), gk));
                }
            }
            hn::StoreU(lambert, d, sums.lambert + b);
            hn::StoreU(spec, d, sums.specular + b);
        }
    }
}

}  // namespace HWY_NAMESPACE
}  // namespace lobe
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace lobe {

HWY_EXPORT(PhongLightSumsImpl);

void phongLightSums(const PhongPointInput& point, const std::vector<PointLight>& lights,
                    bool combined, PhongSums& sums) {
    // The lights in the kernel's form, kept per thread (core/light_table.h).
    HWY_DYNAMIC_DISPATCH(PhongLightSumsImpl)(point, lightTable(lights), combined, sums);
}

}  // namespace lobe
#endif  // HWY_ONCE
