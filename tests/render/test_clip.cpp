// Clipping (core/clip.h) against closed forms: the kept intervals of a ray; a clipped sphere and a
// clipped box (exact, meshed and level-set iso-surfaces: hit distances; caps: distances and
// normals); a clipped emitting slab's composited opacity; empty-space skipping on/off and 1 and 2
// threads identical with clipping.
//
// Set-up (spacing 1, so voxels = world units, voxel (i, j, k) at world (i, j, k)):
//  - Box: a 32³ float grid of zeros with a block of ones at voxels 8…23 in every axis. At iso
//    0.5 the trilinear interpolant crosses 0.5 half-way between a one and a zero, so away from
//    the block's edges its faces are exactly the planes 7.5 and 23.5 (a linear function of one
//    variable on each face cell). The solid (value > 0.5) is [7.5, 23.5]³.
//  - Sphere: a 40³ grid of f = 13 − |x − c|, c = (19.3, 19.6, 19.2); the iso 1 surface is the
//    sphere of radius 12 about c up to the trilinear interpolation of the distance (an error of
//    order h²/(8R) ≈ 0.01 voxel; the tolerance is 0.05). Iso 1, not 0: outside the grid the
//    field reads 0, below the iso like the grid's border, so the border makes no surface.
//  - Slab: the box's grid as a volume whose transfer function is "opacity α per voxel for value
//    > 0.5": inside the block the medium is homogeneous, T = (1 − α)^ℓ over a length ℓ (Max
//    1995, eq. 3; transfer_function.h, opacity per voxel).
#include "core/clip.h"
#include "core/rng.h"
#include "label_test_maps.h"
#include "render/integrator.h"
#include "render/render_scene.h"
#include "render/scene_file.h"
#include "render/shading.h"
#include "surface/iso_exact.h"
#include "surface/iso_levelset.h"
#include "surface/iso_mesh.h"
#include "surface/surface_scene.h"
#include "test_files.h"

#include <gtest/gtest.h>
#include <openvdb/openvdb.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace lobe {
namespace {

namespace fs = std::filesystem;

const Vec3 kCentre(19.3, 19.6, 19.2);
constexpr double kRadius = 12.0;

float boxValue(int i, int j, int k) {
    auto in = [](int x) { return x >= 8 && x <= 23; };
    return in(i) && in(j) && in(k) ? 1.0f : 0.0f;
}
float sphereValue(int i, int j, int k) {
    return float(kRadius + 1.0 - (Vec3(i, j, k) - kCentre).length());
}

fs::path dataDir() {
    static const fs::path dir = [] {
        const fs::path d = fs::temp_directory_path() / ("lobe_clip_" + std::to_string(getpid()));
        fs::create_directories(d);
        std::vector<float> box(32 * 32 * 32), sphere(40 * 40 * 40);
        for (int k = 0; k < 32; ++k)
            for (int j = 0; j < 32; ++j)
                for (int i = 0; i < 32; ++i) box[(k * 32 + j) * 32 + i] = boxValue(i, j, k);
        for (int k = 0; k < 40; ++k)
            for (int j = 0; j < 40; ++j)
                for (int i = 0; i < 40; ++i) sphere[(k * 40 + j) * 40 + i] = sphereValue(i, j, k);
        test::writeFloatsAtomically(d / "box.raw", box);
        test::writeFloatsAtomically(d / "sphere.raw", sphere);
        return d;
    }();
    return dir;
}

openvdb::FloatGrid::Ptr gridOf(int n, float (*value)(int, int, int), float background) {
    openvdb::initialize();
    auto grid = openvdb::FloatGrid::create(background);
    auto acc = grid->getAccessor();
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) acc.setValue(openvdb::Coord(i, j, k), value(i, j, k));
    return grid;
}

ClipShape plane(const Vec3& p, const Vec3& n, bool invert = false, bool cap = false) {
    ClipShape s;
    s.kind = ClipShape::Kind::Plane;
    s.point = p;
    s.normal = normalized(n);
    s.invert = invert;
    s.cap = cap;
    return s;
}
ClipShape box(const Vec3& lo, const Vec3& hi, bool invert = false, bool cap = false) {
    ClipShape s;
    s.kind = ClipShape::Kind::Box;
    s.lo = lo;
    s.hi = hi;
    s.invert = invert;
    s.cap = cap;
    return s;
}

Ray rayOf(const Vec3& o, const Vec3& d) {
    Ray r;
    r.o = o;
    r.d = normalized(d);
    return r;
}

