// The hybrid integrator against closed forms: iso-surfaces and homogeneous volume slabs along one
// ray, composited front to back in depth order (apps/render/render_scene.h).
//
// Set-up: the camera looks down −z through (1.5, 1.5). A slab volume of 4×4×40 voxels of value 1
// (spacing 1, voxel centres z = 0…39) with a step transfer function (opacity α per voxel above
// value 0.5) fills z ∈ [−0.5, 39.5] (the trilinear value crosses 0.5 exactly half a voxel beyond
// the last centre). A ramp volume of 4×4×200 voxels placed at z ∈ [−100, 99] with value = 99 − z
// has its iso-surface at z = 99 − iso exactly (trilinear is exact for a linear field); its grid
// ends at z = −100, where the value drops to the background 0 and the iso-surface of the
// interpolant has a second, far sheet at z ≈ −100.5, behind everything else: the expected values
// include it when the near plane is translucent (it is shaded exactly like the near plane). One light far up the z axis with I/d² = 1 at the origin (relative
// variation < 2e-4 over the scene), so a Lambert sample with no normal (the slab: zero gradient)
// sends colour·kd/π, and the plane (normal ±z, shaded two-sided) sends kd/π. Along the ray the
// slab then contributes L_v (1 − T) for a path through it with transmittance T, and a sequence
// of media with equal emission L_v gives L_v (1 − Π T).
#include "apps/render/render_scene.h"
#include "apps/render/scene_file.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

namespace lobe {
namespace {

namespace fs = std::filesystem;

fs::path writeVolumes() {
    const fs::path dir = fs::temp_directory_path() / "lobe_hybrid_test";
    fs::create_directories(dir);
    std::vector<float> slab(4 * 4 * 40, 1.0f), ramp(4 * 4 * 200);
    for (int k = 0; k < 200; ++k)
        for (int i = 0; i < 16; ++i) ramp[k * 16 + i] = float(199 - k);
    std::ofstream(dir / "slab.raw", std::ios::binary)
        .write(reinterpret_cast<const char*>(slab.data()), slab.size() * 4);
    std::ofstream(dir / "ramp.raw", std::ios::binary)
        .write(reinterpret_cast<const char*>(ramp.data()), ramp.size() * 4);
    return dir;
}

const double kLightIntensity = 1e12;  // at z = 1e6: I/d² = 1 at the origin

std::string slabObject(double alpha, double kd, const std::string& colour, double dz) {
    char buf[768];
    std::snprintf(buf, sizeof buf,
                  R"({"kind": "volume", "source": {"path": "slab.raw", "dims": [4, 4, 40],
                     "type": "float32"}, "transform": {"translate": [0, 0, %g]},
                     "transfer_function": {"points": [{"value": 0.5, "opacity": 0},
                       {"value": 0.5, "opacity": %g, "color": %s}]},
                     "brdf": {"model": "lambert", "kd": 0}, "kd": %g})",
                  dz, alpha, colour.c_str(), kd);
    return buf;
}

// A plane at height z (the ramp's iso-surface).
std::string planeObject(double z, double opacity, double kd) {
    char buf[512];
    std::snprintf(buf, sizeof buf,
                  R"({"kind": "isosurface", "source": {"path": "ramp.raw", "dims": [4, 4, 200],
                     "type": "float32"}, "transform": {"translate": [0, 0, -100]}, "iso": %.17g,
                     "opacity": %g, "brdf": {"model": "lambert", "kd": 0}, "kd": %g})",
                  99.0 - z, opacity, kd);
    return buf;
}

Spectrum traceDown(const std::vector<std::string>& objects, double step = 0.05) {
    static const fs::path dir = writeVolumes();
    std::string list;
    for (const auto& o : objects) list += (list.empty() ? "" : ",") + o;
    char head[512];
    std::snprintf(head, sizeof head,
                  R"({"camera": {"position": [1.5, 1.5, 200], "target": [1.5, 1.5, 0],
                      "up": [0, 1, 0]}, "lights": [{"position": [1.5, 1.5, 1e6],
                      "intensity": %g}], "backdrop": {"enabled": false},
                      "volume": {"step_voxels": %g, "termination_transmittance": 0},
                      "objects": [)",
                  kLightIntensity, step);
    const SceneSpec spec = parseScene(std::string(head) + list + "]}", dir.string(), "hybrid");
    const RenderScene scene(spec, false);
    Ray ray;
    ray.o = Vec3(1.5, 1.5, 200);
    ray.d = Vec3(0, 0, -1);
    return scene.traceRay(ray, 0.5);
}

