// Benchmark of the flux-overlap standard test (docs/flux-overlap.md): the whole default
// test (256², 4×4 samples, 3 primitives, 3 bands, every specular model, all pairs) on 2 threads,
// the lattice render of each model alone (which model dominates), and the metric alone.
//
//   lobe_bench_overlap                 the benchmarks
//   lobe_bench_overlap --study         instead: the convergence study (128²/256²/512² ×
//                                      1/4/16/64 spp against 512²/64 spp), a Markdown table on
//                                      stdout; takes minutes
#include "analysis/overlap_ranking.h"
#include "analysis/overlap_report.h"
#include "materials/registry.h"

#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <stdexcept>
#include <string>

namespace lobe {
namespace {

constexpr int kThreads = 2;  // the budget is stated for 2 cores

// The benchmark's output check: the right number of pairs, finite non-negative scores, some pair
// with separated lobes, and a thread-count-independent small render (the reference).
void checkResult(const std::vector<PairScore>& pairs, size_t models) {
    if (pairs.size() != models * (models - 1) / 2) throw std::runtime_error("wrong pair count");
    for (const PairScore& p : pairs)
        if (!std::isfinite(p.score) || p.score < 0.0) throw std::runtime_error("bad score");
    if (!(pairs.front().score > 0.0)) throw std::runtime_error("no pair scores above 0");
    StandardTestOptions small;
    small.size = 24;
    small.samplesPerPixel = 4;
    small.threads = 1;
    const LatticeSet one = renderStandardLattices(small);
    small.threads = kThreads;
    if (!(renderStandardLattices(small).data == one.data))
        throw std::runtime_error("lattices depend on the thread count");
}

void BM_DefaultTest(benchmark::State& state) {
    StandardTestOptions options;
    options.threads = kThreads;
    std::vector<PairScore> pairs;
    double renderSeconds = 0.0, metricSeconds = 0.0;
    // Process CPU time of all threads: on a shared machine the wall time depends on the other
    // jobs, cpu_s / 2 is the wall time the test would take on two free cores.
    const std::clock_t cpu0 = std::clock();
    for (auto _ : state) {
        const auto t0 = std::chrono::steady_clock::now();
        const LatticeSet lattices = renderStandardLattices(options);
        const auto t1 = std::chrono::steady_clock::now();
        pairs = scoreAllPairs(lattices, options.threshold, OverlapVariant::Sum, kThreads);
        const auto t2 = std::chrono::steady_clock::now();
        renderSeconds += std::chrono::duration<double>(t1 - t0).count();
        metricSeconds += std::chrono::duration<double>(t2 - t1).count();
    }
    checkResult(pairs, specularModelNames().size());
    state.counters["models"] = double(specularModelNames().size());
    state.counters["pairs"] = double(pairs.size());
    state.counters["render_s"] = renderSeconds / double(state.iterations());
    state.counters["metric_s"] = metricSeconds / double(state.iterations());
    state.counters["cpu_s"] =
        double(std::clock() - cpu0) / CLOCKS_PER_SEC / double(state.iterations());
    state.SetLabel("best " + pairs.front().modelA + "+" + pairs.front().modelB + ", worst " +
                   pairs.back().modelA + "+" + pairs.back().modelB);
}
BENCHMARK(BM_DefaultTest)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(2);

// One model's lattices alone at the default size (geometry + that model's evaluations); lambert
// is the baseline of geometry and lighting with an almost free BRDF.
void BM_RenderOneModel(benchmark::State& state, const std::string& model) {
    StandardTestOptions options;
    options.threads = kThreads;
    // The test asks for two models: the model plus lambert (the baseline's cost counts twice
    // in lambert_only, once here).
    options.models = {model, "lambert"};
    for (auto _ : state) {
        benchmark::DoNotOptimize(renderStandardLattices(options).data.data());
    }
}

void BM_Metric(benchmark::State& state) {
    StandardTestOptions options;
    options.threads = kThreads;
    const LatticeSet lattices = renderStandardLattices(options);
    for (auto _ : state)
        benchmark::DoNotOptimize(
            scoreAllPairs(lattices, options.threshold, OverlapVariant::Sum, kThreads).data());
}
BENCHMARK(BM_Metric)->Unit(benchmark::kMillisecond)->UseRealTime();

int runStudy() {
    StandardTestOptions options;
    options.threads = kThreads;
    const auto start = std::chrono::steady_clock::now();
    const std::vector<StudyRow> rows =
        runConvergenceStudy(options, {128, 256, 512}, {1, 4, 16, 64}, OverlapVariant::Sum);
    std::printf("%s", studyMarkdown(rows).c_str());
    std::printf("\n(study wall time %.1f s on %d threads)\n",
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
                kThreads);
    return 0;
}

}  // namespace
}  // namespace lobe

int main(int argc, char** argv) {
    for (int i = 1; i < argc; ++i)
        if (std::strcmp(argv[i], "--study") == 0) return lobe::runStudy();
    for (const std::string& model : lobe::specularModelNames())
        benchmark::RegisterBenchmark(("BM_RenderOneModel/" + model).c_str(),
                                     lobe::BM_RenderOneModel, model)
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime()
            ->Iterations(1);
    benchmark::RegisterBenchmark("BM_RenderOneModel/lambert_only", lobe::BM_RenderOneModel,
                                 std::string("lambert"))
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime()
        ->Iterations(1);
    benchmark::Initialize(&argc, argv);
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
