#include "figure/contact_sheet.h"

#include "core/error.h"
#include "figure/image_text.h"

#include <algorithm>
#include <cmath>

namespace lobe {

BoxResizer::BoxResizer(int sourceWidth, int sourceHeight, int width, int height)
    : sourceWidth_(sourceWidth),
      sourceHeight_(sourceHeight),
      width_(width),
      height_(height),
      sums_(size_t(width) * size_t(height) * 3, 0.0),
      counts_(size_t(width) * size_t(height), 0) {
    // Every source pixel the destination pixel covers (at least one).
    const double sx = double(sourceWidth) / width, sy = double(sourceHeight) / height;
    for (int x = 0; x < width; ++x) {
        x0_.push_back(int(x * sx));
        x1_.push_back(
            std::min(sourceWidth, std::max(x0_.back() + 1, int(std::ceil((x + 1) * sx)))));
    }
    for (int y = 0; y < height; ++y) {
        y0_.push_back(int(y * sy));
        y1_.push_back(
            std::min(sourceHeight, std::max(y0_.back() + 1, int(std::ceil((y + 1) * sy)))));
    }
}

void BoxResizer::addRows(const RgbImage& band) {
    if (band.width != sourceWidth_ || nextRow_ + band.height > sourceHeight_)
        throw Error("internal: a band of " + std::to_string(band.width) + " x " +
                    std::to_string(band.height) + " does not continue a " +
                    std::to_string(sourceWidth_) + " x " + std::to_string(sourceHeight_) +
                    " image");
    for (int r = 0; r < band.height; ++r) {
        const int v = nextRow_ + r;
        // Source rows ascending, and within a row columns ascending: resizeImage's order.
        for (int y = 0; y < height_; ++y) {
            if (v < y0_[size_t(y)] || v >= y1_[size_t(y)]) continue;
            for (int x = 0; x < width_; ++x) {
                double* sum = &sums_[(size_t(y) * size_t(width_) + size_t(x)) * 3];
                for (int u = x0_[size_t(x)]; u < x1_[size_t(x)]; ++u) {
                    const float* p = band.pixel(u, r);
                    for (int c = 0; c < 3; ++c) sum[c] += p[c];
                }
                counts_[size_t(y) * size_t(width_) + size_t(x)] += x1_[size_t(x)] - x0_[size_t(x)];
            }
        }
    }
    nextRow_ += band.height;
}

RgbImage BoxResizer::result() const {
    RgbImage out(width_, height_);
    for (size_t i = 0; i < counts_.size(); ++i)
        for (int c = 0; c < 3; ++c)
            out.rgb[i * 3 + size_t(c)] = float(sums_[i * 3 + size_t(c)] / std::max(1, counts_[i]));
    return out;
}

RgbImage resizeImage(const RgbImage& image, int width, int height) {
    BoxResizer resizer(image.width, image.height, width, height);
    resizer.addRows(image);
    return resizer.result();
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

}  // namespace lobe