// --- The kept intervals -------------------------------------------------------------------

TEST(Clip, IntervalsOfPlanesAndBoxesByHand) {
    const Ray r = rayOf(Vec3(0, 0, 0), Vec3(1, 0, 0));
    // Keep x ≥ 5: [5, ∞), the bound made by the plane with outward normal −x.
    ClipIntervals iv = clipRay(r, {plane(Vec3(5, 1, 2), Vec3(1, 0, 0))});
    ASSERT_EQ(iv.count, 1);
    EXPECT_DOUBLE_EQ(iv.v[0].lo.t, 5.0);
    EXPECT_TRUE(iv.v[0].lo.clipped);
    EXPECT_FALSE(iv.v[0].hi.clipped);
    EXPECT_EQ(iv.v[0].lo.normal, Vec3(-1, 0, 0));
    // Inverted: keep x ≤ 5.
    iv = clipRay(r, {plane(Vec3(5, 1, 2), Vec3(1, 0, 0), true)});
    ASSERT_EQ(iv.count, 1);
    EXPECT_DOUBLE_EQ(iv.v[0].lo.t, 0.0);
    EXPECT_DOUBLE_EQ(iv.v[0].hi.t, 5.0);
    EXPECT_EQ(iv.v[0].hi.normal, Vec3(1, 0, 0));
    // A tilted plane x + y = 8 through (4, 4, 0) met at x = 8 by the ray along +x (y = 0).
    iv = clipRay(r, {plane(Vec3(4, 4, 0), Vec3(1, 1, 0))});
    ASSERT_EQ(iv.count, 1);
    EXPECT_NEAR(iv.v[0].lo.t, 8.0, 1e-12);
    // Box [2, 6] × [−1, 1]²: inside [2, 6]; inverted [0, 2] ∪ [6, ∞) with normals into the box.
    iv = clipRay(r, {box(Vec3(2, -1, -1), Vec3(6, 1, 1))});
    ASSERT_EQ(iv.count, 1);
    EXPECT_DOUBLE_EQ(iv.v[0].lo.t, 2.0);
    EXPECT_DOUBLE_EQ(iv.v[0].hi.t, 6.0);
    EXPECT_EQ(iv.v[0].lo.normal, Vec3(-1, 0, 0));
    EXPECT_EQ(iv.v[0].hi.normal, Vec3(1, 0, 0));
    iv = clipRay(r, {box(Vec3(2, -1, -1), Vec3(6, 1, 1), true)});
    ASSERT_EQ(iv.count, 2);
    EXPECT_DOUBLE_EQ(iv.v[0].hi.t, 2.0);
    EXPECT_EQ(iv.v[0].hi.normal, Vec3(1, 0, 0));
    EXPECT_DOUBLE_EQ(iv.v[1].lo.t, 6.0);
    EXPECT_EQ(iv.v[1].lo.normal, Vec3(-1, 0, 0));
    // The intersection of both lists: the cut-away box and the plane x ≥ 5 leave [6, ∞).
    iv = clipRay(r,
                 {box(Vec3(2, -1, -1), Vec3(6, 1, 1), true), plane(Vec3(5, 0, 0), Vec3(1, 0, 0))});
    ASSERT_EQ(iv.count, 1);
    EXPECT_DOUBLE_EQ(iv.v[0].lo.t, 6.0);
    // A box the ray misses, kept inside: nothing.
    EXPECT_TRUE(clipRay(r, {box(Vec3(2, 3, -1), Vec3(6, 4, 1))}).empty());
    // clipBox: the box [0, 10]³ cut by x + y ≥ 10 keeps the prism whose box is [0, 10]³ still;
    // by x ≥ 4 it is [4, 10] × [0, 10]²; by a kept box it is the intersection.
    Vec3 lo(0.0), hi(10.0);
    clipBox({plane(Vec3(4, 0, 0), Vec3(1, 0, 0))}, lo, hi);
    EXPECT_EQ(lo, Vec3(4, 0, 0));
    EXPECT_EQ(hi, Vec3(10, 10, 10));
    clipBox({plane(Vec3(0, 0, 2), Vec3(0, 0, -1)), box(Vec3(-5, 1, -5), Vec3(8, 20, 20))}, lo, hi);
    EXPECT_EQ(lo, Vec3(4, 1, 0));
    EXPECT_EQ(hi, Vec3(8, 10, 2));
}

// --- Clipped surfaces: hit distances -----------------------------------------------------

