#include "core/camera.h"
#include "core/error.h"
#include "core/frame.h"

#include <gtest/gtest.h>

#include <cmath>

namespace lobe {

TEST(Frame, FromNormalIsOrthonormalEverywhere) {
    const Vec3 normals[] = {{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {0.3, -0.4, 0.866}, {0, 1e-9, -1}};
    for (Vec3 n : normals) {
        n.normalize();
        const Frame f = Frame::fromNormal(n);
        EXPECT_NEAR(f.t.length(), 1.0, 1e-12);
        EXPECT_NEAR(f.b.length(), 1.0, 1e-12);
        EXPECT_NEAR(f.t.dot(f.b), 0.0, 1e-12);
        EXPECT_NEAR(f.t.dot(f.n), 0.0, 1e-12);
        EXPECT_NEAR(f.b.dot(f.n), 0.0, 1e-12);
        EXPECT_NEAR(f.t.cross(f.b).dot(f.n), 1.0, 1e-12);  // right-handed: b = n × t
    }
}

TEST(Frame, TangentFollowsProjectedAxisWithFallback) {
    const Vec3 n = Vec3(1, 0, 1).normalized();
    const Frame f = Frame::fromNormalAndAxis(n, Vec3(0, 1, 0), Vec3(1, 0, 0));
    EXPECT_NEAR(f.t.y, 1.0, 1e-12);  // world y lies in the tangent plane already
    const Frame g = Frame::fromNormalAndAxis(Vec3(0, 1, 0), Vec3(0, 1, 0), Vec3(1, 0, 0));
    EXPECT_NEAR(g.t.x, 1.0, 1e-12);  // axis parallel to n: the fallback axis is used
    const Vec3 local = f.toLocal(Vec3(0.2, 0.3, 0.4));
    const Vec3 back = f.toWorld(local);
    EXPECT_NEAR((back - Vec3(0.2, 0.3, 0.4)).length(), 0.0, 1e-12);
}

// The axis is used exactly where |axis × n| ≥ minSine as length() rounds it (frame.h skips the
// square root far from the threshold): axes swept across the threshold in steps of a few ulps
// of the angle, each choice checked against the comparison of length() itself.
TEST(Frame, AxisOrFallbackChosenAsTheRoundedLengthCompares) {
    const Vec3 n(0, 0, 1), fallback(1, 0, 0);
    int axisUsed = 0, fallbackUsed = 0;
    for (const double minSine : {1e-3, 0.25, 1e-6})
        for (int k = -2000; k <= 2000; ++k) {
            const double s = minSine * (1.0 + k * 1e-15);
            const Vec3 axis(0.0, s, std::sqrt(1.0 - s * s));  // |axis × n| = s up to rounding
            const bool expected = axis.cross(n).length() >= minSine;
            const Frame f = Frame::fromNormalAndAxis(n, axis, fallback, minSine);
            EXPECT_EQ(f.t.y == 1.0, expected) << minSine << " " << k;
            EXPECT_EQ(f.t.x == 1.0, !expected) << minSine << " " << k;
            ++(expected ? axisUsed : fallbackUsed);
        }
    EXPECT_GT(axisUsed, 1000);
    EXPECT_GT(fallbackUsed, 1000);
}

TEST(Camera, CentreRayLooksAtTargetAndCornersSpanTheFieldOfView) {
    const PinholeCamera cam(Vec3(0, 0, 4), Vec3(0, 0, 0), Vec3(0, 1, 0), 40.0, 1.0);
    const Ray centre = cam.generateRay(0.5, 0.5);
    EXPECT_NEAR((centre.d - Vec3(0, 0, -1)).length(), 0.0, 1e-12);
    const Ray top = cam.generateRay(0.5, 0.0);
    EXPECT_NEAR(std::acos(top.d.dot(centre.d)), radians(20.0), 1e-12);
    EXPECT_GT(top.d.y, 0.0);  // v = 0 is the top of the image
    EXPECT_GT(cam.generateRay(1.0, 0.5).d.x, 0.0);
}

TEST(Camera, CropWindowZoomsIntoTheFullView) {
    const PinholeCamera full(Vec3(0, 0, 4), Vec3(0), Vec3(0, 1, 0), 40.0, 1.0);
    const PinholeCamera crop(Vec3(0, 0, 4), Vec3(0), Vec3(0, 1, 0), 40.0, 1.0,
                             CropWindow{0.5, 0.25, 0.75, 0.5});
    const Ray a = crop.generateRay(0.0, 0.0), b = full.generateRay(0.5, 0.25);
    EXPECT_NEAR((a.d - b.d).length(), 0.0, 1e-12);
    const Ray c = crop.generateRay(1.0, 1.0), d = full.generateRay(0.75, 0.5);
    EXPECT_NEAR((c.d - d.d).length(), 0.0, 1e-12);
}

TEST(Camera, BadSetupsAreErrors) {
    EXPECT_THROW(PinholeCamera(Vec3(0), Vec3(0), Vec3(0, 1, 0), 40, 1), Error);
    EXPECT_THROW(PinholeCamera(Vec3(0, 0, 4), Vec3(0), Vec3(0, 0, 1), 40, 1), Error);
    EXPECT_THROW(PinholeCamera(Vec3(0, 0, 4), Vec3(0), Vec3(0, 1, 0), 0, 1), Error);
    EXPECT_THROW(
        PinholeCamera(Vec3(0, 0, 4), Vec3(0), Vec3(0, 1, 0), 40, 1, CropWindow{0.5, 0, 0.4, 1}),
        Error);
}

}  // namespace lobe
