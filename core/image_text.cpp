#include "core/image_text.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

namespace lobe {

namespace {
constexpr const char* kFontPath = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
}

bool drawText(RgbImage& image, int x, int y, const std::string& text, int size,
              const std::array<float, 3>& color, bool centered) {
    OIIO::ImageSpec spec(image.width, image.height, 3, OIIO::TypeDesc::FLOAT);
    OIIO::ImageBuf buf(spec, image.rgb.data());  // wraps our pixels: drawing writes in place
    const float c[3] = {color[0], color[1], color[2]};
    return OIIO::ImageBufAlgo::render_text(
        buf, x, y, text, size, kFontPath, c,
        centered ? OIIO::ImageBufAlgo::TextAlignX::Center : OIIO::ImageBufAlgo::TextAlignX::Left);
}

}  // namespace lobe