// The first hit of `ray` on a scene of one object, clipped by `shapes`; -1 when none.
double firstHit(const std::shared_ptr<const SurfaceGeometry>& g,
                const std::vector<ClipShape>& shapes, const Ray& ray) {
    SurfaceScene scene;
    const int id = scene.add(g);
    scene.setClip(id, shapes);
    scene.commit();
    const auto hit = scene.intersect(ray);
    EXPECT_EQ(scene.occluded(ray), bool(hit));
    return hit ? hit->t : -1.0;
}

TEST(Clip, ClippedSphereHitsTheKeptPartOnly) {
    const auto grid = gridOf(40, sphereValue, 0.0f);
    const std::vector<std::shared_ptr<const SurfaceGeometry>> methods = {
        std::make_shared<IsoExactSurface>(*grid, 1.0, "sphere"),
        std::make_shared<IsoMeshSurface>(*grid, 1.0, "sphere"),
    };
    // A ray along +x through the centre from x = −10: the sphere at t = 10 + c.x ∓ R.
    const Ray ray = rayOf(Vec3(-10, kCentre.y, kCentre.z), Vec3(1, 0, 0));
    const double front = 10 + kCentre.x - kRadius, back = 10 + kCentre.x + kRadius;
    // The mesh is a polygon of the surface: chords up to ~0.1 voxel from it where rays graze.
    const std::vector<double> grazing = {0.05, 0.1};
    for (size_t m = 0; m < methods.size(); ++m) {
        SCOPED_TRACE("method " + std::to_string(m));
        EXPECT_NEAR(firstHit(methods[m], {}, ray), front, 0.05);
        // Keep x ≥ c.x: the front half is cut away, the first hit is the back of the sphere.
        EXPECT_NEAR(firstHit(methods[m], {plane(kCentre, Vec3(1, 0, 0))}, ray), back, 0.05);
        // Keep x ≤ c.x (inverted): the front stays.
        EXPECT_NEAR(firstHit(methods[m], {plane(kCentre, Vec3(1, 0, 0), true)}, ray), front, 0.05);
        // A cut-away box around the whole sphere: nothing is hit.
        EXPECT_EQ(firstHit(methods[m], {box(Vec3(0.0), Vec3(40.0), true)}, ray), -1.0);
        // A tilted plane: keep n·(x − p) ≥ 0 with n ∝ (1, 1, 0) through p = c + (3, 0, 0). Along
        // the ray (y = c.y) the plane is met at x = c.x + 3: the first sphere point kept is
        // the back one at x = c.x + R.
        EXPECT_NEAR(firstHit(methods[m], {plane(kCentre + Vec3(3, 0, 0), Vec3(1, 1, 0))}, ray),
                    back, 0.05);
        // Off-centre rays: at height h the sphere spans x = c.x ± √(R² − h²); a plane at
        // x = c.x + 5 keeps the back hit only when √(R² − h²) > 5, i.e. h < √119 ≈ 10.9.
        for (const double h : {0.0, 6.0, 10.0, 11.5}) {
            const Ray r = rayOf(Vec3(-10, kCentre.y + h, kCentre.z), Vec3(1, 0, 0));
            const double half = std::sqrt(kRadius * kRadius - h * h);
            const double got =
                firstHit(methods[m], {plane(kCentre + Vec3(5, 0, 0), Vec3(1, 0, 0))}, r);
            if (half > 5.0 + 0.1)
                EXPECT_NEAR(got, 10 + kCentre.x + half, grazing[m]) << "h = " << h;
            else
                EXPECT_EQ(got, -1.0) << "h = " << h;
        }
    }
}

TEST(Clip, ClippedBoxHitsByClosedForm) {
    const auto grid = gridOf(32, boxValue, 0.0f);
    const std::vector<std::shared_ptr<const SurfaceGeometry>> methods = {
        std::make_shared<IsoExactSurface>(*grid, 0.5, "box"),
        std::make_shared<IsoMeshSurface>(*grid, 0.5, "box"),
        LevelSetSurface::fromDensity(*grid, 0.5, LevelSetOptions{}, "box"),
    };
    const std::vector<double> tolerance = {1e-6, 1e-4, 0.1};  // level set: a rebuilt surface
    // A ray along +x at y = 12.2, z = 14.7 (away from edges): faces at x = 7.5 and 23.5.
    const Ray ray = rayOf(Vec3(0, 12.2, 14.7), Vec3(1, 0, 0));
    for (size_t m = 0; m < methods.size(); ++m) {
        SCOPED_TRACE("method " + std::to_string(m));
        EXPECT_NEAR(firstHit(methods[m], {}, ray), 7.5, tolerance[m]);
        // A cut-away box over the block's front (x ≤ 15): the first face kept is the back one.
        EXPECT_NEAR(firstHit(methods[m], {box(Vec3(0, 0, 0), Vec3(15, 32, 32), true)}, ray), 23.5,
                    tolerance[m]);
        // A kept box x ∈ [10, 40]: the same.
        EXPECT_NEAR(firstHit(methods[m], {box(Vec3(10, 0, 0), Vec3(40, 32, 32))}, ray), 23.5,
                    tolerance[m]);
        // A kept box that ends before the back face: nothing.
        EXPECT_EQ(firstHit(methods[m], {box(Vec3(10, 0, 0), Vec3(20, 32, 32))}, ray), -1.0);
    }
}

