// `lobe assign` (analysis/assign_scene.h).
#include "analysis/assign_scene.h"

#include "analysis/overlap_report.h"
#include "analysis/scene_passes.h"
#include "core/error.h"
#include "core/format.h"
#include "core/temporary_file.h"
#include "materials/registry.h"
#include "render/render_scene.h"
#include "render/scene_file.h"

#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>

namespace lobe {
namespace {

namespace fs = std::filesystem;

std::string modelTitle(const BrdfCandidate& c) {
    std::string t = c.brdf ? brdfName(*c.brdf) : c.model;
    try {
        t = findBrdfModel(t).title;
    } catch (const Error&) {
    }
    for (const std::string& x : c.settings) t += " " + x;
    if (c.albedo > 0.0) t += " a=" + formatNumber("%g", c.albedo);
    return t;
}

// "assign: skull Ward / cortex Phong / …" and the group "assign-ward-phong-…" (the distinct
// models in object order; a file-safe name, as scene groups must be).
std::string assignedTitle(const SceneSpec& spec, const std::vector<BrdfCandidate>& candidates,
                          const std::vector<int>& chosen) {
    std::string t = "assign: ";
    for (size_t o = 0; o < spec.objects.size(); ++o)
        t += (o ? " / " : "") + spec.objects[o].name + " " +
             modelTitle(candidates[size_t(chosen[o])]);
    return t;
}
std::string assignedGroup(const std::vector<BrdfCandidate>& candidates,
                          const std::vector<int>& chosen) {
    std::string g = "assign";
    std::set<std::string> seen;
    for (int c : chosen) {
        const BrdfCandidate& k = candidates[size_t(c)];
        const std::string m = k.brdf ? brdfName(*k.brdf) : k.model;
        if (seen.insert(m).second) g += "-" + m;
    }
    return g;
}

// The input scene's JSON with each object's brdf replaced by its chosen candidate, the title and
// group naming the chosen models, and every source path rewritten relative to the output's folder.
std::string chosenSceneJson(const SceneSpec& spec, const std::vector<BrdfCandidate>& candidates,
                            const std::vector<int>& chosen, const std::vector<bool>& kept,
                            const std::string& outPath) {
    std::ifstream in(spec.path);
    nlohmann::json j = nlohmann::json::parse(in);
    j["title"] = assignedTitle(spec, candidates, chosen);
    j["group"] = assignedGroup(candidates, chosen);
    const fs::path outDir = fs::absolute(fs::path(outPath)).parent_path();
    const fs::path sceneDir = fs::absolute(fs::path(spec.path)).parent_path();
    size_t next = 0;  // the JSON object of the next object that is not from a segmentation
    for (size_t o = 0; o < spec.objects.size(); ++o) {
        // A segmentation's labels (docs/scene-format.md, "Labels") are one JSON object: their
        // choices go into its "overrides", keyed by the label's name (or number).
        const std::string& seg = spec.objects[o].segmentation;
        const size_t index =
            seg.empty() ? next++ : size_t(std::stoul(seg.substr(seg.find('[') + 1)));
        if (!seg.empty() &&
            (o + 1 == spec.objects.size() || spec.objects[o + 1].segmentation != seg))
            next = index + 1;
        nlohmann::json& object = j["objects"][index];
        const VolumeSourceSpec& source = spec.objects[o].source;
        const auto relative = [&](const std::string& p) {
            return fs::relative(fs::absolute(p), outDir).generic_string();
        };
        if (source.morePaths.empty()) {
            object["source"]["path"] = relative(source.path);
        } else {  // the files of a DICOM series
            nlohmann::json list = nlohmann::json::array({relative(source.path)});
            for (const std::string& p : source.morePaths) list.push_back(relative(p));
            object["source"]["path"] = list;
        }
        nlohmann::json& table = object["source"]["label_table"];
        if (table.is_string() && !fs::path(table.get<std::string>()).is_absolute())
            table = relative((sceneDir / table.get<std::string>()).lexically_normal().string());
        else if (table.is_null())
            object["source"].erase("label_table");
        if (kept[o]) continue;
        nlohmann::json* target = &object;
        if (!seg.empty()) {
            // The label's key: an existing override's (by name or number), else its name.
            const std::string prefix = object.value("name", std::string());
            std::string name = spec.objects[o].name;
            if (!prefix.empty() && name.rfind(prefix + ": ", 0) == 0)
                name = name.substr(prefix.size() + 2);
            std::string key = name;
            const std::string number = std::to_string(source.labels.front());
            if (object.contains("overrides") && object["overrides"].contains(number)) key = number;
            target = &object["overrides"][key];
        }
        const BrdfCandidate& c = candidates[size_t(chosen[o])];
        nlohmann::json brdf = {{"model", c.model}};
        for (const std::string& kv : c.settings) {
            const auto eq = kv.find('=');
            const std::string value = kv.substr(eq + 1);
            if (value.find(',') == std::string::npos) {
                brdf[kv.substr(0, eq)] = std::stod(value);
            } else {
                nlohmann::json bands = nlohmann::json::array();
                size_t start = 0;
                for (size_t comma; (comma = value.find(',', start)) != std::string::npos;
                     start = comma + 1)
                    bands.push_back(std::stod(value.substr(start, comma - start)));
                bands.push_back(std::stod(value.substr(start)));
                brdf[kv.substr(0, eq)] = bands;
            }
        }
        if (c.albedo > 0.0) brdf["albedo"] = c.albedo;
        (*target)["brdf"] = brdf;
    }
    return j.dump(1) + "\n";
}

}  // namespace

void assignScene(const AssignRequest& cmd) {
    cmd.overrides.validate();
    if (cmd.top < 1 || cmd.top > 1000) throw Error("--top must be in [1, 1000]");
    if (!(cmd.keepFraction >= 0.0 && cmd.keepFraction <= 1.0))
        throw Error("--keep-visible must be in [0, 1], got " + std::to_string(cmd.keepFraction));
    if (!(cmd.brightnessBand == 0.0 || cmd.brightnessBand > 1.0))
        throw Error("--brightness-band must be > 1 (or 0: no band), got " +
                    std::to_string(cmd.brightnessBand));
    double albedo = 0.0;
    if (!cmd.equalAlbedo.empty()) {
        try {
            size_t used = 0;
            albedo = std::stod(cmd.equalAlbedo, &used);
            if (used != cmd.equalAlbedo.size()) albedo = -1.0;
        } catch (const std::exception&) {
            albedo = -1.0;
        }
        if (!(albedo > 0.0 && albedo <= 1.0))
            throw Error("--equal-albedo: expected an albedo in (0, 1], got '" + cmd.equalAlbedo +
                        "'");
    }
    const SeparationMetric metric = parseSeparationMetric(cmd.metric);
    const fs::path out(cmd.out);
    if (out.extension() != ".json")
        throw Error("--out: expected a .json scene file, got '" + cmd.out + "'");
    const std::string report = (out.parent_path() / (out.stem().string() + "-assign.md")).string();
    if (!cmd.force)
        for (const std::string& p : {cmd.out, report})
            if (fs::exists(p)) throw Error("'" + p + "' exists (use --force to replace it)");
    if (!out.parent_path().empty() && !fs::is_directory(out.parent_path()))
        throw Error("--out: folder '" + out.parent_path().string() + "' does not exist");

    SceneSpec spec = loadSceneFile(cmd.scene);
    // Reduced size by default: the layers only need to show where the highlights lie.
    SceneOverrides o = cmd.overrides;
    if (o.width <= 0 && o.height <= 0 && !o.preview) o.width = 256;
    if (o.spp <= 0 && !o.preview) o.spp = 2;
    const SceneSpec full = spec;
    o.apply(spec);

    std::set<std::string> excluded;
    for (const std::string& m : cmd.exclude) {
        findBrdfModel(m);
        excluded.insert(m);
    }
    std::vector<BrdfCandidate> candidates;
    for (const BrdfCandidate& c : brdfCandidates(cmd.tune))
        if (!excluded.count(c.model)) candidates.push_back(c);
    if (albedo > 0.0) equalizeAlbedo(candidates, albedo);
    std::vector<bool> allowed(candidates.size(), true);
    // Kept objects: their own BRDF, exactly as in the scene, as a candidate only they may use.
    std::vector<int> fixed(spec.objects.size(), -1);
    std::vector<bool> kept(spec.objects.size(), false);
    for (const std::string& name : cmd.keep) {
        bool found = false;
        for (size_t i = 0; i < spec.objects.size(); ++i)
            if (spec.objects[i].name == name) {
                found = true;
                kept[i] = true;
                BrdfCandidate own{spec.objects[i].brdfModel,
                                  {},
                                  spec.objects[i].material.specular,
                                  "(" + name + " as in the scene)"};
                own.scale = spec.objects[i].material.specularScale;
                fixed[i] = int(candidates.size());
                candidates.push_back(own);
                allowed.push_back(false);
            }
        if (!found) {
            std::string names;
            for (const ObjectSpec& obj : spec.objects)
                names += (names.empty() ? "" : ", ") + obj.name;
            throw Error("--keep: the scene has no object '" + name + "' (objects: " + names + ")");
        }
    }
    if (std::count(allowed.begin(), allowed.end(), true) == 0)
        throw Error("--exclude leaves no BRDF to choose from");

    AovRequest request;
    request.objects = request.backdrop = true;
    requestCandidateLayers(candidates, request);
    const auto start = std::chrono::steady_clock::now();
    VolumeCache cache;
    const RenderScene scene(spec, !cmd.quiet, &cache);
    RenderOptions options;
    options.threads = cmd.threads;
    options.progress = !cmd.quiet;
    options.label = "assign layers";
    AovImage aovs;
    scene.render(options, nullptr, &request, &aovs);
    // The same layers at the next seed: glints are what changes between the two (glintShare).
    SceneSpec nextSeed = spec;
    nextSeed.seed = spec.seed + 1;
    AovImage aovsNextSeed;
    {
        const RenderScene again(nextSeed, false, &cache);
        options.label = "assign layers, second seed";
        again.render(options, nullptr, &request, &aovsNextSeed);
    }
    const double renderSeconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const AssignmentLayers layers = assignmentLayers(spec, aovs, candidates);
    const AssignmentLayers layersNextSeed = assignmentLayers(nextSeed, aovsNextSeed, candidates);
    // The input as it is: its own specular passes, from the same render.
    const SeparationLayers inputLayers = separationLayers(spec, aovs);
    const double threshold = metric == SeparationMetric::Itp ? kItpThreshold : kWeberContrast;
    const SeparationReport input = measureSeparation(inputLayers, threshold, metric);
    // The Weber report always gives visibility and chroma (the itp metric's too; the same passes).
    const SeparationScorer weber(layers.scene);

    AssignOptions search;
    search.fixed = fixed;
    search.allowed = allowed;
    search.top = cmd.top;
    search.metric = metric;
    search.distinct = cmd.distinct;
    const size_t k = spec.objects.size();
    if (cmd.keepFraction > 0.0)
        for (const ObjectVisibility& v : input.objects) {
            search.minVisibility.push_back(cmd.keepFraction * v.visibility);
            // An achromatic object (a grey or white colour) has no colour to keep.
            search.minChroma.push_back(
                v.chromatic && v.chroma >= kAchromaticChroma ? cmd.keepFraction * v.chroma : 0.0);
        }
    if (cmd.brightnessBand > 0.0)
        for (const ObjectVisibility& v : input.objects) {
            search.minLuminance.push_back(v.meanLuminance / cmd.brightnessBand);
            search.maxLuminance.push_back(v.meanLuminance * cmd.brightnessBand);
        }
    // No sparkle (analysis/assign.h excludeSparkle), for every candidate: a highlight mostly
    // isolated specks in the layers, or one whose specks come and go between the two seeds'
    // layers (glints) — narrower than a pixel of the layers, which are no finer than the final
    // render — is not offered for that object.
    std::vector<bool> reference(candidates.size());
    for (size_t c = 0; c < candidates.size(); ++c)
        reference[c] = candidates[c].settings.empty() && !candidates[c].brdf;
    std::string sparkleNote;
    for (const std::string& line : excludeSparkle(layers, reference, search, &layersNextSeed))
        sparkleNote += "\n- " + line;
    // The scene's own assignment, where every object's model is a default-parameter candidate.
    std::vector<int> current(k, -1);
    for (size_t i = 0; i < k; ++i) {
        if (fixed[i] >= 0) {
            current[i] = fixed[i];
            continue;
        }
        for (size_t c = 0; c < candidates.size(); ++c)
            if (candidates[c].model == spec.objects[i].brdfModel &&
                candidates[c].settings.empty() && !candidates[c].brdf && albedo == 0.0 &&
                spec.objects[i].material.specularScale == 1.0)
                current[i] = int(c);
    }
    const bool hasCurrent = std::find(current.begin(), current.end(), -1) == current.end();
    if (hasCurrent) search.start = current;
    const auto searchStart = std::chrono::steady_clock::now();
    const AssignResult result = searchAssignments(layers, search);
    const double searchSeconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - searchStart).count();
    if (result.ranked.empty()) {
        // Which objects the nearest assignment found could not keep within the bounds.
        std::string short_;
        if (!result.closest.empty()) {
            const SeparationReport near = assignmentReport(weber, layers, result.closest);
            for (size_t i = 0; i < k && short_.size() < 400; ++i) {
                const ObjectVisibility& v = near.objects[i];
                std::string what;
                if (i < search.minVisibility.size() && v.visibility < search.minVisibility[i])
                    what += " V " + formatNumber("%.3g", v.visibility) + " < " +
                            formatNumber("%.3g", search.minVisibility[i]);
                if (i < search.minChroma.size() && v.chroma < search.minChroma[i])
                    what += " C* " + formatNumber("%.3g", v.chroma) + " < " +
                            formatNumber("%.3g", search.minChroma[i]);
                if (i < search.minLuminance.size() && (v.meanLuminance < search.minLuminance[i] ||
                                                       v.meanLuminance > search.maxLuminance[i]))
                    what += " Y out of the band";
                if (!what.empty())
                    short_ += (short_.empty() ? "" : ";") + std::string(" ") +
                              spec.objects[i].name + ":" + what;
            }
        }
        throw Error(
            "no assignment keeps every object's visibility and chroma at " +
            formatNumber("%g", cmd.keepFraction) + " of the input's" +
            (cmd.brightnessBand > 0.0 ? " and its luminance in the band" : std::string()) +
            (cmd.distinct ? " with distinct models" : std::string()) +
            (short_.empty() ? std::string() : " (the nearest found falls short on" + short_ + ")") +
            " (lower --keep-visible, widen --brightness-band, or drop --distinct); nothing "
            "written");
    }

