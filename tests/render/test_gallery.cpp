#include "core/error.h"
#include "core/math.h"
#include "materials/registry.h"
#include "render/gallery.h"

#include <gtest/gtest.h>

namespace lobe {
namespace {

GalleryOptions smallGallery(int threads) {
    GalleryOptions options;
    options.cellSize = 24;
    options.samplesPerPixel = 4;
    options.threads = threads;
    options.progress = false;
    return options;
}

}  // namespace

TEST(Gallery, SameImageForOneAndTwoThreads) {
    const Gallery one = renderGallery(smallGallery(1));
    const Gallery two = renderGallery(smallGallery(2));
    ASSERT_EQ(one.film.pixels().size(), two.film.pixels().size());
    for (size_t i = 0; i < one.film.pixels().size(); ++i)
        for (int c = 0; c < 3; ++c) ASSERT_EQ(one.film.pixels()[i][c], two.film.pixels()[i][c]);
}

TEST(Gallery, NineLabelledCellsAndFiniteNonNegativePixels) {
    const Gallery g = renderGallery(smallGallery(0));
    EXPECT_EQ(g.labels.size(), specularModelNames().size()) << "one cell per specular model";
    for (const Spectrum& s : g.film.pixels()) {
        ASSERT_TRUE(s.isFinite());
        for (int c = 0; c < 3; ++c) ASSERT_GE(s[c], 0.0);
    }
}

// With the specular term switched off (phong ks = 0) the sphere is Lambertian, and the radiance
// seen through the cell's centre pixel is Σ_lights kd/π · I · cos θi / d², computed here from the
// geometry: the camera at (0, -0.18, 4) looks along -z, so that ray hits the unit sphere at
// (0, -0.18, sqrt(1 - 0.18²)), where the normal equals the point.
TEST(Gallery, LambertOnlySphereMatchesClosedForm) {
    GalleryOptions options = smallGallery(1);
    options.cellSize = 101;
    options.samplesPerPixel = 1;
    options.settings = {"phong.ks=0"};
    const Gallery g = renderGallery(options);
    // Cell 0 is phong with ks = 0: Lambert only. Pixel (50, 50) looks along (0, 0, -1) from
    // (0, -0.18, 4) up to half a pixel of jitter; the hit is near (0, -0.18, 0.9837).
    const Vec3 p(0.0, -0.18, std::sqrt(1.0 - 0.18 * 0.18));
    const Vec3 n = p;
    const Vec3 lights[3] = {{-3, 3, 3}, {3, 2, 3}, {0, -3, 2.5}};
    double expected = 0.0;
    for (const Vec3& l : lights) {
        const Vec3 d = l - p;
        expected +=
            0.2 / kPi * options.lightIntensity * std::max(0.0, n.dot(d.normalized())) / d.length2();
    }
    EXPECT_NEAR(g.film.at(50, 50)[0], expected, 0.01 * expected);  // jitter moves the hit slightly
}

TEST(Gallery, BadSettingsAreErrors) {
    GalleryOptions options = smallGallery(1);
    options.settings = {"nosuchmodel.ks=1"};
    EXPECT_THROW(renderGallery(options), Error);
    options.settings = {"ward.alpha_x=-1"};
    EXPECT_THROW(renderGallery(options), Error);
    options.settings = {"ks=1"};
    EXPECT_THROW(renderGallery(options), Error);
}

}  // namespace lobe
