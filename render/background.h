// What is behind the objects in an image: the paper's backdrop (render/backdrop.h, the default),
// nothing (a transparent background: an alpha channel in EXR, PNG and TIFF), or a solid colour.
//
// Scene key "background" (docs/scene-format.md) and `lobe render --background`:
//   "backdrop"                the paper's blurred random-colour plane (as before; the "backdrop"
//                             block still sets it up, and "backdrop": {"enabled": false} still
//                             leaves black behind the objects);
//   "none"                    no backdrop; the image's colour is the objects' light alone
//                             (premultiplied by alpha) and alpha is their coverage (below);
//   "#rrggbb" or [r, g, b]    a solid colour as a colour picker gives it (sRGB-encoded, [0, 1]
//                             for the array): the objects over it by their coverage.
// Coverage (alpha) of a pixel: 1 − T, T the transmittance through every object along the camera
// ray (the product of (1 − opacity) over every surface hit and volume sample the ray composites),
// averaged over the pixel's samples. 1 where an opaque surface covers the whole pixel, 0 where no
// object is met. A ray the integrator stops early because T fell below the scene's
// termination_transmittance (1e-3 by default) keeps that T, so such a pixel's alpha is
// ≥ 0.999, not exactly 1. Over a colour C (linear) the pixel is objects + (1 − alpha) · C, the
// same composite the backdrop gets.
#pragma once

#include <array>
#include <string>
#include <vector>

namespace lobe {

struct Background {
    enum class Mode { Backdrop, None, Colour };
    Mode mode = Mode::Backdrop;
    std::array<double, 3> colour{0.0, 0.0, 0.0};  // linear sRGB (Mode::Colour)
    std::string text = "backdrop";                // as given, for messages

    bool needsAlpha() const { return mode != Mode::Backdrop; }
};

// "backdrop", "none" or "#rrggbb" (hex digits, either case); throws lobe::Error naming `where`
// and the expected forms otherwise.
Background parseBackground(const std::string& text, const std::string& where);
// [r, g, b], each in [0, 1], sRGB-encoded.
Background backgroundFromColour(const std::array<double, 3>& srgb, const std::string& where);

// Film += (1 − alpha) · colour (the background's linear sRGB in bands, divided by the exposure so
// the display shows it as given), alpha the coverage per pixel. Nothing for other backgrounds.
// What every rendered image gets before it is written (figure/figure_output.h) or returned (the
// Python module).
class Film;
void compositeBackground(Film& film, const std::vector<float>& alpha, const Background& background,
                         double exposure);

}  // namespace lobe
