#include "core/rgb_image.h"

#include <cmath>

namespace lobe {

RgbImage filmToRgb(const Film& film, double exposure) {
    RgbImage image(film.width(), film.height());
    for (int y = 0; y < film.height(); ++y)
        for (int x = 0; x < film.width(); ++x) {
            auto rgb = bandsToLinearSrgb(film.at(x, y) * exposure);
            for (double& c : rgb)
                if (!std::isfinite(c)) c = 0.0;
            image.set(x, y, rgb);
        }
    return image;
}

}  // namespace lobe
