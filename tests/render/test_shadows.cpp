// Shadows (render/integrator.h, "Shadows") against closed forms: a sphere's shadow on a plane
// under a point light; the transmittance through a slab of known opacity per voxel; the cache
// (render/shadow_cache.h) against exact shadow rays; skipping on/off, 1 and 2 threads, and the
// per-object passes with shadows.
//
// Set-up (spacing 1: voxels = world units):
//  - Floor: a 48×48×8 grid, ones at k = 1…3 for i, j = 1…46, zeros elsewhere; at iso 0.5 its top
//    face is exactly the plane z = 3.5 away from the edges (the interpolant crosses 0.5 half-way
//    between a one and a zero, linearly). Normal +z.
//  - Sphere: a 48×48×24 grid of f = 6 − |x − C|, C = (24, 24, 14), iso 1: the sphere of radius
//    R = 5 up to the trilinear interpolation of the distance (~0.02 voxel).
//  - Point light at L = (24, 24, 60). A floor point q is in shadow iff the segment q → L meets
//    the ball; around the axis through L and C the shadow is the disc cut from the plane by the
//    tangent cone, of half-angle θ with sin θ = R / |L − C|: radius r_s = (L_z − 3.5) tan θ.
//  - Slab: a 16×16×40 grid, ones at k = 8…23, as a volume with opacity α per voxel for values
//    above 0.5: the medium fills z ∈ [7.5, 23.5] and a shadow ray crossing it along a direction
//    at angle φ to z has T = (1 − α)^(16 / cos φ) (Max 1995, eq. 3; opacity per unit length).
#include "core/error.h"
#include "core/rng.h"
#include "render/aov.h"
#include "render/integrator.h"
#include "render/render_scene.h"
#include "render/scene_file.h"
#include "render/shadow_cache.h"
#include "test_files.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

