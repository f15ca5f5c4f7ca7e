// The BRDF gallery: the nine specular models side by side on spheres, each with a Lambertian
// kd = 0.2, lit by the three point lights of the flux-overlap test (docs/flux-overlap.md),
// labelled — the paper's Figure 3 on simple shapes.
#pragma once

#include "core/film.h"
#include "core/rgb_image.h"

#include <cstdint>
#include <string>
#include <vector>

namespace lobe {

struct GalleryOptions {
    int cellSize = 256;       // pixels per sphere cell (square)
    int samplesPerPixel = 4;  // jittered
    int threads = 0;
    uint64_t seed = 1;
    double lightIntensity = 12.0;
    bool progress = true;
    std::vector<std::string> settings;  // "model.key=value" overrides
};

struct Gallery {
    Film film;                        // radiometric bands, no labels
    std::vector<std::string> labels;  // one per cell, row-major
    int columns = 3;
    int cellSize = 0;
};

Gallery renderGallery(const GalleryOptions& options);

// The film in display colour with each cell's label drawn under its sphere.
RgbImage labelledGalleryImage(const Gallery& gallery);

}  // namespace lobe
