#include "render/background.h"

#include "core/error.h"
#include "core/film.h"
#include "core/spectrum.h"

#include <cctype>
#include <cmath>
#include <cstdio>

namespace lobe {

Background parseBackground(const std::string& text, const std::string& where) {
    Background b;
    b.text = text;
    if (text == "backdrop") return b;
    if (text == "none") {
        b.mode = Background::Mode::None;
        return b;
    }
    bool hex = text.size() == 7 && text[0] == '#';
    for (size_t i = 1; hex && i < 7; ++i) hex = std::isxdigit(static_cast<unsigned char>(text[i]));
    if (!hex)
        throw Error(where + ": background '" + text +
                    "' is not one of backdrop, none, a colour \"#rrggbb\" or [r, g, b] in [0, 1]");
    std::array<double, 3> srgb;
    for (int c = 0; c < 3; ++c)
        srgb[size_t(c)] = std::stoi(text.substr(1 + 2 * size_t(c), 2), nullptr, 16) / 255.0;
    Background colour = backgroundFromColour(srgb, where);
    colour.text = text;
    return colour;
}

Background backgroundFromColour(const std::array<double, 3>& srgb, const std::string& where) {
    Background b;
    b.mode = Background::Mode::Colour;
    char buf[64];
    std::snprintf(buf, sizeof buf, "[%g, %g, %g]", srgb[0], srgb[1], srgb[2]);
    b.text = buf;
    for (int c = 0; c < 3; ++c) {
        if (!(srgb[size_t(c)] >= 0.0 && srgb[size_t(c)] <= 1.0))
            throw Error(where + ": background colour " + b.text +
                        " has a component outside [0, 1]");
        b.colour[size_t(c)] = srgbDecode(srgb[size_t(c)]);
    }
    return b;
}

void compositeBackground(Film& film, const std::vector<float>& alpha, const Background& background,
                         double exposure) {
    if (background.mode != Background::Mode::Colour) return;
    const size_t n = size_t(film.width()) * film.height();
    if (alpha.size() != n) throw Error("internal: no coverage for the background colour");
    // Linear sRGB → bands without clamping: a colour outside the CIE RGB gamut keeps its exact
    // display colour.
    const std::array<double, 3>& rgb = background.colour;
    const Spectrum colour = linearSrgbToBandsUnclamped(rgb[0], rgb[1], rgb[2]) * (1.0 / exposure);
    Spectrum* pixels = film.data();
    for (size_t i = 0; i < n; ++i) pixels[i] += colour * (1.0 - double(alpha[i]));
}

}  // namespace lobe
