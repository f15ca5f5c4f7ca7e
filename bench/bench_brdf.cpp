// Nanoseconds per BRDF evaluation, one benchmark per registered model (the registry is iterated,
// so a model added later is timed with no edit here), at the model's defaults, through the same
// std::variant dispatch (evalBrdf) the renderer uses. Each iteration evaluates one pair from a
// fixed, precomputed set of 4096 random direction pairs (both above the horizon, half of them
// within 0.1 rad of the mirror direction so that every lobe's full formula is exercised, not only
// its early-outs), so the reported time per iteration is the time per evaluation (3 bands).
//
// Before timing, each model is checked against a reference: its value for one pair computed
// independently by tests/materials/reference_values.py (wi at θ 30°, φ 10°; wo at θ 35°, φ 185°),
// and every value of the pair set must be finite and ≥ 0 with some > 0. A model without a
// reference value (added later) is timed after the finiteness check only, and says so.
//
// Run: build/bench/lobe_bench_brdf  (`make bench`); the table is in docs/brdf-properties.md.
#include "core/rng.h"
#include "materials/registry.h"

#include <benchmark/benchmark.h>

#include <cmath>
#include <map>
#include <string>
#include <vector>

namespace lobe {
namespace {

struct Pair {
    Vec3 wi, wo;
};

Vec3 fromAngles(double theta, double phi) {
    return Vec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
}

const std::vector<Pair>& pairs() {
    static const std::vector<Pair> set = [] {
        std::vector<Pair> out;
        Rng rng(2003, 1);
        while (out.size() < 4096) {
            const Vec3 wi = fromAngles(std::acos(1.0 - rng.uniform()), 2.0 * kPi * rng.uniform());
            Vec3 wo;
            if (out.size() % 2) {
                const Vec3 jitter(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5);
                wo = (mirrorLocal(wi) + 0.2 * jitter).normalized();
            } else {
                wo = fromAngles(std::acos(1.0 - rng.uniform()), 2.0 * kPi * rng.uniform());
            }
            if (wi.z > 0.0 && wo.z > 0.0) out.push_back({wi, wo});
        }
        return out;
    }();
    return set;
}

// tests/materials/reference_values.py, first case of each model (band 700 nm; defaults);
// he_torrance from the independent Python implementation pasted in test_he_torrance.cpp,
// poulin_fournier from the Python brute-force profile integration in test_poulin_fournier.cpp
// (accurate to ~1e-5 because of its shadow edges, hence its looser tolerance below).
const std::map<std::string, double>& referenceValues() {
    static const std::map<std::string, double> values = {
        {"he_torrance", 0.1305645380548555},
        {"poulin_fournier", 0.18405284},
        {"phong", 0.7616790509105564},
        {"strauss", 0.20180457619639322},
        {"schlick_lewis", 1.456230535546167},
        {"ward", 0.13008838629709385},
        {"cook_torrance", 0.5699460886829282},
        {"lafortune", 0.43863573566364245},
        {"ashikhmin_shirley", 0.22300699731821702},
        {"lambert", 0.06366197723675814},
    };
    return values;
}

// Empty string when the model passes its reference checks, else the reason.
std::string checkModel(const std::string& name, const Brdf& brdf) {
    const auto it = referenceValues().find(name);
    if (it != referenceValues().end()) {
        const Vec3 wi(0.49240387650610395, 0.08682408883346515, 0.8660254037844387);
        const Vec3 wo(-0.5713938048432696, -0.04999048033273017, 0.8191520442889918);
        const double f = evalBrdf(brdf, wi, wo)[0];
        const double tolerance = name == "poulin_fournier" ? 1e-4 : 1e-9;
        if (!(std::abs(f - it->second) <= tolerance * it->second))
            return "value " + std::to_string(f) + " differs from the reference " +
                   std::to_string(it->second);
    }
    bool anyPositive = false;
    for (const Pair& p : pairs()) {
        const Spectrum f = evalBrdf(brdf, p.wi, p.wo);
        if (!f.isFinite() || f[0] < 0.0 || f[1] < 0.0 || f[2] < 0.0)
            return "non-finite or negative value";
        anyPositive |= f.maxValue() > 0.0;
    }
    return anyPositive ? "" : "every value of the pair set is 0";
}

void benchEval(benchmark::State& state, const std::string& name) {
    const Brdf brdf = makeBrdf(name);
    const std::string problem = checkModel(name, brdf);
    if (!problem.empty()) {
        state.SkipWithError(problem.c_str());
        return;
    }
    if (referenceValues().count(name) == 0) state.SetLabel("no reference value; finiteness only");
    const std::vector<Pair>& set = pairs();
    const size_t mask = set.size() - 1;  // 4096 = 2^12
    size_t i = 0;
    for (auto _ : state) {
        const Pair& p = set[i++ & mask];
        Spectrum f = evalBrdf(brdf, p.wi, p.wo);
        benchmark::DoNotOptimize(f);
    }
    state.SetItemsProcessed(state.iterations());
}

}  // namespace
}  // namespace lobe

int main(int argc, char** argv) {
    for (const lobe::BrdfModelInfo& model : lobe::brdfModels()) {
        const std::string name = model.name;
        benchmark::RegisterBenchmark(("eval/" + name).c_str(),
                                     [name](benchmark::State& s) { lobe::benchEval(s, name); });
    }
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