// --- Caps: the cut face through the integrator ------------------------------------------

struct Recorder : EventSink {
    struct Event {
        int object;
        double t;
        Vec3 normal;
    };
    std::vector<Event> events;
    void onEvent(const ShadingEvent& e) override {
        if (e.object == ShadingEvent::kBackdrop || !e.point) return;
        events.push_back({e.object, e.t, e.point->frame.n});
    }
};

std::string sceneText(const std::string& objects, const std::string& extra = "",
                      const std::string& volume = "") {
    return R"({"image": {"width": 12, "height": 10, "samples_per_pixel": 2},
               "camera": {"position": [-40, 15.3, 15.6], "target": [16, 15.3, 15.6],
                          "up": [0, 0, 1], "fov_deg": 40},
               "lights": [{"position": [-60, 30, 40], "intensity": 3000}],
               "backdrop": {"enabled": false},
               "volume": {"step_voxels": 0.1, "shading_roulette": 0, "termination_transmittance": 0)" +
           volume + R"(}, )" + extra + R"("objects": [)" + objects + "]}";
}

std::string boxSurface(const std::string& clip = "", double opacity = 1.0) {
    return R"({"kind": "isosurface", "source": {"path": "box.raw", "dims": [32, 32, 32],
               "type": "float32"}, "iso": 0.5, "opacity": )" +
           std::to_string(opacity) + R"(, "brdf": {"model": "lambert"}, "kd": 0.7)" +
           (clip.empty() ? "" : ", \"clip\": " + clip) + "}";
}

std::vector<Recorder::Event> eventsOf(const SceneSpec& spec, const Ray& ray) {
    Scene scene(spec, false);
    Integrator integrator(scene);
    TraceState st = integrator.newState();
    Rng rng(1);
    RenderStats stats;
    Recorder rec;
    integrator.trace(ray, 0.5, rng, st, stats, &rec);
    return rec.events;
}

SceneSpec parse(const std::string& text) {
    return parseScene(text, dataDir().string(), "clip.json");
}

