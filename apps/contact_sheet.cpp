#include "apps/contact_sheet.h"

#include "apps/figure_output.h"
#include "core/image_output.h"
#include "core/image_text.h"

#include <algorithm>
#include <cmath>

namespace lobe {

RgbImage resizeImage(const RgbImage& image, int width, int height) {
    RgbImage out(width, height);
    const double sx = double(image.width) / width, sy = double(image.height) / height;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            // Average every source pixel the destination pixel covers (at least one).
            const int x0 = int(x * sx), x1 = std::max(x0 + 1, int(std::ceil((x + 1) * sx)));
            const int y0 = int(y * sy), y1 = std::max(y0 + 1, int(std::ceil((y + 1) * sy)));
            double sum[3] = {0, 0, 0};
            int count = 0;
            for (int v = y0; v < std::min(y1, image.height); ++v)
                for (int u = x0; u < std::min(x1, image.width); ++u, ++count)
                    for (int c = 0; c < 3; ++c) sum[c] += image.pixel(u, v)[c];
            for (int c = 0; c < 3; ++c) out.pixel(x, y)[c] = float(sum[c] / std::max(1, count));
        }
    return out;
}

RgbImage makeContactSheet(const std::vector<ContactSheetEntry>& entries, int columns,
                          int thumbSize) {
    if (entries.empty()) return RgbImage();
    columns = std::max(1, std::min(columns, int(entries.size())));
    const int rows = int((entries.size() + columns - 1) / columns);
    int thumbHeight = 0;
    for (const auto& e : entries)
        thumbHeight = std::max(thumbHeight, int(std::lround(double(thumbSize) * e.image.height /
                                                            std::max(1, e.image.width))));
    const int caption = std::max(14, thumbSize / 12);
    const int pad = 4;
    const int cellW = thumbSize + 2 * pad, cellH = thumbHeight + caption + 2 * pad;
    RgbImage sheet(columns * cellW, rows * cellH);
    std::fill(sheet.rgb.begin(), sheet.rgb.end(), 0.01f);
    for (size_t i = 0; i < entries.size(); ++i) {
        const int cx = int(i % columns) * cellW + pad, cy = int(i / columns) * cellH + pad;
        const RgbImage& src = entries[i].image;
        const int h = int(std::lround(double(thumbSize) * src.height / std::max(1, src.width)));
        const RgbImage thumb = resizeImage(src, thumbSize, std::max(1, h));
        for (int y = 0; y < thumb.height; ++y)
            for (int x = 0; x < thumb.width; ++x)
                std::copy_n(thumb.pixel(x, y), 3, sheet.pixel(cx + x, cy + y));
        // Long captions shrink (down to 8 pixels) until their measured width fits the cell.
        int size = caption * 3 / 4;
        while (size > 8 && textWidth(entries[i].caption, size) > thumbSize) --size;
        drawText(sheet, cx + thumbSize / 2, cy + thumbHeight + caption - caption / 4,
                 entries[i].caption, size, {0.85f, 0.85f, 0.85f}, true);
    }
    return sheet;
}

void writeContactSheet(const std::string& path, const std::vector<ContactSheetEntry>& entries,
                       int columns, int thumbSize) {
    std::vector<std::string> captions;
    for (const ContactSheetEntry& e : entries) captions.push_back(e.caption);
    ImageWriteOptions options;
    options.attributes = sheetProvenance(captions);
    writeImagePending(path, makeContactSheet(entries, columns, thumbSize), options).commit();
}

}  // namespace lobe
