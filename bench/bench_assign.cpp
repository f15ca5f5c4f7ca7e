// lobe_bench_assign: `lobe assign`'s shortcut checked and timed (issue "lobe assign").
//
//  1. The paper scene (rendering 1's geometry, 3 objects, 9 models: 729 assignments) at low
//     resolution: the separation score of every assignment from one render's per-model layers
//     (the shortcut) against a full render of each assignment — the same best? how far apart are
//     the scores (max |Δ|, Kendall tau)? — with the time of each.
//  2. Where the paper's 24 renderings rank among the 729 assignments (by the shortcut).
//  3. Tuning: the best with each model at its defaults against the best with the documented
//     parameter variants as candidates too (analysis/properties.h).
//  4. Many objects (assets/scenes/assign/six-objects.json: the four density maps as separate
//     objects, 9⁶ = 531 441 assignments): the local search (coordinate ascent from the scene's
//     own assignment and 16 random starts) against exhaustive search of all assignments, and on
//     random 3-object subsets (the other three held at random models) against exhaustive search.
// A Markdown report on stdout.
#include "analysis/overlap_ranking.h"
#include "analysis/properties.h"
#include "analysis/scene_passes.h"
#include "bench/bench_common.h"
#include "core/rng.h"
#include "materials/registry.h"
#include "render/render_scene.h"
#include "render/scene_file.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <map>
#include <stdexcept>
#include <string>

using namespace lobe;

