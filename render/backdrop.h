// The paper's backdrop: a random-coloured, blurred plane behind the objects, the same for every
// image (fixed seed), lit with ambient and diffuse terms only so that it carries no information
// about the BRDFs ("Rendering settings": ambient Ka 0.2, diffuse Kd 0.3). Its random colours
// avoid the Gelb effect; the blur sets it apart in depth.
//
// Geometry: a plane facing the camera, through the point `distance` beyond the camera target
// along the view direction. Texture: cells × cells uniform random colours (core/rng.h, seeded),
// Gaussian-blurred (σ = blur cells), looked up bilinearly in plane coordinates, so it is anchored
// in the world and a close-up (crop window) shows the same backdrop magnified.
// Radiance = colour/π · (ambient · Σ_lights I/d² + diffuse · Σ_lights max(0, n·l) · I/d²): the
// paper's classic ambient + diffuse terms in the objects' units (their Lambertian term is kd/π,
// render/shading.h), with the ambient light scaled by the lights' irradiance so that the
// backdrop keeps the paper's brightness relative to the objects whatever the light intensities.
#pragma once

#include "core/light.h"
#include "core/ray.h"
#include "core/spectrum.h"

#include <cstdint>
#include <vector>

namespace lobe {

struct BackdropSettings {
    uint64_t seed = 7;
    double ambient = 0.2;
    double diffuse = 0.3;
    int cells = 24;
    double blur = 1.5;
    bool grey = false;  // random lightness per cell, no hue
};

class Backdrop {
public:
    Backdrop() = default;
    // The plane faces the camera at `planePoint` with normal `-forward`; `halfExtent` is half the
    // width of the textured square (outside it the texture repeats).
    Backdrop(const BackdropSettings& settings, const Vec3& planePoint, const Vec3& forward,
             const Vec3& right, const Vec3& up, double halfExtent);

    bool enabled() const { return !texture_.empty(); }
    // Distance along the ray to the plane, or +inf when the ray does not reach it.
    double intersect(const Ray& ray) const;
    Spectrum radiance(const Vec3& point, const std::vector<PointLight>& lights) const;

private:
    Spectrum textureAt(double u, double v) const;

    BackdropSettings settings_;
    Vec3 point_{0.0}, normal_{0, 0, 1}, right_{1, 0, 0}, up_{0, 1, 0};
    double halfExtent_ = 1.0;
    int resolution_ = 0;
    std::vector<Spectrum> texture_;
};

}  // namespace lobe
