// Measured properties of the reflection models; see properties.h for what is measured and how.
#include "analysis/properties.h"

#include "core/error.h"
#include "core/frame.h"
#include "core/rng.h"
#include "core/sampling.h"
#include "materials/registry.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace lobe {
namespace {

// ---- Sampling densities of the albedo estimator (properties.h) -------------------------------

// Smallest angle from the mirror direction the scale-free density covers; narrower lobes than
// this (exponents ≳ 1e8) are left to the cosine component.
constexpr double kMinAlpha = 1e-4;
const double kLogAlphaRange = std::log(kPi / kMinAlpha);

Vec3 directionFromAngles(double theta, double phi) {
    return Vec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
}

// Cosine-weighted hemisphere about n (Malley's method): pdf = cos θ / π.
Vec3 sampleCosine(const Vec2& u) {
    const double r = std::sqrt(u.x), phi = 2.0 * kPi * u.y;
    return Vec3(r * std::cos(phi), r * std::sin(phi), safeSqrt(1.0 - u.x));
}
double cosinePdf(const Vec3& w) { return std::max(0.0, w.z) * kInvPi; }

// Angle α from the axis r: log-uniform in [kMinAlpha, π], so p(α) = 1/(α·ln(π/kMinAlpha)); with
// a uniform azimuth the solid-angle density is p(α)/(2π sin α).
double mirrorPdfOfAngle(double alpha) {
    if (!(alpha >= kMinAlpha) || alpha >= kPi) return 0.0;
    return 1.0 / (alpha * kLogAlphaRange * 2.0 * kPi * std::sin(alpha));
}
double mirrorPdf(const Vec3& r, const Vec3& w) {
    // atan2 of |r × w| and r·w is accurate at small angles where acos(r·w) is not.
    return mirrorPdfOfAngle(std::atan2(r.cross(w).length(), r.dot(w)));
}
Vec3 sampleMirror(const Frame& frameR, const Vec2& u, double& alpha) {
    alpha = kMinAlpha * std::exp(u.x * kLogAlphaRange);
    const double phi = 2.0 * kPi * u.y;
    return frameR.toWorld(directionFromAngles(alpha, phi));
}

// Half vector h on the upper hemisphere with polar angle θh log-uniform in [kMinAlpha, π/2]
// (p(θh) = 1/(θh·ln(π/2/kMinAlpha)), uniform azimuth), reflected: wo = 2(wi·h)h − wi. The map
// h → wo has Jacobian dωo/dωh = 4|wo·h| (Walter et al. 2007, eq. 14), and every wo comes from
// exactly one upper-hemisphere h (± normalize(wi + wo)). Resolves half-vector lobes (Ward,
// Cook–Torrance, Ashikhmin–Shirley, He–Torrance) at grazing incidence, where their image in wo
// is stretched and off the mirror direction.
const double kLogHalfRange = std::log(0.5 * kPi / kMinAlpha);
Vec3 sampleHalfVector(const Vec3& wi, const Vec2& u) {
    const double thetaH = kMinAlpha * std::exp(u.x * kLogHalfRange);
    const Vec3 h = directionFromAngles(thetaH, 2.0 * kPi * u.y);
    return 2.0 * wi.dot(h) * h - wi;
}
double halfVectorPdf(const Vec3& wi, const Vec3& wo) {
    const Vec3 sum = wi + wo;
    const double len = sum.length();
    if (!(len > 1e-12)) return 0.0;
    Vec3 h = sum / len;
    if (h.z < 0.0) h = -h;
    const double sinH = std::sqrt(h.x * h.x + h.y * h.y);
    const double thetaH = std::atan2(sinH, h.z);
    const double cosWoH = std::abs(wo.dot(h));
    if (!(thetaH >= kMinAlpha) || !(sinH > 0.0) || !(cosWoH > 0.0)) return 0.0;
    return 1.0 / (thetaH * kLogHalfRange * 2.0 * kPi * sinH) / (4.0 * cosWoH);
}

// A random pair for the reciprocity and anisotropy measures: wi uniform on the upper hemisphere
// (cos θi uniform in (0, 1], so grazing pairs are as likely as any), wo alternately uniform on the
// hemisphere and drawn around the mirror direction, so that narrow lobes are hit.
void samplePair(Rng& rng, bool nearMirror, Vec3& wi, Vec3& wo) {
    const double zi = 1.0 - rng.uniform();  // (0, 1]
    wi = directionFromAngles(std::acos(zi), 2.0 * kPi * rng.uniform());
    if (nearMirror) {
        double alpha;
        wo = sampleMirror(Frame::fromNormal(mirrorLocal(wi)), Vec2(rng.uniform(), rng.uniform()),
                          alpha);
    } else {
        const double zo = 1.0 - rng.uniform();
        wo = directionFromAngles(std::acos(zo), 2.0 * kPi * rng.uniform());
    }
}

// Max over pairs of |difference| and of f, per band, for one chunk of pairs; combined later.
struct AsymmetryChunk {
    std::array<double, kBandCount> maxDiff{0.0, 0.0, 0.0};
    std::array<double, kBandCount> maxValue{0.0, 0.0, 0.0};
};

constexpr int kPairsPerChunk = 4096;

// Runs `pairs` pairs in fixed chunks (so the result does not depend on the thread count) and
// returns max over bands of maxDiff/maxValue. `other(wi, wo, rng)` returns the value compared
// with f(wi, wo).
template <class Other>
double relativeAsymmetry(const Brdf& brdf, int64_t pairs, uint64_t seed, const Other& other) {
    const int64_t chunks = std::max<int64_t>(1, (pairs + kPairsPerChunk - 1) / kPairsPerChunk);
    std::vector<AsymmetryChunk> results(static_cast<size_t>(chunks));
    tbb::parallel_for(int64_t(0), chunks, [&](int64_t c) {
        Rng rng(mixBits(seed ^ mixBits(uint64_t(c) + 1)), 7);
        AsymmetryChunk& out = results[size_t(c)];
        const int64_t end = std::min(pairs, (c + 1) * kPairsPerChunk);
        for (int64_t i = c * kPairsPerChunk; i < end; ++i) {
            Vec3 wi, wo;
            samplePair(rng, (i & 1) != 0, wi, wo);
            const Spectrum a = evalBrdf(brdf, wi, wo);
            const Spectrum b = other(wi, wo, rng);
            for (int k = 0; k < kBandCount; ++k) {
                out.maxDiff[k] = std::max(out.maxDiff[k], std::abs(a[k] - b[k]));
                out.maxValue[k] = std::max(out.maxValue[k], std::max(a[k], b[k]));
            }
        }
    });
    double worst = 0.0;
    for (int k = 0; k < kBandCount; ++k) {
        double diff = 0.0, value = 0.0;
        for (const AsymmetryChunk& r : results) {
            diff = std::max(diff, r.maxDiff[k]);
            value = std::max(value, r.maxValue[k]);
        }
        if (value > 0.0) worst = std::max(worst, diff / value);
    }
    return worst;
}

// ---- The documented sweep ----------------------------------------------------------------------

// Per model, besides the defaults: roughness / exponent low and high, and where it tests a claim,
// one more setting (isotropic or anisotropic variant, full reflectance, a metal). Entries for
// models that are not registered are skipped. docs/brdf-properties.md lists the same table.
struct SweepEntry {
    const char* model;
    std::vector<std::string> settings;
};
const std::vector<SweepEntry>& sweepTable() {
    static const std::vector<SweepEntry> table = {
        {"phong", {"exponent=1"}},
        {"phong", {"exponent=100"}},
        {"strauss", {"smoothness=0.3"}},
        {"strauss", {"smoothness=0.95"}},
        {"strauss", {"metalness=1", "color=0.5"}},
        {"schlick_lewis", {"exponent=1"}},
        {"schlick_lewis", {"exponent=100"}},
        {"ward", {"alpha_x=0.02", "alpha_y=0.12"}},
        {"ward", {"alpha_x=0.2", "alpha_y=0.8"}},
        {"ward", {"alpha_x=0.1", "alpha_y=0.1"}},
        {"ward", {"rho_s=1"}},
        {"cook_torrance", {"m=0.03"}},
        {"cook_torrance", {"m=0.3"}},
        {"cook_torrance", {"ks=1", "m=0.5", "eta=0.2", "kappa=3.5"}},
        {"poulin_fournier", {"exponent=20"}},
        {"poulin_fournier", {"gap=0.5"}},
        {"he_torrance", {"sigma0_over_lambda=0.2"}},
        {"he_torrance", {"sigma0_over_lambda=3"}},
        {"lafortune", {"exponent=5"}},
        {"lafortune", {"exponent=100"}},
        {"lafortune", {"cz=1"}},
        {"lafortune", {"cx=-1", "cy=-0.6"}},
        {"ashikhmin_shirley", {"nu=100", "nv=100"}},
        {"ashikhmin_shirley", {"nu=1", "nv=1"}},
        {"ashikhmin_shirley", {"rs=1"}},
        {"lambert", {"kd=1"}},
    };
    return table;
}

std::string joinSettings(const std::vector<std::string>& settings) {
    std::string s;
    for (const std::string& x : settings) s += (s.empty() ? "" : " ") + x;
    return s;
}

int indexOf(const std::vector<double>& grid, double value) {
    for (size_t i = 0; i < grid.size(); ++i)
        if (grid[i] == value) return int(i);
    return -1;
}

}  // namespace