namespace {

struct Clock {
    bench::Stopwatch watch;
    double wallSeconds() const { return watch.wall(); }
    double cpuSeconds() const { return watch.cpu(); }
};

SceneSpec load(const std::string& path, int size, int spp) {
    SceneSpec spec = loadSceneFile(path);
    spec.width = spec.height = size;
    spec.samplesPerPixel = spp;
    return spec;
}

AssignmentLayers layersOf(const SceneSpec& spec, const std::vector<BrdfCandidate>& candidates,
                          int threads) {
    AovRequest request;
    request.objects = request.backdrop = true;
    requestCandidateLayers(candidates, request);
    const RenderScene scene(spec, false);
    RenderOptions options;
    options.threads = threads;
    options.progress = false;
    AovImage aovs;
    scene.render(options, nullptr, &request, &aovs);
    return assignmentLayers(spec, aovs, candidates);
}

// The paper's scene has three BRDF slots: skull, cortex, density maps. Scenes that split the
// maps into four objects ("density map 0" … "3") fill the third slot with all four: their
// layers are summed per candidate and scored as one object, as the paper's single object was.
bool isMap(const std::string& name) { return name.rfind("density map ", 0) == 0; }

std::vector<int> slotOfObject(const SceneSpec& spec) {
    std::vector<int> slot;
    int next = 0, mapSlot = -1;
    for (const ObjectSpec& o : spec.objects) {
        if (isMap(o.name)) {
            if (mapSlot < 0) mapSlot = next++;
            slot.push_back(mapSlot);
        } else {
            slot.push_back(next++);
        }
    }
    return slot;
}

// --albedo: "A" for every object, or "NAME=A,…" per object (a NAME "density maps" stands for
// every "density map N"; an entry without a name is the value of the objects not named).
// Throws naming the entry or the object left without a value.
std::map<std::string, double> objectAlbedos(const std::string& text, const SceneSpec& spec) {
    std::map<std::string, double> named;
    double fallback = -1.0;
    size_t start = 0;
    while (start <= text.size()) {
        const size_t comma = std::min(text.find(',', start), text.size());
        const std::string entry = text.substr(start, comma - start);
        const size_t eq = entry.find('=');
        const std::string value = eq == std::string::npos ? entry : entry.substr(eq + 1);
        char* end = nullptr;
        const double a = std::strtod(value.c_str(), &end);
        if (value.empty() || *end != '\0' || !(a > 0.0 && a <= 1.0))
            throw std::runtime_error("--albedo: expected A or OBJECT=A with A in (0, 1], got '" +
                                     entry + "'");
        if (eq == std::string::npos)
            fallback = a;
        else
            named[entry.substr(0, eq)] = a;
        start = comma + 1;
    }
    std::map<std::string, double> out;
    for (const ObjectSpec& o : spec.objects) {
        double a = fallback;
        if (named.count(o.name))
            a = named.at(o.name);
        else if (isMap(o.name) && named.count("density maps"))
            a = named.at("density maps");
        if (a < 0.0) throw std::runtime_error("--albedo: no value for object '" + o.name + "'");
        out[o.name] = a;
    }
    for (const auto& [name, a] : named)
        if (name != "density maps" && !out.count(name))
            throw std::runtime_error("--albedo: the scene has no object '" + name + "'");
    return out;
}

AssignmentLayers mergeMaps(const AssignmentLayers& in, const SceneSpec&) {
    std::vector<std::string> maps;
    for (const std::string& o : in.objects())
        if (isMap(o)) maps.push_back(o);
    return maps.empty() ? in : mergeAssignmentObjects(in, "density maps", maps);
}

SeparationLayers mergeMapLayers(const SeparationLayers& l) {
    std::vector<std::string> maps;
    for (const std::string& o : l.objects)
        if (isMap(o)) maps.push_back(o);
    return maps.empty() ? l : mergeObjects(l, "density maps", maps);
}

double fullRenderScore(SceneSpec spec, const std::vector<BrdfCandidate>& candidates,
                       const std::vector<int>& assignment, int threads) {
    const std::vector<int> slot = slotOfObject(spec);
    for (size_t o = 0; o < spec.objects.size(); ++o) {
        const BrdfCandidate& c = candidates[size_t(assignment[size_t(slot[o])])];
        spec.objects[o].material.specular = makeBrdf(c.model, c.settings);
        spec.objects[o].brdfModel = c.model;
    }
    const RenderScene scene(spec, false);
    RenderOptions options;
    options.threads = threads;
    options.progress = false;
    AovRequest request;
    request.objects = request.backdrop = true;
    AovImage aovs;
    scene.render(options, nullptr, &request, &aovs);
    return measureSeparation(mergeMapLayers(separationLayers(spec, aovs))).score;
}

std::string label(const std::vector<BrdfCandidate>& c, const std::vector<int>& a) {
    std::string s;
    for (int i : a) s += (s.empty() ? "" : " / ") + c[size_t(i)].label();
    return s;
}

int candidateIndex(const std::vector<BrdfCandidate>& c, const std::string& model) {
    for (size_t i = 0; i < c.size(); ++i)
        if (c[i].model == model && c[i].settings.empty()) return int(i);
    return -1;
}

}  // namespace

