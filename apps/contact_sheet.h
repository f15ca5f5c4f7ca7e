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

// makeContactSheet written to `path` (temporary name, then renamed) with the provenance every
// Lobe image carries and the cells' captions (apps/figure_output.h, sheetProvenance).
void writeContactSheet(const std::string& path, const std::vector<ContactSheetEntry>& entries,
                       int columns, int thumbSize);

// Box-filtered resize to width × height (used for thumbnails).
RgbImage resizeImage(const RgbImage& image, int width, int height);

}  // namespace lobe
