// A contact sheet: several images side by side in a grid, each with a caption underneath, for
// comparing renderings at a glance (the paper's Figures 12–22 show its renderings this way).
#pragma once

#include "core/rgb_image.h"

#include <string>
#include <vector>

namespace lobe {

struct ContactSheetEntry {
    RgbImage image;
    std::string caption;
};

// Images are scaled (box filter) to `thumbSize` pixels wide, keeping their aspect, and placed
// `columns` to a row on a dark background with a caption strip under each.
RgbImage makeContactSheet(const std::vector<ContactSheetEntry>& entries, int columns,
                          int thumbSize);

// Box-filtered resize to width × height (used for thumbnails): each destination pixel the mean
// of every source pixel it covers.
RgbImage resizeImage(const RgbImage& image, int width, int height);

// The same resize fed the source a band of rows at a time, top first: a poster's thumbnail built
// while its bands are rendered, without the whole image. The same sums in the same order as
// resizeImage, so the same floats.
class BoxResizer {
public:
    BoxResizer(int sourceWidth, int sourceHeight, int width, int height);
    // The next band.height rows of the source (band.width == sourceWidth).
    void addRows(const RgbImage& band);
    // After the last row.
    RgbImage result() const;

private:
    int sourceWidth_, sourceHeight_, width_, height_;
    int nextRow_ = 0;
    // The source pixels [x0, x1) × [y0, y1) each destination pixel covers.
    std::vector<int> x0_, x1_, y0_, y1_;
    std::vector<double> sums_;  // [(y · width + x) · 3 + c]
    std::vector<int> counts_;
};

}  // namespace lobe