namespace lobe {
namespace {

namespace fs = std::filesystem;

const Vec3 kC(24, 24, 14), kLight(24, 24, 60);
constexpr double kR = 5.0, kFloorZ = 3.5;

void write(const fs::path& p, const std::vector<float>& v) { test::writeFloatsAtomically(p, v); }

fs::path dataDir() {
    static const fs::path dir = [] {
        const fs::path d = fs::temp_directory_path() / ("lobe_shadows_" + std::to_string(getpid()));
        fs::create_directories(d);
        std::vector<float> floor(48 * 48 * 8, 0.0f), sphere(48 * 48 * 24), slab(16 * 16 * 40, 0.0f);
        for (int k = 1; k <= 3; ++k)
            for (int j = 1; j <= 46; ++j)
                for (int i = 1; i <= 46; ++i) floor[(k * 48 + j) * 48 + i] = 1.0f;
        for (int k = 0; k < 24; ++k)
            for (int j = 0; j < 48; ++j)
                for (int i = 0; i < 48; ++i)
                    sphere[(k * 48 + j) * 48 + i] = float(kR + 1.0 - (Vec3(i, j, k) - kC).length());
        for (int k = 8; k <= 23; ++k)
            for (int j = 0; j < 16; ++j)
                for (int i = 0; i < 16; ++i) slab[(k * 16 + j) * 16 + i] = 1.0f;
        write(d / "floor.raw", floor);
        write(d / "sphere.raw", sphere);
        write(d / "slab.raw", slab);
        return d;
    }();
    return dir;
}

std::string floorObject(double kd = 0.5) {
    return R"({"kind": "isosurface", "source": {"path": "floor.raw", "dims": [48, 48, 8],
               "type": "float32"}, "iso": 0.5, "brdf": {"model": "lambert", "kd": 0}, "kd": )" +
           std::to_string(kd) + "}";
}
std::string sphereObject(double opacity, bool casts = true) {
    return R"({"kind": "isosurface", "source": {"path": "sphere.raw", "dims": [48, 48, 24],
               "type": "float32"}, "iso": 1, "opacity": )" +
           std::to_string(opacity) + R"(, "casts_shadows": )" + (casts ? "true" : "false") +
           R"(, "brdf": {"model": "lambert", "kd": 0}, "kd": 0.5})";
}
std::string slabObject(double alpha) {
    return R"({"kind": "volume", "source": {"path": "slab.raw", "dims": [16, 16, 40],
               "type": "float32"}, "transfer_function": {"points": [{"value": 0.5, "opacity": 0},
               {"value": 0.5, "opacity": )" +
           std::to_string(alpha) +
           R"(, "color": [1, 0.8, 0.6]}]}, "brdf": {"model": "lambert", "kd": 0}, "kd": 0.6})";
}

SceneSpec sceneOf(const std::string& objects, const std::string& shadows,
                  const Vec3& light = kLight, const std::string& volume = "") {
    char head[900];
    std::snprintf(head, sizeof head,
                  R"({"image": {"width": 14, "height": 10, "samples_per_pixel": 2},
                      "camera": {"position": [-30, 24, 30], "target": [21, 24, 3.5],
                                 "up": [0, 0, 1], "fov_deg": 50},
                      "lights": [{"position": [%.17g, %.17g, %.17g], "intensity": 4000}],
                      "backdrop": {"enabled": false}, "shadows": %s,
                      "volume": {"step_voxels": 0.1, "shading_roulette": 0%s},
                      "objects": [)",
                  light.x, light.y, light.z,
                  (shadows[0] == '{' ? shadows : '"' + shadows + '"').c_str(), volume.c_str());
    return parseScene(std::string(head) + objects + "]}", dataDir().string(), "shadows.json");
}

struct Tracer {
    explicit Tracer(const SceneSpec& spec) : scene(spec, false), integrator(scene) {
        state = integrator.newState();
    }
    double transmittance(const Vec3& from, double jitter = 0.5, double tMin = 1e-4) {
        return integrator.lightTransmittance(from, scene.spec().lights[0], jitter, state, tMin);
    }
    Spectrum trace(const Ray& ray) {
        Rng rng(3);
        RenderStats stats;
        return integrator.trace(ray, 0.5, rng, state, stats);
    }
    Scene scene;
    Integrator integrator;
    TraceState state;
};

TEST(Shadows, SphereShadowOnAPlaneIsTheTangentConesDisc) {
    const double sinT = kR / (kLight - kC).length();
    const double rs = (kLight.z - kFloorZ) * sinT / std::sqrt(1 - sinT * sinT);  // 6.178
    Tracer opaque(sceneOf(floorObject() + "," + sphereObject(1.0), "exact"));
    Tracer glass(sceneOf(floorObject() + "," + sphereObject(0.6), "exact"));
    Tracer ghost(sceneOf(floorObject() + "," + sphereObject(1.0, false), "exact"));
    // Floor points at distance r from the axis, in several directions.
    for (const double phi : {0.0, 1.1, 2.9, 4.4}) {
        const Vec3 dir(std::cos(phi), std::sin(phi), 0);
        for (const double r : {0.0, 2.0, 4.0, 5.8, 6.6, 8.0, 12.0, 18.0}) {
            const Vec3 q = Vec3(kC.x, kC.y, kFloorZ) + dir * r;
            const bool shadowed = r < rs;
            SCOPED_TRACE("phi " + std::to_string(phi) + ", r " + std::to_string(r));
            EXPECT_EQ(opaque.transmittance(q), shadowed ? 0.0 : 1.0);
            // Through a translucent closed surface the ray crosses it twice: (1 − 0.6)².
            EXPECT_NEAR(glass.transmittance(q), shadowed ? 0.16 : 1.0, 1e-12);
            EXPECT_EQ(ghost.transmittance(q), 1.0);  // casts_shadows false
        }
        // The edge itself, by bisection on r: at r_s within the sphere's interpolation error (the
        // interpolated distance overestimates |x − C| by up to h²/(8R) = 0.025 voxel, and
        // dr_s/dR = (L_z − 3.5)/(|L − C| cos²θ) ≈ 1.24: 0.03, up to twice that between voxel
        // axes; tolerance 0.08).
        double lo = 0.0, hi = 12.0;
        for (int i = 0; i < 30; ++i) {
            const double mid = 0.5 * (lo + hi);
            (opaque.transmittance(Vec3(kC.x, kC.y, kFloorZ) + dir * mid) == 0.0 ? lo : hi) = mid;
        }
        EXPECT_NEAR(lo, rs, 0.08) << "phi " << phi;
    }
    // Through the integrator: a camera ray from the side (it passes below the sphere) meets the
    // floor at q; lit, the Lambert floor sends kd/π · I cos θ / d²; in the shadow nothing.
    for (const double r : {-3.0, -10.0}) {
        const Vec3 q(kC.x + r, kC.y, kFloorZ);
        Ray ray;
        ray.o = Vec3(-30, 24, 30);
        ray.d = normalized(q - ray.o);
        const Vec3 toL = kLight - q;
        const double lit = 0.5 / kPi * 4000 * (toL.z / toL.length()) / toL.length2();
        const double got = opaque.trace(ray)[0];
        const double off =
            Tracer(sceneOf(floorObject() + "," + sphereObject(1.0), "off")).trace(ray)[0];
        EXPECT_NEAR(off, lit, 1e-9 * lit);
        EXPECT_NEAR(got, std::abs(r) < rs ? 0.0 : lit, 1e-9 * lit) << "r " << r;
    }
}

TEST(Shadows, SlabTransmittanceIsTheExponentialOfItsOpticalDepth) {
    const double alpha = 0.1, sigma = -std::log(1 - alpha);
    // Below the slab at (8.3, 7.6, 2); the light straight above, and tilted by φ (tan φ = 0.25:
    // the ray stays inside the slab's 16 × 16 footprint while it crosses z ∈ [7.5, 23.5]).
    const Vec3 p(8.3, 7.6, 2.0);
    for (const double tanPhi : {0.0, 0.25}) {
        const Vec3 light = p + Vec3(tanPhi, 0, 1) * 1e3;
        const double cosPhi = 1.0 / std::sqrt(1 + tanPhi * tanPhi);
        const double want = std::pow(1 - alpha, 16.0 / cosPhi);
        Tracer on(sceneOf(slabObject(alpha), "exact", light));
        Tracer off(
            sceneOf(slabObject(alpha), "exact", light, R"(, "empty_space_skipping": false)"));
        for (const double jitter : {0.05, 0.5, 0.95}) {
            const double got = on.transmittance(p, jitter, 0.0);
            // The lattice (step 0.1 voxel along the ray's index length) is off the slab's ends by
            // less than a step each: |ΔT| ≤ 2 σ (0.1 / cos φ) T.
            EXPECT_NEAR(got, want, 2 * sigma * 0.1 / cosPhi * want) << "tan phi " << tanPhi;
            EXPECT_NEAR(off.transmittance(p, jitter, 0.0), got, 1e-12);
        }
        // The cache: below the slab T does not vary, so the interpolated nodes give it too (each
        // node a shadow ray at jitter 0.5 and the cache's step, 0.5 voxel by default: the
        // lattice bound is then 2 σ (0.5 / cos φ) T; nodes are floats). The cache's own lookup
        // (through the integrator's shading) is checked against it.
        Tracer cached(sceneOf(slabObject(alpha), "cached", light));
        ASSERT_NE(cached.integrator.shadowCache(), nullptr);
        const double fromCache = cached.integrator.shadowCache()->lookup(0, p, [&](const Vec3& x) {
            return cached.integrator.lightTransmittance(x, cached.scene.spec().lights[0], 0.5,
                                                        cached.state, 0.0, 5.0, false, true);
        });
        EXPECT_NEAR(fromCache, want, 2 * sigma * 0.5 / cosPhi * want);
        EXPECT_GT(cached.integrator.shadowCache()->computedNodes(), 0);
    }
    // Without shadows the slab is not there for the light: a surface under it is fully lit.
    EXPECT_EQ(Tracer(sceneOf(slabObject(alpha), "off")).integrator.shadowCache(), nullptr);
}

// Surface hits reading the cache (the default "cached"): a hit interpolates only the nodes of its
// cell on the light's side of its tangent plane (render/integrator.h, "Shadows"), so the floor
// does not shadow itself (the nodes below z = 3.5 lie inside the opaque floor: T = 0), and away
// from the shadow's edge (farther than a cell) the values are the closed forms of the exact test
// above: 0 under the opaque sphere, (1 − 0.6)² under the glass one, 1 outside. The nodes are
// exact shadow rays through the surfaces, stored as floats. At the edge the cache blurs the
// shadow over about a node spacing; the exact-surface variant ("surfaces": "exact") keeps it
// sharp.
TEST(Shadows, CachedSurfaceShadowsAreTheClosedFormsAwayFromTheEdge) {
    const double sinT = kR / (kLight - kC).length();
    const double rs = (kLight.z - kFloorZ) * sinT / std::sqrt(1 - sinT * sinT);  // 6.178
    for (const double opacity : {1.0, 0.6}) {
        Tracer cached(sceneOf(floorObject() + "," + sphereObject(opacity),
                              R"({"mode": "cached", "cache_voxels": 2})"));
        Tracer off(sceneOf(floorObject() + "," + sphereObject(opacity), "off"));
        ASSERT_NE(cached.integrator.shadowCache(), nullptr);
        const double spacing = cached.integrator.shadowCache()->spacing();
        EXPECT_EQ(spacing, 2.0);  // cache_voxels 2 of the unit voxels
        const double inside = (1 - opacity) * (1 - opacity);
        // Directions away from the sphere as the camera sees it (its rays reach the floor).
        for (const double phi : {1.6, 2.6, 3.6, 4.7}) {
            const Vec3 dir(std::cos(phi), std::sin(phi), 0);
            // The nodes read lie at most one cell beside q in x and y (√2 spacings) and up to a
            // spacing above it, where the shadow's disc is narrower by that height × tan θ
            // (0.11 × 2): inside for r < 6.18 − 2.83 − 0.22, outside for r > 6.18 + 2.83.
            for (const double r : {0.0, 1.5, 2.5, 10.0, 14.0, 20.0}) {
                ASSERT_TRUE(r < rs - 1.7 * spacing || r > rs + 1.5 * spacing);
                const Vec3 q = Vec3(kC.x, kC.y, kFloorZ) + dir * r;
                Ray ray;
                ray.o = Vec3(-30, 24, 30);
                ray.d = normalized(q - ray.o);
                const double lit = off.trace(ray)[0];
                ASSERT_GT(lit, 0.0);
                const double want = r < rs ? inside : 1.0;
                EXPECT_NEAR(cached.trace(ray)[0] / lit, want, 1e-6)
                    << "opacity " << opacity << ", phi " << phi << ", r " << r;
            }
        }
    }
}

// The one-sided interpolation by hand: nodes 1 apart over [0, 2]³ holding x + 2z.
TEST(Shadows, LookupAboveUsesTheNodesOnTheNormalsSideOnly) {
    const ShadowCache cache(Vec3(0, 0, 0), Vec3(2, 2, 2), 1.0, 1);
    const auto value = [](const Vec3& x) { return x.x + 2 * x.z; };
    // Trilinear interpolation of a linear function is the function.
    EXPECT_NEAR(cache.lookup(0, Vec3(0.5, 0.5, 0.25), value), 1.0, 1e-12);
    // Above z = 0.25: the four nodes at z = 1, weights (1 − u)·(1 − v) … renormalised: x̄ = 0.5.
    EXPECT_NEAR(cache.lookupAbove(0, Vec3(0.5, 0.5, 0.25), Vec3(0, 0, 1), value), 2.5, 1e-12);
    // Below it (n = −z): the four at z = 0.
    EXPECT_NEAR(cache.lookupAbove(0, Vec3(0.5, 0.5, 0.25), Vec3(0, 0, -1), value), 0.5, 1e-12);
    // The plane x + z = 1 through the cell's centre: (1, y, 1) above it, (1, y, 0) and (0, y, 1)
    // on it (not counted), (0, y, 0) below: only x + 2z = 3 remains.
    EXPECT_NEAR(cache.lookupAbove(0, Vec3(0.5, 0.5, 0.5), normalized(Vec3(1, 0, 1)), value), 3.0,
                1e-12);
    // Off-centre, x = 0.2, y = 0.7, z = 0.4, n = +x: nodes at x = 1, weights (1 − v or v)·(1 − w
    // or w), renormalised: 1 + 2·0.4.
    EXPECT_NEAR(cache.lookupAbove(0, Vec3(0.2, 0.7, 0.4), Vec3(1, 0, 0), value), 1.8, 1e-12);
    // On a cell face with n across it no node of the cell lies above (the ones at z = 1 have
    // weight 0): negative, and the integrator steps to the next cell.
    EXPECT_LT(cache.lookupAbove(0, Vec3(0.5, 0.5, 0.0), Vec3(0, 0, 1), value), 0.0);
}

Film renderOf(const RenderScene& scene, int threads, const AovRequest* request = nullptr,
              AovImage* passes = nullptr) {
    RenderOptions o;
    o.threads = threads;
    o.progress = false;
    return scene.render(o, nullptr, request, passes);
}

TEST(Shadows, ImagesAreTheSameForAnyThreadCountAndPassesStillAddUp) {
    const std::string objects = floorObject() + "," + sphereObject(0.7) + "," + slabObject(0.05);
    std::map<std::string, double> effect;
    // The caches at 2 unit voxels (the default 4 is coarse for a 16-voxel slab).
    const std::string cached = R"({"mode": "cached", "cache_voxels": 2})";
    const std::string sharp = R"({"mode": "cached", "cache_voxels": 2, "surfaces": "exact"})";
    for (const std::string& mode : {std::string("exact"), cached, sharp}) {
        SCOPED_TRACE(mode);
        const RenderScene scene(sceneOf(objects, mode, Vec3(10, 20, 60)), false);
        const Film one = renderOf(scene, 1), two = renderOf(scene, 2);
        const RenderScene noSkip(
            sceneOf(objects, mode, Vec3(10, 20, 60), R"(, "empty_space_skipping": false)"), false);
        const Film three = renderOf(noSkip, 2);
        const RenderScene unshadowed(sceneOf(objects, "off", Vec3(10, 20, 60)), false);
        const Film none = renderOf(unshadowed, 2);
        AovRequest request = AovRequest::parse("all");
        AovImage passes;
        const Film withPasses = renderOf(scene, 2, &request, &passes);
        double darker = 0.0;
        for (size_t p = 0; p < one.pixels().size(); ++p) {
            Spectrum sum = passes.backdropAt(p);
            for (int o = 0; o < passes.objectCount; ++o)
                sum += passes.lambertAt(p, o) + passes.specularAt(p, o);
            for (int b = 0; b < kBandCount; ++b) {
                ASSERT_EQ(one.pixels()[p][b], two.pixels()[p][b]) << "pixel " << p;
                EXPECT_NEAR(three.pixels()[p][b], one.pixels()[p][b],
                            1e-9 * (1 + one.pixels()[p][b]));
                EXPECT_EQ(withPasses.pixels()[p][b], one.pixels()[p][b]);
                EXPECT_NEAR(sum[b], one.pixels()[p][b], 2e-6 * std::abs(one.pixels()[p][b]) + 1e-9);
                EXPECT_LE(one.pixels()[p][b], none.pixels()[p][b] * (1 + 1e-12) + 1e-12);
            }
            darker += none.pixels()[p][1] - one.pixels()[p][1];
        }
        EXPECT_GT(darker, 0.0);  // the shadows are there
        effect[mode] = darker;
    }
    // The cache darkens the image as exact shadow rays do (the slab's shadow falls on the floor,
    // outside the slab's box: the cache is read where the shadow ray enters the box), within 5 %.
    EXPECT_NEAR(effect[sharp], effect["exact"], 0.05 * effect["exact"]);
    EXPECT_NEAR(effect[cached], effect["exact"], 0.05 * effect["exact"]);
}

TEST(Shadows, SceneKeysAndErrors) {
    auto error = [](const std::string& shadows) {
        try {
            parseScene(R"({"camera": {"position": [0, 0, 9]}, "shadows": )" + shadows +
                           R"(, "objects": []})",
                       dataDir().string(), "s.json");
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    EXPECT_EQ(error(R"("exact")"), "");
    EXPECT_EQ(error(R"({"mode": "cached", "cache_voxels": 4})"), "");
    EXPECT_EQ(error(R"({"mode": "cached", "surfaces": "exact"})"), "");
    EXPECT_NE(error(R"({"mode": "cached", "surfaces": "soft"})").find("shadows.surfaces"),
              std::string::npos);
    EXPECT_NE(error(R"("soft")").find("shadows"), std::string::npos);
    EXPECT_NE(error(R"({"mode": "cached", "cache_voxels": 0})").find("cache_voxels"),
              std::string::npos);
}

}  // namespace
}  // namespace lobe
