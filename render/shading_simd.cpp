// Phong's, Ward's and Ashikhmin–Shirley's light loops with Google Highway: this file is compiled
// once per SIMD target (hwy/foreach_target.h) and the best target the CPU supports is chosen at run
// time (HWY_DYNAMIC_DISPATCH). See shading_simd.h for the exactness argument; CMake compiles this
// file with -ffp-contract=off.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "render/shading_simd.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
// clang-format off: foreach_target.h must come before highway.h
#include <hwy/contrib/math/math-inl.h>
#include <hwy/highway.h>
// clang-format on

#include "materials/brdf.h"
#include "render/shading_simd.h"

#include <algorithm>
#include <limits>

HWY_BEFORE_NAMESPACE();
namespace lobe {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// At most four lanes: four lights (or the three bands) at a time.
using D = hn::CappedTag<double, 4>;
using V = hn::Vec<D>;

constexpr int kChunk = 8;  // lights per pass

// clampBrdfValue (materials/brdf.h) lane by lane: NaN → 0, then std::clamp(v, 0, max).
HWY_INLINE V ClampBrdf(V v) {
    const D d;
    const V zero = hn::Zero(d), big = hn::Set(d, kMaxBrdfValue);
    const V f = hn::IfThenElse(hn::Lt(v, zero), zero, hn::IfThenElse(hn::Lt(big, v), big, v));
    return hn::IfThenElse(hn::IsNaN(v), zero, f);
}

// One light's share of the band sums, in the scalar loop's order: (kd/π + f_s · s) · I · g
// into `lambert` when `combined`, else kd/π · I · g there and f_s · s · I · g into `spec`.
HWY_INLINE void AddLight(bool combined, bool specularOn, V diffuse, V f, V scale, V I, V gk,
                         V& lambert, V& spec) {
    if (combined) {
        const V sum = specularOn ? hn::Add(diffuse, hn::Mul(f, scale)) : diffuse;
        lambert = hn::Add(lambert, hn::Mul(hn::Mul(sum, I), gk));
    } else {
        lambert = hn::Add(lambert, hn::Mul(hn::Mul(diffuse, I), gk));
        if (specularOn) spec = hn::Add(spec, hn::Mul(hn::Mul(hn::Mul(f, scale), I), gk));
    }
}

// The shaded point's position and frame in every lane.
struct PointVectors {
    V px, py, pz, tx, ty, tz, bx, by, bz, nx, ny, nz;
    PointVectors(const Vec3& p, const Frame& f)
        : px(hn::Set(D(), p.x)),
          py(hn::Set(D(), p.y)),
          pz(hn::Set(D(), p.z)),
          tx(hn::Set(D(), f.t.x)),
          ty(hn::Set(D(), f.t.y)),
          tz(hn::Set(D(), f.t.z)),
          bx(hn::Set(D(), f.b.x)),
          by(hn::Set(D(), f.b.y)),
          bz(hn::Set(D(), f.b.z)),
          nx(hn::Set(D(), f.n.x)),
          ny(hn::Set(D(), f.n.y)),
          nz(hn::Set(D(), f.n.z)) {}
};

// Imath's dot order: (a.x·b.x + a.y·b.y) + a.z·b.z.
HWY_INLINE V Dot3(V ax, V ay, V az, V bx, V by, V bz) {
    return hn::Add(hn::Add(hn::Mul(ax, bx), hn::Mul(ay, by)), hn::Mul(az, bz));
}

// The shadow factors of lights [start, start + count), or null: copied into `tail` when the
// last vector would read past the caller's array.
HWY_INLINE const double* ShadowChunk(const double* shadow, int start, int count, int lanes,
                                     double* tail) {
    if (!shadow) return nullptr;
    const double* sh = shadow + start;
    if (count % lanes == 0) return sh;
    std::copy(sh, sh + count, tail);
    return tail;
}

// Lights start + i … start + i + lanes − 1 of the table as lanes (`sh`: the chunk's shadow),
// core/light_directions.cpp's operations: toLight = light − position, d² = toLight · toLight, u =
// toLight / √d²; then wi.z = u·n, g = wi.z / d² (× shadow) and `ok` where d² > 0, wi.z > 0 (and g >
// 0 under a shadow).
struct LightLanes {
    V ux, uy, uz, d2, wz, g;
    hn::Mask<D> ok;
    LightLanes(const PointVectors& P, const LightTable& table, int start, const double* sh, int i) {
        const D d;
        const V dx = hn::Sub(hn::LoadU(d, table.px + start + i), P.px);
        const V dy = hn::Sub(hn::LoadU(d, table.py + start + i), P.py);
        const V dz = hn::Sub(hn::LoadU(d, table.pz + start + i), P.pz);
        d2 = Dot3(dx, dy, dz, dx, dy, dz);
        const V s = hn::Sqrt(d2);
        ux = hn::Div(dx, s);
        uy = hn::Div(dy, s);
        uz = hn::Div(dz, s);
        wz = Dot3(ux, uy, uz, P.nx, P.ny, P.nz);
        const V zero = hn::Zero(d);
        g = hn::Div(wz, d2);
        ok = hn::And(hn::Lt(zero, d2), hn::Lt(zero, wz));
        if (sh) {
            g = hn::Mul(g, hn::LoadU(d, sh + i));
            ok = hn::And(ok, hn::Lt(zero, g));
        }
    }
    // wi.x = u·t, wi.y = u·b (Frame::toLocal).
    V wx(const PointVectors& P) const { return Dot3(ux, uy, uz, P.tx, P.ty, P.tz); }
    V wy(const PointVectors& P) const { return Dot3(ux, uy, uz, P.bx, P.by, P.bz); }
};

void PhongLightSumsImpl(const PhongPointInput& point, const LightTable& table, bool combined,
                        PhongSums& sums) {
    const D d;
    const int lanes = int(hn::Lanes(d));
    const PointVectors P(point.position, point.frame);
    // Mirror of wi about n in the local frame, (−wi.x, −wi.y, wi.z) (brdf_common.h, cosAlpha).
    const V wox = hn::Set(d, point.wo.x), woy = hn::Set(d, point.wo.y),
            woz = hn::Set(d, point.wo.z);
    const V vx = hn::Set(d, point.toViewer.x), vy = hn::Set(d, point.toViewer.y),
            vz = hn::Set(d, point.toViewer.z);
    const V zero = hn::Zero(d), one = hn::Set(d, 1.0);
    const V scale = hn::Set(d, point.specularScale);

    const int n = table.count;
    for (int start = 0; start < n; start += kChunk) {
        const int count = std::min(n - start, kChunk);
        HWY_ALIGN double shTail[kChunk] = {};
        const double* sh = ShadowChunk(point.shadow, start, count, lanes, shTail);
        HWY_ALIGN double g[kChunk], power[kChunk], lit[kChunk];
        // Lights as lanes: core/light_directions.cpp's operations, then Phong's power.
        for (int i = 0; i < count; i += lanes) {
            const LightLanes L(P, table, start, sh, i);
            const V wz = L.wz, gi = L.g;
            const auto ok = L.ok;
            // cos α = max(0, r(wi)·wo); std::max(0, c) = 0 < c ? c : 0.
            V c;
            if (point.frameFree) {
                // 2 (n·u)(n·v) − u·v
                const V uv = Dot3(L.ux, L.uy, L.uz, vx, vy, vz);
                c = hn::Sub(hn::Mul(hn::Add(wz, wz), woz), uv);
            } else {
                // wi = frame.toLocal(u); r(wi) = (−wi.x, −wi.y, wi.z); Imath's dot order.
                c = Dot3(hn::Neg(L.wx(P)), hn::Neg(L.wy(P)), wz, wox, woy, woz);
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
                if (point.specularOn) f = ClampBrdf(hn::Mul(ks, hn::Set(d, power[k])));
                AddLight(combined, point.specularOn, diffuse, f, scale, I, gk, lambert, spec);
            }
            hn::StoreU(lambert, d, sums.lambert + b);
            hn::StoreU(spec, d, sums.specular + b);
        }
    }
}

// Ward's and Ashikhmin–Shirley's loop (shading_simd.h, AnisoPointInput). Model: 0 Ward, 1 A–S.
template <int kModel>
bool AnisoLightSums(const AnisoPointInput& point, const LightTable& table, bool combined,
                    PhongSums& sums) {
    const D d;
    const int lanes = int(hn::Lanes(d));
    const PointVectors P(point.position, point.frame);
    const V wox = hn::Set(d, point.wo.x), woy = hn::Set(d, point.wo.y),
            woz = hn::Set(d, point.wo.z);
    const V zero = hn::Zero(d), one = hn::Set(d, 1.0);
    const V scale = hn::Set(d, point.specularScale);
    const V sx = hn::Set(d, point.shapeX), sy = hn::Set(d, point.shapeY);
    // Ward's normalisation 4π αx αy √(cos θi cos θo): the product's first factors, in its order.
    const V wardNorm = hn::Set(d, 4.0 * kPi * point.shapeX * point.shapeY);
    const V tiny = hn::Set(d, 2.0 * std::numeric_limits<double>::min());

    const int n = table.count;
    for (int start = 0; start < n; start += kChunk) {
        const int count = std::min(n - start, kChunk);
        HWY_ALIGN double shTail[kChunk] = {};
        const double* sh = ShadowChunk(point.shadow, start, count, lanes, shTail);
        // Per light: g = cos θi / d² (× shadow), lit, and the model's terms: Ward gauss and
        // norm; A–S (h.z)^e, h·wi · max(cos θi, cos θo), 1 − clamp(h·wi) and its square.
        HWY_ALIGN double g[kChunk], lit[kChunk], t0[kChunk], t1[kChunk], t2[kChunk], t3[kChunk];
        for (int i = 0; i < count; i += lanes) {
            const LightLanes L(P, table, start, sh, i);
            const V wx = L.wx(P), wy = L.wy(P), wz = L.wz, gi = L.g;
            const auto ok = L.ok;
            // H = wi + wo (both models; Vec3's +).
            const V hx = hn::Add(wx, wox), hy = hn::Add(wy, woy), hz = hn::Add(wz, woz);
            if constexpr (kModel == 0) {
                // materials/ward.h: tx = H.x / H.z, ty = H.y / H.z,
                // gauss = exp(−((tx/αx)² + (ty/αy)²)), norm = 4π αx αy · √(wi.z wo.z).
                const V ax = hn::Div(hn::Div(hx, hz), sx), ay = hn::Div(hn::Div(hy, hz), sy);
                // Lanes of unlit lights (NaN where a light is at the point) pass 0 to Exp.
                const V q = hn::IfThenElseZero(ok, hn::Add(hn::Mul(ax, ax), hn::Mul(ay, ay)));
                hn::Store(hn::Exp(d, hn::Neg(q)), d, t0 + i);
                hn::Store(hn::Mul(wardNorm, hn::Sqrt(hn::Mul(wz, woz))), d, t1 + i);
            } else {
                // materials/ashikhmin_shirley.h with halfVector (brdf_common.h): h = H / |H|,
                // |H| = √(H·H) (Imath's length away from its tiny-vector path).
                const V len2 = hn::Add(hn::Add(hn::Mul(hx, hx), hn::Mul(hy, hy)), hn::Mul(hz, hz));
                if (!hn::AllFalse(d, hn::And(ok, hn::Lt(len2, tiny)))) return false;
                const V len = hn::Sqrt(len2);
                const V ex = hn::Div(hx, len), ey = hn::Div(hy, len), ez = hn::Div(hz, len);
                const V hx2 = hn::Mul(ex, ex), hy2 = hn::Mul(ey, ey);
                const V sin2 = hn::Add(hx2, hy2);
                const V hDotWi =
                    hn::Add(hn::Add(hn::Mul(ex, wx), hn::Mul(ey, wy)), hn::Mul(ez, wz));
                // std::max(wi.z, wo.z) = wi.z < wo.z ? wo.z : wi.z
                const V denom = hn::Mul(hDotWi, hn::IfThenElse(hn::Lt(wz, woz), woz, wz));
                const auto valid = hn::And(hn::Lt(zero, hDotWi), hn::Lt(zero, denom));
                // e = (nu h.x² + nv h.y²) / sin², 1 at h = n; (h.z)^e = exp(e · ln h.z).
                const V e =
                    hn::IfThenElse(hn::Lt(zero, sin2),
                                   hn::Div(hn::Add(hn::Mul(sx, hx2), hn::Mul(sy, hy2)), sin2), one);
                // Lanes of unlit lights pass 1 to Log and 0 to Exp.
                const V lnHz = hn::Log(d, hn::IfThenElse(ok, ez, one));
                const V power = hn::Exp(d, hn::IfThenElseZero(ok, hn::Mul(e, lnHz)));
                // fresnelSchlick: m = 1 − min(1, max(0, c)), c = h·wi.
                const V c0 = hn::IfThenElse(hn::Lt(zero, hDotWi), hDotWi, zero);
                const V m = hn::Sub(one, hn::IfThenElse(hn::Lt(c0, one), c0, one));
                hn::Store(hn::IfThenElseZero(valid, power), d, t0 + i);
                hn::Store(hn::IfThenElse(valid, denom, one), d, t1 + i);
                hn::Store(m, d, t2 + i);
                hn::Store(hn::Mul(m, m), d, t3 + i);
            }
            hn::Store(gi, d, g + i);
            hn::Store(hn::IfThenElseZero(ok, one), d, lit + i);
        }
        for (int k = 0; k < count; ++k) sums.evaluations += lit[k] != 0.0;
        // Bands as lanes, the lights in the scene's order (Phong's kernel).
        for (int b = 0; b < 4; b += lanes) {
            const V diffuse = hn::LoadU(d, point.diffuse + b);
            const V rho = hn::LoadU(d, point.reflectance + b), norm = hn::LoadU(d, point.norm + b);
            const V oneMinusRho = hn::Sub(one, rho);
            V lambert = hn::LoadU(d, sums.lambert + b), spec = hn::LoadU(d, sums.specular + b);
            for (int k = 0; k < count; ++k) {
                if (lit[k] == 0.0) continue;
                const V I = hn::LoadU(d, table.intensity + 4 * (start + k) + b);
                const V gk = hn::Set(d, g[k]);
                V f = zero;
                if (point.specularOn) {
                    V v;
                    if constexpr (kModel == 0) {
                        // rho_s · gauss / norm
                        v = hn::Div(hn::Mul(rho, hn::Set(d, t0[k])), hn::Set(d, t1[k]));
                    } else {
                        // norm · power / denom · (rs + (1 − rs) m² m² m)
                        const V m = hn::Set(d, t2[k]), m2 = hn::Set(d, t3[k]);
                        const V fresnel =
                            hn::Add(rho, hn::Mul(hn::Mul(hn::Mul(oneMinusRho, m2), m2), m));
                        v = hn::Mul(hn::Div(hn::Mul(norm, hn::Set(d, t0[k])), hn::Set(d, t1[k])),
                                    fresnel);
                    }
                    f = ClampBrdf(v);
                }
                AddLight(combined, point.specularOn, diffuse, f, scale, I, gk, lambert, spec);
            }
            hn::StoreU(lambert, d, sums.lambert + b);
            hn::StoreU(spec, d, sums.specular + b);
        }
    }
    return true;
}

bool WardLightSumsImpl(const AnisoPointInput& point, const LightTable& table, bool combined,
                       PhongSums& sums) {
    return AnisoLightSums<0>(point, table, combined, sums);
}

bool AshikhminShirleyLightSumsImpl(const AnisoPointInput& point, const LightTable& table,
                                   bool combined, PhongSums& sums) {
    return AnisoLightSums<1>(point, table, combined, sums);
}

}  // namespace HWY_NAMESPACE
}  // namespace lobe
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace lobe {

HWY_EXPORT(PhongLightSumsImpl);
HWY_EXPORT(WardLightSumsImpl);
HWY_EXPORT(AshikhminShirleyLightSumsImpl);

void phongLightSums(const PhongPointInput& point, const std::vector<PointLight>& lights,
                    bool combined, PhongSums& sums) {
    // The lights in the kernel's form, kept per thread (core/light_table.h).
    HWY_DYNAMIC_DISPATCH(PhongLightSumsImpl)(point, lightTable(lights), combined, sums);
}

bool anisoLightSums(const AnisoPointInput& point, const std::vector<PointLight>& lights,
                    bool combined, PhongSums& sums) {
    const LightTable& table = lightTable(lights);
    return point.model == AnisoPointInput::Model::ward
               ? HWY_DYNAMIC_DISPATCH(WardLightSumsImpl)(point, table, combined, sums)
               : HWY_DYNAMIC_DISPATCH(AshikhminShirleyLightSumsImpl)(point, table, combined, sums);
}

}  // namespace lobe
#endif  // HWY_ONCE
