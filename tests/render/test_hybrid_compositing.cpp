// The hybrid integrator (render/render_scene.h) against closed forms: a tilted translucent
// plane inside, in front of and behind an emitting/absorbing slab; two overlapping slabs of
// different extinction and colour; the skull's 0.97 opacity; thread-count invariance of render().
// (tests/render/test_hybrid.cpp covers level planes with equal-extinction slabs; these cases add
// a tilted surface with cos θ ≠ 1, coloured surface and media, unequal extinctions in the
// overlap, whole renders, and the empty_space_skipping scene key.)
//
// Set-up shared by all cases (every length in voxels; spacing 1, so voxels = world units):
//  - Camera ray straight down −z through (x, y) = (1.5, 1.5) from z = 200.
//  - One point light at (1.5, 1.5, 10⁶) of intensity 10¹², so the irradiance factor at height z
//    is E(z) = I / d² = 1 / (1 − 10⁻⁶ z)² (≈ 1, varying by < 1e-4 over the slabs) and the light
//    comes from +z at every point the ray meets.
//  - Slab: a 4×4×40 float raw grid of ones. With the step transfer function "opacity α for value
//    > 0.5" the trilinear value crosses 0.5 half a voxel beyond the outer voxel centres, so the
//    slab fills z ∈ [dz − 0.5, dz + 39.5] (dz: the object's translation). A sample has colour c,
//    and (gradient zero inside; ±z at the faces, where the light is straight above) its
//    radiance is L_v = c · kd_v/π · E(z)  (Lambert with cos θ = 1; materials/material.h,
//    volume/volume_marcher.h "Normals"). Per voxel length the extinction is σ = −ln(1 − α)
//    (transfer_function.h: opacity per voxel, corrected for the step). A homogeneous segment
//    of length ℓ therefore sends L_v (1 − e^{−σℓ}) and transmits T = e^{−σℓ} = (1 − α)^ℓ
//    (Max 1995, eq. 3 with constant source and extinction).
//  - Tilted plane: a 4×4×360 ramp f(i, j, k) = k + 0.75 i + 1 placed at z = k − 120 (f ≥ 1
//    everywhere, so the only iso crossing for iso > 1 on the ray is the plane; the grid's top
//    end is above the camera). Trilinear is exact for a linear field: at x = 1.5 the plane
//    f = iso lies at z_p = iso − 120 − 2.125. Its normal is ∝ (0.75, 0, 1), so with the light
//    straight above cos θ = 1/√(1 + 0.75²) = 0.8 and a Lambert surface of colour c_s sends
//    L_s = c_s · kd_s/π · 0.8 · E(z_p); composited with opacity o (Porter & Duff "over").
#include "render/render_scene.h"
#include "render/scene_file.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

