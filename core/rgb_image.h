// A linear-sRGB float image (3 channels, row-major, row 0 at the top): the display form of a
// Film, and what the tools that draw diagrams (heat maps, lobe images, contact sheets) produce.
#pragma once

#include "core/film.h"
#include "core/math.h"

#include <array>
#include <string>
#include <vector>

namespace lobe {

struct RgbImage {
    int width = 0;
    int height = 0;
    std::vector<float> rgb;  // 3 floats per pixel, linear sRGB

    RgbImage() = default;
    RgbImage(int w, int h) : width(w), height(h), rgb(size_t(w) * h * 3, 0.0f) {}
    float* pixel(int x, int y) { return &rgb[(size_t(y) * width + x) * 3]; }
    const float* pixel(int x, int y) const { return &rgb[(size_t(y) * width + x) * 3]; }
    void set(int x, int y, const std::array<double, 3>& c) {
        float* p = pixel(x, y);
        p[0] = imageFloat(c[0]);
        p[1] = imageFloat(c[1]);
        p[2] = imageFloat(c[2]);
    }
};

// Film → linear sRGB through CIE RGB → XYZ → sRGB (core/spectrum.h), times `exposure`.
// Non-finite values (which the renderer never produces on purpose) become 0, never NaN.
RgbImage filmToRgb(const Film& film, double exposure = 1.0);

// Display tone curves for 8-bit output (the EXR stays linear). "clip": values above 1 clip to
// white. "shoulder": the identity up to a knee k = 0.6, then k + (1 − k)(1 − e^{−(x − k)/(1 − k)}),
// continuous with slope 1 at the knee and approaching 1 (reached in doubles only past x ≈ 15), so
// highlights keep their shape instead of merging into flat white (a filmic shoulder; Reinhard et
// al. 2002 discuss why a global curve with a soft shoulder keeps detail a clip loses). Applied per
// channel, so a bright highlight also desaturates towards white as film does.
double shoulderTone(double linear);
// Throws lobe::Error for an unknown curve name.
void applyTone(RgbImage& image, const std::string& curve);

}  // namespace lobe
