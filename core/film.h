// The image being rendered: one band triple per pixel (linear, unbounded), row-major, row 0 at
// the top. Writing it to disk is core/image_output.h's job.
#pragma once

#include "core/spectrum.h"

#include <vector>

namespace lobe {

class Film {
public:
    Film() = default;
    Film(int width, int height) : width_(width), height_(height), pixels_(size_t(width) * height) {}

    int width() const { return width_; }
    int height() const { return height_; }
    Spectrum& at(int x, int y) { return pixels_[size_t(y) * width_ + x]; }
    const Spectrum& at(int x, int y) const { return pixels_[size_t(y) * width_ + x]; }
    const std::vector<Spectrum>& pixels() const { return pixels_; }
    Spectrum* data() { return pixels_.data(); }

private:
    int width_ = 0;
    int height_ = 0;
    std::vector<Spectrum> pixels_;
};

}  // namespace lobe