namespace lobe {
namespace {

namespace fs = std::filesystem;

constexpr double kSlope = 0.75;  // the ramp's slope in x: cos θ = 1/√(1 + kSlope²) = 0.8
constexpr double kCosPlane = 0.8;
constexpr double kRampBase = -120;  // world z of the ramp's first voxel layer

double irradiance(double z) {  // E(z) = I / d² for the light at height 10⁶ of intensity 10¹²
    const double d = 1e6 - z;
    return 1e12 / (d * d);
}

fs::path dataDir() {
    static const fs::path dir = [] {
        const fs::path d =
            fs::temp_directory_path() / ("lobe_hybrid_compositing_" + std::to_string(getpid()));
        fs::create_directories(d);
        std::vector<float> slab(4 * 4 * 40, 1.0f), ramp(4 * 4 * 360);
        for (int k = 0; k < 360; ++k)
            for (int j = 0; j < 4; ++j)
                for (int i = 0; i < 4; ++i)
                    ramp[(k * 4 + j) * 4 + i] = float(k + kSlope * i + 1.0);  // exact in float
        // A 24³ box of value 0.1 (stored, active, transparent under the slab's transfer
        // function) with a 4³ block of ones at voxels 10…13: bricks to skip around the block.
        std::vector<float> box(24 * 24 * 24, 0.1f);
        for (int k = 10; k < 14; ++k)
            for (int j = 10; j < 14; ++j)
                for (int i = 10; i < 14; ++i) box[(k * 24 + j) * 24 + i] = 1.0f;
        std::ofstream(d / "box.raw", std::ios::binary)
            .write(reinterpret_cast<const char*>(box.data()), std::streamsize(box.size() * 4));
        std::ofstream(d / "slab.raw", std::ios::binary)
            .write(reinterpret_cast<const char*>(slab.data()), std::streamsize(slab.size() * 4));
        std::ofstream(d / "ramp.raw", std::ios::binary)
            .write(reinterpret_cast<const char*>(ramp.data()), std::streamsize(ramp.size() * 4));
        return d;
    }();
    return dir;
}

std::string slab(double alpha, double kd, const std::string& colour, double dz) {
    char buf[768];
    std::snprintf(buf, sizeof buf,
                  R"({"kind": "volume", "source": {"path": "slab.raw", "dims": [4, 4, 40],
                     "type": "float32"}, "transform": {"translate": [0, 0, %.17g]},
                     "transfer_function": {"points": [{"value": 0.5, "opacity": 0},
                       {"value": 0.5, "opacity": %.17g, "color": %s}]},
                     "brdf": {"model": "lambert", "kd": 0}, "kd": %.17g})",
                  dz, alpha, colour.c_str(), kd);
    return buf;
}

// The tilted plane crossing x = 1.5 at height z.
std::string plane(double z, double opacity, double kd, const std::string& colour) {
    char buf[768];
    std::snprintf(buf, sizeof buf,
                  R"({"kind": "isosurface", "source": {"path": "ramp.raw", "dims": [4, 4, 360],
                     "type": "float32"}, "transform": {"translate": [0, 0, %g]}, "iso": %.17g,
                     "opacity": %.17g, "color": %s, "brdf": {"model": "lambert", "kd": 0},
                     "kd": %.17g})",
                  kRampBase, z - kRampBase + 1.0 + kSlope * 1.5, opacity, colour.c_str(), kd);
    return buf;
}

SceneSpec sceneOf(const std::vector<std::string>& objects, double step, bool backdrop = false) {
    std::string list;
    for (const auto& o : objects) list += (list.empty() ? "" : ",") + o;
    char head[768];
    std::snprintf(head, sizeof head,
                  R"({"image": {"width": 20, "height": 16, "samples_per_pixel": 2},
                      "camera": {"position": [1.5, 1.5, 200], "target": [1.5, 1.5, 0],
                      "up": [0, 1, 0], "fov_deg": 3}, "lights": [{"position": [1.5, 1.5, 1e6],
                      "intensity": 1e12}], "backdrop": {"enabled": %s},
                      "volume": {"step_voxels": %.17g, "termination_transmittance": 0,
                                 "shading_roulette": 0},
                      "objects": [)",
                  backdrop ? "true" : "false", step);
    return parseScene(std::string(head) + list + "]}", dataDir().string(), "hybrid-compositing");
}

Spectrum traceDown(const std::vector<std::string>& objects, double step, bool backdrop = false,
                   double tMax = std::numeric_limits<double>::infinity()) {
    const RenderScene scene(sceneOf(objects, step, backdrop), false);
    Ray ray;
    ray.o = Vec3(1.5, 1.5, 200);
    ray.d = Vec3(0, 0, -1);
    ray.tMax = tMax;
    return scene.traceRay(ray, 0.5);
}

// Radiance of a homogeneous segment [z0, z1] with opacity α per voxel, emission colour·kd/π·E
// (E at the segment's middle: it varies by < 1e-4 over 40 voxels), and its transmittance.
struct Segment {
    Spectrum L;
    double T;
};
Segment segment(double alpha, double kd, const Spectrum& colour, double z0, double z1) {
    const double T = std::pow(1.0 - alpha, z1 - z0);
    return {colour * (kd / kPi * irradiance(0.5 * (z0 + z1)) * (1.0 - T)), T};
}