double transmittance(double alpha, double voxels) { return std::pow(1.0 - alpha, voxels); }

}  // namespace

TEST(Hybrid, OpaquePlaneBehindAnAbsorbingSlabIsAttenuatedByTheSlabInFront) {
    const double alpha = 0.05, kd = 0.6;
    const Spectrum L = traceDown({slabObject(alpha, 0.0, "1", 0), planeObject(20.3, 1.0, kd)});
    const double expected = transmittance(alpha, 39.5 - 20.3) * kd / kPi;
    for (int b = 0; b < 3; ++b) EXPECT_NEAR(L[b], expected, 0.01 * expected) << b;
}

TEST(Hybrid, TranslucentPlaneInFrontOfAnEmittingSlab) {
    const double alpha = 0.05, kdV = 0.5, kdS = 0.6, opacity = 0.97;
    // The plane at z = 70.3 is met first; 3 % of the slab shows through, then the far sheet.
    const Spectrum L = traceDown({slabObject(alpha, kdV, "1", 0), planeObject(70.3, opacity, kdS)});
    const double ls = kdS / kPi, t = transmittance(alpha, 40.0);
    const double slab = kdV / kPi * (1.0 - t);
    const double expected = opacity * ls + (1.0 - opacity) * (slab + t * opacity * ls);
    for (int b = 0; b < 3; ++b) EXPECT_NEAR(L[b], expected, 0.005 * expected) << b;
}

TEST(Hybrid, TranslucentPlaneInsideAnEmittingSlabIsCompositedInDepthOrder) {
    const double alpha = 0.05, kdV = 0.1, kdS = 1.0, opacity = 0.8;
    const Spectrum L = traceDown({slabObject(alpha, kdV, "1", 0), planeObject(20.3, opacity, kdS)});
    const double lv = kdV / kPi, ls = kdS / kPi;
    const double t1 = transmittance(alpha, 39.5 - 20.3), t2 = transmittance(alpha, 20.3 + 0.5);
    const double expected = lv * (1 - t1) + t1 * (opacity * ls + (1 - opacity) * lv * (1 - t2)) +
                            t1 * (1 - opacity) * t2 * opacity * ls;  // the far sheet
    for (int b = 0; b < 3; ++b) EXPECT_NEAR(L[b], expected, 0.01 * expected) << b;
    // The wrong order (the plane composited after the whole slab) differs clearly.
    const double wrong = lv * (1 - t1 * t2) + t1 * t2 * (opacity * ls + (1 - opacity) * opacity * ls);
    EXPECT_GT(std::abs(L[0] - wrong), 0.3 * expected);
}

// Two slabs overlapping over z ∈ [19.5, 39.5]: B (green) in front from 59.5 down, A (red)
// behind down to −0.5. In the continuous limit (extinction σ = −ln(1 − α) per voxel, summed where
// they overlap) the green band gets L(1 − e^{−20σ}) + e^{−20σ} L ½ (1 − e^{−40σ}) and the red band
// e^{−20σ} L ½ (1 − e^{−40σ}) + e^{−60σ} L (1 − e^{−20σ}).
TEST(Hybrid, TwoOverlappingVolumesMergeByDepth) {
    const double alpha = 0.04, kd = 0.5;
    const Spectrum L = traceDown({slabObject(alpha, kd, "[1, 0, 0]", 0),
                                  slabObject(alpha, kd, "[0, 1, 0]", 20)},
                                 0.02);
    const double l = kd / kPi, s = -std::log(1.0 - alpha);
    const double green = l * (1 - std::exp(-20 * s)) + std::exp(-20 * s) * l * 0.5 * (1 - std::exp(-40 * s));
    const double red = std::exp(-20 * s) * l * 0.5 * (1 - std::exp(-40 * s)) +
                       std::exp(-60 * s) * l * (1 - std::exp(-20 * s));
    EXPECT_NEAR(L[1], green, 0.01 * green);
    EXPECT_NEAR(L[0], red, 0.02 * red);
    EXPECT_NEAR(L[2], 0.0, 1e-12);
}

}  // namespace lobe
