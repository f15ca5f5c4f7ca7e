// SurfaceScene::collectHits (one traversal gathering a ray's hits in depth order, surface_scene.h
// "HitList") against the reference it replaces, allHits() (one traversal per hit, each from just
// beyond the last): on concentric shells of sin(ω r) = 0, 1.5 voxels apart, so that one 8³ brick
// holds several roots along a ray and a ray through the centre makes more hits than the list's
// capacity, as an exact iso-surface (user geometry) and a meshed one (built-in geometry, the filter
// path), with and without a clip plane or a mask; the opacity cut (an opaque object ends the list
// at its first hit, a translucent one where the product of transmittances falls below the cut-off).
#include "core/clip.h"
#include "core/rng.h"
#include "surface/iso_exact.h"
#include "surface/iso_mesh.h"
#include "surface/surface_scene.h"
#include "surface_test_grids.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

namespace lobe {
namespace {

using test::makeGrid;

const double kIdentity[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
using test::kShellSpacing;
using test::shellGrid;
const Vec3& kCentre = test::kShellCentre;

class OpenVdbInit : public ::testing::Environment {
public:
    void SetUp() override { openvdb::initialize(); }
};
const auto* const kOpenVdbEnv = ::testing::AddGlobalTestEnvironment(new OpenVdbInit);

ClipShape plane(const Vec3& point, const Vec3& normal) {
    ClipShape c;
    c.kind = ClipShape::Kind::Plane;
    c.point = point;
    c.normal = normal;
    return c;
}

Vec3 randomUnit(Rng& rng) {
    const double z = 2.0 * rng.uniform() - 1.0, phi = 2.0 * kPi * rng.uniform();
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    return Vec3(r * std::cos(phi), r * std::sin(phi), z);
}

// Every hit from collectHits as the integrator consumes them: entries before the running tMin
// passed over, a new traversal from just beyond the last hit when a list was cut short.
std::vector<SurfaceHit> gatheredHits(const SurfaceScene& scene, const Ray& ray,
                                     const std::vector<double>& transmittance, double cutoff,
                                     int* traversals = nullptr) {
    std::vector<SurfaceHit> hits;
    Ray segment = ray;
    HitList list;
    int n = 0;
    for (int guard = 0; guard < 64; ++guard) {
        scene.collectHits(segment, transmittance, cutoff, list);
        ++n;
        for (int i = 0; i < list.count; ++i) {
            if (list.hits[i].t < segment.tMin) continue;
            hits.push_back(scene.shadeHit(segment, list.hits[i]));
            segment.tMin = HitList::nextStart(list.hits[i].t);
        }
        if (list.complete) break;
    }
    if (traversals) *traversals = n;
    return hits;
}

void expectSameHits(const std::vector<SurfaceHit>& got, const std::vector<SurfaceHit>& want,
                    int ray) {
    ASSERT_EQ(got.size(), want.size()) << "ray " << ray;
    for (size_t i = 0; i < got.size(); ++i) {
        EXPECT_NEAR(got[i].t, want[i].t, 1e-7) << "ray " << ray << " hit " << i;
        EXPECT_EQ(got[i].objectId, want[i].objectId) << "ray " << ray << " hit " << i;
        EXPECT_NEAR(got[i].normal.dot(want[i].normal), 1.0, 1e-6) << "ray " << ray;
    }
}

struct ShellScene {
    openvdb::FloatGrid::Ptr a = shellGrid(Vec3(0.0)), b = shellGrid(Vec3(50.0, 0.0, 0.0));
    SurfaceScene scene{"threads=1"};
    explicit ShellScene(bool clip, bool mask = false) {
        scene.add(std::make_shared<IsoExactSurface>(*a, 0.0, "a"));
        scene.add(std::make_shared<IsoMeshSurface>(*b, 0.0, "b"));
        if (mask) {
            // Keep z ≤ centre + 2 of the exact shells and z ≥ centre − 4 of the meshed ones.
            scene.setMask(0, [](const Vec3& x) { return x.z <= kCentre.z + 2.0; });
            scene.setMask(1, [](const Vec3& x) { return x.z >= kCentre.z - 4.0; });
        }
        if (clip) {
            // Keep y ≥ centre + 3 of the exact shells, x ≤ 70 of the meshed ones.
            scene.setClip(0, {plane(kCentre + Vec3(0, 3, 0), Vec3(0, 1, 0))});
            scene.setClip(1, {plane(Vec3(70, 0, 0), Vec3(-1, 0, 0))});
        }
        scene.commit();
    }
};

void compareOnRandomRays(const SurfaceScene& scene, std::uint64_t stream, int minMany) {
    Rng rng(7, stream);
    const std::vector<double> clear = {1.0, 1.0};
    int many = 0, more = 0;
    for (int n = 0; n < 400; ++n) {
        Ray ray;
        // From outside both shell sets, towards a random point near one of the two centres.
        const Vec3 target = kCentre + Vec3(n % 2 ? 50.0 : 0.0, 0, 0) +
                            Vec3(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5) *
                                (n % 4 < 2 ? 2.0 : 30.0);
        ray.o = target - randomUnit(rng) * 60.0;
        ray.d = normalized(target - ray.o);
        const std::vector<SurfaceHit> want = scene.allHits(ray, 200);
        int traversals = 0;
        expectSameHits(gatheredHits(scene, ray, clear, 0.0, &traversals), want, n);
        if (want.size() > size_t(HitList::kCapacity)) {
            ++many;
            EXPECT_GT(traversals, 1);
        }
        if (want.size() > 1) ++more;
        // One traversal whenever the hits fit the list.
        if (want.size() < size_t(HitList::kCapacity)) {
            EXPECT_EQ(traversals, 1) << "ray " << n;
        }
    }
    EXPECT_GT(many, minMany);  // rays through the centres: up to 26 shells each
    EXPECT_GT(more, 300);      // and several hits on most rays
}

TEST(HitList, OneTraversalGivesTheHitsOfOneTraversalPerHit) {
    ShellScene s(false);
    compareOnRandomRays(s.scene, 1, 20);
}

TEST(HitList, ClippedObjectsGiveTheSameHits) {
    ShellScene s(true);
    compareOnRandomRays(s.scene, 2, 5);
}

TEST(HitList, MaskedObjectsGiveTheSameHits) {
    ShellScene s(false, true);
    compareOnRandomRays(s.scene, 3, 5);
}

TEST(HitList, TwoRootsInOneBrickAreBothFound) {
    ShellScene s(false);
    // Along x through the exact shells' centre: shells 1.5 voxels apart, so each 8-cell brick
    // holds 5 or 6 roots; 26 in all (r = 1.5 … 19.5 on either side).
    Ray ray;
    ray.o = Vec3(0.5, kCentre.y, kCentre.z);
    ray.d = Vec3(1, 0, 0);
    ray.tMax = 45.0;
    const std::vector<SurfaceHit> hits = gatheredHits(s.scene, ray, {1.0, 1.0}, 0.0);
    ASSERT_EQ(hits.size(), 26u);
    for (size_t i = 0; i < hits.size(); ++i) {
        const double r = std::abs(hits[i].position.x - kCentre.x);
        // Roots of the trilinear interpolant of sin (3 samples a period): within 0.25 voxel of
        // the true shells.
        EXPECT_NEAR(r, kShellSpacing * std::round(r / kShellSpacing), 0.25);
    }
}

TEST(HitList, OpacityCutEndsTheList) {
    ShellScene s(false);
    Ray ray;
    ray.o = Vec3(0.5, kCentre.y + 0.2, kCentre.z - 0.1);
    ray.d = Vec3(1, 0, 0);
    const std::vector<SurfaceHit> all = s.scene.allHits(ray, 200);
    ASSERT_GT(all.size(), 20u);
    HitList list;
    // Opaque: only the first hit, as intersect() finds it.
    s.scene.collectHits(ray, {0.0, 0.0}, 1e-3, list);
    ASSERT_EQ(list.count, 1);
    EXPECT_FALSE(list.complete);
    const auto first = s.scene.intersect(ray);
    ASSERT_TRUE(first);
    EXPECT_NEAR(list.hits[0].t, first->t, 1e-9);
    // Transmittance 0.5: 0.5³ = 0.125 is the first product below 0.2, at the third hit.
    // The ray runs in the face z = 24 between two bricks, so both find each root: the list holds
    // every hit twice, and the second of each pair (closer than nextStart) does not count.
    s.scene.collectHits(ray, {0.5, 0.5}, 0.2, list);
    std::vector<double> distinct;
    for (int i = 0; i < list.count; ++i)
        if (distinct.empty() || list.hits[i].t >= HitList::nextStart(distinct.back()))
            distinct.push_back(list.hits[i].t);
    EXPECT_EQ(list.count, 5);
    ASSERT_EQ(distinct.size(), 3u);
    EXPECT_FALSE(list.complete);
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(distinct[size_t(i)], all[size_t(i)].t, 1e-7);
    // Clear: the capacity cuts it, the nearest kCapacity hits in order (each twice).
    s.scene.collectHits(ray, {1.0, 1.0}, 1e-3, list);
    ASSERT_EQ(list.count, HitList::kCapacity);
    EXPECT_FALSE(list.complete);
    for (int i = 0; i < HitList::kCapacity; ++i)
        EXPECT_NEAR(list.hits[i].t, all[size_t(i / 2)].t, 1e-7);
    // A ray that ends before the shells: an empty, complete list.
    ray.tMax = 1.0;
    s.scene.collectHits(ray, {1.0, 1.0}, 1e-3, list);
    EXPECT_EQ(list.count, 0);
    EXPECT_TRUE(list.complete);
}

// Two exact iso-surfaces (planes x = c) closer along the ray than one float step of Embree's
// tfar: at t ≈ 540 a float step is 6.1e-5, the planes are 5e-6 apart. The farther one, found
// first, used to set tfar to float(t) rounded to nearest, which can lie before the nearer root,
// and so hid it (rendering 1 lost a skull hit behind a density map this way in one pixel at
// 256² × 2 spp). Both orders of adding the two: one of them has Embree visit the farther first.
TEST(HitList, ARootWithinOneFloatStepOfAnotherIsNotHidden) {
    const int dims[3] = {16, 16, 16};
    const auto planeGrid = [&](double c) {
        return makeGrid(dims, kIdentity, Vec3(0.0), -1.0f, [c](const Vec3& x) { return x.x - c; });
    };
    const double cNear = 8.0 + 2.0e-5, cFar = 8.0 + 2.5e-5;
    Ray ray;
    ray.o = Vec3(8.0 - 540.0, 5.3, 6.7);
    ray.d = Vec3(1, 0, 0);
    ray.tMax = 545.0;  // before the far face of the grids, where x − c meets the background −1
    for (int nearFirst = 0; nearFirst < 2; ++nearFirst) {
        const auto nearGrid = planeGrid(cNear), farGrid = planeGrid(cFar);
        SurfaceScene scene("threads=1");
        const int a = scene.add(std::make_shared<IsoExactSurface>(nearFirst ? *nearGrid : *farGrid,
                                                                  0.0, nearFirst ? "near" : "far"));
        const int b = scene.add(std::make_shared<IsoExactSurface>(nearFirst ? *farGrid : *nearGrid,
                                                                  0.0, nearFirst ? "far" : "near"));
        scene.commit();
        const int nearId = nearFirst ? a : b;
        const auto hit = scene.intersect(ray);
        ASSERT_TRUE(hit);
        EXPECT_EQ(hit->objectId, nearId) << "near plane added " << (nearFirst ? "first" : "second");
        EXPECT_NEAR(hit->t, 540.0 + 2.0e-5, 1e-7);
        HitList list;
        scene.collectHits(ray, {1.0, 1.0}, 0.0, list);
        ASSERT_EQ(list.count, 2);
        EXPECT_NEAR(list.hits[0].t, hit->t, 1e-9);
    }
}

}  // namespace
}  // namespace lobe
