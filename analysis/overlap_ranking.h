// The flux-overlap standard test (docs/flux-overlap.md, "The standard test"; the paper's
// "Flux overlap test", Figure 6): every model's specular flux lattices for three implicit
// primitives and three bands, each rendered once and reused for all its pairs, then the metric over
// all unordered pairs and a ranking.
//
// Rendering shares the geometry between models: one ray, hit, shading frame and light set per
// pixel sample, then every model is evaluated there. Parallel over primitives × tiles (render) and
// pairs × primitives × bands (metric); every pixel sample has its own generator seeded from
// (seed, x, y, sample), so the lattices and the ranking are the same for any thread count.
#pragma once

#include "analysis/flux_overlap.h"

#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace lobe {

constexpr uint64_t kStandardTestSeed = 20030601;  // fixed seed of the jitter (any value will do)
constexpr int kStandardPrimitiveCount = 3;
extern const std::array<const char*, kStandardPrimitiveCount> kStandardPrimitiveNames;

struct StandardTestOptions {
    int size = 256;            // lattice side m = n
    int samplesPerPixel = 16;  // s² jittered samples (16 → 4×4)
    double threshold = kFluxThreshold;
    uint64_t seed = kStandardTestSeed;
    int threads = 0;        // 0: all hardware threads
    bool progress = false;  // progress display on stderr
    // Models to test; empty: specularModelNames() (the nine specular models).
    std::vector<std::string> models;
    // Parameter overrides per model, "key=value" as for the registry.
    std::map<std::string, std::vector<std::string>> settings;
};

// Flux lattices of every model: [model][primitive][band], each size×size floats, row 0 at the top.
struct LatticeSet {
    int size = 0;
    std::vector<std::string> models;
    std::vector<float> data;

    size_t latticeSize() const { return size_t(size) * size; }
    const float* lattice(int model, int primitive, int band) const {
        return &data[((size_t(model) * kStandardPrimitiveCount + primitive) * 3 + band) *
                     latticeSize()];
    }
    float* lattice(int model, int primitive, int band) {
        return &data[((size_t(model) * kStandardPrimitiveCount + primitive) * 3 + band) *
                     latticeSize()];
    }
    int modelIndex(const std::string& name) const;  // -1 if absent
};

// Validates options (size, samples, model names, settings) and throws lobe::Error before any work.
void validateStandardTestOptions(const StandardTestOptions& options);

// Renders all lattices: pixel flux per band = mean over the pixel's samples of
// Σ_lights f_s(wi, wo, λ) · I/d² · cos θi (flux-overlap.md, "Pixel flux"; paper eq. 1.20 for a
// pinhole camera and point lights), a miss is 0.
LatticeSet renderStandardLattices(const StandardTestOptions& options);

struct PairScore {
    int rank = 0;
    int a = 0, b = 0;  // model indices, a < b in the model order
    std::string modelA, modelB;
    double score = 0.0;  // of the ranking variant: mean over 3 primitives × 3 bands
    double scoreSum = 0.0, scoreMse = 0.0;
    std::array<double, kStandardPrimitiveCount> perPrimitive{};  // ranking variant, mean of bands
};

// The metric for every unordered pair, ranked by descending score; equal scores share a rank
// (competition ranking: 1, 2, 2, 4).
std::vector<PairScore> scoreAllPairs(const LatticeSet& lattices, double threshold,
                                     OverlapVariant variant, int threads = 0);

// Ranks in place: sort by descending score (ties by model order) and assign shared ranks.
void rankPairs(std::vector<PairScore>& pairs);

// Convergence helpers. Kendall's tau-b between two score lists over the same pairs (1: same order),
// and the number of pairs of pairs whose order differs (discordant, ties excluded).
struct RankAgreement {
    double kendallTau = 1.0;
    int discordant = 0;
    int comparable = 0;
};
RankAgreement compareRankings(const std::vector<double>& x, const std::vector<double>& y);

// Convergence study (benchmark and `lobe overlap --study`): the test at every lattice size ×
// samples-per-pixel combination, each compared with the largest of both (the reference).
struct StudyRow {
    int size = 0;
    int samplesPerPixel = 0;
    double seconds = 0.0;        // render + metric wall time
    double cpuSeconds = 0.0;     // the same in CPU time of all threads (robust to other jobs)
    double maxRelChange = 0.0;   // max over pairs |score − ref| / ref
    double meanRelChange = 0.0;  // mean over pairs of the same
    RankAgreement agreement;     // of the pair scores with the reference's
    bool sameBest = false, sameWorst = false;
};
std::vector<StudyRow> runConvergenceStudy(const StandardTestOptions& base,
                                          const std::vector<int>& sizes,
                                          const std::vector<int>& samplesPerPixel,
                                          OverlapVariant variant);

}  // namespace lobe
