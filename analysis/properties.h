// Measured properties of the reflection models: the quantities of docs/models.md,
// "Properties to measure, not assume", which the paper's Table 1 (Koldenhof 2003, "BRDF model
// selection") lists as claims. `lobe brdf props`, docs/brdf-properties.md and the generic tests
// all use these functions, so the table and the tests measure the same thing.
//
//   reciprocity error  max |f(wi,wo) − f(wo,wi)| / max f over random pairs (max over bands);
//   directional albedo a(θi) = ∫ f(wi,wo) cos θo dωo, by stratified multi-sample importance
//                      sampling with a standard error from independent replicas;
//   anisotropy         max |f(R wi, R wo) − f(wi, wo)| / max f for random rotations R about n;
//   Fresnel behaviour  a(80°) > a(0°);   physically plausible = reciprocal and a(θi) ≤ 1 for all
//   θi.
//
// Everything is deterministic for a given seed and independent of the thread count.
#pragma once

#include "materials/brdf.h"

#include <cstdint>
#include <string>
#include <vector>

namespace lobe {

// A value with its one-sigma Monte Carlo standard error.
struct Estimate {
    double value = 0.0;
    double stdError = 0.0;
};

// Directional albedo per band of `brdf` for wi at polar angle thetaI and azimuth phiI (radians,
// local frame). `samples` evaluations in total, split into `replicas` independent stratified
// estimates whose spread gives the standard error (replicas ≥ 2).
//
// Estimator: a third of the samples per replica from each of three densities, combined with
// Veach's balance heuristic (multi-sample MIS, Veach 1997, eq. 9.13): the cosine-weighted
// hemisphere; a "scale-free" density around the mirror direction r(wi) (angle from r
// log-uniform in [1e-4, π], azimuth uniform); and the same scale-free density for the half
// vector about n, reflected into wo. The two scale-free densities resolve lobes of any width
// from 1e-4 rad up, mirror-centred and half-vector (also at grazing incidence, where a
// half-vector lobe is stretched and off the mirror direction), with a variance that grows only
// with log(width); the cosine density covers everything else (off-specular, retro-reflection).
struct SpectrumEstimate {
    Spectrum value;
    Spectrum stdError;
};
SpectrumEstimate directionalAlbedo(const Brdf& brdf, double thetaI, double phiI, int64_t samples,
                                   int replicas, uint64_t seed);

// max over bands of max |f(wi,wo) − f(wo,wi)| / max f, over `pairs` random pairs (wi uniform on
// the upper hemisphere; wo half uniform, half from the mirror density above, so that many pairs lie
// inside narrow lobes). Returns 0 when f is 0 for every pair.
double reciprocityError(const Brdf& brdf, int64_t pairs, uint64_t seed);

// max over bands of max |f(R wi, R wo) − f(wi, wo)| / max f, with R a random rotation about n per
// pair; pairs drawn as for reciprocityError. 0 for an isotropic model up to rounding.
double anisotropyMeasure(const Brdf& brdf, int64_t pairs, uint64_t seed);

// Decision thresholds (documented in docs/brdf-properties.md).
// Relative asymmetry below which a model counts as reciprocal / isotropic: far above rounding of
// symmetric formulas (≈1e-13 even through a power of 1000) and above the 1e-6 relative accuracy of
// quadrature-based models (Poulin–Fournier), far below any modelled asymmetry (Strauss: ≈0.1).
constexpr double kReciprocityTolerance = 1e-5;
constexpr double kAnisotropyTolerance = 1e-5;
// A property decided from Monte Carlo estimates needs the difference to exceed this many
// standard errors. 4, not 2 or 3: each σ is itself estimated from 16 replicas (Student t with 15
// degrees of freedom, P(t > 4) ≈ 6e-4), and a(θi) ≤ 1 is checked at 33 (θi, φi) points per
// setting, so a model exactly at the bound (lambert kd=1) must not be flagged by chance.
constexpr double kSigmaThreshold = 4.0;

// One measured configuration: a registered model and parameter overrides (key=value).
struct ModelSetting {
    std::string model;
    std::string label;  // "defaults" or the overrides joined by spaces
    std::vector<std::string> settings;
};

// Every registered model at its defaults, plus the documented sweep (properties.cpp,
// kSweep) for the models that are registered. Models in the registry with no sweep entry are
// measured at their defaults only.
std::vector<ModelSetting> propertySettings();

// Factor by which a model's sample counts are scaled down because one evaluation is slow
// (1 for the closed-form models; documented in properties.cpp).
double sampleScale(const std::string& model);

struct PropertyOptions {
    int64_t albedoSamples = 8192;  // per (θi, φi) albedo estimate
    int replicas = 16;             // independent replicas per albedo estimate
    int64_t pairs = 65536;         // pairs for reciprocity and anisotropy each
    uint64_t seed = 20030101;
};

// The θi grid (degrees) of the albedo curve, and the φi at which every θi is measured (the
// albedo of an anisotropic model depends on the azimuth; the maximum over φi is reported).
const std::vector<double>& albedoThetasDeg();
const std::vector<double>& albedoPhisDeg();

struct PropertyReport {
    ModelSetting setting;
    double reciprocityError = 0.0;
    double anisotropy = 0.0;
    std::vector<Estimate> albedo;  // per albedoThetasDeg(), max over φi and bands
    Estimate maxAlbedo;            // max over θi
    double thetaAtMaxDeg = 0.0;
    Estimate albedoRatio80To0;  // a(80°)/a(0°) (value 0 if a(0°) = 0)
    bool reciprocal = false;
    bool energyConserving = false;  // max a(θi) ≤ 1 + kSigmaThreshold·σ
    bool plausible = false;         // reciprocal && energyConserving
    bool anisotropic = false;
    bool fresnel = false;  // a(80°) − a(0°) > kSigmaThreshold·σ
};

// Measures one setting (parallel inside, via TBB). Throws lobe::Error for a bad setting.
PropertyReport measureProperties(const ModelSetting& setting, const PropertyOptions& options);

// The paper's Table 1 claims (Koldenhof 2003, "BRDF model selection") for a registry name;
// found = false for models the paper does not list (lambert).
struct PaperClaims {
    bool found = false;
    int number = 0;  // the paper's model number (1..9)
    bool plausible = false, fresnel = false, anisotropic = false, popular = false;
    int score = 0;
    int tableRow = -1;  // the row in the paper's printed table (sorted by score), 0..8
};
PaperClaims paperClaims(const std::string& model);

}  // namespace lobe
