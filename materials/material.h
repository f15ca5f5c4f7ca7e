// What an object reflects with: its own specular BRDF plus a Lambertian term kd, and the direct
// lighting from point lights that every renderer in Lobe uses:
//   L = Σ_lights (kd/π + f_s(wi, wo)) · I/d² · cos θi      (shared/docs/brdf-models.md,
// "Conventions"; the paper's eq. 1.10 with point lights, no shadows).
#pragma once

#include "core/frame.h"
#include "core/light.h"
#include "materials/brdf.h"

#include <vector>

namespace lobe {

struct Material {
    Brdf specular = Phong{};
    Spectrum kd{0.2};
    bool specularOn = true;  // false: Lambert only (the backdrop; samples with no usable normal)
};

// Reflected radiance towards the viewer at `position` with shading frame `frame`; `toViewer` is
// the unit world direction from the point to the viewer. Lights below the surface contribute 0.
// A two-sided variant flips the frame to the viewer's side first (volume samples have no inside).
Spectrum directLighting(const Material& material, const Frame& frame, const Vec3& position,
                        const Vec3& toViewer, const std::vector<PointLight>& lights,
                        bool twoSided = false);

}  // namespace lobe
