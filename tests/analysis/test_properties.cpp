// The property measurements of materials/properties.{h,cpp} against cases with known answers:
// analytic directional albedos, a model that is non-reciprocal and one that is anisotropic by
// construction, the isotropic limits, determinism across thread counts, and the transcription of
// the paper's Table 1.
#include "analysis/properties.h"
#include "core/tile_scheduler.h"
#include "materials/registry.h"

#include <gtest/gtest.h>

#include <cmath>

namespace lobe {
namespace {

// Analytic albedos at normal incidence, wi = n, so r(wi) = n and cos α = cos θo
// (tests/materials/reference_values.py prints them):
//  Phong: a(0) = ks ∫ cos^n θ cos θ dω = ks · 2π/(n + 2).
//  Schlick–Lewis: a(0) = ks (n + 2) ∫_0^1 u²/(n − (n − 1)u) du (Simpson, 2·10^6 intervals):
//   n = 1: 0.8 (S(u) = u: Lewis' normalisation is exact); n = 10: 1.313692303531242;
//   n = 100: 2.6281569616852885. Lewis' (n+2)/2π normalises cos^n, but Schlick's S(u) has a
//   much heavier tail than cos^n (S(0.9) = 0.47 at n = 10, 0.9^10 = 0.35), so the albedo
//   exceeds 1 for n > 1: a measured finding, reported by `lobe brdf props`.
TEST(Properties, AlbedoMatchesAnalyticValuesAtNormalIncidence) {
    struct Case {
        const char* model;
        const char* exponent;
        double expected;
    };
    const Case cases[] = {
        {"phong", "exponent=1", 0.8 * 2.0 * kPi / 3.0},
        {"phong", "exponent=10", 0.8 * 2.0 * kPi / 12.0},
        {"phong", "exponent=100", 0.8 * 2.0 * kPi / 102.0},
        {"schlick_lewis", "exponent=1", 0.8},
        {"schlick_lewis", "exponent=10", 1.313692303531242},
        {"schlick_lewis", "exponent=100", 2.6281569616852885},
    };
    for (const Case& c : cases) {
        const Brdf brdf = makeBrdf(c.model, {c.exponent});
        const SpectrumEstimate a = directionalAlbedo(brdf, 0.0, 0.0, 65536, 8, 3);
        for (int b = 0; b < kBandCount; ++b) {
            // The standard error is small (the estimator resolves the lobe) and honest (the
            // true value lies within 4 of them).
            EXPECT_LT(a.stdError[b], 3e-3 * c.expected) << c.model << " " << c.exponent;
            EXPECT_NEAR(a.value[b], c.expected, 4.0 * a.stdError[b] + 1e-12)
                << c.model << " " << c.exponent;
        }
    }
}

// Lambert: a(θi) = kd for every θi (∫ cos θo dωo = π), so the measured curve is flat, never
// conserving-violating, and shows no "Fresnel behaviour".
TEST(Properties, LambertAlbedoIsKdAtEveryAngle) {
    PropertyOptions options;
    const PropertyReport r = measureProperties({"lambert", "kd=1", {"kd=1"}}, options);
    ASSERT_EQ(r.albedo.size(), albedoThetasDeg().size());
    for (const Estimate& a : r.albedo) EXPECT_NEAR(a.value, 1.0, 4.0 * a.stdError + 1e-12);
    EXPECT_TRUE(r.reciprocal);
    EXPECT_FALSE(r.anisotropic);
    EXPECT_TRUE(r.energyConserving);
    EXPECT_FALSE(r.fresnel);
    EXPECT_NEAR(r.albedoRatio80To0.value, 1.0, 4.0 * r.albedoRatio80To0.stdError);
}

// Phong's value is a function of cos α, symmetric and rotation invariant (rounding only);
// Strauss' j uses F(x(θi)) alone, so swapping wi and wo changes it.
TEST(Properties, ReciprocityErrorSeparatesSymmetricFromAsymmetricDefinitions) {
    EXPECT_LT(reciprocityError(makeBrdf("phong"), 20000, 1), 1e-12);
    EXPECT_GT(reciprocityError(makeBrdf("strauss"), 20000, 1), 1e-2);
}

// Ward with αx ≠ αy weighs H·t and H·b differently: rotating both directions changes f by
// O(1). With αx = αy the exponent depends on (H·t)² + (H·b)² only: rotation invariant.
// Lafortune likewise with cx ≠ cy versus cx = cy. The isotropic bound is 1e-9, not 1e-16:
// rotation changes H.x, H.y by rounding (≈1e-16 relative), and exp(x) turns an absolute error δ
// in x into a relative error δ, with |x| up to ~1e3 for directions far from the lobe.
TEST(Properties, AnisotropyMeasureSeparatesIsotropicFromAnisotropic) {
    EXPECT_GT(anisotropyMeasure(makeBrdf("ward"), 20000, 1), 0.1);
    EXPECT_LT(anisotropyMeasure(makeBrdf("ward", {"alpha_x=0.1", "alpha_y=0.1"}), 20000, 1), 1e-9);
    EXPECT_GT(anisotropyMeasure(makeBrdf("lafortune", {"cy=-0.6"}), 20000, 1), 0.1);
    EXPECT_LT(anisotropyMeasure(makeBrdf("lafortune"), 20000, 1), 1e-9);
}

TEST(Properties, ResultsDoNotDependOnTheThreadCount) {
    PropertyOptions options;
    options.albedoSamples = 2048;
    options.pairs = 10000;
    PropertyReport one, two;
    const ModelSetting setting{"ward", "defaults", {}};
    runWithThreads(1, [&] { one = measureProperties(setting, options); });
    runWithThreads(2, [&] { two = measureProperties(setting, options); });
    EXPECT_EQ(one.reciprocityError, two.reciprocityError);
    EXPECT_EQ(one.anisotropy, two.anisotropy);
    ASSERT_EQ(one.albedo.size(), two.albedo.size());
    for (size_t i = 0; i < one.albedo.size(); ++i)
        EXPECT_EQ(one.albedo[i].value, two.albedo[i].value);
}

// Every registered model is measured at its defaults, and every sweep entry parses.
TEST(Properties, SweepCoversEveryRegisteredModelAndParses) {
    const auto settings = propertySettings();
    for (const BrdfModelInfo& m : brdfModels()) {
        bool found = false;
        for (const ModelSetting& s : settings) found |= s.model == m.name && s.label == "defaults";
        EXPECT_TRUE(found) << m.name;
    }
    for (const ModelSetting& s : settings)
        EXPECT_NO_THROW(makeBrdf(s.model, s.settings)) << s.label;
}

// Koldenhof 2003 Table 1: the score is the number of properties listed.
TEST(Properties, PaperTableTranscriptionIsConsistent) {
    int found = 0;
    for (const char* name : {"phong", "strauss", "schlick_lewis", "ward", "cook_torrance",
                             "poulin_fournier", "he_torrance", "lafortune", "ashikhmin_shirley"}) {
        const PaperClaims c = paperClaims(name);
        ASSERT_TRUE(c.found) << name;
        EXPECT_EQ(c.score, int(c.plausible) + int(c.fresnel) + int(c.anisotropic) + int(c.popular))
            << name;
        found += c.found;
    }
    EXPECT_EQ(found, 9);
    EXPECT_FALSE(paperClaims("lambert").found);
    EXPECT_EQ(paperClaims("ward").score, 4);
    EXPECT_EQ(paperClaims("poulin_fournier").score, 0);
}

// The table's printed order (by score, ties as printed), which `lobe brdf props` follows: rows
// 0..8 once each, scores never falling down the table.
TEST(Properties, PaperTableRowsAreThePrintedOrder) {
    const char* printed[] = {
        "poulin_fournier", "phong",       "lafortune",         "strauss", "schlick_lewis",
        "cook_torrance",   "he_torrance", "ashikhmin_shirley", "ward"};
    int previousScore = -1;
    for (int row = 0; row < 9; ++row) {
        const PaperClaims c = paperClaims(printed[row]);
        EXPECT_EQ(c.tableRow, row) << printed[row];
        EXPECT_GE(c.score, previousScore) << printed[row];
        previousScore = c.score;
    }
    EXPECT_EQ(paperClaims("lambert").tableRow, -1);
}

}  // namespace
}  // namespace lobe