TEST(Clip, CapsCloseTheCutSolidWithTheBoundaryNormal) {
    // The solid [7.5, 23.5]³ cut by the plane x = 12 keeping x ≥ 12, with a cap: a ray along +x
    // at (y, z) = (12.2, 14.7) meets the cap at x = 12 (t = 12) with normal −x (out of the kept
    // solid, into the cut-away side), then the back face at x = 23.5 (normal +x).
    const Ray ray = rayOf(Vec3(0, 12.2, 14.7), Vec3(1, 0, 0));
    const std::string cap =
        R"([{"plane": {"point": [12, 0, 0], "normal": [1, 0, 0]}, "cap": true}])";
    auto ev = eventsOf(parse(sceneText(boxSurface(cap, 0.5))), ray);
    ASSERT_EQ(ev.size(), 2u);
    EXPECT_NEAR(ev[0].t, 12.0, 1e-12);
    // Shading frames face the viewer (two-sided): the cap's normal −x already does.
    EXPECT_NEAR(ev[0].normal.x, -1.0, 1e-12);
    EXPECT_NEAR(ev[1].t, 23.5, 1e-6);
    // Without "cap" the cut is open: the back face only.
    const std::string open = R"([{"plane": {"point": [12, 0, 0], "normal": [1, 0, 0]}}])";
    ev = eventsOf(parse(sceneText(boxSurface(open, 0.5))), ray);
    ASSERT_EQ(ev.size(), 1u);
    EXPECT_NEAR(ev[0].t, 23.5, 1e-6);
    // A ray that misses the solid (z = 28) crosses the plane outside it: no cap.
    ev = eventsOf(parse(sceneText(boxSurface(cap, 0.5))), rayOf(Vec3(0, 12.2, 28), Vec3(1, 0, 0)));
    EXPECT_TRUE(ev.empty());
    // A cut-away corner box (x ≤ 16, y ≤ 16 removed, scene-wide) seen along +y at x = 10,
    // z = 14.7: the ray leaves the removed box at y = 16 inside the solid: a cap there with
    // the normal −y (into the box), then the back face at y = 23.5.
    const std::string corner =
        R"("clip": [{"box": {"min": [-1, -1, -1], "max": [16, 16, 40]}, "invert": true, "cap": true}],)";
    ev = eventsOf(parse(sceneText(boxSurface("", 0.5), corner)),
                  rayOf(Vec3(10, 0, 14.7), Vec3(0, 1, 0)));
    ASSERT_EQ(ev.size(), 2u);
    EXPECT_NEAR(ev[0].t, 16.0, 1e-12);
    EXPECT_NEAR(ev[0].normal.y, -1.0, 1e-12);
    EXPECT_NEAR(ev[1].t, 23.5, 1e-6);
    // A tilted capped plane through the sphere: the cap's normal is −n and its distance the
    // plane's, t = n·(p − o) / n·d.
    const Vec3 n = normalized(Vec3(2, 1, -1));
    char sphere[640];
    std::snprintf(sphere, sizeof sphere,
                  R"({"kind": "isosurface", "source": {"path": "sphere.raw", "dims": [40, 40, 40],
                      "type": "float32"}, "iso": 1, "brdf": {"model": "lambert"},
                      "clip": [{"plane": {"point": [%.17g, %.17g, %.17g], "normal": [2, 1, -1]},
                                "cap": true}]})",
                  kCentre.x, kCentre.y, kCentre.z);
    const Ray r2 = rayOf(Vec3(-5, kCentre.y + 1, kCentre.z - 2), Vec3(1, 0.1, 0.05));
    ev = eventsOf(parse(sceneText(sphere)), r2);
    ASSERT_GE(ev.size(), 1u);
    EXPECT_NEAR(ev[0].t, n.dot(kCentre - r2.o) / n.dot(r2.d), 1e-9);
    EXPECT_NEAR((ev[0].normal + n).length(), 0.0, 1e-12);
}

// --- Clipped volume -----------------------------------------------------------------------