Spectrum planeRadiance(double kd, const Spectrum& colour, double z) {
    return colour * (kd / kPi * kCosPlane * irradiance(z));
}

double maxAbsDiff(const Spectrum& a, const Spectrum& b) {
    double m = 0;
    for (int k = 0; k < kBandCount; ++k) m = std::max(m, std::abs(a[k] - b[k]));
    return m;
}

void expectNear(const Spectrum& got, const Spectrum& want, double rel, const std::string& what) {
    for (int b = 0; b < kBandCount; ++b)
        EXPECT_NEAR(got[b], want[b], rel * want.maxValue() + 1e-12) << what << ", band " << b;
}

// Case (a): slab z ∈ [−0.5, 39.5], α = 0.05, kd_v = 0.4, colour c_v = (0.2, 1, 0.5); plane
// kd_s = 0.9, colour c_s = (1, 0.5, 0.25), opacity o = 0.6, at z_p. Front to back:
//  plane above the slab (z_p = 60):   o L_s + (1 − o) S(−0.5, 39.5)
//  plane inside (z_p = 20.3):         S(z_p, 39.5) + T_front [o L_s + (1 − o) S(−0.5, z_p)]
//  plane below (z_p = −20):           S(−0.5, 39.5) + T_slab o L_s
// where S(a, b) is the segment's radiance. Step 0.02 voxel: the Riemann sum's lattice differs
// from the segment ends by < 1 step, so T is off by at most σ·0.02 ≈ 1e-3 relative; the
// tolerance is 1e-3 of the largest band (measured: ~1e-5, the midpoint jitter cancels most of it).
TEST(HybridCompositing, TiltedTranslucentPlaneAgainstAnEmittingSlabInDepthOrder) {
    const double alpha = 0.05, kdV = 0.4, kdS = 0.9, o = 0.6, step = 0.02;
    const Spectrum cV(0.2, 1.0, 0.5), cS(1.0, 0.5, 0.25);
    const std::string colV = "[0.2, 1, 0.5]", colS = "[1, 0.5, 0.25]";
    const Segment whole = segment(alpha, kdV, cV, -0.5, 39.5);

    const double zAbove = 60, zInside = 20.3, zBelow = -20;
    const Spectrum above =
        traceDown({slab(alpha, kdV, colV, 0), plane(zAbove, o, kdS, colS)}, step);
    const Spectrum wantAbove = planeRadiance(kdS, cS, zAbove) * o + whole.L * (1 - o);
    expectNear(above, wantAbove, 1e-3, "plane above the slab");

    const Spectrum inside =
        traceDown({slab(alpha, kdV, colV, 0), plane(zInside, o, kdS, colS)}, step);
    const Segment front = segment(alpha, kdV, cV, zInside, 39.5);
    const Segment back = segment(alpha, kdV, cV, -0.5, zInside);
    const Spectrum wantInside =
        front.L + (planeRadiance(kdS, cS, zInside) * o + back.L * (1 - o)) * front.T;
    expectNear(inside, wantInside, 1e-3, "plane inside the slab");

    const Spectrum below =
        traceDown({slab(alpha, kdV, colV, 0), plane(zBelow, o, kdS, colS)}, step);
    const Spectrum wantBelow = whole.L + planeRadiance(kdS, cS, zBelow) * (o * whole.T);
    expectNear(below, wantBelow, 1e-3, "plane below the slab");

    // Moving the plane changes the result as the closed forms say: the three differ by far more
    // than the tolerance (here by > 20 % of the largest band), so a compositor that ignored
    // depth order would fail at least two of the checks above.
    for (const auto& [a, b] : {std::pair{wantAbove, wantInside}, std::pair{wantInside, wantBelow},
                               std::pair{wantAbove, wantBelow}})
        EXPECT_GT(maxAbsDiff(a, b), 0.2 * a.maxValue());

    // An opaque plane inside the slab hides the part behind it: S(z_p, 39.5) + T_front L_s.
    const Spectrum opaque =
        traceDown({slab(alpha, kdV, colV, 0), plane(zInside, 1.0, kdS, colS)}, step);
    expectNear(opaque, front.L + planeRadiance(kdS, cS, zInside) * front.T, 1e-3,
               "opaque plane inside the slab");
}

