// core/camera_rays.h: the SIMD camera rays against PinholeCamera::generateRay at the image point
// the pixel loop forms (jitteredSample, then (x + j.x) / width), bit for bit: random cameras,
// crop windows, strata grids and sample counts that leave a remainder after the last vector,
// and points whose direction is NaN (made by generateRay itself).
#include "core/camera_rays.h"
#include "core/pixel_loop.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <vector>

namespace lobe {
namespace {

bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

TEST(CameraRays, DirectionsAreGenerateRaysBitForBit) {
    std::mt19937_64 gen(2026);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    const auto vec = [&](double s) {
        return Vec3(s * (uni(gen) - 0.5), s * (uni(gen) - 0.5), s * (uni(gen) - 0.5));
    };
    long long compared = 0;
    for (int trial = 0; trial < 60; ++trial) {
        CropWindow crop;
        if (trial % 3 == 1)
            crop = {0.1 * uni(gen), 0.1 * uni(gen), 0.5 + 0.5 * uni(gen), 0.5 + 0.5 * uni(gen)};
        const Vec3 position = vec(1000.0);
        const PinholeCamera camera(position, position + vec(10.0) + Vec3(0.0, 0.0, 0.1),
                                   Vec3(0, 0, 1), 5.0 + 150.0 * uni(gen), 0.5 + uni(gen), crop);
        const int spp = 1 + trial % 9;  // grids 1×1 … 3×3, 2×4, 1×7
        const StrataGrid strata = strataFor(spp);
        const PixelSampling sampling{spp, uint64_t(trial)};
        const int width = 17 + trial, height = 9 + 2 * trial;
        const int y = trial % height;
        const int pixels = 1 + trial % 13;  // n = pixels·spp: remainders 0 … 3 after vectors of 4
        std::vector<double> x, yy, sx, sy;
        std::vector<Vec3> expected;
        for (int px = 0; px < pixels; ++px) {
            const PixelSamples samples(sampling, strata, px, y);
            for (int s = 0; s < spp; ++s) {
                Rng a, b;
                const Vec2 j = samples.start(s, a);
                const Vec2 q = samples.startInStrata(s, b);
                expected.push_back(camera.generateRay((px + j.x) / width, (y + j.y) / height).d);
                x.push_back(px);
                yy.push_back(y);
                sx.push_back(q.x);
                sy.push_back(q.y);
            }
        }
        if (trial % 5 == 4) {  // a NaN point: generateRay's normalized() gives 0
            sx[0] = std::nan("");
            expected[0] = camera
                              .generateRay((x[0] + sx[0] / strata.cols) / width,
                                           (yy[0] + sy[0] / strata.rows) / height)
                              .d;
            EXPECT_EQ(expected[0], Vec3(0.0));
        }
        CameraSamplePoints pts;
        pts.n = int(x.size());
        pts.x = x.data();
        pts.y = yy.data();
        pts.sx = sx.data();
        pts.sy = sy.data();
        pts.cols = strata.cols;
        pts.rows = strata.rows;
        pts.width = width;
        pts.height = height;
        std::vector<double> dx(x.size()), dy(x.size()), dz(x.size());
        cameraRayDirections(camera, pts, dx.data(), dy.data(), dz.data());
        for (size_t i = 0; i < x.size(); ++i) {
            ASSERT_TRUE(sameBits(dx[i], expected[i].x) && sameBits(dy[i], expected[i].y) &&
                        sameBits(dz[i], expected[i].z))
                << "trial " << trial << ", sample " << i << ": " << dx[i] << " " << dy[i] << " "
                << dz[i] << " vs " << expected[i];
            ++compared;
        }
    }
    EXPECT_GT(compared, 1000);
}

}  // namespace
}  // namespace lobe