    std::string md =
        "# BRDF assignment: " + full.title + "\n\nScene `" + cmd.scene + "`; layers rendered at " +
        std::to_string(spec.width) + "×" + std::to_string(spec.height) + ", " +
        std::to_string(spec.samplesPerPixel) + " spp in " + formatNumber("%.1f", renderSeconds) +
        " s; " + std::to_string(candidates.size()) + " candidate BRDFs" +
        (albedo > 0.0 ? ", every lobe scaled to albedo " + formatNumber("%g", albedo) +
                            " at normal incidence"
                      : std::string()) +
        "; " +
        (result.exhaustive ? "exhaustive search"
                           : "local search (coordinate ascent, " +
                                 std::to_string(search.restarts + 1) + " starts)") +
        " over " + std::to_string(result.space) + " assignments, " +
        std::to_string(result.evaluated) + " scored (" + std::to_string(result.rejected) +
        " broke a constraint) in " + formatNumber("%.2f", searchSeconds) +
        " s. Score: the separation score, metric " + cmd.metric +
        " (docs/separation.md). Constraints: " +
        (cmd.keepFraction > 0.0 ? "every object's visibility V and chroma C* at least " +
                                      formatNumber("%g", cmd.keepFraction) + " of the input's"
                                : std::string("none on visibility and chroma")) +
        (cmd.brightnessBand > 0.0
             ? "; mean luminance within ×1/" + formatNumber("%g", cmd.brightnessBand) + " … ×" +
                   formatNumber("%g", cmd.brightnessBand) + " of the input's"
             : std::string()) +
        (cmd.distinct ? "; no two objects share a model" : std::string()) + ".\n\n";
    if (!sparkleNote.empty())
        md += "Not offered (sparkle: more than " + formatNumber("%.0f", 100 * kSparkleLimit) +
              " % of the highlight in isolated pixels, " + formatNumber("%g", kSparklePeak) +
              "× the mean of their neighbours, or more than " +
              formatNumber("%g", 100 * kGlintLimit) +
              " % of the seen highlight in glints, specks that change by " +
              formatNumber("%g", 100 * kGlintContrast) +
              " % of the pixel between two seeds; each also twice the least specky, or the "
              "median, default model's share):" +
              sparkleNote + "\n\n";
    md += "| rank | score |";
    for (const ObjectSpec& obj : spec.objects) md += " " + obj.name + " |";
    md += "\n|---:|---:|";
    for (size_t i = 0; i < k; ++i) md += "---|";
    md += "\n";
    for (size_t r = 0; r < result.ranked.size(); ++r) {
        md += "| " + std::to_string(r + 1) + " | " + formatNumber("%.4g", result.ranked[r].score) +
              " |";
        for (int c : result.ranked[r].assignment) md += " " + candidates[size_t(c)].label() + " |";
        md += "\n";
    }
    const ScoredAssignment& best = result.ranked.front();
    const SeparationReport before = measureSeparation(inputLayers);
    const SeparationReport after = assignmentReport(weber, layers, best.assignment);
    md +=
        "\n## Before and after, per object\n\nInput: score " + formatNumber("%.4g", input.score) +
        "; chosen: " + formatNumber("%.4g", best.score) +
        ". V: visibility (share of the pixel, "
        "docs/separation.md); C*: mean CIELAB chroma where the object shows; Y: its mean "
        "luminance there.\n\n| object | input model | chosen model | V before | V after | ratio | "
        "C* before | C* after | ratio | Y ratio "
        "|\n|---|---|---|---:|---:|---:|---:|---:|---:|---:|\n";
    for (size_t i = 0; i < k; ++i) {
        const ObjectVisibility& b = before.objects[i];
        const ObjectVisibility& a = after.objects[i];
        const auto ratio = [](double x, double y) {
            return y > 0.0 ? formatNumber("%.2f", x / y) : std::string("—");
        };
        md += "| " + spec.objects[i].name + " | " + spec.objects[i].brdfModel + " | " +
              candidates[size_t(best.assignment[i])].label() + " | " +
              formatNumber("%.3f", b.visibility) + " | " + formatNumber("%.3f", a.visibility) +
              " | " + ratio(a.visibility, b.visibility) + " | " + formatNumber("%.1f", b.chroma) +
              " | " + formatNumber("%.1f", a.chroma) + " | " + ratio(a.chroma, b.chroma) + " | " +
              ratio(a.meanLuminance, b.meanLuminance) + " |\n";
    }
    if (hasCurrent) {
        const double score =
            assignmentReport(SeparationScorer(layers.scene, threshold, metric), layers, current)
                .score;
        md += "\nThe scene's own assignment scores " + formatNumber("%.4g", score) +
              " from the layers";
        if (result.exhaustive)
            md += ", rank " + std::to_string(countBetter(layers, search, current) + 1) + " of " +
                  std::to_string(result.space) + " (among the admissible ones)";
        md += ".\n";
    }
    writeTextFileAtomic(cmd.out, chosenSceneJson(full, candidates, best.assignment, kept, cmd.out));
    writeTextFileAtomic(report, md);
    if (!cmd.quiet) {
        std::fprintf(stderr, "\nbest (score %.4g; input %.4g):\n", best.score, input.score);
        for (size_t i = 0; i < k; ++i)
            std::fprintf(stderr,
                         "  %-20s %s -> %s   visibility %.3f -> %.3f   chroma %.1f -> %.1f\n",
                         spec.objects[i].name.c_str(), spec.objects[i].brdfModel.c_str(),
                         candidates[size_t(best.assignment[i])].label().c_str(),
                         before.objects[i].visibility, after.objects[i].visibility,
                         before.objects[i].chroma, after.objects[i].chroma);
        std::fprintf(stderr, "-> %s, %s\n", cmd.out.c_str(), report.c_str());
    }
}

}  // namespace lobe