// Case (b): slab A (α_A = 0.06, colour (1, 0.5, 0)) fills z ∈ [−0.5, 39.5], slab B (α_B = 0.03,
// colour (0, 0.5, 1)) z ∈ [24.5, 64.5]; both kd 0.5. Down the ray: B alone over [39.5, 64.5],
// both over [24.5, 39.5], A alone over [−0.5, 24.5]. In the overlap the medium is the sum of the
// two (extinction σ_A + σ_B, source (σ_A L_A + σ_B L_B)/(σ_A + σ_B); Max 1995, eq. 3 with
// constant coefficients), so
//   L = L_B (1 − e^{−25σ_B})
//     + e^{−25σ_B} (σ_A L_A + σ_B L_B)/(σ_A + σ_B) (1 − e^{−15(σ_A + σ_B)})
//     + e^{−25σ_B − 15(σ_A + σ_B)} L_A (1 − e^{−25σ_A}).
// The merged-by-depth Riemann sum converges to it; at 0.02 voxel the error is O(σ · step) ≈
// 1e-3 relative (tolerance 2e-3 of the largest band; measured ~2e-4). E is taken as 1 here: it
// varies by < 1.3e-4 over the 65 voxels, well inside the tolerance.
TEST(HybridCompositing, TwoOverlappingVolumesFollowTheExponentialLawWithSummedExtinction) {
    const double aA = 0.06, aB = 0.03, kd = 0.5;
    const double sA = -std::log(1 - aA), sB = -std::log(1 - aB);
    const Spectrum LA = Spectrum(1, 0.5, 0) * (kd / kPi);
    const Spectrum LB = Spectrum(0, 0.5, 1) * (kd / kPi);
    const double tB = std::exp(-25 * sB), tO = std::exp(-15 * (sA + sB));
    const Spectrum want = LB * (1 - tB) + (LA * sA + LB * sB) * (tB * (1 - tO) / (sA + sB)) +
                          LA * (tB * tO * (1 - std::exp(-25 * sA)));
    const std::vector<std::string> objects = {slab(aA, kd, "[1, 0.5, 0]", 0),
                                              slab(aB, kd, "[0, 0.5, 1]", 25)};
    expectNear(traceDown(objects, 0.02), want, 2e-3, "step 0.02");
    // The object order in the file does not matter: samples are merged by depth.
    expectNear(traceDown({objects[1], objects[0]}, 0.02), want, 2e-3, "step 0.02, swapped");
    // Treating the overlap as "A then B" or "B then A" (no merging) is clearly different: the
    // blue band (B only) would lose or keep the overlap's whole B emission unattenuated by A.
    const Spectrum bThenA =
        LB * (1 - std::exp(-40 * sB)) + LA * (std::exp(-40 * sB) * (1 - std::exp(-40 * sA)));
    EXPECT_GT(std::abs(bThenA[2] - want[2]) + std::abs(bThenA[0] - want[0]),
              0.02 * want.maxValue());
}

