#include "figure/image_text.h"

#include "core/utf8.h"

#include <ft2build.h>
#include FT_FREETYPE_H

#include <algorithm>
#include <mutex>

namespace lobe {

namespace {

constexpr const char* kFontPath = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";

// One FreeType face for the process, loaded on first use; FreeType faces are not thread-safe,
// so every use holds the mutex.
struct Font {
    std::mutex mutex;
    FT_Library library = nullptr;
    FT_Face face = nullptr;
    bool loaded = false;

    Font() {
        if (FT_Init_FreeType(&library) != 0) return;
        if (FT_New_Face(library, kFontPath, 0, &face) != 0) return;
        loaded = true;
    }
    ~Font() {
        if (face) FT_Done_Face(face);
        if (library) FT_Done_FreeType(library);
    }
};

Font& font() {
    static Font f;
    return f;
}

int missingAdvance(int size) { return std::max(3, int(size * 0.6 + 0.5)); }

// Walks the text's characters at `size`: visit(pen, glyph index or 0 for a missing one, the
// glyph slot when loaded). Returns the total advance. Caller holds the font's mutex.
template <class Visit>
int layout(Font& f, const std::vector<char32_t>& text, int size, bool render, Visit&& visit) {
    FT_Set_Pixel_Sizes(f.face, 0, FT_UInt(size));
    const bool kerning = FT_HAS_KERNING(f.face);
    int pen = 0;
    FT_UInt previous = 0;
    for (char32_t cp : text) {
        FT_UInt index = cp < 0x20 || cp == 0x7F ? 0 : FT_Get_Char_Index(f.face, FT_ULong(cp));
        if (index != 0 &&
            FT_Load_Glyph(f.face, index, render ? FT_LOAD_RENDER : FT_LOAD_DEFAULT) != 0)
            index = 0;
        if (index == 0) {
            visit(pen, 0u, nullptr);
            pen += missingAdvance(size);
            previous = 0;
            continue;
        }
        if (kerning && previous != 0) {
            FT_Vector delta;
            if (FT_Get_Kerning(f.face, previous, index, FT_KERNING_DEFAULT, &delta) == 0)
                pen += int(delta.x >> 6);
        }
        visit(pen, index, f.face->glyph);
        pen += int(f.face->glyph->advance.x >> 6);
        previous = index;
    }
    return pen;
}

void blend(RgbImage& image, int x, int y, double coverage, const std::array<float, 3>& color) {
    if (x < 0 || y < 0 || x >= image.width || y >= image.height || coverage <= 0.0) return;
    float* p = image.pixel(x, y);
    for (int c = 0; c < 3; ++c) p[c] = float(p[c] * (1.0 - coverage) + color[size_t(c)] * coverage);
}

}  // namespace

MissingGlyphBox missingGlyphBox(int x, int y, int size) {
    const int advance = missingAdvance(size);
    const int height = std::max(3, int(size * 0.7 + 0.5));
    return {x + 1, y - height + 1, x + advance - 2, y};
}

int textWidth(const std::string& text, int size) {
    Font& f = font();
    std::lock_guard<std::mutex> lock(f.mutex);
    if (!f.loaded || size < 1) return 0;
    return layout(f, decodeUtf8(text), size, false, [](int, FT_UInt, FT_GlyphSlot) {});
}

bool drawText(RgbImage& image, int x, int y, const std::string& text, int size,
              const std::array<float, 3>& color, bool centered) {
    Font& f = font();
    std::lock_guard<std::mutex> lock(f.mutex);
    if (!f.loaded || size < 1) return false;
    const std::vector<char32_t> chars = decodeUtf8(text);
    const int width = layout(f, chars, size, false, [](int, FT_UInt, FT_GlyphSlot) {});
    const int x0 = centered ? x - width / 2 : x;
    const int line = std::max(1, size / 14);
    layout(f, chars, size, true, [&](int pen, FT_UInt index, FT_GlyphSlot glyph) {
        if (index == 0) {
            const MissingGlyphBox b = missingGlyphBox(x0 + pen, y, size);
            for (int py = b.y0; py <= b.y1; ++py)
                for (int px = b.x0; px <= b.x1; ++px) {
                    const bool edge = px < b.x0 + line || px > b.x1 - line || py < b.y0 + line ||
                                      py > b.y1 - line;
                    if (edge) blend(image, px, py, 1.0, color);
                }
            return;
        }
        const FT_Bitmap& bm = glyph->bitmap;
        if (bm.pixel_mode != FT_PIXEL_MODE_GRAY) return;
        const int left = x0 + pen + glyph->bitmap_left, top = y - glyph->bitmap_top;
        for (unsigned r = 0; r < bm.rows; ++r)
            for (unsigned c = 0; c < bm.width; ++c) {
                const unsigned char v = bm.buffer[int(r) * bm.pitch + int(c)];
                blend(image, left + int(c), top + int(r), v / 255.0, color);
            }
    });
    return true;
}

}  // namespace lobe