SpectrumEstimate directionalAlbedo(const Brdf& brdf, double thetaI, double phiI, int64_t samples,
                                   int replicas, uint64_t seed) {
    if (replicas < 2) throw Error("directionalAlbedo: at least 2 replicas are needed");
    const Vec3 wi = directionFromAngles(thetaI, phiI);
    const Frame frameR = Frame::fromNormal(mirrorLocal(wi));
    // A third of each replica's samples per component, at least one.
    // (--samples is bounded, so a component's count fits the strata's int.)
    const int perComponent = int(
        std::clamp<int64_t>(samples / (3 * int64_t(replicas)), 1, std::numeric_limits<int>::max()));
    const StrataGrid grid = strataFor(perComponent);
    const auto pdfSum = [&](const Vec3& w) {
        return cosinePdf(w) + mirrorPdf(frameR.n, w) + halfVectorPdf(wi, w);
    };
    std::vector<Spectrum> estimates(replicas);
    for (int rep = 0; rep < replicas; ++rep) {
        Rng rng(mixBits(seed ^ mixBits(uint64_t(rep) + 0x51ed27)), 11);
        Spectrum sum(0.0);
        // Multi-sample MIS with the balance heuristic and equal counts n per component (Veach
        // 1997, eq. 9.13): F = (1/n) Σ over all components' samples of g(w)/Σ_k p_k(w),
        // g = f(wi, w)·cos θo.
        const auto add = [&](const Vec3& w) {
            if (!(w.z > 0.0)) return;
            const double p = pdfSum(w);
            if (p > 0.0 && std::isfinite(p)) sum += evalBrdf(brdf, wi, w) * (w.z / p);
        };
        for (int i = 0; i < perComponent; ++i) add(sampleCosine(jitteredSample(grid, i, rng)));
        for (int i = 0; i < perComponent; ++i) {
            double alpha;
            add(sampleMirror(frameR, jitteredSample(grid, i, rng), alpha));
        }
        for (int i = 0; i < perComponent; ++i)
            add(sampleHalfVector(wi, jitteredSample(grid, i, rng)));
        estimates[rep] = sum * (1.0 / perComponent);
    }
    SpectrumEstimate out;
    for (int k = 0; k < kBandCount; ++k) {
        double mean = 0.0;
        for (const Spectrum& e : estimates) mean += e[k];
        mean /= replicas;
        double var = 0.0;
        for (const Spectrum& e : estimates) var += (e[k] - mean) * (e[k] - mean);
        var /= (replicas - 1);
        out.value[k] = mean;
        out.stdError[k] = std::sqrt(var / replicas);
    }
    return out;
}

