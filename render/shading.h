// Shading: the one place that lights a surface hit or a volume sample with its object's material
// (materials/material.h) under the scene's point lights, through the one light loop
// (core/light.h):
//   L = Σ_lights (kd/π + f_s(wi, wo)) · I/d² · cos θi      (docs/models.md,
// "Conventions"; the paper's eq. 1.10 with point lights; with shadows each light's term is
// multiplied by the transmittance towards it, ShadingPoint::shadow).
#pragma once

#include "core/frame.h"
#include "core/light.h"
#include "materials/material.h"
#include "volume/volume_marcher.h"

#include <vector>

namespace lobe {

// The frame mirrored to the viewer's side when the viewer is below it (two-sided shading: a ray
// through a translucent shell sees its inner side, and volume samples have no inside). Flipping
// n and b keeps the frame right-handed and the tangent (the anisotropy direction) unchanged.
inline Frame facingViewer(Frame frame, const Vec3& toViewer) {
    if (frame.n.dot(toViewer) < 0.0) {
        frame.n = -frame.n;
        frame.b = -frame.b;
    }
    return frame;
}

// Reflected radiance towards the viewer at `position` with shading frame `frame`; `toViewer` is
// the unit world direction from the point to the viewer. Lights below the surface contribute 0.
// twoSided: the frame is first turned to the viewer (facingViewer).
Spectrum directLighting(const Material& material, const Frame& frame, const Vec3& position,
                        const Vec3& toViewer, const std::vector<PointLight>& lights,
                        bool twoSided = false);

// Radiance leaving a volume sample towards the viewer: the transfer-function colour × direct
// lighting with the object's material, two-sided, in a frame around the sample normal whose
// tangent is `tangentAxis` projected (`fallbackAxis` where that degenerates). A sample without a
// usable normal (volume/volume_marcher.h, "Normals") is not BRDF-shaded: colour × Σ kd/π · I/d²
// (Lambert with cos θ = 1).
Spectrum shadeVolumeSample(const Material& material, const VolumeSample& sample,
                           const Vec3& toViewer, const std::vector<PointLight>& lights,
                           const Vec3& tangentAxis = Vec3(0, 0, 1),
                           const Vec3& fallbackAxis = Vec3(1, 0, 0));

// What the integrator lights at one surface hit or volume sample: the object's material, the
// colour multiplying the reflected light (surface colour or transfer-function colour), and the
// shading frame — absent for a volume sample without a usable normal.
struct ShadingPoint {
    const Material* material = nullptr;
    Spectrum colour{1.0};     // multiplies the Lambert term
    Spectrum highlight{1.0};  // multiplies the specular term (the light's colour: 1; or colour)
    Vec3 position{0.0};
    bool hasFrame = true;
    Frame frame;
    // Set by setNormal: frame.n is the normal, and frame.t, frame.b are built by shading only
    // when the material needs them (Frame::fromNormalAndAxis(n, tangentAxis, fallbackAxis), as
    // frameOf returns). Phong with one whole exponent does not: it is lit from n alone (the
    // "frame-free" path, render/shading_simd.h), which rounds cos α differently (within 1e-12 of
    // the framed value relative to ks · I · cos θi / d², tests/render/test_shading.cpp).
    bool tangentsPending = false;
    Vec3 tangentAxis{0, 0, 1}, fallbackAxis{1, 0, 0};
    void setNormal(const Vec3& n, const Vec3& axis, const Vec3& fallback) {
        frame.n = n;
        tangentAxis = axis;
        fallbackAxis = fallback;
        tangentsPending = true;
    }
    // Shadows (render/integrator.h, "Shadows"): per light (in the scene's order) the
    // transmittance from the point to it, multiplying that light's irradiance; null: no shadows.
    const double* shadow = nullptr;
};

// The point's full shading frame (built from its normal and axes where setNormal left the tangents
// pending).
inline Frame frameOf(const ShadingPoint& point) {
    return point.tangentsPending
               ? Frame::fromNormalAndAxis(point.frame.n, point.tangentAxis, point.fallbackAxis)
               : point.frame;
}

// colour × Lambert + highlight × specular, two-sided (without a frame: colour × the Lambert term
// with cos θ = 1). Where highlight = colour this is colour × directLighting, bit for bit the value
// of shadeVolumeSample.
Spectrum shade(const ShadingPoint& point, const Vec3& toViewer,
               const std::vector<PointLight>& lights);
// The same radiance (bit for bit), adding to `brdfEvaluations` the evaluations of the material's
// BRDF it made: one per light above the surface, none without a frame. For `lobe cost`
// (render/render_cost.h).
Spectrum shade(const ShadingPoint& point, const Vec3& toViewer,
               const std::vector<PointLight>& lights, long long& brdfEvaluations);

// The same radiance split into the material's Lambertian and specular parts (their sum equals
// shade() up to rounding), for per-object passes (render/aov.h).
struct ShadingTerms {
    Spectrum lambert;
    Spectrum specular;
};
ShadingTerms shadeTerms(const ShadingPoint& point, const Vec3& toViewer,
                        const std::vector<PointLight>& lights);

// The specular part the point would reflect with each of `models` instead of its own BRDF
// (colour × Σ f_s^m · I cos θi / d²), written to out[0 … models.size()−1]; zero without a frame.
// One frame and light loop serve all models (as the flux-overlap lattices do), so `lobe assign`
// gets every model's layer from one render. `scales` (one per model, or null): factors on each
// model's f_s, as Material::specularScale.
void shadeSpecularPerModel(const ShadingPoint& point, const Vec3& toViewer,
                           const std::vector<PointLight>& lights, const std::vector<Brdf>& models,
                           Spectrum* out, const double* scales = nullptr);

}  // namespace lobe
