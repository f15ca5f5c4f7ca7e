// Phong's, Ward's and Ashikhmin–Shirley's light loops for one shaded point as SIMD kernels (Google
// Highway, the best target the CPU supports chosen at run time): the light directions and Phong's
// power with the lights as lanes, then the sums with the bands as lanes. It returns
// render/shading.cpp's loops' sums bit for bit: every operation is a correctly rounded IEEE add,
// multiply, divide or square root in the scalar code's order (CMake compiles the file with
// -ffp-contract=off), the comparisons are those of std::max and std::clamp, and the lights are
// summed in the scene's order. T2 and T3 shade millions of Phong samples under four lights
// (docs/performance.md, round 4).
#pragma once

#include "core/frame.h"
#include "core/light.h"

#include <vector>

namespace lobe {

// One point and one Phong material whose exponent is whole (0 … 1024) and shared by the bands
// (materials/brdf.h, ModelAtView<Phong>).
struct PhongPointInput {
    Vec3 position{0.0};
    Frame frame;                       // already turned to the viewer where two-sided
    Vec3 wo{0, 0, 1};                  // frame.toLocal(toViewer), wo.z > 0
    unsigned exponent = 0;             // the shared whole exponent
    double ks[4] = {0, 0, 0, 0};       // per band, the 4th 0
    double diffuse[4] = {0, 0, 0, 0};  // kd/π per band, the 4th 0
    double specularScale = 1.0;
    bool specularOn = true;
    const double* shadow = nullptr;  // per light, or null
    // Frame-free (ShadingPoint::setNormal): only frame.n and wo.z are set, and cos α is worked
    // out as r(wi)·wo = 2 (n·wi)(n·wo) − wi·wo in world coordinates, wi the unit direction to the
    // light and wo = toViewer: the same d², wi.z, cos θi / d² and lit lights bit for bit, so the
    // Lambert sum is identical; cos α to rounding (a few ulps of 1), so the specular sum within
    // 1e-12 of the framed one relative to Σ ks · s · I · g (tests/render/test_shading.cpp).
    bool frameFree = false;
    Vec3 toViewer{0, 0, 1};
};

// The sums over the lights of forEachLitLight's loop (render/shading.cpp), bands 0 … 2 (the 4th
// lane is padding), and the number of BRDF evaluations (lights lit).
struct PhongSums {
    double lambert[4] = {0, 0, 0, 0};  // terms: Σ kd/π · I · g;  combined: Σ (kd/π + f_s·s) · I · g
    double specular[4] = {0, 0, 0, 0};  // terms: Σ f_s · s · I · g; combined: unused
    long long evaluations = 0;
};

// combined = false: shadeTermsLoop's two sums; true: directLightingLoop's one.
void phongLightSums(const PhongPointInput& point, const std::vector<PointLight>& lights,
                    bool combined, PhongSums& sums);

// Ward (materials/ward.h) and Ashikhmin–Shirley (materials/ashikhmin_shirley.h) whose shape
// parameters are shared by the bands (αx, αy; nu, nv — the usual case, and rendering 1's skull and
// cortex), lit with the lights as lanes for the model's per-light terms and the bands as lanes for
// the sums, as Phong's kernel. Every operation is the scalar eval's and loop's in its order
// (correctly rounded IEEE adds, multiplies, divides, square roots, the comparisons of std::max,
// std::min and clampBrdfValue), except the transcendental functions: Ward's exp is Highway's Exp
// (≤ 1 ulp, hwy/contrib/math) and Ashikhmin–Shirley's pow(h.z, e) is Exp(e · Log(h.z)) (Log
// ≤ 4 ulp). So the Lambert sum is the scalar loop's bit for bit, and each specular value differs
// from the one with std::exp / std::pow (< 1 ulp) by at most 2 ulps relative (Ward) and
// |x| · 4.5 ulps + 2 ulps with x = e ln h.z (A–S; |x| ≤ 708 wherever the power is a normal
// number, so below 7.1e-13 relative). The tolerance, tested against the scalar loop on every SIMD
// target the CPU has (tests/render/test_shading.cpp), is |Δ specular| ≤ 1e-12 · S + 1e-290 per
// band, S = Σ_lights f_s · s · I · g; the absolute term covers powers below the normal range (there
// the power's relative error grows, the power being below 2.2e-308), tested rather than bounded.
struct AnisoPointInput {
    enum class Model { ward, ashikhminShirley };
    Model model = Model::ward;
    Vec3 position{0.0};
    Frame frame;       // already turned to the viewer where two-sided, with its tangents
    Vec3 wo{0, 0, 1};  // frame.toLocal(toViewer), wo.z > 0
    // Ward: αx, αy; Ashikhmin–Shirley: nu, nv (the bands' common values).
    double shapeX = 0.0, shapeY = 0.0;
    double reflectance[4] = {0, 0, 0, 0};  // Ward: rho_s; A–S: rs (Schlick's F0); the 4th 0
    double norm[4] = {0, 0, 0, 0};         // A–S: sqrt((nu+1)(nv+1))/(8π) per band (norms())
    double diffuse[4] = {0, 0, 0, 0};      // kd/π per band, the 4th 0
    double specularScale = 1.0;
    bool specularOn = true;
    const double* shadow = nullptr;  // per light, or null
};

// The sums of forEachLitLight's loop for such a point, as phongLightSums. Returns false (sums
// then meaningless) when a lit light of an Ashikhmin–Shirley point has |wi + wo|² below twice the
// smallest normal double (wi ≈ −wo at the horizon), where Imath's length() takes its own path:
// the caller lights that point with the scalar loop.
bool anisoLightSums(const AnisoPointInput& point, const std::vector<PointLight>& lights,
                    bool combined, PhongSums& sums);

}  // namespace lobe
