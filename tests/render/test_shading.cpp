// Shading (render/shading.h) and the light loop (core/light.h) against hand-computed values:
// a volume sample without a usable normal is lit as Lambert with cos θ = 1, and agrees with a
// normal facing the light; directLighting is Σ (kd/π + f_s) · I · cos θi / d², two-sided only when
// asked; lights below the surface and a viewer below it contribute nothing.
#include "core/rng.h"
#include "materials/registry.h"
#include "render/shading.h"

#include <gtest/gtest.h>
#include <hwy/targets.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <string>

namespace lobe {
namespace {

TEST(Shading, VolumeSampleWithoutNormalIsLambertWithCosineOne) {
    VolumeSample inside;
    inside.position = Vec3(19.7, 7.3, 8.1);
    inside.colour = Spectrum(0.5, 1.0, 0.25);
    inside.hasNormal = false;
    // Unshaded sample: colour × kd/π × I/d², light at distance 10 with I = 100.
    Material m;
    m.kd = Spectrum(0.2);
    const std::vector<PointLight> lights = {{inside.position + Vec3(0, 10, 0), Spectrum(100.0)}};
    const Spectrum L = shadeVolumeSample(m, inside, Vec3(-1, 0, 0), lights);
    EXPECT_NEAR(L[1], 1.0 * 0.2 / kPi * 100.0 / 100.0, 1e-12);
    EXPECT_NEAR(L[0], 0.5 * 0.2 / kPi, 1e-12);
    EXPECT_NEAR(L[2], 0.25 * 0.2 / kPi, 1e-12);
    // With a usable normal facing the light head-on (cos θ = 1) and the specular term off, the
    // two rules agree: Lambert is Lambert.
    VolumeSample lit = inside;
    lit.hasNormal = true;
    lit.normal = Vec3(0, 1, 0);
    m.specularOn = false;
    const Spectrum L2 = shadeVolumeSample(m, lit, normalized(Vec3(-1, 1, 0)), lights);
    EXPECT_NEAR(L2[1], L[1], 1e-12);
    // The normal pointing away from the light and the viewer: two-sided, so the same value.
    lit.normal = Vec3(0, -1, 0);
    EXPECT_NEAR(shadeVolumeSample(m, lit, normalized(Vec3(-1, 1, 0)), lights)[1], L[1], 1e-12);
}

TEST(Shading, DirectLightingSumsLightsWithCosineOverDistanceSquared) {
    // Lambert only (kd = 0.3): a light at 60° from the normal at distance 2 with I = 4, and one
    // straight above at distance 3 with I = 9: L = 0.3/π (4 · 0.5 / 4 + 9 · 1 / 9) = 0.3/π · 1.5.
    Material m;
    m.kd = Spectrum(0.3);
    m.specularOn = false;
    const Frame frame = Frame::fromNormalAndAxis(Vec3(0, 0, 1), Vec3(1, 0, 0), Vec3(0, 1, 0));
    const Vec3 p(1, 2, 3);
    const double s60 = std::sin(kPi / 3), c60 = std::cos(kPi / 3);
    const std::vector<PointLight> lights = {{p + Vec3(2 * s60, 0, 2 * c60), Spectrum(4.0)},
                                            {p + Vec3(0, 0, 3), Spectrum(9.0)},
                                            {p + Vec3(0, 0, -1), Spectrum(100.0)}};  // below
    const Vec3 toViewer = normalized(Vec3(0.3, -0.2, 1));
    const Spectrum L = directLighting(m, frame, p, toViewer, lights);
    for (int band = 0; band < 3; ++band) EXPECT_NEAR(L[band], 0.3 / kPi * 1.5, 1e-12);
    // A viewer below the surface sees nothing one-sided, and the mirrored frame two-sided: the
    // light below (I = 100, d = 1, cos 1) then lights it alone: 0.3/π · 100.
    const Vec3 below = normalized(Vec3(0.3, -0.2, -1));
    EXPECT_EQ(directLighting(m, frame, p, below, lights)[0], 0.0);
    EXPECT_NEAR(directLighting(m, frame, p, below, lights, true)[0], 0.3 / kPi * 100.0, 1e-10);
}

TEST(Shading, SpecularTermIsTheModelsValueTimesIrradiance) {
    // One light at the mirror direction of the viewer: L = (kd/π + f_s(wi, wo)) · I cos θi / d²,
    // with f_s taken from the model itself (materials/ tests check its values).
    Material m;
    m.specular = Ward{};
    m.kd = Spectrum(0.2);
    const Frame frame = Frame::fromNormalAndAxis(Vec3(0, 0, 1), Vec3(1, 0, 0), Vec3(0, 1, 0));
    const Vec3 wo = normalized(Vec3(0.5, 0.1, 1.0));
    const Vec3 wi(-wo.x, -wo.y, wo.z);
    const std::vector<PointLight> lights = {{wi * 5.0, Spectrum(25.0)}};
    const Spectrum L = directLighting(m, frame, Vec3(0.0), wo, lights);
    const Spectrum expected =
        (Spectrum(0.2 / kPi) + evalBrdf(m.specular, wi, wo)) * (25.0 * wi.z / 25.0);
    for (int band = 0; band < 3; ++band) EXPECT_NEAR(L[band], expected[band], 1e-12);
}

namespace lobe {
namespace {

TEST(Shading, HighlightTakesTheLightsColourNotTheBodyColour) {
    // A blue body colour: the Lambert term is blue, the specular term white (highlight 1), so
    // shade = colour · lambert + 1 · specular; with highlight = colour it is colour · (both).
    Material m;
    m.specular = Phong{};
    m.kd = Spectrum(0.2);
    ShadingPoint p;
    p.material = &m;
    p.colour = Spectrum(0.1, 0.2, 0.9);
    p.highlight = Spectrum(1.0);
    p.frame = Frame::fromNormalAndAxis(Vec3(0, 0, 1), Vec3(1, 0, 0), Vec3(0, 1, 0));
    const Vec3 wo = normalized(Vec3(0.2, 0.1, 1.0));
    const std::vector<PointLight> lights = {{Vec3(-wo.x, -wo.y, wo.z) * 3.0, Spectrum(9.0)}};
    const ShadingTerms t = shadeTerms(p, wo, lights);
    const Spectrum white = shade(p, wo, lights);
    for (int b = 0; b < 3; ++b) EXPECT_NEAR(white[b], t.lambert[b] + t.specular[b], 1e-12);
    // The specular part is the same in every band (Phong's ks is grey): white, not blue.
    EXPECT_GT(t.specular[0], 0.0);
    EXPECT_NEAR(t.specular[0], t.specular[2], 1e-12);
    EXPECT_NEAR(t.lambert[2] / t.lambert[0], 9.0, 1e-9);
    p.highlight = p.colour;
    const Spectrum tinted = shade(p, wo, lights);
    const Spectrum expected = p.colour * directLighting(m, p.frame, p.position, wo, lights, true);
    for (int b = 0; b < 3; ++b) EXPECT_EQ(tinted[b], expected[b]);
    EXPECT_LT(tinted[0], white[0]);
}

}  // namespace
}  // namespace lobe

// The fast light loop (render/shading.cpp: the model chosen once per point; core/light.h: light
// directions of up to eight lights at once with SIMD, core/light_directions.h) against the plain
// one it replaced — one light at a time with evalBrdf per light — bit for bit (tolerance
// 0), for every model, random points, frames, viewers and lights (1 to 11: one SIMD chunk,
// partial vectors, and more than one chunk), with and without shadows, lights below the surface
// and a light at the point included.
namespace reference {

// The light loop one light at a time, as core/light.h's forEachLightInFrame was written before
// it worked out the directions with SIMD: fn(light, wi, wo, cos θi / d²).
template <class Fn>
void forEachLightInFrame(const std::vector<PointLight>& lights, const Frame& frame,
                         const Vec3& position, const Vec3& toViewer, Fn&& fn) {
    const Vec3 wo = frame.toLocal(toViewer);
    if (!(wo.z > 0.0)) return;
    for (const PointLight& light : lights) {
        const Vec3 toLight = light.position - position;
        const double d2 = toLight.length2();
        if (!(d2 > 0.0)) continue;
        const Vec3 wi = frame.toLocal(toLight / std::sqrt(d2));
        if (!(wi.z > 0.0)) continue;
        fn(light, wi, wo, wi.z / d2);
    }
}

ShadingTerms shadeTerms(const ShadingPoint& point, const Vec3& toViewer,
                        const std::vector<PointLight>& lights, long long& evaluations) {
    const Material& m = *point.material;
    ShadingTerms terms;
    const Frame frame = facingViewer(point.frame, toViewer);
    reference::forEachLightInFrame(
        lights, frame, point.position, toViewer,
        [&](const PointLight& light, const Vec3& wi, const Vec3& wo, double g) {
            if (point.shadow) {
                g *= point.shadow[&light - lights.data()];
                if (!(g > 0.0)) return;
            }
            ++evaluations;
            terms.lambert += m.kd * kInvPi * light.intensity * g;
            if (m.specularOn)
                terms.specular +=
                    evalBrdf(m.specular, wi, wo) * m.specularScale * light.intensity * g;
        });
    terms.lambert = point.colour * terms.lambert;
    terms.specular = point.highlight * terms.specular;
    return terms;
}

Spectrum directLighting(const Material& m, const Frame& frameIn, const Vec3& position,
                        const Vec3& toViewer, const std::vector<PointLight>& lights,
                        const double* shadow = nullptr) {
    const Frame frame = facingViewer(frameIn, toViewer);
    Spectrum radiance;
    reference::forEachLightInFrame(
        lights, frame, position, toViewer,
        [&](const PointLight& light, const Vec3& wi, const Vec3& wo, double g) {
            if (shadow) {
                g *= shadow[&light - lights.data()];
                if (!(g > 0.0)) return;
            }
            Spectrum f = m.kd * kInvPi;
            if (m.specularOn) f += evalBrdf(m.specular, wi, wo) * m.specularScale;
            radiance += f * light.intensity * g;
        });
    return radiance;
}

}  // namespace reference

bool sameBits(const Spectrum& a, const Spectrum& b) {
    return std::memcmp(a.v.data(), b.v.data(), sizeof a.v) == 0;
}

// The tolerance of Ward's and Ashikhmin–Shirley's SIMD kernels (render/shading_simd.h) on a
// specular sum S = Σ f_s · s · I · g (per band, here times the highlight): |Δ| ≤ 1e-12 · S +
// 1e-290.
constexpr double kAnisoRelative = 1e-12, kAnisoAbsolute = 1e-290;

// 200 random points of material m (its specularOn is varied) against the plain loop; returns the
// number of cases. largest null: bit for bit. Otherwise (Ward's and A–S's kernels): the Lambert
// sum and the count bit for bit, the specular sum within kAniso…, shade() within that plus the
// rounding of the sums it adds the difference to (1e-14 of the value); half of the viewers near a
// light's mirror direction (the highlight, where the power matters), and *largest the largest
// |Δ specular| / S seen.
int checkAgainstThePlainLoop(Material m, const std::string& name, Rng& rng,
                             double* largest = nullptr) {
    const auto uniform = [&](double lo, double hi) { return lo + (hi - lo) * rng.uniform(); };
    const auto unit = [&] {
        for (;;) {
            const Vec3 v(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
            if (v.length2() > 1e-4 && v.length2() <= 1.0) return normalized(v);
        }
    };
    int cases = 0;
    for (int trial = 0; trial < 200; ++trial) {
        const int n = 1 + trial % 11;
        std::vector<PointLight> lights;
        std::vector<double> shadow;
        const Vec3 p(uniform(-50, 50), uniform(-50, 50), uniform(-50, 50));
        for (int i = 0; i < n; ++i) {
            const Vec3 at = trial % 17 == 0 && i == n - 1 ? p  // a light at the point: skipped
                                                          : p + unit() * uniform(0.5, 400.0);
            lights.push_back({at, Spectrum(uniform(10, 1e5), uniform(10, 1e5), 50.0)});
            shadow.push_back(i % 4 == 3 ? 0.0 : uniform(0.0, 1.0));
        }
        ShadingPoint point;
        point.material = &m;
        point.colour = Spectrum(0.9, 0.6, 0.3);
        point.highlight = trial % 2 ? Spectrum(1.0) : point.colour;
        point.position = p;
        point.frame = Frame::fromNormalAndAxis(unit(), Vec3(0, 0, 1), Vec3(1, 0, 0));
        point.shadow = trial % 3 == 0 ? shadow.data() : nullptr;
        m.specularOn = trial % 13 != 0;
        Vec3 toViewer = unit();
        if (largest && trial % 2) {
            const Vec3 n = point.frame.n, toLight = normalized(lights[0].position - p);
            const Vec3 mirror = n * (2.0 * n.dot(toLight)) - toLight;
            if (mirror.length2() > 0.5) toViewer = normalized(mirror + unit() * 0.02);
        }

        long long expectedCount = 0, count = 0;
        const ShadingTerms a = shadeTerms(point, toViewer, lights);
        const ShadingTerms b = reference::shadeTerms(point, toViewer, lights, expectedCount);
        EXPECT_TRUE(sameBits(a.lambert, b.lambert)) << name << " trial " << trial;
        const Spectrum L = shade(point, toViewer, lights, count);
        EXPECT_EQ(count, expectedCount) << name << " trial " << trial;
        if (largest) {
            Spectrum ref = b.lambert + b.specular;
            if (point.highlight == point.colour)
                ref = point.colour *
                      reference::directLighting(m, point.frame, p, toViewer, lights, point.shadow);
            for (int band = 0; band < 3; ++band) {
                const double S = b.specular[band], d = std::abs(a.specular[band] - S);
                EXPECT_LE(d, kAnisoRelative * S + kAnisoAbsolute)
                    << name << " trial " << trial << " band " << band << ": " << a.specular[band]
                    << " against " << S;
                EXPECT_LE(std::abs(L[band] - ref[band]),
                          kAnisoRelative * S + kAnisoAbsolute + 1e-14 * std::abs(ref[band]))
                    << name << " trial " << trial << " band " << band;
                if (S > 0.0) *largest = std::max(*largest, d / S);
            }
            ++cases;
            continue;
        }
        EXPECT_TRUE(sameBits(a.specular, b.specular)) << name << " trial " << trial;
        if (point.highlight == point.colour) {
            const Spectrum ref =
                point.colour *
                reference::directLighting(m, point.frame, p, toViewer, lights, point.shadow);
            EXPECT_TRUE(sameBits(L, ref)) << name << " " << trial;
            EXPECT_TRUE(sameBits(directLighting(m, point.frame, p, toViewer, lights, true),
                                 reference::directLighting(m, point.frame, p, toViewer, lights)))
                << name << " trial " << trial;
        } else {
            EXPECT_TRUE(sameBits(L, b.lambert + b.specular)) << name << " " << trial;
        }
        ++cases;
    }
    return cases;
}

// Ward and Ashikhmin–Shirley with their default parameters (one shape for all bands) take their
// SIMD kernels: within the kernels' tolerance (the test after the next).
TEST(Shading, FastLightLoopEqualsThePlainOneBitForBit) {
    Rng rng(31, 7);
    int cases = 0;
    for (const BrdfModelInfo& info : brdfModels()) {
        Material m;
        m.specular = makeBrdf(info.name);
        m.kd = Spectrum(0.2, 0.5, 0.7);
        m.specularScale = 0.8;
        const std::string name = info.name;
        double largest = 0.0;
        const bool kernel = name == "ward" || name == "ashikhmin_shirley";
        cases += checkAgainstThePlainLoop(m, name, rng, kernel ? &largest : nullptr);
    }
    EXPECT_EQ(cases, 200 * int(brdfModels().size()));
}

// Phong with one whole exponent goes through the SIMD kernel (render/shading_simd.h); the other
// exponents through the model's own loop. Every form against the plain loop, bit for bit: whole
// exponents 0, 1, 2, 30 (T2's) and the largest, 1024; fractional and > 1024 ones (std::pow);
// per-band exponents; ks of 0 and a specular scale other than 1.
TEST(Shading, PhongKernelEqualsThePlainLoopBitForBit) {
    const std::vector<Spectrum> exponents = {Spectrum(0.0),    Spectrum(1.0),       Spectrum(2.0),
                                             Spectrum(30.0),   Spectrum(1024.0),    Spectrum(7.5),
                                             Spectrum(2000.0), Spectrum(10, 20, 30)};
    // On every SIMD target this CPU runs (the kernel and the light directions are dispatched).
    int targets = 0;
    for (const int64_t target : hwy::SupportedAndGeneratedTargets()) {
        hwy::SetSupportedTargetsForTest(target);
        Rng rng(32, 3);
        int cases = 0;
        for (const Spectrum& e : exponents) {
            for (const Spectrum& ks : {Spectrum(0.3), Spectrum(0.9, 0.4, 0.0)}) {
                Material m;
                Phong phong;
                phong.exponent = e;
                phong.ks = ks;
                m.specular = phong;
                m.kd = Spectrum(0.8, 0.75, 0.1);
                m.specularScale = 1.7;
                cases += checkAgainstThePlainLoop(
                    m, std::string(hwy::TargetName(target)) + " phong " + std::to_string(e[2]),
                    rng);
            }
        }
        EXPECT_EQ(cases, 200 * 2 * int(exponents.size()));
        ++targets;
    }
    hwy::SetSupportedTargetsForTest(0);
    EXPECT_GE(targets, 1);
}

// Ward and Ashikhmin–Shirley with one shape for all bands go through their SIMD kernels
// (render/shading_simd.h): every target this CPU runs against the plain loop with evalBrdf
// (std::exp, std::pow), the specular sums within |Δ| ≤ 1e-12 · S + 1e-290 and the rest bit for bit
// (checkAgainstThePlainLoop). The shapes span the parameter ranges (Ward αx, αy ∈ [1e-3, 1];
// A–S nu, nv ∈ [0, 1e6], where (h.z)^e underflows), with per-band reflectances and a zero one;
// per-band shapes take the model's own loop, bit for bit. The kernels do differ from the loop (the
// largest difference is > 0: the comparison is not vacuous, and fails without the kernels).
TEST(Shading, AnisoKernelsAreThePlainLoopWithinTheirTolerance) {
    std::vector<std::pair<std::string, Material>> shared, perBand;
    const auto add = [](std::vector<std::pair<std::string, Material>>& to, const std::string& name,
                        const Brdf& brdf) {
        Material m;
        m.specular = brdf;
        m.kd = Spectrum(0.8, 0.75, 0.1);
        m.specularScale = 1.7;
        to.push_back({name, m});
    };
    for (const auto& [ax, ay] : std::vector<std::pair<double, double>>{
             {0.05, 0.3}, {1e-3, 1e-3}, {1.0, 1e-3}, {1.0, 1.0}, {0.2, 0.2}}) {
        for (const Spectrum& rho : {Spectrum(0.05), Spectrum(0.9, 0.4, 0.0)}) {
            Ward w;
            w.alphaX = Spectrum(ax);
            w.alphaY = Spectrum(ay);
            w.rhoS = rho;
            add(shared, "ward " + std::to_string(ax) + " " + std::to_string(ay), w);
        }
    }
    for (const auto& [nu, nv] : std::vector<std::pair<double, double>>{
             {10.0, 1000.0}, {0.0, 0.0}, {1.0, 1.0}, {1e6, 1e6}, {1e6, 0.0}, {100.0, 100.0}}) {
        for (const Spectrum& rs : {Spectrum(0.05), Spectrum(0.9, 0.4, 0.0)}) {
            AshikhminShirley as;
            as.nu = Spectrum(nu);
            as.nv = Spectrum(nv);
            as.rs = rs;
            add(shared, "A-S " + std::to_string(nu) + " " + std::to_string(nv), as);
        }
    }
    Ward wardBands;
    wardBands.alphaX = Spectrum(0.05, 0.1, 0.05);
    add(perBand, "ward per band", wardBands);
    AshikhminShirley asBands;
    asBands.nv = Spectrum(1000.0, 1000.0, 10.0);
    add(perBand, "A-S per band", asBands);

    int targets = 0;
    for (const int64_t target : hwy::SupportedAndGeneratedTargets()) {
        hwy::SetSupportedTargetsForTest(target);
        const std::string targetName = hwy::TargetName(target);
        Rng rng(34, 9);
        double largest = 0.0;
        int cases = 0;
        for (const auto& [name, m] : shared)
            cases += checkAgainstThePlainLoop(m, targetName + " " + name, rng, &largest);
        for (const auto& [name, m] : perBand)
            cases += checkAgainstThePlainLoop(m, targetName + " " + name, rng);
        EXPECT_EQ(cases, 200 * int(shared.size() + perBand.size()));
        EXPECT_GT(largest, 0.0) << targetName;
        std::printf("%s: largest specular difference / S: %.17g\n", targetName.c_str(), largest);
        ++targets;
    }
    hwy::SetSupportedTargetsForTest(0);
    EXPECT_GE(targets, 1);
}

// Ashikhmin–Shirley with wi ≈ −wo at the horizon: wi = (0, 1, 7e-155), wo = (1e-154, −1, 7e-155),
// |wi + wo|² ≈ 2.96e-308 is below twice the smallest normal double, where Imath's length() takes
// its tiny-vector path. There h.z ≈ 0.81, and with nu = 3200 f_s ≈ 1e23 is not clamped: the
// kernel hands such a point back and the model's loop lights it — bit for bit (the kernel's own
// power would differ from std::pow's).
TEST(Shading, AnisoKernelLeavesATinyHalfVectorToTheLoop) {
    Material m;
    AshikhminShirley as;
    as.nu = Spectrum(3200.0);
    as.nv = Spectrum(0.0);
    m.specular = as;
    m.kd = Spectrum(0.2);
    ShadingPoint point;
    point.material = &m;
    point.colour = Spectrum(0.9, 0.6, 0.3);
    point.highlight = Spectrum(1.0);
    point.frame = Frame();  // t = x, b = y, n = z
    const std::vector<PointLight> lights = {{Vec3(0.0, 100.0, 7e-153), Spectrum(1e3)}};
    const Vec3 toViewer(1e-154, -1.0, 7e-155);
    const Vec3 sum = Vec3(0.0, 1.0, 7e-155) + toViewer;
    EXPECT_LT(sum.length2(), 2.0 * std::numeric_limits<double>::min());
    const Spectrum f = evalBrdf(m.specular, Vec3(0.0, 1.0, 7e-155), toViewer);
    EXPECT_GT(f[0], 1e15);
    EXPECT_LT(f[0], kMaxBrdfValue);
    for (const int64_t target : hwy::SupportedAndGeneratedTargets()) {
        hwy::SetSupportedTargetsForTest(target);
        long long n = 0;
        const ShadingTerms a = shadeTerms(point, toViewer, lights);
        const ShadingTerms b = reference::shadeTerms(point, toViewer, lights, n);
        EXPECT_EQ(n, 1);
        EXPECT_GT(b.specular[0], 0.0);
        EXPECT_TRUE(sameBits(a.lambert, b.lambert)) << hwy::TargetName(target);
        EXPECT_TRUE(sameBits(a.specular, b.specular)) << hwy::TargetName(target);
    }
    hwy::SetSupportedTargetsForTest(0);
}

}  // namespace
}  // namespace lobe

namespace lobe {
namespace {

// The light loop reads the lights from a per-thread table (core/light_table.h). Lights changed in
// place — the same vector, the same address — must be seen at the next point, as must a second
// set of lights used in between: every light loop (the Phong kernel and the others) against the
// plain loop after each change.
TEST(Shading, LightTableFollowsLightsChangedInPlace) {
    Material phong, ward;
    phong.specular = Phong{};
    ward.specular = Ward{};
    ShadingPoint point;
    point.colour = Spectrum(0.9, 0.6, 0.3);
    point.highlight = Spectrum(1.0);
    point.position = Vec3(1, 2, 3);
    point.frame =
        Frame::fromNormalAndAxis(normalized(Vec3(0.1, 0.2, 1)), Vec3(0, 0, 1), Vec3(1, 0, 0));
    const Vec3 toViewer = normalized(Vec3(0.3, -0.1, 1));
    std::vector<PointLight> lights = {{Vec3(4, 5, 20), Spectrum(100.0)},
                                      {Vec3(-3, 1, 15), Spectrum(50.0)}};
    const std::vector<PointLight> others = {{Vec3(2, -6, 9), Spectrum(70.0)}};
    for (int change = 0; change < 4; ++change) {
        if (change == 1) lights[0].intensity = Spectrum(400.0, 30.0, 5.0);
        if (change == 2) lights[1].position = Vec3(6, 6, 8);
        if (change == 3) lights.push_back({Vec3(0, 0, 30), Spectrum(9.0)});
        for (const Material* m : {&phong, &ward}) {
            point.material = m;
            long long n = 0;
            const ShadingTerms a = shadeTerms(point, toViewer, lights);
            const ShadingTerms b = reference::shadeTerms(point, toViewer, lights, n);
            EXPECT_TRUE(sameBits(a.lambert, b.lambert)) << change;
            EXPECT_TRUE(sameBits(a.specular, b.specular)) << change;
            const ShadingTerms c = shadeTerms(point, toViewer, others);
            const ShadingTerms d = reference::shadeTerms(point, toViewer, others, n);
            EXPECT_TRUE(sameBits(c.lambert, d.lambert)) << change;
        }
    }
}

}  // namespace
}  // namespace lobe

namespace lobe {
namespace {

// ShadingPoint::setNormal leaves the tangents to shading. Every model but Phong with one whole
// exponent builds the same frame then (frameOf): bit for bit the framed point's radiance. Phong
// with one whole exponent is lit frame-free (render/shading_simd.h): its Lambert sum bit for bit,
// its specular sum within 1e-12 of the framed one relative to Σ ks · s · I · cos θi / d² (the sum
// with cos α = 1, i.e. exponent 0) — cos α rounds differently, by a few ulps, and the power
// multiplies that by at most the exponent (1024 · 4 ulps ≈ 1e-12).
TEST(Shading, FrameFreePhongIsTheFramedOneWithinItsTolerance) {
    Rng rng(33, 5);
    const auto uniform = [&](double lo, double hi) { return lo + (hi - lo) * rng.uniform(); };
    const auto unit = [&] {
        for (;;) {
            const Vec3 v(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
            if (v.length2() > 1e-4 && v.length2() <= 1.0) return normalized(v);
        }
    };
    std::vector<Material> materials;
    for (const double e : {0.0, 1.0, 2.0, 30.0, 40.0, 1024.0}) {
        Material m;
        Phong phong;
        phong.exponent = Spectrum(e);
        phong.ks = Spectrum(0.4, 0.3, 0.2);
        m.specular = phong;
        m.kd = Spectrum(0.8, 0.7, 0.6);
        m.specularScale = 1.3;
        materials.push_back(m);
    }
    const size_t phongs = materials.size();
    for (const char* name : {"ward", "ashikhmin_shirley", "he_torrance", "lambert"}) {
        Material m;
        m.specular = makeBrdf(name);
        materials.push_back(m);
    }
    Material phongFractional = materials[1];
    std::get<Phong>(phongFractional.specular).exponent = Spectrum(7.5);
    materials.push_back(phongFractional);
    double largest = 0.0;
    long long framedCount = 0, freeCount = 0;
    for (size_t i = 0; i < materials.size(); ++i) {
        Material& m = materials[i];
        Material exponent0 = m;  // the bound: the same material with cos^0 α
        if (i < phongs) std::get<Phong>(exponent0.specular).exponent = Spectrum(0.0);
        for (int trial = 0; trial < 400; ++trial) {
            const int n = 1 + trial % 6;
            std::vector<PointLight> lights;
            std::vector<double> shadow;
            const Vec3 p(uniform(-50, 50), uniform(-50, 50), uniform(-50, 50));
            for (int k = 0; k < n; ++k) {
                lights.push_back({p + unit() * uniform(0.5, 400.0),
                                  Spectrum(uniform(10, 1e5), uniform(10, 1e5), 50.0)});
                shadow.push_back(k % 3 == 2 ? 0.0 : uniform(0.0, 1.0));
            }
            const Vec3 normal = unit(), axis = trial % 5 ? unit() : normal, fallback(1, 0, 0);
            ShadingPoint framed;
            framed.material = &m;
            framed.colour = Spectrum(0.9, 0.6, 0.3);
            framed.highlight = trial % 2 ? Spectrum(1.0) : framed.colour;
            framed.position = p;
            framed.shadow = trial % 4 == 0 ? shadow.data() : nullptr;
            m.specularOn = trial % 11 != 0;
            ShadingPoint free = framed;
            framed.frame = Frame::fromNormalAndAxis(normal, axis, fallback);
            free.setNormal(normal, axis, fallback);
            ShadingPoint bound = framed;
            bound.material = &exponent0;
            exponent0.specularOn = m.specularOn;
            // The viewer near the mirror direction of a light half of the time: the highlight.
            Vec3 toViewer = unit();
            if (trial % 2) {
                const Vec3 toLight = normalized(lights[0].position - p);
                toViewer =
                    normalized(normal * (2.0 * normal.dot(toLight)) - toLight + unit() * 0.01);
            }

            const ShadingTerms a = shadeTerms(framed, toViewer, lights);
            const ShadingTerms b = shadeTerms(free, toViewer, lights);
            const ShadingTerms c = shadeTerms(bound, toViewer, lights);
            const Spectrum la = shade(framed, toViewer, lights, framedCount);
            const Spectrum lb = shade(free, toViewer, lights, freeCount);
            EXPECT_TRUE(sameBits(a.lambert, b.lambert)) << i << " " << trial;
            if (i >= phongs) {  // the same frame, built later: the same bits
                EXPECT_TRUE(sameBits(a.specular, b.specular)) << i << " " << trial;
                EXPECT_TRUE(sameBits(la, lb)) << i << " " << trial;
                continue;
            }
            for (int band = 0; band < 3; ++band) {
                const double scale = 1e-12 * c.specular[band];
                const double d = std::abs(a.specular[band] - b.specular[band]);
                EXPECT_LE(d, scale) << i << " " << trial;
                // shade: colour × (both) or the two terms, so the bound with the colour
                EXPECT_LE(std::abs(la[band] - lb[band]),
                          1e-12 * (c.specular[band] + a.lambert[band] + b.lambert[band]) +
                              1e-15 * std::abs(la[band]))
                    << i << " " << trial;
                if (c.specular[band] > 0.0) largest = std::max(largest, d / c.specular[band]);
            }
        }
    }
    EXPECT_EQ(framedCount, freeCount);
    EXPECT_GT(largest, 0.0);  // the paths do differ: the comparison above is not vacuous
    std::printf("largest specular difference / bound: %.3g\n", largest);
}

}  // namespace
}  // namespace lobe
