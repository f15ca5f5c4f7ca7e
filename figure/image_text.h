// Text labels drawn into an RgbImage with FreeType and the DejaVu Sans font (Debian package
// fonts-dejavu-core, installed by scripts/setup.sh). Part of lobe_captions.
//
// Text is UTF-8 (core/utf8.h): every character DejaVu Sans holds (Latin, Greek, Cyrillic, most
// symbols — "é", "μ", "°", "±") is drawn with its glyph; a character the font lacks (CJK, emoji),
// a control character or a byte that is not valid UTF-8 is drawn as a visible box outline
// ("tofu"), never as another character. Glyph coverage is blended linearly over the pixels.
#pragma once

#include "core/rgb_image.h"

#include <array>
#include <string>

namespace lobe {

// Draws `text` with its baseline at (x, y), `size` pixels high (the font's em), in linear-sRGB
// `color`; `centered`: x is the middle of the text. Returns false (and draws nothing) when the
// font cannot be loaded, so a missing font costs the labels, never the image.
bool drawText(RgbImage& image, int x, int y, const std::string& text, int size,
              const std::array<float, 3>& color = {1.0f, 1.0f, 1.0f}, bool centered = false);

// The advance width in pixels of `text` at `size` (what drawText covers horizontally); 0 when
// the font cannot be loaded.
int textWidth(const std::string& text, int size);

// The box drawn for a character the font lacks, as drawText places it: its left edge at pen
// position x, the baseline at y. Exposed so tests can check the box against drawn pixels.
struct MissingGlyphBox {
    int x0, y0, x1, y1;  // inclusive pixel bounds of the outline
};
MissingGlyphBox missingGlyphBox(int x, int y, int size);

}  // namespace lobe
