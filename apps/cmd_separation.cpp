// `lobe separation SCENE… [--out DIR]`: renders each scene once with per-object passes
// (render/aov.h) and measures how far each pair of objects' highlights stay apart where both are
// seen, and how much of the image each object is visible in (analysis/separation.h,
// docs/separation.md). Writes per scene <stem>.md, <stem>.csv, the beauty <stem>.png and the
// per-pair maps <stem>/<a>_vs_<b>.png (A red, B green, overlap yellow); over all scenes
// separation.csv (one row per scene). Every scene is read and checked before any is rendered.
#include "analysis/overlap_report.h"
#include "analysis/scene_passes.h"
#include "apps/commands.h"
#include "apps/options.h"
#include "core/error.h"
#include "core/image_output.h"
#include "core/output_folder.h"
#include "core/temporary_file.h"
#include "render/render_scene.h"
#include "render/scene_file.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <filesystem>
#include <map>

namespace lobe {
namespace {

namespace fs = std::filesystem;

struct SeparationCommand {
    std::vector<std::string> scenes;
    std::string outDir = "separation";
    SceneOverrides overrides;
    double contrast = -1.0;  // default: the metric's (Weber 0.02, ΔE_ITP 1)
    std::string metric = "weber";
    double peak = 100.0;
    int threads = 0;
    bool quiet = false;
    std::vector<std::string> merge;  // NAME=OBJECT,OBJECT,...
};

std::string fileSafe(const std::string& s) {
    std::string out;
    for (char c : s)
        out += (std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_') ? c : '_';
    return out.empty() ? "object" : out;
}

void runSeparation(const SeparationCommand& cmd) {
    cmd.overrides.validate();
    const SeparationMetric metric = parseSeparationMetric(cmd.metric);
    const bool itp = metric == SeparationMetric::Itp;
    const double threshold = cmd.contrast > 0.0 ? cmd.contrast
                             : itp              ? kItpThreshold
                                                : kWeberContrast;
    if (!itp && !(threshold > 0.0 && threshold < 1.0))
        throw Error("--contrast must be in (0, 1) for --metric weber, got " +
                    std::to_string(threshold));
    if (!(cmd.peak >= 1.0 && cmd.peak <= 10000.0))
        throw Error("--peak must be in [1, 10000] cd/m², got " + std::to_string(cmd.peak));
    if (cmd.scenes.empty()) throw Error("no scene given");
    std::vector<SceneSpec> specs;
    std::map<std::string, std::string> stems;
    for (const std::string& path : cmd.scenes) {
        specs.push_back(loadSceneFile(path));
        cmd.overrides.apply(specs.back());
        if (specs.back().objects.size() < 2)
            throw Error(path + ": the separation score needs at least two objects");
        const std::string stem = fs::path(path).stem().string();
        const auto [it, fresh] = stems.emplace(stem, path);
        if (!fresh)
            throw Error("scenes '" + it->second + "' and '" + path +
                        "' would write the same files (" + stem + ".*): rename one");
    }
    createOutputFolder(cmd.outDir);
    AovRequest request;
    request.objects = request.backdrop = true;
    std::string summary = "scene,score,highlight";
    const size_t maxObjects = [&] {
        size_t m = 0;
        for (const SceneSpec& s : specs) m = std::max(m, s.objects.size());
        return m;
    }();
    for (size_t o = 0; o < maxObjects; ++o)
        summary += ",object" + std::to_string(o + 1) + ",visible" + std::to_string(o + 1) +
                   ",highlight" + std::to_string(o + 1);
    summary += "\n";
    for (size_t i = 0; i < specs.size(); ++i) {
        const SceneSpec& spec = specs[i];
        const RenderScene scene(spec, !cmd.quiet);
        RenderOptions options;
        options.threads = cmd.threads;
        options.progress = !cmd.quiet;
        options.label = "separation " + spec.title;
        AovImage aovs;
        const Film film = scene.render(options, nullptr, &request, &aovs);  // its PNG below
        SeparationLayers layers = separationLayers(spec, aovs);
        layers.peakLuminance = cmd.peak;
        for (const std::string& m : cmd.merge) {
            const auto eq = m.find('=');
            if (eq == std::string::npos || eq == 0 || eq + 1 == m.size())
                throw Error("--merge: expected NAME=OBJECT,OBJECT,..., got '" + m + "'");
            std::vector<std::string> members;
            size_t start = eq + 1;
            for (size_t comma; (comma = m.find(',', start)) != std::string::npos; start = comma + 1)
                members.push_back(m.substr(start, comma - start));
            members.push_back(m.substr(start));
            layers = mergeObjects(layers, m.substr(0, eq), members);
        }
        const SeparationReport report = measureSeparation(layers, threshold, metric);

        const std::string stem = fs::path(spec.path).stem().string();
        const fs::path base = fs::path(cmd.outDir) / stem;
        writeTextFileAtomic(base.string() + ".md",
                            separationMarkdown(report, layers.objects, spec.title));
        writeTextFileAtomic(base.string() + ".csv", separationCsv(report, layers.objects));
        RgbImage rgb = filmToRgb(film, spec.exposure);
        applyTone(rgb, spec.tone);
        writeImage(base.string() + ".png", rgb);
        fs::create_directories(base);
        for (const PairSeparation& p : report.pairs)
            writeImage((base / (fileSafe(layers.objects[size_t(p.a)]) + "_vs_" +
                                fileSafe(layers.objects[size_t(p.b)]) + ".png"))
                           .string(),
                       separationMap(layers, p.a, p.b, itp ? kWeberContrast : threshold));
        char buf[64];
        std::snprintf(buf, sizeof buf, "%.6g", report.score);
        summary += stem + "," + buf;
        std::snprintf(buf, sizeof buf, ",%.6g", report.highlight);
        summary += buf;
        for (const ObjectVisibility& v : report.objects) {
            std::snprintf(buf, sizeof buf, ",%.4f,%.4f", v.visibleShare, v.specularShare);
            summary += "," + v.name + buf;
        }
        summary += "\n";
        if (!cmd.quiet) {
            std::fprintf(stderr, "\n[%zu/%zu] %s: separation %.4g;", i + 1, specs.size(),
                         spec.title.c_str(), report.score);
            for (const ObjectVisibility& v : report.objects)
                std::fprintf(stderr, " %s highlight on %.1f %%", v.name.c_str(),
                             100.0 * v.specularShare);
            std::fprintf(stderr, " -> %s.md\n", base.string().c_str());
        }
    }
    writeTextFileAtomic((fs::path(cmd.outDir) / "separation.csv").string(), summary);
}

}  // namespace

void registerSeparationCommand(CLI::App& app) {
    static SeparationCommand cmd;
    CLI::App* sub = app.add_subcommand(
        "separation",
        "Measure whether a viewer can tell the objects of a rendering apart: highlight separation "
        "(total flux overlap) weighted by each object's visibility, veiling and colour identity "
        "(per-object passes; docs/separation.md)");
    sub->add_option("scenes", cmd.scenes, "scene files")->required();
    sub->add_option("--out", cmd.outDir, "output folder")->capture_default_str();
    addOverrideOptions(*sub, cmd.overrides);
    sub->add_option("--metric", cmd.metric,
                    "weber: Weber-contrast highlights × visibility, veiling, identity; itp: "
                    "ΔE_ITP detection maps of each specular pass (BT.2124)")
        ->capture_default_str();
    sub->add_option("--contrast", cmd.contrast,
                    "threshold at which a highlight counts as seen (default: Weber contrast "
                    "0.02; ΔE_ITP 1 with --metric itp)");
    sub->add_option("--peak", cmd.peak,
                    "display peak luminance in cd/m² for --metric itp (sRGB display model)")
        ->capture_default_str();
    sub->add_option("--merge", cmd.merge,
                    "score several objects as one: NAME=OBJECT,OBJECT,... (repeatable)");
    sub->add_option("--threads", cmd.threads, "worker threads (0: all cores)")
        ->capture_default_str()
        ->check(CLI::Range(0, 1024));
    sub->add_flag("--quiet", cmd.quiet, "no progress display or summary");
    sub->callback([] { runSeparation(cmd); });
}

}  // namespace lobe
