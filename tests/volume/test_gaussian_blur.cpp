#include "core/error.h"
#include "volume/gaussian_blur.h"

#include <gtest/gtest.h>

namespace lobe {
namespace {

// A 41³ volume with one unit impulse in the middle, spacing (1, 1, 2).
Volume impulseVolume() {
    openvdb::initialize();
    Volume v;
    v.dims = {41, 41, 41};
    v.spacing = {1.0, 1.0, 2.0};
    v.sourcePath = "impulse";
    v.grid = openvdb::FloatGrid::create(0.0f);
    v.grid->setTransform(openvdb::math::Transform::createLinearTransform(
        openvdb::math::Mat4d(1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 2, 0, 0, 0, 0, 1)));
    v.grid->tree().setValue(openvdb::Coord(20, 20, 20), 1.0f);
    return v;
}

}  // namespace

// The blurred impulse is the sampled kernel: it keeps the total mass and has, along each axis,
// the variance σ²/spacing² in voxels with σ = FWHM / 2.3548 (here FWHM 8 → σ = 3.3973 world
// units: 3.3973 voxels along x and y, 1.6986 voxels along z where voxels are 2 units long).
TEST(GaussianBlur, ImpulseBecomesAGaussianOfTheRightWidth) {
    Volume v = impulseVolume();
    gaussianBlurFwhm(v, 8.0);
    const double sigma = 8.0 / (2.0 * std::sqrt(2.0 * std::log(2.0)));
    double mass = 0.0, varX = 0.0, varZ = 0.0;
    auto acc = v.grid->getConstAccessor();
    for (int k = 0; k < 41; ++k)
        for (int j = 0; j < 41; ++j)
            for (int i = 0; i < 41; ++i) {
                const double w = acc.getValue(openvdb::Coord(i, j, k));
                mass += w;
                varX += w * (i - 20) * (i - 20);
                varZ += w * (k - 20) * (k - 20);
            }
    EXPECT_NEAR(mass, 1.0, 1e-5);
    // Sampled Gaussians truncated at 4σ have the continuous variance to within ~1e-3 relative.
    EXPECT_NEAR(varX / mass, sigma * sigma, 2e-3 * sigma * sigma);
    EXPECT_NEAR(varZ / mass, sigma * sigma / 4.0, 2e-3 * sigma * sigma);
    EXPECT_GT(acc.getValue(openvdb::Coord(20, 20, 20)), acc.getValue(openvdb::Coord(21, 20, 20)));
}

TEST(GaussianBlur, ZeroWidthChangesNothingAndNegativeIsAnError) {
    Volume v = impulseVolume();
    gaussianBlurFwhm(v, 0.0);
    EXPECT_EQ(v.grid->tree().getValue(openvdb::Coord(20, 20, 20)), 1.0f);
    EXPECT_THROW(gaussianBlurFwhm(v, -1.0), Error);
}

}  // namespace lobe
