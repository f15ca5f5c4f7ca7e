#include "core/rgb_image.h"

#include "core/error.h"

#include <cmath>

namespace lobe {

RgbImage filmToRgb(const Film& film, double exposure) {
    RgbImage image(film.width(), film.height());
    for (int y = 0; y < film.height(); ++y)
        for (int x = 0; x < film.width(); ++x) {
            image.set(x, y, bandsToLinearSrgb(film.at(x, y) * exposure));
        }
    return image;
}

double shoulderTone(double x) {
    constexpr double k = 0.6;
    if (!(x > k)) return x;
    return k + (1.0 - k) * (1.0 - std::exp(-(x - k) / (1.0 - k)));
}

void applyTone(RgbImage& image, const std::string& curve) {
    if (curve == "clip") return;
    if (curve != "shoulder") throw Error("unknown tone curve '" + curve + "' (clip or shoulder)");
    for (float& v : image.rgb) v = float(shoulderTone(v));
}

}  // namespace lobe
