// The light directions of one shaded point for several lights at once, with SIMD across the
// lights (Google Highway, the best target the CPU supports chosen at run time): what the light
// loop, forEachLightInFrame (core/light.h), works out per light before the BRDF. Every
// operation is a correctly rounded IEEE add, multiply, divide or square root in the scalar code's
// order (no fused multiply-add: CMake compiles the file with -ffp-contract=off), so each lane
// holds the scalar value exactly. The square root and the four divisions per light were most of
// the light loop's time when done one light after another (docs/performance.md, round 3).
#pragma once

#include "core/frame.h"
#include "core/light_table.h"

namespace lobe {

// Up to kMaxLights lights in structure-of-arrays form; arrays padded to kMaxLights.
struct LightDirections {
    static constexpr int kMaxLights = 8;
    // Per light: d² = |toLight|² (toLight = light − position), the unit direction to the
    // light in the local frame, wi = frame.toLocal(toLight / √d²), and wi.z / d² (cos θi / d²).
    // d² = 0 (a light at the point) leaves wi and g NaN: callers test d² > 0 and wi.z > 0 first.
    double d2[kMaxLights], wx[kMaxLights], wy[kMaxLights], wz[kMaxLights], g[kMaxLights];
};

// Fills `out` for lights start … start+count−1 of `lights` (count ≤ kMaxLights) seen from
// `position`.
void computeLightDirections(LightDirections& out, const LightTable& lights, int start, int count,
                            const Vec3& position, const Frame& frame);

}  // namespace lobe
