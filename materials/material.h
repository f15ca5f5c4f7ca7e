// What an object reflects with: its own specular BRDF plus a Lambertian term kd,
//   f = kd/π + f_s(wi, wo)      (docs/models.md, "Conventions"; the paper's eq. 1.10).
// Lighting a point with it is render/shading.h's job.
#pragma once

#include "materials/brdf.h"

namespace lobe {

struct Material {
    Brdf specular = Phong{};
    Spectrum kd{0.2};
    bool specularOn = true;  // false: Lambert only
    // Multiplies f_s: the lobe scaled to a stated albedo at normal incidence (scene key
    // brdf.albedo, materials/albedo.h); 1 leaves the model as its parameters make it.
    double specularScale = 1.0;
};

}  // namespace lobe