double reciprocityError(const Brdf& brdf, int64_t pairs, uint64_t seed) {
    return relativeAsymmetry(brdf, pairs, seed, [&](const Vec3& wi, const Vec3& wo, Rng&) {
        return evalBrdf(brdf, wo, wi);
    });
}

double anisotropyMeasure(const Brdf& brdf, int64_t pairs, uint64_t seed) {
    return relativeAsymmetry(brdf, pairs, seed ^ 0xa5a5,
                             [&](const Vec3& wi, const Vec3& wo, Rng& rng) {
                                 const double psi = 2.0 * kPi * rng.uniform();
                                 const double c = std::cos(psi), s = std::sin(psi);
                                 const auto rotate = [&](const Vec3& w) {
                                     return Vec3(c * w.x - s * w.y, s * w.x + c * w.y, w.z);
                                 };
                                 return evalBrdf(brdf, rotate(wi), rotate(wo));
                             });
}

std::vector<ModelSetting> propertySettings() {
    std::vector<ModelSetting> out;
    for (const BrdfModelInfo& model : brdfModels()) {
        out.push_back({model.name, "defaults", {}});
        for (const SweepEntry& e : sweepTable())
            if (model.name == e.model)
                out.push_back({e.model, joinSettings(e.settings), e.settings});
    }
    return out;
}

double sampleScale(const std::string& model) {
    // Costly models (BrdfFlags): Poulin–Fournier integrates a profile per evaluation
    // (Gauss–Kronrod on pieces of the arc) and He–Torrance sums a series and solves for z0 by
    // Newton per evaluation: both count 1/4 of the samples. Checked with all nine models registered
    // (docs/brdf-properties.md, "The sweep"): on the albedo estimator's directions PF costs ~2–3 µs
    // and HT 2.3–9.6 µs (growing with σ0/λ) per evaluation, against ~0.3 µs per sample for a
    // closed-form model, so one of their settings costs ~1–9× a closed-form one and `lobe brdf
    // props` at its defaults stays at a few seconds. (PF was at 1/32 while it cost 12–15 µs per
    // evaluation, before commit 05eae7f.)
    return findBrdfModel(model).flags.costly ? 1.0 / 4.0 : 1.0;
}