std::string slab(double alpha, const std::string& clip = "") {
    return R"({"kind": "volume", "source": {"path": "box.raw", "dims": [32, 32, 32],
               "type": "float32"}, "transfer_function": {"points": [{"value": 0.5, "opacity": 0},
               {"value": 0.5, "opacity": )" +
           std::to_string(alpha) +
           R"(, "color": [1, 1, 1]}]}, "brdf": {"model": "lambert"}, "kd": 0.5)" +
           (clip.empty() ? "" : ", \"clip\": " + clip) + "}";
}

// Composited opacity 1 − T along a ray: the sum of T·α over the events.
double opacityAlong(const SceneSpec& spec, const Ray& ray, double jitter) {
    Scene scene(spec, false);
    Integrator integrator(scene);
    TraceState st = integrator.newState();
    Rng rng(1);
    RenderStats stats;
    struct Sum : EventSink {
        double opacity = 0.0;
        void onEvent(const ShadingEvent& e) override { opacity += e.transmittanceBefore * e.alpha; }
    } sum;
    integrator.trace(ray, jitter, rng, st, stats, &sum);
    return sum.opacity;
}

TEST(Clip, ClippedSlabOpacityFollowsTheClippedLength) {
    // Along +x at (12.2, 14.7) the medium fills x ∈ [7.5, 23.5] (16 voxels). Clipped by the
    // plane x ≥ 12.25 it fills [12.25, 23.5], 11.25 voxels; a cut-away box x ∈ [14, 18] leaves
    // [7.5, 14] ∪ [18, 23.5], 12 voxels. Opacity 1 − (1 − α)^ℓ. At step 0.1 the Riemann sum
    // counts the lattice points in each interval: at most one step (0.1 voxel) off per
    // interval end, |Δ(1 − T)| ≤ σ T · 0.1 per end, σ = −ln(1 − α); the tolerance is two ends.
    const double alpha = 0.08, sigma = -std::log(1 - alpha);
    const Ray ray = rayOf(Vec3(0, 12.2, 14.7), Vec3(1, 0, 0));
    const auto want = [&](double length) { return 1.0 - std::pow(1.0 - alpha, length); };
    const std::string half = R"([{"plane": {"point": [12.25, 0, 0], "normal": [1, 0, 0]}}])";
    const std::string hole =
        R"([{"box": {"min": [14, 0, 0], "max": [18, 32, 32]}, "invert": true}])";
    for (const double jitter : {0.1, 0.5, 0.93}) {
        SCOPED_TRACE("jitter " + std::to_string(jitter));
        EXPECT_NEAR(opacityAlong(parse(sceneText(slab(alpha))), ray, jitter), want(16.0),
                    2 * sigma * 0.1 * (1 - want(16.0)) + 0.02 * sigma);
        EXPECT_NEAR(opacityAlong(parse(sceneText(slab(alpha, half))), ray, jitter), want(11.25),
                    2 * sigma * 0.1);
        // Interval [7.5, 14] has T_front = (1−α)^6.5, the second adds (1−α)^6.5 · (1 − (1−α)^5.5).
        EXPECT_NEAR(opacityAlong(parse(sceneText(slab(alpha, hole))), ray, jitter), want(12.0),
                    4 * sigma * 0.1);
        // The same cut given scene-wide.
        EXPECT_NEAR(
            opacityAlong(parse(sceneText(slab(alpha), R"("clip": )" + hole + ",")), ray, jitter),
            want(12.0), 4 * sigma * 0.1);
    }
    // The lengths differ by far more than the tolerances: an unclipped march fails both.
    EXPECT_GT(want(16.0) - want(12.0), 3 * 4 * sigma * 0.1);
}

// --- Renders: skipping on/off, 1 and 2 threads -------------------------------------------

Film renderOf(const SceneSpec& spec, int threads) {
    const RenderScene scene(spec, false);
    RenderOptions o;
    o.threads = threads;
    o.progress = false;
    return scene.render(o);
}

TEST(Clip, SkippingAndThreadsDoNotChangeAClippedRender) {
    const std::string clip =
        R"("clip": [{"box": {"min": [-1, -1, 14], "max": [16, 40, 40]}, "invert": true, "cap": true},
                    {"plane": {"point": [0, 0, 9], "normal": [0, 0.2, 1]}}],)";
    const std::string objects =
        slab(0.05) + "," +
        boxSurface(R"([{"plane": {"point": [20, 0, 0], "normal": [-1, 0, 0]}, "cap": true}])", 0.4);
    const SceneSpec on = parse(sceneText(objects, clip));
    const SceneSpec off = parse(sceneText(objects, clip, R"(, "empty_space_skipping": false)"));
    const Film a = renderOf(on, 1), b = renderOf(on, 2), c = renderOf(off, 2);
    const SceneSpec unclipped = parse(sceneText(objects));
    const Film d = renderOf(unclipped, 2);
    double diffSkip = 0.0, diffClip = 0.0;
    for (size_t i = 0; i < a.pixels().size(); ++i)
        for (int k = 0; k < kBandCount; ++k) {
            EXPECT_EQ(a.pixels()[i][k], b.pixels()[i][k]) << "pixel " << i;
            diffSkip = std::max(diffSkip, std::abs(a.pixels()[i][k] - c.pixels()[i][k]));
            diffClip = std::max(diffClip, std::abs(a.pixels()[i][k] - d.pixels()[i][k]));
        }
    EXPECT_LT(diffSkip, 1e-9);
    EXPECT_GT(diffClip, 1e-3);  // the clip changes the image
}

TEST(Clip, SceneFileErrorsNameTheKey) {
    auto error = [](const std::string& clip) {
        try {
            parse(sceneText(slab(0.1), R"("clip": )" + clip + ","));
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    EXPECT_NE(error(R"([{"plane": {"point": [0, 0, 0], "normal": [0, 0, 0]}}])")
                  .find("clip[0].plane.normal"),
              std::string::npos);
    EXPECT_NE(error(R"([{"box": {"min": [1, 0, 0], "max": [0, 1, 1]}}])").find("min < max"),
              std::string::npos);
    EXPECT_NE(error(R"([{"plane": {"point": [0, 0, 0], "normal": [0, 0, 1]}, "box": {}}])")
                  .find("exactly one of plane or box"),
              std::string::npos);
    EXPECT_NE(error(R"({"plane": {}})").find("expected an array"), std::string::npos);
    EXPECT_NE(error(R"([{"plane": {"point": [0, 0, 0], "normal": [0, 0, 1]}, "invrt": true}])")
                  .find("unknown key"),
              std::string::npos);
}

// --- Masks (volume/volume_mask.h) ----------------------------------------------------------
//
// The mask is the sphere grid at iso 1: the ball of radius 12 about c (up to its interpolation,
// ~0.02 voxel). Along +x at (y, z) = (12.2, 14.7) the ball spans x = c.x ± √(144 − 54.76 − 20.25)
// = 19.3 ± 8.306; the block [7.5, 23.5] therefore keeps x ∈ [10.994, 23.5] inside the mask,
// [7.5, 10.994] outside it.

// The synthetic label map (tests/render/label_test_maps.h), under this process's own name.
std::string labelMap() {
    static const std::string path =
        test::writeSyntheticMap("clip-mask-" + std::to_string(getpid()) + ".nii");
    return path;
}
const std::string kTable = R"({"1": "Left", "2": "Ball", "3": "Right", "4": "Cube"})";

const std::string kMask = R"("mask": {"source": {"path": "sphere.raw", "dims": [40, 40, 40],
                                                 "type": "float32"}, "iso": 1)";