// Case (c): the skull's opacity 0.97. A dark tilted plane (kd 0.05, white) at z = 50 with
// opacity 0.97 over a bright opaque blue plane (kd 1, colour (0, 0, 1)) at z = 10: surfaces only,
// no discretisation, so L = 0.97 L_1 + 0.03 L_2 to rounding (the hit points are exact to
// ~1e-4 voxel, which moves E by ~2e-10). The blue band comes only from the 3 % behind.
TEST(HybridCompositing, OpacityPoint97LetsThreePercentOfWhatIsBehindShow) {
    const Spectrum L1 = planeRadiance(0.05, Spectrum(1.0), 50);
    const Spectrum L2 = planeRadiance(1.0, Spectrum(0, 0, 1), 10);
    const Spectrum got =
        traceDown({plane(50, 0.97, 0.05, "[1, 1, 1]"), plane(10, 1.0, 1.0, "[0, 0, 1]")}, 0.05);
    expectNear(got, L1 * 0.97 + L2 * 0.03, 1e-7, "0.97 over an opaque plane");
    EXPECT_NEAR(got[2] - got[0], 0.03 * L2[2], 1e-7 * L2[2]);  // exactly 3 % of the blue shows
    // With opacity 1 nothing behind shows.
    const Spectrum hidden =
        traceDown({plane(50, 1.0, 0.05, "[1, 1, 1]"), plane(10, 1.0, 1.0, "[0, 0, 1]")}, 0.05);
    expectNear(hidden, L1, 1e-7, "opaque front plane");

    // The backdrop behind a 0.97 plane: 3 % of what the ray sees with the plane at opacity 0
    // (same objects, so the same backdrop placement).
    const Spectrum clear = traceDown({plane(50, 0.0, 0.05, "[1, 1, 1]")}, 0.05, true);
    ASSERT_GT(clear.maxValue(), 0.0);
    const Spectrum shell = traceDown({plane(50, 0.97, 0.05, "[1, 1, 1]")}, 0.05, true);
    expectNear(shell, L1 * 0.97 + clear * 0.03, 1e-7, "0.97 over the backdrop");

    // A ray that ends (tMax = 170, z = 30) between the planes sees neither the far plane nor the
    // backdrop: only 0.97 L_1.
    const std::vector<std::string> both = {plane(50, 0.97, 0.05, "[1, 1, 1]"),
                                           plane(10, 1.0, 1.0, "[0, 0, 1]")};
    expectNear(traceDown(both, 0.05, false, 170.0), L1 * 0.97, 1e-7, "ray ending between planes");
    expectNear(traceDown(both, 0.05, true, 170.0), L1 * 0.97, 1e-7, "ray ending before backdrop");
}

// Renders `spec` seen obliquely — the image crosses the slabs' sides, the plane and the backdrop —
// on 1 and 2 threads, and expects the same bits, finite everywhere, and renderPixel's values.
struct ObliqueRender {
    Film image;
    RenderStats stats;
};
ObliqueRender renderObliqueOnOneAndTwoThreads(SceneSpec spec) {
    spec.cameraPosition = Vec3(60, -40, 120);
    spec.cameraTarget = Vec3(1.5, 1.5, 20);
    spec.cameraUp = Vec3(0, 0, 1);
    spec.fovDegrees = 40;
    const RenderScene scene(spec, false);
    RenderOptions one, two;
    one.threads = 1;
    two.threads = 2;
    one.progress = two.progress = false;
    RenderStats stats;
    Film a = scene.render(one, &stats);
    const Film b = scene.render(two);
    EXPECT_EQ(a.pixels().size(), b.pixels().size());
    size_t differing = 0;
    for (size_t i = 0; i < a.pixels().size() && i < b.pixels().size(); ++i)
        for (int k = 0; k < kBandCount; ++k) {
            EXPECT_TRUE(std::isfinite(a.pixels()[i][k])) << i;
            if (a.pixels()[i][k] != b.pixels()[i][k]) ++differing;
        }
    EXPECT_EQ(differing, 0u);
    for (const auto& [x, y] : {std::pair{0, 0}, std::pair{10, 8}, std::pair{19, 15}})
        for (int k = 0; k < kBandCount; ++k) EXPECT_EQ(scene.renderPixel(x, y)[k], a.at(x, y)[k]);
    return {std::move(a), stats};
}