const std::vector<double>& albedoThetasDeg() {
    static const std::vector<double> thetas = {0, 10, 20, 30, 40, 50, 60, 70, 80, 85, 89};
    return thetas;
}

const std::vector<double>& albedoPhisDeg() {
    static const std::vector<double> phis = {0, 45, 90};
    return phis;
}

PropertyReport measureProperties(const ModelSetting& setting, const PropertyOptions& options) {
    const Brdf brdf = makeBrdf(setting.model, setting.settings);
    const double scale = sampleScale(setting.model);
    const int replicas = std::max(2, options.replicas);
    const int64_t samples =
        std::max<int64_t>(2 * replicas, std::llround(double(options.albedoSamples) * scale));
    const int64_t pairs = std::max<int64_t>(256, std::llround(double(options.pairs) * scale));
    const auto& thetas = albedoThetasDeg();
    const auto& phis = albedoPhisDeg();

    PropertyReport report;
    report.setting = setting;
    std::vector<SpectrumEstimate> grid(thetas.size() * phis.size());
    tbb::parallel_invoke(
        [&] {
            tbb::parallel_for(size_t(0), grid.size(), [&](size_t i) {
                const size_t t = i / phis.size(), p = i % phis.size();
                grid[i] = directionalAlbedo(brdf, radians(thetas[t]), radians(phis[p]), samples,
                                            replicas, mixBits(options.seed + 1000 * t + p));
            });
        },
        [&] { report.reciprocityError = reciprocityError(brdf, pairs, options.seed); },
        [&] { report.anisotropy = anisotropyMeasure(brdf, pairs, options.seed); });

    // a(θi): max over φi and bands, with the standard error of the maximising estimate.
    report.albedo.resize(thetas.size());
    for (size_t t = 0; t < thetas.size(); ++t) {
        Estimate best{-1.0, 0.0};
        for (size_t p = 0; p < phis.size(); ++p)
            for (int k = 0; k < kBandCount; ++k) {
                const SpectrumEstimate& e = grid[t * phis.size() + p];
                if (e.value[k] > best.value) best = {e.value[k], e.stdError[k]};
            }
        report.albedo[t] = best;
        if (t == 0 || best.value > report.maxAlbedo.value) {
            report.maxAlbedo = best;
            report.thetaAtMaxDeg = thetas[t];
        }
    }
    const Estimate a0 = report.albedo[indexOf(thetas, 0.0)];
    const Estimate a80 = report.albedo[indexOf(thetas, 80.0)];
    if (a0.value > 0.0) {
        const double r = a80.value / a0.value;
        const double rel0 = a0.stdError / a0.value;
        const double rel80 = a80.value > 0.0 ? a80.stdError / a80.value : 0.0;
        report.albedoRatio80To0 = {r, r * std::sqrt(rel0 * rel0 + rel80 * rel80)};
    }
    report.reciprocal = report.reciprocityError <= kReciprocityTolerance;
    report.anisotropic = report.anisotropy > kAnisotropyTolerance;
    report.energyConserving =
        report.maxAlbedo.value <= 1.0 + kSigmaThreshold * report.maxAlbedo.stdError;
    report.plausible = report.reciprocal && report.energyConserving;
    report.fresnel =
        a80.value - a0.value >
        kSigmaThreshold * std::sqrt(a0.stdError * a0.stdError + a80.stdError * a80.stdError);
    return report;
}

PaperClaims paperClaims(const std::string& model) {
    // Koldenhof 2003, Table 1 "BRDF scores": # BRDF | Properties | Score.
    struct Row {
        const char* name;
        PaperClaims claims;
    };
    static const Row rows[] = {
        {"poulin_fournier", {true, 6, false, false, false, false, 0}},
        {"phong", {true, 1, false, false, false, true, 1}},
        {"lafortune", {true, 8, true, false, false, false, 1}},
        {"strauss", {true, 2, false, false, false, true, 1}},
        {"schlick_lewis", {true, 3, true, false, false, true, 2}},
        {"cook_torrance", {true, 5, true, true, false, false, 2}},
        {"he_torrance", {true, 7, true, true, false, false, 2}},
        {"ashikhmin_shirley", {true, 9, true, true, true, false, 3}},
        {"ward", {true, 4, true, true, true, true, 4}},
    };
    for (const Row& r : rows)
        if (model == r.name) {
            PaperClaims claims = r.claims;
            claims.tableRow = int(&r - rows);
            return claims;
        }
    return {};
}

}  // namespace lobe