TEST(Mask, SurfacesKeepTheHitsInsideTheMask) {
    const Ray ray = rayOf(Vec3(0, 12.2, 14.7), Vec3(1, 0, 0));
    auto surface = [](const std::string& mask) {
        return R"({"kind": "isosurface", "source": {"path": "box.raw", "dims": [32, 32, 32],
                   "type": "float32"}, "iso": 0.5, "opacity": 0.5, "brdf": {"model": "lambert"}, )" +
               mask + "}";
    };
    // The front face (x = 7.5) lies outside the ball, the back face (x = 23.5) inside.
    auto ev = eventsOf(parse(sceneText(surface(kMask + "}"))), ray);
    ASSERT_EQ(ev.size(), 1u);
    EXPECT_NEAR(ev[0].t, 23.5, 1e-6);
    ev = eventsOf(parse(sceneText(surface(kMask + R"(, "invert": true})"))), ray);
    ASSERT_EQ(ev.size(), 1u);
    EXPECT_NEAR(ev[0].t, 7.5, 1e-6);
    ev = eventsOf(parse(sceneText(surface(R"("name": "plain")"))), ray);
    EXPECT_EQ(ev.size(), 2u);
}

TEST(Mask, VolumesKeepTheSamplesInsideTheMask) {
    const double alpha = 0.08, sigma = -std::log(1 - alpha);
    const Ray ray = rayOf(Vec3(0, 12.2, 14.7), Vec3(1, 0, 0));
    const double enter = kCentre.x - std::sqrt(144 - 7.4 * 7.4 - 4.5 * 4.5);
    const auto want = [&](double length) { return 1.0 - std::pow(1.0 - alpha, length); };
    auto masked = [&](const std::string& mask) {
        std::string o = slab(alpha);
        o.insert(o.size() - 1, ", " + mask);
        return o;
    };
    for (const double jitter : {0.2, 0.7}) {
        EXPECT_NEAR(opacityAlong(parse(sceneText(masked(kMask + "}"))), ray, jitter),
                    want(23.5 - enter), 2 * sigma * 0.1 + 0.05 * sigma);
        EXPECT_NEAR(
            opacityAlong(parse(sceneText(masked(kMask + R"(, "invert": true})"))), ray, jitter),
            want(enter - 7.5), 2 * sigma * 0.1 + 0.05 * sigma);
    }
    // Skipping on/off and 1/2 threads with a mask.
    const SceneSpec on = parse(sceneText(masked(kMask + "}")));
    const SceneSpec off =
        parse(sceneText(masked(kMask + "}"), "", R"(, "empty_space_skipping": false)"));
    const Film a = renderOf(on, 1), b = renderOf(on, 2), c = renderOf(off, 2);
    for (size_t i = 0; i < a.pixels().size(); ++i)
        for (int k = 0; k < kBandCount; ++k) {
            EXPECT_EQ(a.pixels()[i][k], b.pixels()[i][k]);
            EXPECT_NEAR(a.pixels()[i][k], c.pixels()[i][k], 1e-9);
        }
}

