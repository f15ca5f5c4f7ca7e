// Point ("omni") lights (PointLight, core/light_table.h): irradiance at distance d is I/d² · cos θ.
// And the one light loop of Lobe: every place that lights a point — surface hits and volume
// samples (render/shading.h), the backdrop, the BRDF gallery, the flux-overlap lattices — walks
// the lights through forEachLight or forEachLightInFrame. The paper's renderings have no shadows
// (docs/paper-scene.md); optional shadows multiply each light's term by the transmittance
// towards it (render/shading.h, ShadingPoint::shadow; render/integrator.h, "Shadows").
#pragma once

#include "core/frame.h"
#include "core/light_directions.h"
#include "core/light_table.h"
#include "core/math.h"
#include "core/spectrum.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace lobe {

// fn(light, toLight, d²) for every light not at `position`; toLight = light.position − position
// (not normalised), d² = |toLight|².
template <class Fn>
inline void forEachLight(const std::vector<PointLight>& lights, const Vec3& position, Fn&& fn) {
    for (const PointLight& light : lights) {
        const Vec3 toLight = light.position - position;
        const double d2 = toLight.length2();
        if (!(d2 > 0.0)) continue;
        fn(light, toLight, d2);
    }
}

// The same loop seen from a surface point with shading frame `frame` (n = frame.n): nothing when
// the viewer is not above the surface (wo.z ≤ 0, where f_s = 0 by docs/models.md);
// otherwise fn(light, wi, wo, cos θi / d²) for every light above it, wi and wo the unit directions
// to the light and to the viewer in the local frame. cos θi / d² is the irradiance per unit
// intensity (eq. 1.20 of the paper for a point light), so the reflected radiance of a BRDF f is
// Σ f(wi, wo) · I · cos θi / d² (docs/models.md, "Conventions").
template <class Fn>
inline void forEachLightInFrame(const std::vector<PointLight>& lights, const Frame& frame,
                                const Vec3& position, const Vec3& toViewer, Fn&& fn) {
    const Vec3 wo = frame.toLocal(toViewer);
    if (!(wo.z > 0.0)) return;
    // For up to kMaxLights lights at once with SIMD across the lights (core/light_directions.h):
    // toLight = light − position, d² = |toLight|², wi = frame.toLocal(toLight / √d²) and
    // wi.z / d², the same IEEE operations in the same order as one light at a time. fn is then
    // called in the lights' order.
    // The positions come from the thread's table of the lights (core/light_table.h).
    constexpr int kChunk = LightDirections::kMaxLights;
    // Fetched per chunk: fn may light another point with other lights, replacing the table.
    const int n = int(lights.size());
    for (int start = 0; start < n; start += kChunk) {
        const int count = std::min(n - start, kChunk);
        LightDirections dirs;
        computeLightDirections(dirs, lightTable(lights), start, count, position, frame);
        for (int k = 0; k < count; ++k)
            if (dirs.d2[k] > 0.0 && dirs.wz[k] > 0.0)
                fn(lights[size_t(start + k)], Vec3(dirs.wx[k], dirs.wy[k], dirs.wz[k]), wo,
                   dirs.g[k]);
    }
}

}  // namespace lobe
