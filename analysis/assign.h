// `lobe assign`: choose each object's BRDF to maximise the scene's separation score
// (analysis/separation.h) — the paper's "adaptive BRDF" (Koldenhof 2003, future work).
//
// The shortcut that makes it fast is exact: a render with per-model passes (render/aov.h) gives,
// for every object o and candidate BRDF m, the specular luminance S[o][m] the object would
// contribute with m, because no BRDF changes any transmittance (opacities come from transfer
// functions and object opacities; the shading roulette draws on T·α only). The rest of the image
// (every object's Lambert term and the backdrop) does not depend on the assignment either, so any
// assignment's image is base + Σ_o S[o][m_o] and its score follows without rendering.
#pragma once

#include "analysis/separation.h"

#include <cstdint>
#include <string>
#include <vector>

namespace lobe {

struct AssignmentLayers {
    SeparationLayers scene;  // objects, lambert, depth, backdrop, display; its specular unused
    std::vector<std::string> candidates;       // BRDF labels, e.g. "ward" or "ward alpha_x=0.1"
    std::vector<std::string> candidateModels;  // the model of each candidate, e.g. "ward"
    std::vector<std::vector<float>> specular;  // [object · candidates + candidate] → rgb triples
    size_t pixelCount() const { return scene.pixelCount(); }
    const std::vector<std::string>& objects() const { return scene.objects; }
    const std::vector<float>& layer(int object, int candidate) const {
        return specular[size_t(object) * candidates.size() + size_t(candidate)];
    }
};

// Sparkle: a highlight narrower than a pixel shows as isolated specks. The share of a specular
// layer's luminance (rgb triples, width × height) in pixels brighter than kSparklePeak × the
// mean of their 8 neighbours (and above 1 % of the layer's maximum, so that noise in dark
// pixels does not count): 0 for a highlight spread over several pixels, near 1 for specks.
constexpr double kSparklePeak = 4.0;
// `lobe assign` does not offer a candidate for an object when more than this share of its
// highlight there is specks.
constexpr double kSparkleLimit = 0.25;
double sparkleShare(const float* rgb, int width, int height);

// Glints: a highlight narrower than the pixel footprint is caught by some of a pixel's samples
// and missed by others, so its pixels change from one seed to the next far more than those of a
// highlight the pixel resolves. (A pixel is the box-filtered radiance over its footprint,
// estimated from spp point samples; the estimate's variance is the radiance's variance over the
// footprint divided by spp: Pharr, Jakob & Humphreys, *Physically Based Rendering* 3rd ed.,
// §7.1 and §13.1.) A candidate's layer rendered at two seeds, `rgbA` and `rgbB` (same size and
// spp), over the luminance `matteY` of the pixels without any highlight (every Lambert term and
// the backdrop): among the pixels where the highlight is seen (mean of the two ≥ kWeberContrast
// of the pixel, analysis/separation.h), the share that glint — change between the seeds by at
// least kGlintContrast of the pixel's luminance and are a speck (above kSparklePeak × the mean
// of their neighbours) at either seed. 0 for a noise-free layer or one never seen. The speck
// condition leaves out the grain of a broad lobe on a jittered volume (noisy but not isolated
// points); the contrast condition leaves out specks too dim against the pixel to be seen. The
// noise is that of the layers' spp (2 by default, no more than a final render's): a render at N
// spp has √(N / 2) times smaller differences, so the rule errs on the side of rejecting.
double glintShare(const float* rgbA, const float* rgbB, int width, int height,
                  const std::vector<double>& matteY);
// A glint: a pixel's luminance changing by a fifth between two seeds — about 8 CIELAB L* units
// at mid-grey (CIE 15:2004; L* ∝ Y^⅓, so ΔL*/L* ≈ ⅓ ΔY/Y), several times the about 1 unit a
// viewer tells apart side by side, so a single pixel that flips by that much is seen as a speck
// that comes and goes with the samples.
constexpr double kGlintContrast = 0.2;
// `lobe assign` does not offer a candidate for an object when more than this share of its seen
// highlight glints (and more than twice the median default model's share there).
constexpr double kGlintLimit = 0.03;

// The layers with `members` summed into one object `name` (analysis/separation.h mergeObjects).
AssignmentLayers mergeAssignmentObjects(const AssignmentLayers& layers, const std::string& name,
                                        const std::vector<std::string>& members);

// The separation report / score of one assignment (a candidate index per object).
SeparationReport assignmentReport(const SeparationScorer& scorer, const AssignmentLayers& layers,
                                  const std::vector<int>& assignment);
double assignmentScore(const AssignmentLayers& layers, const std::vector<int>& assignment);

struct AssignOptions {
    std::vector<int> fixed;     // per object: −1 free, else the candidate it keeps
    std::vector<bool> allowed;  // per candidate: may be chosen for a free object
    std::vector<std::vector<bool>> objectAllowed;  // per object, per candidate (empty: all)
    int top = 10;                                  // how many ranked assignments to keep
    uint64_t exhaustiveLimit = 200000;             // search every assignment up to this many
    // … and only while assignments × the pixels of the object that changes at every step (the
    // one with the fewest) stay within this many pixel updates (a pixel update costs about a
    // microsecond: some 20 s of work): beyond, the local search.
    double exhaustiveWork = 2e7;
    int restarts = 16;       // local search: random starts besides `start`
    std::vector<int> start;  // local search: a first start (e.g. the scene's own)
    uint64_t seed = 1;
    SeparationMetric metric = SeparationMetric::Weber;
    // Constraints; an assignment that breaks one is not ranked. distinct: no two objects share a
    // model (AssignmentLayers::candidateModels). Per object (empty: no bound): the least
    // visibility V and chroma C* (ObjectVisibility), and the band of its mean luminance.
    bool distinct = false;
    std::vector<double> minVisibility, minChroma, minLuminance, maxLuminance;
};

// No sparkle, whatever the candidates (defaults, --tune variants, lobes scaled to equal albedo):
// for every free object (options.fixed −1), a candidate is not offered when
// - more than kSparkleLimit of its highlight there is specks (sparkleShare on its layer: a
//   highlight narrower than a pixel) and more than twice the least specky `reference`
//   candidate's share there, or
// - with `nextSeed` (the same layers rendered at another seed), more than kGlintLimit of its seen
//   highlight glints (glintShare: specks that come and go with the samples) and more than twice
//   the median `reference` candidate's glint share there (the lower median: a glint share counts
//   a few pixels on a small structure or coarse layers, and the least of nine is often 0 by
//   chance).
// `reference`: the nine models at their defaults; on a structure a few pixels across every
// highlight is a speck and most glint, and the defaults stay. Sets options.objectAllowed; returns
// one line per candidate not offered, "object: candidate (NN % in specks, NN % glints; …)".
// sparkleShare does not depend on the layer's scale, so an equal-albedo lobe is judged by its
// shape; glintShare does where the lobe is dim against the pixel (a glint not seen does not
// count).
std::vector<std::string> excludeSparkle(const AssignmentLayers& layers,
                                        const std::vector<bool>& reference, AssignOptions& options,
                                        const AssignmentLayers* nextSeed = nullptr);

// Whether `report`'s objects keep the bounds of `options` (not the distinct rule).
bool withinBounds(const SeparationReport& report, const AssignOptions& options);

struct ScoredAssignment {
    std::vector<int> assignment;
    double score = 0.0;
};

struct AssignResult {
    std::vector<ScoredAssignment> ranked;  // best first, at most options.top; may be empty when
                                           // no assignment keeps the constraints
    uint64_t rejected = 0;                 // assignments scored but breaking a constraint
    bool exhaustive = false;
    uint64_t evaluated = 0;  // assignments scored
    uint64_t space = 0;      // assignments in the search space (saturates at UINT64_MAX)
    // When `ranked` is empty: the assignment found nearest to the bounds (least sum of relative
    // shortfalls), to say which objects could not keep them.
    std::vector<int> closest;
};

// Exhaustive when the space is at most options.exhaustiveLimit; otherwise local search: from
// `start` and `restarts` random assignments, repeatedly give each free object the candidate that
// scores best with the others held (coordinate ascent) until no object changes.
AssignResult searchAssignments(const AssignmentLayers& layers, const AssignOptions& options);

// How many admissible assignments of the exhaustive space score strictly better than `assignment`
// (its rank is this + 1); scores every assignment once.
uint64_t countBetter(const AssignmentLayers& layers, const AssignOptions& options,
                     const std::vector<int>& assignment);

}  // namespace lobe