int main(int argc, char** argv) {
    int size = 64, spp = 1, threads = 2, manySize = 32, subsets = 20, tuneSize = 64;
    bool skipFull = false, onlyRenderings = false, kendall = false;
    std::string kendallAlbedo = "0.1";
    std::string paperDir = std::string(LOBE_SOURCE_DIR) + "/assets/scenes/paper";
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto next = [&] { return i + 1 < argc ? std::atoi(argv[++i]) : 0; };
        if (a == "--size")
            size = next();
        else if (a == "--spp")
            spp = next();
        else if (a == "--threads")
            threads = next();
        else if (a == "--many-size")
            manySize = next();
        else if (a == "--subsets")
            subsets = next();
        else if (a == "--tune-size")
            tuneSize = next();
        else if (a == "--skip-full")
            skipFull = true;
        else if (a == "--paper-dir" && i + 1 < argc)
            paperDir = argv[++i];
        else if (a == "--only-renderings")
            onlyRenderings = true;
        else if (a == "--kendall")
            kendall = true;
        else if (a == "--albedo" && i + 1 < argc)
            kendallAlbedo = argv[++i];
        else {
            std::fprintf(stderr,
                         "usage: %s [--size N] [--spp N] [--threads N] [--many-size N] "
                         "[--subsets N] [--tune-size N] [--skip-full] [--paper-dir DIR] "
                         "[--only-renderings] [--kendall [--albedo A|OBJECT=A,…]]\n",
                         argv[0]);
            return 2;
        }
    }
    const std::string scenes = std::string(LOBE_SOURCE_DIR) + "/assets/scenes/";
    const std::vector<BrdfCandidate> nine = brdfCandidates(false);
    if (kendall) {
        // Rank agreement of the two measures (docs/separation.md) over all 729 assignments of the
        // paper scene (maps merged), at the paper's parameters and at equal albedo (one per
        // object: --albedo skull=0.05,cortex=0.5,… as the paper-shape set is written).
        const SceneSpec paper = load(paperDir + "/rendering-01.json", size, spp);
        std::map<std::string, double> albedoOf;
        try {
            albedoOf = objectAlbedos(kendallAlbedo, paper);
        } catch (const std::exception& e) {
            std::fprintf(stderr, "lobe_bench_assign: error: %s\n", e.what());
            return 2;
        }
        std::printf(
            "# Weber score against the ΔE_ITP measure, %s/rendering-01.json at %d² × %d spp\n\n"
            "| lobes | Kendall τ (score, itp) | discordant / comparable | τ (highlight term H, "
            "itp) | "
            "best by score | best by itp |\n|---|---:|---:|---:|---|---|\n",
            paperDir.c_str(), size, spp);
        double group[2][4][3] = {};  // [lobes][group][score, H, ΔE_ITP]: means of six
        for (int equal = 0; equal < 2; ++equal) {
            AssignmentLayers full;
            if (!equal) {
                full = layersOf(paper, nine, threads);
            } else {
                // One render per distinct albedo; each object takes the layers of its own.
                std::map<double, AssignmentLayers> byAlbedo;
                for (const auto& [name, a] : albedoOf)
                    if (!byAlbedo.count(a)) {
                        std::vector<BrdfCandidate> c = nine;
                        equalizeAlbedo(c, a);
                        byAlbedo[a] = layersOf(paper, c, threads);
                    }
                full = byAlbedo.begin()->second;
                for (size_t o = 0; o < full.objects().size(); ++o) {
                    const AssignmentLayers& own = byAlbedo.at(albedoOf.at(full.objects()[o]));
                    for (size_t c = 0; c < nine.size(); ++c)
                        full.specular[o * nine.size() + c] = own.layer(int(o), int(c));
                }
            }
            const AssignmentLayers l = mergeMaps(full, paper);
            const std::vector<BrdfCandidate>& c = nine;
            const SeparationScorer weber(l.scene);
            const SeparationScorer itp(l.scene, kItpThreshold, SeparationMetric::Itp);
            std::vector<double> w, h, d;
            std::vector<std::vector<int>> all;
            for (int a = 0; a < 9; ++a)
                for (int b = 0; b < 9; ++b)
                    for (int m = 0; m < 9; ++m) {
                        const std::vector<int> x = {a, b, m};
                        const SeparationReport rw = assignmentReport(weber, l, x);
                        w.push_back(rw.score);
                        h.push_back(rw.highlight);
                        d.push_back(assignmentReport(itp, l, x).score);
                        all.push_back(x);
                    }
            const RankAgreement t = compareRankings(w, d), th = compareRankings(h, d);
            const size_t bw = size_t(std::max_element(w.begin(), w.end()) - w.begin());
            const size_t bd = size_t(std::max_element(d.begin(), d.end()) - d.begin());
            std::printf("| %s | %.3f | %d / %d | %.3f | %s | %s |\n",
                        equal ? ("albedo " + kendallAlbedo).c_str() : "paper's parameters",
                        t.kendallTau, t.discordant, t.comparable, th.kendallTau,
                        label(c, all[bw]).c_str(), label(c, all[bd]).c_str());
            // The paper's four groups of six renderings: A 1–6, B 7–12, C 13–18, D 19–24.
            for (int r = 1; r <= 24; ++r) {
                char name[64];
                std::snprintf(name, sizeof name, "/rendering-%02d.json", r);
                const SceneSpec s = loadSceneFile(paperDir + name);
                const std::vector<int> slot = slotOfObject(s);
                std::vector<int> x(3, -1);
                for (size_t o = 0; o < s.objects.size(); ++o)
                    x[size_t(slot[o])] = candidateIndex(nine, s.objects[o].brdfModel);
                const size_t i = size_t(x[0] * 81 + x[1] * 9 + x[2]);
                std::fprintf(stderr, "%s rendering %d: score %.4f highlight %.4f itp %.3f\n",
                             equal ? "equal" : "paper", r, w[i], h[i], d[i]);
                group[equal][(r - 1) / 6][0] += w[i] / 6.0;
                group[equal][(r - 1) / 6][1] += h[i] / 6.0;
                group[equal][(r - 1) / 6][2] += d[i] / 6.0;
            }
        }
        std::printf(
            "\nGroup means (A 1–6, B 7–12, C 13–18, D 19–24):\n\n| group | score | H | ΔE_ITP | "
            "score, albedo %s | H | ΔE_ITP |\n|---|---:|---:|---:|---:|---:|---:|\n",
            kendallAlbedo.c_str());
        for (int g = 0; g < 4; ++g)
            std::printf("| %c | %.4f | %.4f | %.2f | %.4f | %.4f | %.2f |\n", char('A' + g),
                        group[0][g][0], group[0][g][1], group[0][g][2], group[1][g][0],
                        group[1][g][1], group[1][g][2]);
        return 0;
    }

    // 1. Shortcut against full renders.
    const SceneSpec paper = load(paperDir + "/rendering-01.json", size, spp);
    Clock layerClock;
    const AssignmentLayers layers = mergeMaps(layersOf(paper, nine, threads), paper);
    const double layerWall = layerClock.wallSeconds(), layerCpu = layerClock.cpuSeconds();
    Clock searchClock;
    AssignOptions all;
    all.top = 729;
    const AssignResult shortcut = searchAssignments(layers, all);
    const double searchWall = searchClock.wallSeconds();
    std::printf("# lobe assign: the shortcut against full renders\n\n");
    std::printf("Paper scene (rendering 1's geometry, %s) at %d² × %d spp, %d threads.\n\n",
                paperDir.c_str(), size, spp, threads);
    std::printf(
        "Shortcut: one render with 9 specular layers per object %.2f s wall (%.2f CPU s), "
        "729 assignments scored in %.3f s. Best: %s (%.4f).\n\n",
        layerWall, layerCpu, searchWall, label(nine, shortcut.ranked[0].assignment).c_str(),
        shortcut.ranked[0].score);
    std::vector<double> fromLayers, fromRenders;
    if (!skipFull && !onlyRenderings) {
        Clock fullClock;
        double maxDiff = 0.0, bestFull = -1.0;
        std::vector<int> bestFullAssignment;
        for (const ScoredAssignment& s : shortcut.ranked) {
            const double full = fullRenderScore(paper, nine, s.assignment, threads);
            fromLayers.push_back(s.score);
            fromRenders.push_back(full);
            maxDiff = std::max(maxDiff, std::abs(full - s.score));
            if (full > bestFull) bestFull = full, bestFullAssignment = s.assignment;
        }
        const RankAgreement agree = compareRankings(fromLayers, fromRenders);
        std::printf(
            "Exhaustive full renders: 729 renders %.1f s wall (%.1f CPU s). Best: %s "
            "(%.4f) — %s the shortcut's. Max |score difference| %.2e; Kendall tau %.6f "
            "(%d discordant of %d comparable pairs).\n\n",
            fullClock.wallSeconds(), fullClock.cpuSeconds(),
            label(nine, bestFullAssignment).c_str(), bestFull,
            bestFullAssignment == shortcut.ranked[0].assignment ? "the same as" : "NOT", maxDiff,
            agree.kendallTau, agree.discordant, agree.comparable);
    }

    // 2. The paper's renderings among the 729, as rendered and with equal-albedo lobes.
    // Equal albedo: every candidate's layer scaled so that its directional albedo at normal
    // incidence (band mean, analysis/properties.h) is 0.1, half the Lambert term's 0.2 — the
    // lobes' magnitude as a controlled variable, leaving their shape and placement.
    AssignmentLayers equal = layers;
    std::printf(
        "## Equal-albedo scale per model (albedo at normal incidence → 0.1)\n\n| model | albedo | "
        "scale |\n|---|---:|---:|\n");
    for (size_t c = 0; c < nine.size(); ++c) {
        const SpectrumEstimate a =
            directionalAlbedo(makeBrdf(nine[c].model), 0.0, 0.0, 16384, 8, 7);
        const double albedo = a.value.average(), k = albedo > 0.0 ? 0.1 / albedo : 1.0;
        std::printf("| %s | %.4f | %.3f |\n", nine[c].model.c_str(), albedo, k);
        for (size_t o = 0; o < equal.objects().size(); ++o)
            for (float& v : equal.specular[o * nine.size() + c]) v = float(v * k);
    }
    std::printf(
        "\n## The paper's 24 renderings among all 729 assignments\n\n"
        "| rendering | skull / cortex / density maps | score | rank of 729 | equal-albedo score | "
        "rank |\n"
        "|---|---|---:|---:|---:|---:|\n");
    double groupRaw[4] = {0, 0, 0, 0}, groupEqual[4] = {0, 0, 0, 0};
    for (int r = 1; r <= 24; ++r) {
        char name[64];
        std::snprintf(name, sizeof name, "/rendering-%02d.json", r);
        const SceneSpec s = loadSceneFile(paperDir + name);
        const std::vector<int> slot = slotOfObject(s);
        std::vector<int> a(size_t(*std::max_element(slot.begin(), slot.end()) + 1), -1);
        for (size_t o = 0; o < s.objects.size(); ++o)
            a[size_t(slot[o])] = candidateIndex(nine, s.objects[o].brdfModel);
        const double score = assignmentScore(layers, a), eq = assignmentScore(equal, a);
        groupRaw[(r - 1) / 6] += score / 6.0;
        groupEqual[(r - 1) / 6] += eq / 6.0;
        std::printf("| %d | %s | %.4f | %llu | %.4f | %llu |\n", r, label(nine, a).c_str(), score,
                    (unsigned long long)(countBetter(layers, all, a) + 1), eq,
                    (unsigned long long)(countBetter(equal, all, a) + 1));
    }
    std::printf(
        "\nGroup means (A best by flux overlap, B worst, C one model everywhere, D mixed): "
        "as rendered A %.4f, B %.4f, C %.4f, D %.4f; equal albedo A %.4f, B %.4f, C %.4f, "
        "D %.4f.\n",
        groupRaw[0], groupRaw[1], groupRaw[2], groupRaw[3], groupEqual[0], groupEqual[1],
        groupEqual[2], groupEqual[3]);
    const AssignResult bestEqual = searchAssignments(equal, all);
    std::printf("\nTop 5 as rendered: ");
    for (int i = 0; i < 5; ++i)
        std::printf("%s%s (%.4f)", i ? "; " : "",
                    label(nine, shortcut.ranked[size_t(i)].assignment).c_str(),
                    shortcut.ranked[size_t(i)].score);
    std::printf(". Bottom: %s (%.4f).\nTop 5 with equal albedo: ",
                label(nine, shortcut.ranked.back().assignment).c_str(),
                shortcut.ranked.back().score);
    for (int i = 0; i < 5; ++i)
        std::printf("%s%s (%.4f)", i ? "; " : "",
                    label(nine, bestEqual.ranked[size_t(i)].assignment).c_str(),
                    bestEqual.ranked[size_t(i)].score);
    std::printf(".\n\n");
    if (onlyRenderings) return 0;

    // 3. Tuning.
    {
        const SceneSpec s = load(paperDir + "/rendering-01.json", tuneSize, spp);
        const std::vector<BrdfCandidate> tuned = brdfCandidates(true);
        Clock c;
        const AssignmentLayers tl = mergeMaps(layersOf(s, tuned, threads), s);
        const double lw = c.wallSeconds();
        Clock c2;
        AssignOptions o;
        o.top = 1;
        const AssignResult best = searchAssignments(tl, o);
        std::vector<bool> defaultsOnly(tuned.size());
        for (size_t i = 0; i < tuned.size(); ++i) defaultsOnly[i] = tuned[i].settings.empty();
        AssignOptions d;
        d.top = 1;
        d.allowed = defaultsOnly;
        const AssignResult bestDefaults = searchAssignments(tl, d);
        std::printf(
            "## Tuning (%d² × %d spp, %zu candidates: the nine models and their documented "
            "variants)\n\nLayers %.2f s, search of %llu assignments %.2f s. Best with "
            "defaults only: %s (%.4f). Best with variants: %s (%.4f).\n\n",
            tuneSize, spp, tuned.size(), lw, (unsigned long long)best.evaluated, c2.wallSeconds(),
            label(tuned, bestDefaults.ranked[0].assignment).c_str(), bestDefaults.ranked[0].score,
            label(tuned, best.ranked[0].assignment).c_str(), best.ranked[0].score);
    }

    // 4. Many objects.
    {
        const SceneSpec six = load(scenes + "assign/six-objects.json", manySize, spp);
        Clock c;
        const AssignmentLayers ml = layersOf(six, nine, threads);
        const double lw = c.wallSeconds();
        std::vector<int> own;
        for (const ObjectSpec& o : six.objects) own.push_back(candidateIndex(nine, o.brdfModel));
        AssignOptions local;
        local.exhaustiveLimit = 0;
        local.start = own;
        local.top = 1;
        Clock lc;
        const AssignResult ls = searchAssignments(ml, local);
        const double localSeconds = lc.wallSeconds();
        AssignOptions ex;
        ex.exhaustiveLimit = 1000000;
        ex.top = 1;
        Clock ec;
        const AssignResult es = searchAssignments(ml, ex);
        const double exSeconds = ec.wallSeconds();
        std::printf(
            "## Six objects (skull, cortex, four density maps; %d² × %d spp)\n\n"
            "Layers %.2f s. Local search: %llu assignments scored in %.2f s, best %s "
            "(%.4f). Exhaustive: %llu assignments in %.1f s, best %s (%.4f). The scene's "
            "own assignment scores %.4f.\n\n",
            manySize, spp, lw, (unsigned long long)ls.evaluated, localSeconds,
            label(nine, ls.ranked[0].assignment).c_str(), ls.ranked[0].score,
            (unsigned long long)es.evaluated, exSeconds,
            label(nine, es.ranked[0].assignment).c_str(), es.ranked[0].score,
            assignmentScore(ml, own));
        Rng rng(2026, 11);
        int same = 0;
        double worstGap = 0.0;
        for (int t = 0; t < subsets; ++t) {
            std::vector<int> order = {0, 1, 2, 3, 4, 5};
            for (int i = 5; i > 0; --i)
                std::swap(order[size_t(i)], order[size_t(rng.uniform() * (i + 1)) % size_t(i + 1)]);
            AssignOptions sub;
            sub.fixed.assign(6, -1);
            for (int i = 3; i < 6; ++i)
                sub.fixed[size_t(order[size_t(i)])] = int(rng.uniform() * 9) % 9;
            sub.top = 1;
            const AssignResult exact = searchAssignments(ml, sub);
            sub.exhaustiveLimit = 0;
            sub.seed = uint64_t(t + 1);
            const AssignResult approx = searchAssignments(ml, sub);
            same += approx.ranked[0].score == exact.ranked[0].score;
            worstGap = std::max(worstGap, exact.ranked[0].score - approx.ranked[0].score);
        }
        std::printf(
            "Random 3-object subsets (the other three at random models): the local search "
            "found the exhaustive best score in %d of %d; worst gap %.2e.\n",
            same, subsets, worstGap);
    }
    return 0;
}