TEST(Mask, ErrorsNameTheKey) {
    auto error = [](const std::string& mask) {
        try {
            std::string o = slab(0.1);
            o.insert(o.size() - 1, ", \"mask\": " + mask);
            parse(sceneText(o));
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    EXPECT_NE(error(R"({"iso": 1})").find("objects[0].mask.source: missing"), std::string::npos);
    EXPECT_NE(
        error(R"({"source": {"path": "sphere.raw", "dims": [40, 40, 40], "type": "float32"}})")
            .find("objects[0].mask.iso: missing"),
        std::string::npos);
    // Label sets: a label map, names from its table, no iso, the labels in the mask's own key.
    const std::string map = labelMap();
    const std::string src =
        R"("source": {"path": ")" + map + R"(", "label_table": )" + kTable + "}";
    EXPECT_EQ(error("{" + src + R"(, "labels": ["Ball", 4]})"), "");
    EXPECT_NE(error(R"({"source": {"path": "sphere.raw", "dims": [40, 40, 40], "type": "float32"},
                        "labels": [3]})")
                  .find("objects[0].mask.source.dims: not with labels"),
              std::string::npos);
    EXPECT_NE(error("{" + src + R"(, "labels": [2], "iso": 0.5})")
                  .find("objects[0].mask.iso: not with labels"),
              std::string::npos);
    EXPECT_NE(error("{" + src + R"(, "labels": ["Bal"]})").find("objects[0].mask.labels"),
              std::string::npos);
    EXPECT_NE(error("{" + src + R"(, "labels": ["Bal"]})").find("Ball"), std::string::npos);
    EXPECT_NE(error(R"({"source": {"path": ")" + map + R"(", "labels": [2]}, "iso": 0.5})")
                  .find("objects[0].mask.source.labels: a mask lists its labels"),
              std::string::npos);
}

// A label set of a label map as the mask (tests/render/label_test_maps.h: label 1 "Left" fills
// x < 11.5 and 2 "Ball" a ball of radius 5 about (12, 12, 12) inside the box [1.5, 21.5]³, 3
// "Right" the rest of that box, 4 "Cube" the voxels 22…27, i.e. [21.5, 27.5]³). The set's mask is
// its smoothed indicator's 0.5 level (σ 0.6 voxel: within half a voxel of the voxel cubes).
// The box surface's faces x = 7.5 and 23.5 are hit along +x:
//  - at (y, z) = (12.2, 12.3), x = 7.5 lies inside Left ∪ Ball (≥ 3 voxels from that union's
//    boundary at x = 1.5 and from its other labels' side), x = 23.5 outside every label but 0;
//    Right holds neither point.
//  - at (y, z) = (22.5, 22.6), x = 23.5 lies in the Cube (1 voxel from two of its faces, 2 from the
//    third: the smoothed corner value Φ(1/0.6)² Φ(2/0.6) ≈ 0.9 > 0.5), x = 7.5 in label 0.
TEST(Mask, LabelSetsOfALabelMapKeepTheirInside) {
    const std::string map = labelMap();
    auto surface = [&](const std::string& labels, bool invert) {
        return R"({"kind": "isosurface", "source": {"path": "box.raw", "dims": [32, 32, 32],
                   "type": "float32"}, "iso": 0.5, "opacity": 0.5, "brdf": {"model": "lambert"},
                   "mask": {"source": {"path": ")" +
               map + R"(", "label_table": )" + kTable + R"(}, "labels": )" + labels +
               R"(, "invert": )" + (invert ? "true" : "false") + "}}";
    };
    auto hits = [&](const std::string& labels, bool invert, const Ray& ray) {
        std::vector<double> t;
        for (const auto& e : eventsOf(parse(sceneText(surface(labels, invert))), ray))
            t.push_back(e.t);
        return t;
    };
    const Ray a = rayOf(Vec3(0, 12.2, 12.3), Vec3(1, 0, 0));
    const Ray b = rayOf(Vec3(0, 22.5, 22.6), Vec3(1, 0, 0));
    using T = std::vector<double>;
    auto near = [](const T& got, const T& want) {
        if (got.size() != want.size()) return false;
        for (size_t i = 0; i < got.size(); ++i)
            if (std::abs(got[i] - want[i]) > 1e-6) return false;
        return true;
    };
    EXPECT_TRUE(near(hits(R"(["Left", "Ball"])", false, a), T{7.5}));
    EXPECT_TRUE(near(hits(R"([1, 2])", true, a), T{23.5}));
    EXPECT_TRUE(near(hits(R"(["Right"])", false, a), T{}));
    EXPECT_TRUE(near(hits(R"(["Right"])", true, a), T{7.5, 23.5}));
    EXPECT_TRUE(near(hits(R"(["Cube"])", false, b), T{23.5}));
    EXPECT_TRUE(near(hits(R"(["Cube"])", true, b), T{7.5}));
}

}  // namespace
}  // namespace lobe