// Case (d): render() gives the same image on 1 and 2 threads, bit for bit (each pixel's samples
// and jitters come from pixelSampleRng(seed, x, y, s), never from thread order), finite
// everywhere, and equal to renderPixel; grazing rays (along the plane, along a slab face, through
// an edge of a voxel) give finite radiance.
TEST(HybridCompositing, RenderIsThreadCountInvariantAndFinite) {
    const SceneSpec spec =
        sceneOf({slab(0.05, 0.4, "[0.2, 1, 0.5]", 0), slab(0.03, 0.5, "[1, 0.2, 0]", 25),
                 plane(20.3, 0.97, 0.9, "[1, 0.5, 0.25]")},
                0.25, true);
    const ObliqueRender r = renderObliqueOnOneAndTwoThreads(spec);
    size_t lit = 0;
    for (const Spectrum& p : r.image.pixels()) lit += p.maxValue() > 0 ? 1 : 0;
    EXPECT_EQ(lit, r.image.pixels().size());  // the backdrop fills what the objects leave
    EXPECT_GT(r.stats.volumeSamples, 0);
    EXPECT_GT(r.stats.surfaceHits, 0);

    const RenderScene scene(spec, false);
    const Vec3 along = normalized(Vec3(1, 0, -kSlope));  // in the plane: normal ∝ (0.75, 0, 1)
    for (const auto& [o, d] :
         {std::pair{Vec3(-50, 1.5, 20.3 + 51.5 * kSlope), along},  // along the tilted plane
          std::pair{Vec3(-50, 1.5, 39.5), Vec3(1, 0, 0)},          // along the slab's top face
          std::pair{Vec3(1.0, 1.0, 200), Vec3(0, 0, -1)},          // through voxel edges
          std::pair{Vec3(3.5, 3.5, 200), normalized(Vec3(0, 0, -1))}}) {  // down the grid's side
        Ray ray;
        ray.o = o;
        ray.d = d;
        for (double jitter : {0.0, 0.5, 0.999999})
            EXPECT_TRUE(scene.traceRay(ray, jitter).isFinite()) << o << " " << d;
    }
}

// Opaque surfaces only, no backdrop: the pixel loop finds the camera rays' first hits 8 at a time
// (Integrator::firstHitsInPackets, SurfaceScene::intersect8) and hands them to trace(); every
// pixel must equal renderPixel's, which traces its samples one at a time.
TEST(HybridCompositing, OpaqueSurfacesFoundInPacketsGiveTheSamePixels) {
    {
        const RenderScene translucent(sceneOf({plane(20.3, 0.5, 0.9, "[1, 0.5, 0.25]")}, 0.25),
                                      false);
        EXPECT_FALSE(Integrator(translucent.scene()).firstHitsInPackets());
        const RenderScene withVolume(
            sceneOf({plane(20.3, 1.0, 0.9, "[1, 0.5, 0.25]"), slab(0.05, 0.4, "[0.2, 1, 0.5]", 0)},
                    0.25),
            false);
        EXPECT_FALSE(Integrator(withVolume.scene()).firstHitsInPackets());
    }
    // Without and with the backdrop (the first search ends where the ray meets it:
    // Integrator::firstSurfaceSegment), seen from above (sceneOf's camera: the upper plane fills
    // the image) and obliquely (both planes, their sides and what lies around them).
    for (const bool backdrop : {false, true})
        for (const bool oblique : {false, true}) {
            SceneSpec spec =
                sceneOf({plane(20.3, 1.0, 0.9, "[1, 0.5, 0.25]"), plane(10, 1.0, 1.0, "[0, 0, 1]")},
                        0.25, backdrop);
            if (oblique) {
                spec.cameraPosition = Vec3(60, -40, 120);
                spec.cameraTarget = Vec3(1.5, 1.5, 20);
                spec.cameraUp = Vec3(0, 0, 1);
                spec.fovDegrees = 40;
            }
            const RenderScene scene(spec, false);
            EXPECT_TRUE(Integrator(scene.scene()).firstHitsInPackets());
            RenderOptions one, two;
            one.threads = 1;
            two.threads = 2;
            one.progress = two.progress = false;
            RenderStats stats;
            const Film image = scene.render(two, &stats);
            const Film single = scene.render(one);
            EXPECT_GT(stats.surfaceHits, 0);
            size_t lit = 0;
            for (int y = 0; y < image.height(); ++y)
                for (int x = 0; x < image.width(); ++x) {
                    const Spectrum want = scene.renderPixel(x, y);
                    lit += want.maxValue() > 0 ? 1 : 0;
                    for (int k = 0; k < kBandCount; ++k) {
                        EXPECT_EQ(image.at(x, y)[k], want[k])
                            << x << " " << y << " backdrop " << backdrop << " oblique " << oblique;
                        EXPECT_EQ(single.at(x, y)[k], want[k]) << x << " " << y;
                    }
                }
            if (!oblique || backdrop) {
                EXPECT_EQ(lit, size_t(image.width()) * size_t(image.height()))
                    << "backdrop " << backdrop;
            } else {
                // Rays that meet nothing: trace() returns the empty compositor's radiance at once
                // for them (Integrator::trace); renderPixel's rays take the whole loop.
                EXPECT_LT(lit, size_t(image.width()) * size_t(image.height()));
            }
        }
}

