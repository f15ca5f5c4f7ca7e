// SurfaceScene::intersect8 (8 rays traced together with rtcIntersect8, surface_scene.h) against
// intersect() one ray at a time: the same hit (distance, object, primitive, position and normal,
// bit for bit) from every kind of user geometry (exact and meshed shells, a level-set ball: each
// lane searched along its own double ray and bounded by its own nearest double root), for
// coherent packets (neighbouring rays from one eye, as the pixel loop makes them) and incoherent
// ones, full and partial packets, rays with a tMin and a tMax; two roots within one float step of
// each other at t ≈ 540 (the nearer must win in every lane); clipped or masked scenes refused.
#include "core/clip.h"
#include "core/error.h"
#include "core/rng.h"
#include "surface/iso_exact.h"
#include "surface/iso_levelset.h"
#include "surface/iso_mesh.h"
#include "surface/surface_scene.h"
#include "surface_test_grids.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <memory>
#include <optional>
#include <vector>

namespace lobe {
namespace {

using test::makeGrid;

const double kIdentity[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
using test::shellGrid;
const Vec3& kCentre = test::kShellCentre;

class OpenVdbInit : public ::testing::Environment {
public:
    void SetUp() override { openvdb::initialize(); }
};
const auto* const kOpenVdbEnv = ::testing::AddGlobalTestEnvironment(new OpenVdbInit);

bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// intersect8 on rays[0 … n) against intersect() on each.
void expectSameAsOneByOne(const SurfaceScene& scene, const std::vector<Ray>& rays, int n, int& hits,
                          const char* what) {
    const Ray* pointers[8];
    for (int k = 0; k < n; ++k) pointers[k] = &rays[size_t(k)];
    std::optional<SurfaceHit> got[8];
    scene.intersect8(pointers, n, got);
    for (int k = 0; k < n; ++k) {
        const std::optional<SurfaceHit> want = scene.intersect(rays[size_t(k)]);
        ASSERT_EQ(got[k].has_value(), want.has_value()) << what << " lane " << k;
        if (!want) continue;
        ++hits;
        EXPECT_TRUE(sameBits(got[k]->t, want->t))
            << what << " lane " << k << ": " << got[k]->t << " vs " << want->t;
        EXPECT_EQ(got[k]->objectId, want->objectId) << what << " lane " << k;
        EXPECT_EQ(got[k]->primId, want->primId) << what << " lane " << k;
        for (int a = 0; a < 3; ++a) {
            EXPECT_TRUE(sameBits(got[k]->normal[a], want->normal[a])) << what << " lane " << k;
            EXPECT_TRUE(sameBits(got[k]->position[a], want->position[a])) << what << " lane " << k;
        }
    }
}

TEST(Packets, EightRaysAtOnceGiveTheHitsOfOneAtATime) {
    const auto a = shellGrid(Vec3(0.0)), b = shellGrid(Vec3(50.0, 0.0, 0.0));
    SurfaceScene scene("threads=1");
    scene.add(std::make_shared<IsoExactSurface>(*a, 0.0, "a"));
    scene.add(std::make_shared<IsoMeshSurface>(*b, 0.0, "b"));
    // A ball of radius 8 around kCentre + (25, 0, 30), rebuilt as a level set (the third user
    // geometry).
    const Vec3 ballCentre = kCentre + Vec3(25.0, 0.0, 30.0);
    const int dims[3] = {24, 24, 24};
    const auto ball = makeGrid(dims, kIdentity, ballCentre - Vec3(12.0), -4.0f,
                               [&](const Vec3& x) { return 8.0 - (x - ballCentre).length(); });
    scene.add(LevelSetSurface::fromDensity(*ball, 0.0, LevelSetOptions{}, "ball"));
    scene.commit();
    ASSERT_TRUE(scene.packetsSupported());
    Rng rng(31, 8);
    int hits = 0, packets = 0;
    for (int p = 0; p < 300; ++p) {
        const int n = 1 + p % 8;  // partial packets too
        std::vector<Ray> rays(8);
        const bool coherent = p % 3 != 0;
        // A row of neighbouring rays from one eye (as the pixel loop makes them), or rays from
        // anywhere outside the shells to anywhere near a centre.
        const Vec3 centre = p % 4 == 3 ? ballCentre : kCentre + Vec3(p % 2 ? 50.0 : 0.0, 0, 0);
        const Vec3 eye = centre + Vec3(-40.0 + 10 * rng.uniform(), -45.0, 12.0 * rng.uniform());
        const Vec3 aim =
            centre + Vec3(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5) * 30.0;
        for (int k = 0; k < 8; ++k) {
            Ray& r = rays[size_t(k)];
            if (coherent) {
                r.o = eye;
                r.d = normalized(aim + Vec3(0.37 * k, 0.0, 0.11 * k) - eye);
            } else {
                const Vec3 target =
                    centre +
                    Vec3(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5) * 30.0;
                const double z = 2.0 * rng.uniform() - 1.0, phi = 2.0 * kPi * rng.uniform();
                const double s = std::sqrt(std::max(0.0, 1.0 - z * z));
                r.o = target - Vec3(s * std::cos(phi), s * std::sin(phi), z) * 60.0;
                r.d = normalized(target - r.o);
            }
            if (p % 5 == 1) r.tMin = 30.0 + 20.0 * rng.uniform();  // starts inside the shells
            if (p % 7 == 2) r.tMax = 40.0 + 20.0 * rng.uniform();  // ends inside them
        }
        expectSameAsOneByOne(scene, rays, n, hits, coherent ? "coherent" : "incoherent");
        ++packets;
    }
    EXPECT_GT(hits, 800);  // most lanes hit a shell
}

// Two exact planes 5e-6 apart at t ≈ 540, less than one float step of Embree's tfar (6.1e-5):
// each lane must bound its search by its own double hit, or the farther plane can win (the
// single-ray case: test_hit_list.cpp, ARootWithinOneFloatStepOfAnotherIsNotHidden).
TEST(Packets, ARootWithinOneFloatStepOfAnotherIsNotHiddenInAnyLane) {
    const int dims[3] = {16, 16, 16};
    const auto planeGrid = [&](double c) {
        return makeGrid(dims, kIdentity, Vec3(0.0), -1.0f, [c](const Vec3& x) { return x.x - c; });
    };
    const double cNear = 8.0 + 2.0e-5, cFar = 8.0 + 2.5e-5;
    for (int nearFirst = 0; nearFirst < 2; ++nearFirst) {
        const auto nearGrid = planeGrid(cNear), farGrid = planeGrid(cFar);
        SurfaceScene scene("threads=1");
        const int a = scene.add(
            std::make_shared<IsoExactSurface>(nearFirst ? *nearGrid : *farGrid, 0.0, "first"));
        const int b = scene.add(
            std::make_shared<IsoExactSurface>(nearFirst ? *farGrid : *nearGrid, 0.0, "second"));
        scene.commit();
        const int nearId = nearFirst ? a : b;
        std::vector<Ray> rays(8);
        for (int k = 0; k < 8; ++k) {
            rays[size_t(k)].o = Vec3(8.0 - 540.0, 3.3 + 1.1 * k, 6.7 + 0.3 * k);
            rays[size_t(k)].d = Vec3(1, 0, 0);
            rays[size_t(k)].tMax = 545.0;
        }
        const Ray* pointers[8];
        for (int k = 0; k < 8; ++k) pointers[k] = &rays[size_t(k)];
        std::optional<SurfaceHit> got[8];
        scene.intersect8(pointers, 8, got);
        for (int k = 0; k < 8; ++k) {
            ASSERT_TRUE(got[k]) << "lane " << k;
            EXPECT_EQ(got[k]->objectId, nearId) << "lane " << k << ", near added " << nearFirst;
            EXPECT_NEAR(got[k]->t, 540.0 + 2.0e-5, 1e-7) << "lane " << k;
        }
    }
}

TEST(Packets, ClippedOrMaskedScenesAreRefused) {
    const auto a = shellGrid(Vec3(0.0));
    SurfaceScene clipped("threads=1"), masked("threads=1");
    clipped.add(std::make_shared<IsoExactSurface>(*a, 0.0, "a"));
    masked.add(std::make_shared<IsoExactSurface>(*a, 0.0, "a"));
    ClipShape plane;
    plane.kind = ClipShape::Kind::Plane;
    plane.point = kCentre;
    plane.normal = Vec3(0, 1, 0);
    clipped.setClip(0, {plane});
    masked.setMask(0, [](const Vec3& x) { return x.z < kCentre.z; });
    clipped.commit();
    masked.commit();
    EXPECT_FALSE(clipped.packetsSupported());
    EXPECT_FALSE(masked.packetsSupported());
    Ray ray;
    ray.o = kCentre - Vec3(0, 0, 60);
    ray.d = Vec3(0, 0, 1);
    const Ray* pointers[1] = {&ray};
    std::optional<SurfaceHit> out[1];
    EXPECT_THROW(clipped.intersect8(pointers, 1, out), Error);
    EXPECT_THROW(masked.intersect8(pointers, 1, out), Error);
}

}  // namespace
}  // namespace lobe
