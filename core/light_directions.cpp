// Light directions with Google Highway: this file is compiled once per SIMD target
// (hwy/foreach_target.h) and the best target the CPU supports is chosen at run time
// (HWY_DYNAMIC_DISPATCH). See light_directions.h for the exactness argument; CMake compiles this
// file with -ffp-contract=off.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "core/light_directions.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
// clang-format off: foreach_target.h must come before highway.h
#include <hwy/highway.h>
// clang-format on

#include "core/light_directions.h"

HWY_BEFORE_NAMESPACE();
namespace lobe {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// At most four lanes: a scene has a few lights, and 512-bit divisions cost twice 256-bit ones.
using D = hn::CappedTag<double, 4>;
using V = hn::Vec<D>;

void LightDirectionsImpl(LightDirections& L, const LightTable& lights, int start, int count,
                         const Vec3& position, const Frame& frame) {
    const D d;
    const V px = hn::Set(d, position.x), py = hn::Set(d, position.y), pz = hn::Set(d, position.z);
    const V tx = hn::Set(d, frame.t.x), ty = hn::Set(d, frame.t.y), tz = hn::Set(d, frame.t.z);
    const V bx = hn::Set(d, frame.b.x), by = hn::Set(d, frame.b.y), bz = hn::Set(d, frame.b.z);
    const V nx = hn::Set(d, frame.n.x), ny = hn::Set(d, frame.n.y), nz = hn::Set(d, frame.n.z);
    const int lanes = int(hn::Lanes(d));
    for (int i = 0; i < count; i += lanes) {
        // toLight = light − position; d² = toLight · toLight (Imath's dot: (x·x + y·y) + z·z).
        const V dx = hn::Sub(hn::LoadU(d, lights.px + start + i), px);
        const V dy = hn::Sub(hn::LoadU(d, lights.py + start + i), py);
        const V dz = hn::Sub(hn::LoadU(d, lights.pz + start + i), pz);
        const V d2 = hn::Add(hn::Add(hn::Mul(dx, dx), hn::Mul(dy, dy)), hn::Mul(dz, dz));
        // toLight / √d², component by component (Imath's Vec3 / scalar).
        const V s = hn::Sqrt(d2);
        const V ux = hn::Div(dx, s), uy = hn::Div(dy, s), uz = hn::Div(dz, s);
        // Frame::toLocal: (u·t, u·b, u·n).
        const V wx = hn::Add(hn::Add(hn::Mul(ux, tx), hn::Mul(uy, ty)), hn::Mul(uz, tz));
        const V wy = hn::Add(hn::Add(hn::Mul(ux, bx), hn::Mul(uy, by)), hn::Mul(uz, bz));
        const V wz = hn::Add(hn::Add(hn::Mul(ux, nx), hn::Mul(uy, ny)), hn::Mul(uz, nz));
        hn::StoreU(d2, d, L.d2 + i);
        hn::StoreU(wx, d, L.wx + i);
        hn::StoreU(wy, d, L.wy + i);
        hn::StoreU(wz, d, L.wz + i);
        hn::StoreU(hn::Div(wz, d2), d, L.g + i);
    }
}

}  // namespace HWY_NAMESPACE
}  // namespace lobe
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace lobe {

HWY_EXPORT(LightDirectionsImpl);

void computeLightDirections(LightDirections& out, const LightTable& lights, int start, int count,
                            const Vec3& position, const Frame& frame) {
    HWY_DYNAMIC_DISPATCH(LightDirectionsImpl)(out, lights, start, count, position, frame);
}

}  // namespace lobe
#endif  // HWY_ONCE