// The same at a step below 0.075 voxel with the cubic B-spline, read through each ray's
// polynomial per cell (GridReconstructor::bsplineOnRay): every march builds its own, so what a
// thread rendered before cannot change a pixel.
TEST(HybridCompositing, BSplineRayPolynomialIsThreadCountInvariant) {
    SceneSpec spec = sceneOf(
        {slab(0.05, 0.4, "[0.2, 1, 0.5]", 0), slab(0.03, 0.5, "[1, 0.2, 0]", 25)}, 0.05, true);
    for (ObjectSpec& o : spec.objects) {
        o.reconstruction = "bspline";
        o.gradient = "bspline";
    }
    EXPECT_GT(renderObliqueOnOneAndTwoThreads(spec).stats.volumeSamples, 0);
}

// "volume": {"empty_space_skipping": false} turns the bricks' skipping off (for timing it,
// bench/bench_hybrid.cpp); the image is the same either way (volume_marcher.h: only lattice
// points whose opacity is exactly 0 are skipped), here with a translucent plane inside the slabs.
TEST(HybridCompositing, EmptySpaceSkippingKeyChangesNothingButTheWork) {
    std::string box = slab(0.2, 0.4, "[0.2, 1, 0.5]", 0);
    box.replace(box.find("slab.raw"), 8, "box.raw");
    box.replace(box.find("[4, 4, 40]"), 10, "[24, 24, 24]");
    box.replace(box.find("[0, 0, 0]"), 9, "[-10, -10, 5]");
    SceneSpec on = sceneOf(
        {box, slab(0.03, 0.5, "[1, 0.2, 0]", 25), plane(8.3, 0.6, 0.9, "[1, 0.5, 0.25]")}, 0.25);
    EXPECT_TRUE(on.emptySpaceSkipping);  // the default
    const SceneSpec off = parseScene(
        R"({"camera": {"position": [0, 0, 1]}, "volume": {"empty_space_skipping": false},
            "objects": []})",
        dataDir().string(), "skip-off");
    EXPECT_FALSE(off.emptySpaceSkipping);
    on.cameraPosition = Vec3(60, -40, 120);
    on.cameraTarget = Vec3(1.5, 1.5, 20);
    on.cameraUp = Vec3(0, 0, 1);
    on.fovDegrees = 30;
    SceneSpec noSkip = on;
    noSkip.emptySpaceSkipping = false;
    RenderOptions options;
    options.progress = false;
    RenderStats statsOn, statsOff;
    const Film a = RenderScene(on, false).render(options, &statsOn);
    const Film b = RenderScene(noSkip, false).render(options, &statsOff);
    double maxValue = 0, maxDiff = 0;
    for (size_t i = 0; i < a.pixels().size(); ++i) {
        maxValue = std::max(maxValue, a.pixels()[i].maxValue());
        maxDiff = std::max(maxDiff, maxAbsDiff(a.pixels()[i], b.pixels()[i]));
    }
    ASSERT_GT(maxValue, 0.0);
    EXPECT_LE(maxDiff, 1e-12 * maxValue);
    EXPECT_EQ(statsOff.volumeSkipped, 0);
    EXPECT_GT(statsOn.volumeSkipped, 0);  // the view has empty space around the slabs
    EXPECT_LT(statsOn.volumeEvaluated, statsOff.volumeEvaluated);
    EXPECT_EQ(statsOn.volumeSamples, statsOff.volumeSamples);
}

}  // namespace
}  // namespace lobe
