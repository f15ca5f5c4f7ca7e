// Text labels drawn into an RgbImage with OpenImageIO's text renderer and the DejaVu Sans font
// (Debian package fonts-dejavu-core, installed by scripts/setup.sh). Part of lobe_image_io.
#pragma once

#include "core/rgb_image.h"

#include <array>
#include <string>

namespace lobe {

// Draws `text` with its baseline at (x, y), `size` pixels high, in linear-sRGB `color`.
// Returns false (and draws nothing) when the font cannot be loaded, so a missing font costs the
// labels, never the image.
bool drawText(RgbImage& image, int x, int y, const std::string& text, int size,
              const std::array<float, 3>& color = {1.0f, 1.0f, 1.0f}, bool centered = false);

}  // namespace lobe
