// The flux-overlap standard test: lattices, pair scores, ranking (docs/flux-overlap.md).
#include "analysis/overlap_ranking.h"

#include "core/camera.h"
#include "core/error.h"
#include "core/frame.h"
#include "core/light.h"
#include "core/pixel_loop.h"
#include "core/progress.h"
#include "materials/registry.h"
#include "surface/implicit_primitives.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>

namespace lobe {

const std::array<const char*, kStandardPrimitiveCount> kStandardPrimitiveNames = {"sphere", "torus",
                                                                                  "superquadric"};

namespace {

constexpr int kMaxSize = 8192;
constexpr int kMaxSamples = 4096;

// flux-overlap.md, "Lights": three point lights of unit intensity, no shadows.
const std::array<Vec3, 3> kLightPositions = {Vec3(-3, 3, 3), Vec3(3, 2, 3), Vec3(0, -3, 2.5)};

std::vector<std::string> testModels(const StandardTestOptions& options) {
    return options.models.empty() ? specularModelNames() : options.models;
}

}  // namespace

int LatticeSet::modelIndex(const std::string& name) const {
    for (size_t i = 0; i < models.size(); ++i)
        if (models[i] == name) return int(i);
    return -1;
}

void validateStandardTestOptions(const StandardTestOptions& options) {
    if (options.size < 1 || options.size > kMaxSize)
        throw Error("--size: expected a lattice side in [1, " + std::to_string(kMaxSize) +
                    "], got " + std::to_string(options.size));
    if (options.samplesPerPixel < 1 || options.samplesPerPixel > kMaxSamples)
        throw Error("--spp: expected samples per pixel in [1, " + std::to_string(kMaxSamples) +
                    "], got " + std::to_string(options.samplesPerPixel));
    if (!(options.threshold >= 0.0) || !std::isfinite(options.threshold))
        throw Error("threshold must be a finite number >= 0");
    const std::vector<std::string> models = testModels(options);
    if (models.size() < 2) throw Error("the flux-overlap test needs at least two models");
    for (const std::string& m : models) findBrdfModel(m);
    for (const auto& [model, settings] : options.settings) {
        if (std::find(models.begin(), models.end(), model) == models.end()) {
            std::string names;
            for (const std::string& m : models) names += (names.empty() ? "" : ", ") + m;
            throw Error("--set " + model + ".KEY=VALUE: '" + model +
                        "' is not one of the models of the test (" + names + ")");
        }
        parseBrdfSettings(findBrdfModel(model), settings, "--set " + model);
    }
}

LatticeSet renderStandardLattices(const StandardTestOptions& options) {
    validateStandardTestOptions(options);
    LatticeSet set;
    set.size = options.size;
    set.models = testModels(options);
    const int modelCount = int(set.models.size());
    set.data.assign(size_t(modelCount) * kStandardPrimitiveCount * 3 * set.latticeSize(), 0.0f);

    std::vector<Brdf> brdfs;
    for (const std::string& m : set.models) {
        const auto it = options.settings.find(m);
        brdfs.push_back(
            makeBrdf(m, it == options.settings.end() ? std::vector<std::string>{} : it->second));
    }
    std::vector<ImplicitPrimitive> primitives;
    for (const char* name : kStandardPrimitiveNames)
        primitives.push_back(ImplicitPrimitive::byName(name));

    // flux-overlap.md, "Camera": pinhole at (0,0,4) looking at the origin, up y, 40° vertical.
    const PinholeCamera camera(Vec3(0, 0, 4), Vec3(0, 0, 0), Vec3(0, 1, 0), 40.0, 1.0);
    const int size = options.size;
    const int spp = options.samplesPerPixel;
    std::vector<PointLight> lights;
    for (const Vec3& position : kLightPositions) lights.push_back({position, Spectrum(1.0)});

    // One image per primitive through the pixel loop; every sample's specular radiance is
    // accumulated for all models at once from one ray, hit and frame.
    ProgressReporter progress("overlap lattices", int64_t(kStandardPrimitiveCount) * size * size,
                              options.progress);
    SchedulerOptions scheduler;
    scheduler.threads = options.threads;
    scheduler.sharedProgress = &progress;
    const PixelSampling sampling{spp, options.seed};
    for (int p = 0; p < kStandardPrimitiveCount; ++p) {
        const ImplicitPrimitive& prim = primitives[size_t(p)];
        forEachPixel(size, size, sampling, scheduler, [&](const PixelSamples& samples) {
            const int x = samples.x(), y = samples.y();
            std::vector<Spectrum> acc(size_t(modelCount), Spectrum(0.0));
            samples.forEach([&](const Vec2& j, Rng&) {
                const Ray ray = camera.generateRay((x + j.x) / size, (y + j.y) / size);
                ImplicitHit hit;
                if (!prim.intersect(ray, hit)) return;  // a miss is 0
                // flux-overlap.md, "Tangent field": a = world y, or world x where |a × n| < 1e-3.
                const Frame frame =
                    Frame::fromNormalAndAxis(hit.n, Vec3(0, 1, 0), Vec3(1, 0, 0), 1e-3);
                // f_s · I/d² · cos θi with I = 1 (eq. 1.20 for a point light); nothing where the
                // viewer or the light is below the surface (docs/models.md).
                forEachLightInFrame(
                    lights, frame, hit.p, -ray.d,
                    [&](const PointLight&, const Vec3& wi, const Vec3& wo, double weight) {
                        for (int m = 0; m < modelCount; ++m)
                            acc[size_t(m)] += evalBrdf(brdfs[size_t(m)], wi, wo) * weight;
                    });
            });
            const size_t pixel = size_t(y) * size + x;
            for (int m = 0; m < modelCount; ++m)
                for (int band = 0; band < 3; ++band) {
                    const double v = acc[size_t(m)][band] / spp;
                    set.lattice(m, p, band)[pixel] = std::isfinite(v) ? float(v) : 0.0f;
                }
        });
    }
    progress.finish();
    return set;
}

std::vector<PairScore> scoreAllPairs(const LatticeSet& lattices, double threshold,
                                     OverlapVariant variant, int threads) {
    const int n = int(lattices.models.size());
    std::vector<PairScore> pairs;
    for (int a = 0; a < n; ++a)
        for (int b = a + 1; b < n; ++b) {
            PairScore p;
            p.a = a;
            p.b = b;
            p.modelA = lattices.models[a];
            p.modelB = lattices.models[b];
            pairs.push_back(p);
        }
    // One metric per (pair, primitive, band), each summed sequentially: deterministic.
    const size_t perPair = size_t(kStandardPrimitiveCount) * 3;
    std::vector<FluxOverlap> results(pairs.size() * perPair);
    runWithThreads(threads, [&] {
        tbb::parallel_for(size_t(0), results.size(), [&](size_t i) {
            const PairScore& p = pairs[i / perPair];
            const int primitive = int((i % perPair) / 3), band = int(i % 3);
            results[i] = fluxOverlap(lattices.lattice(p.a, primitive, band),
                                     lattices.lattice(p.b, primitive, band), lattices.latticeSize(),
                                     threshold);
        });
    });
    for (size_t k = 0; k < pairs.size(); ++k) {
        PairScore& p = pairs[k];
        // Score of a pair = mean of e over the 3 primitives × 3 bands (flux-overlap.md).
        for (int primitive = 0; primitive < kStandardPrimitiveCount; ++primitive) {
            double primSum = 0.0;
            for (int band = 0; band < 3; ++band) {
                const FluxOverlap& r = results[k * perPair + size_t(primitive) * 3 + band];
                p.scoreSum += r.eSum / perPair;
                p.scoreMse += r.eMse / perPair;
                primSum += r.value(variant) / 3.0;
            }
            p.perPrimitive[primitive] = primSum;
        }
        p.score = variant == OverlapVariant::Sum ? p.scoreSum : p.scoreMse;
    }
    rankPairs(pairs);
    return pairs;
}

void rankPairs(std::vector<PairScore>& pairs) {
    std::stable_sort(pairs.begin(), pairs.end(), [](const PairScore& x, const PairScore& y) {
        if (x.score != y.score) return x.score > y.score;
        return std::make_pair(x.a, x.b) < std::make_pair(y.a, y.b);
    });
    for (size_t i = 0; i < pairs.size(); ++i)
        pairs[i].rank =
            (i > 0 && pairs[i].score == pairs[i - 1].score) ? pairs[i - 1].rank : int(i) + 1;
}

RankAgreement compareRankings(const std::vector<double>& x, const std::vector<double>& y) {
    if (x.size() != y.size()) throw Error("compareRankings: lists of different length");
    // Kendall's tau-b = (C − D) / sqrt((n0 − n1)(n0 − n2)), n1/n2 the pairs tied in x/y.
    int64_t concordant = 0, discordant = 0, tiesX = 0, tiesY = 0, total = 0;
    for (size_t i = 0; i < x.size(); ++i)
        for (size_t j = i + 1; j < x.size(); ++j) {
            ++total;
            const double dx = x[i] - x[j], dy = y[i] - y[j];
            if (dx == 0.0) ++tiesX;
            if (dy == 0.0) ++tiesY;
            if (dx == 0.0 || dy == 0.0) continue;
            (dx * dy > 0.0 ? concordant : discordant)++;
        }
    RankAgreement r;
    r.discordant = int(discordant);
    r.comparable = int(concordant + discordant);
    const double denom = std::sqrt(double(total - tiesX) * double(total - tiesY));
    r.kendallTau = denom > 0.0 ? double(concordant - discordant) / denom : 1.0;
    return r;
}

std::vector<StudyRow> runConvergenceStudy(const StandardTestOptions& base,
                                          const std::vector<int>& sizes,
                                          const std::vector<int>& samplesPerPixel,
                                          OverlapVariant variant) {
    if (sizes.empty() || samplesPerPixel.empty()) throw Error("convergence study: empty grid");
    const auto run = [&](int size, int spp, double& seconds, double& cpuSeconds) {
        StandardTestOptions o = base;
        o.size = size;
        o.samplesPerPixel = spp;
        const auto start = std::chrono::steady_clock::now();
        const std::clock_t cpuStart = std::clock();  // process CPU time, all threads
        std::vector<PairScore> pairs =
            scoreAllPairs(renderStandardLattices(o), o.threshold, variant, o.threads);
        seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        cpuSeconds = double(std::clock() - cpuStart) / CLOCKS_PER_SEC;
        // Back to pair order (a, b) so lists compare element by element.
        std::sort(pairs.begin(), pairs.end(), [](const PairScore& x, const PairScore& y) {
            return std::make_pair(x.a, x.b) < std::make_pair(y.a, y.b);
        });
        return pairs;
    };
    const int refSize = *std::max_element(sizes.begin(), sizes.end());
    const int refSpp = *std::max_element(samplesPerPixel.begin(), samplesPerPixel.end());
    double refSeconds = 0.0, refCpuSeconds = 0.0;
    const std::vector<PairScore> ref = run(refSize, refSpp, refSeconds, refCpuSeconds);
    std::vector<double> refScores;
    for (const PairScore& p : ref) refScores.push_back(p.score);
    const auto bestOf = [](const std::vector<PairScore>& v, bool best) {
        return *std::max_element(v.begin(), v.end(), [&](const PairScore& x, const PairScore& y) {
            return best ? x.score < y.score : x.score > y.score;
        });
    };
    const PairScore refBest = bestOf(ref, true), refWorst = bestOf(ref, false);

    std::vector<StudyRow> rows;
    for (int size : sizes)
        for (int spp : samplesPerPixel) {
            StudyRow row;
            row.size = size;
            row.samplesPerPixel = spp;
            const bool isRef = size == refSize && spp == refSpp;
            const std::vector<PairScore> pairs =
                isRef ? ref : run(size, spp, row.seconds, row.cpuSeconds);
            if (isRef) {
                row.seconds = refSeconds;
                row.cpuSeconds = refCpuSeconds;
            }
            std::vector<double> scores;
            for (size_t i = 0; i < pairs.size(); ++i) {
                scores.push_back(pairs[i].score);
                const double rel = refScores[i] > 0.0
                                       ? std::abs(pairs[i].score - refScores[i]) / refScores[i]
                                       : std::abs(pairs[i].score);
                row.maxRelChange = std::max(row.maxRelChange, rel);
                row.meanRelChange += rel / double(pairs.size());
            }
            row.agreement = compareRankings(scores, refScores);
            const PairScore best = bestOf(pairs, true), worst = bestOf(pairs, false);
            row.sameBest = best.a == refBest.a && best.b == refBest.b;
            row.sameWorst = worst.a == refWorst.a && worst.b == refWorst.b;
            rows.push_back(row);
        }
    return rows;
}

}  // namespace lobe
