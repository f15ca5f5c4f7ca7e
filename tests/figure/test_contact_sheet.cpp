// Thumbnails (figure/contact_sheet.h): the box filter against hand-computed means, and the same
// filter fed a poster's bands of rows (BoxResizer) against the whole image, float for float.
#include "figure/contact_sheet.h"

#include <gtest/gtest.h>

namespace {

using lobe::RgbImage;

TEST(BoxResizer, MeansOfTheCoveredPixels) {
    // 3 × 1 → 2 × 1: each destination pixel covers 1.5 source pixels, so both take two
    // (x ∈ [0, 2) and [1, 3)): (1 + 2) / 2 and (2 + 4) / 2.
    RgbImage row(3, 1);
    for (int x = 0; x < 3; ++x) row.set(x, 0, {double(1 << x), 0.0, 10.0});
    const RgbImage half = lobe::resizeImage(row, 2, 1);
    EXPECT_EQ(half.pixel(0, 0)[0], 1.5f);
    EXPECT_EQ(half.pixel(1, 0)[0], 3.0f);
    EXPECT_EQ(half.pixel(1, 0)[2], 10.0f);
    // 4 × 2 → 2 × 1: 2 × 2 blocks.
    RgbImage block(4, 2);
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 4; ++x) block.set(x, y, {double(x + 4 * y), 0.0, 0.0});
    const RgbImage small = lobe::resizeImage(block, 2, 1);
    EXPECT_EQ(small.pixel(0, 0)[0], (0 + 1 + 4 + 5) / 4.0f);
    EXPECT_EQ(small.pixel(1, 0)[0], (2 + 3 + 6 + 7) / 4.0f);
}

TEST(BoxResizer, BandsGiveTheWholeImagesFloats) {
    // 37 × 29 → 8 × 6 (ratios 4.625 and 4.83: destination rows share source rows), with values
    // whose sums round differently in another order.
    RgbImage image(37, 29);
    for (size_t i = 0; i < image.rgb.size(); ++i)
        image.rgb[i] = float(1.0 / (1.0 + double(i % 97))) * 1e3f;
    const RgbImage whole = lobe::resizeImage(image, 8, 6);
    for (const int bandRows : {1, 3, 5, 29}) {
        lobe::BoxResizer resizer(37, 29, 8, 6);
        for (int y0 = 0; y0 < 29; y0 += bandRows) {
            RgbImage band(37, std::min(bandRows, 29 - y0));
            std::copy_n(image.pixel(0, y0), band.rgb.size(), band.rgb.begin());
            resizer.addRows(band);
        }
        EXPECT_EQ(resizer.result().rgb, whole.rgb) << bandRows;
    }
    // A band beyond the image is an error, not a write out of bounds.
    lobe::BoxResizer resizer(37, 29, 8, 6);
    EXPECT_THROW(resizer.addRows(RgbImage(37, 30)), std::exception);
}

}  // namespace
