// `lobe overlap`: the total flux overlap test of the paper's "BRDF flux overlap" section, as fixed
// by docs/flux-overlap.md. Renders every specular model's lattices once (3 implicit
// primitives × 3 bands), scores all unordered pairs, and writes overlap.csv, overlap.md,
// overlap-heatmap.png and lobes/<a>_vs_<b>.png into --out. `--study` instead runs the convergence
// study (lattice size × samples per pixel against the largest of both) and writes study.md.
#include "analysis/overlap_ranking.h"
#include "analysis/overlap_report.h"
#include "apps/commands.h"
#include "core/error.h"
#include "core/output_folder.h"
#include "core/progress.h"
#include "core/temporary_file.h"
#include "materials/registry.h"

#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace lobe {
namespace {

struct OverlapCommand {
    StandardTestOptions options;
    std::string variant = "sum";
    std::vector<std::string> settings;  // MODEL.key=value
    std::vector<std::string> pairs;     // a,b
    std::string outDir;
    bool quiet = false;
    bool study = false;
};

// "MODEL.key=value" → options.settings[MODEL] += "key=value"; the registry validates the rest.
void parseSettings(const std::vector<std::string>& settings, StandardTestOptions& options) {
    for (const std::string& s : settings) {
        const auto dot = s.find('.');
        const auto eq = s.find('=');
        if (dot == std::string::npos || dot == 0 || eq == std::string::npos || eq < dot)
            throw Error("--set: expected MODEL.key=value, got '" + s + "'");
        options.settings[s.substr(0, dot)].push_back(s.substr(dot + 1));
    }
}

std::vector<std::pair<std::string, std::string>> parsePairs(const std::vector<std::string>& pairs) {
    std::vector<std::pair<std::string, std::string>> out;
    for (const std::string& p : pairs) {
        const auto comma = p.find(',');
        if (comma == std::string::npos || comma == 0 || comma + 1 == p.size() ||
            p.find(',', comma + 1) != std::string::npos)
            throw Error("--pair: expected MODEL_A,MODEL_B, got '" + p + "'");
        out.push_back({p.substr(0, comma), p.substr(comma + 1)});
    }
    return out;
}

void runOverlap(OverlapCommand& cmd) {
    StandardTestOptions options = cmd.options;
    options.progress = !cmd.quiet;
    parseSettings(cmd.settings, options);
    if (options.threads < 0)
        throw Error("--threads " + std::to_string(options.threads) +
                    ": must be ≥ 0 (0: all cores)");
    const OverlapVariant variant = parseOverlapVariant(cmd.variant);
    const auto extraPairs = parsePairs(cmd.pairs);
    validateStandardTestOptions(options);
    // Check --pair names before the (long) render, so bad input fails at once.
    {
        LatticeSet names;
        names.models = options.models.empty() ? specularModelNames() : options.models;
        for (const auto& [a, b] : extraPairs)
            if (names.modelIndex(a) < 0 || names.modelIndex(b) < 0 || a == b)
                throw Error("--pair " + a + "," + b +
                            ": expected two different models of the test");
    }

    if (cmd.study) {
        const std::vector<StudyRow> rows =
            runConvergenceStudy(options, {128, 256, 512}, {1, 4, 16, 64}, variant);
        createOutputFolder(cmd.outDir);
        const std::string path = (std::filesystem::path(cmd.outDir) / "study.md").string();
        writeTextFileAtomic(
            path, "# Flux overlap: convergence against 512² × 64 spp\n\n" + studyMarkdown(rows));
        if (!cmd.quiet) std::printf("wrote %s\n", path.c_str());
        return;
    }

    const auto start = std::chrono::steady_clock::now();
    const std::clock_t cpuStart = std::clock();  // process CPU time: robust to other jobs
    const LatticeSet lattices = renderStandardLattices(options);
    const std::vector<PairScore> pairs =
        scoreAllPairs(lattices, options.threshold, variant, options.threads);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const double cpuSeconds = double(std::clock() - cpuStart) / CLOCKS_PER_SEC;

    std::string settingsLine =
        "Lattice " + std::to_string(options.size) + "², " +
        std::to_string(options.samplesPerPixel) + " jittered samples per pixel, threshold " +
        std::to_string(options.threshold) + ", " + std::to_string(lattices.models.size()) +
        " models, " + std::to_string(pairs.size()) + " pairs; test time " +
        formatDuration(seconds) + " (CPU " + formatDuration(cpuSeconds) + ").";
    for (const std::string& s : cmd.settings) settingsLine += " Override: `" + s + "`.";
    const OverlapReportFiles files = writeOverlapReport(cmd.outDir, lattices, pairs, extraPairs,
                                                        options.threshold, variant, settingsLine);
    if (!cmd.quiet) {
        std::printf(
            "flux overlap: %zu pairs in %s (CPU %s); best %s + %s (%.4g), worst %s + %s "
            "(%.4g)\n",
            pairs.size(), formatDuration(seconds).c_str(), formatDuration(cpuSeconds).c_str(),
            pairs.front().modelA.c_str(), pairs.front().modelB.c_str(), pairs.front().score,
            pairs.back().modelA.c_str(), pairs.back().modelB.c_str(), pairs.back().score);
        std::printf("wrote %s, %s, %s and %zu lobe image(s)\n", files.csv.c_str(),
                    files.markdown.c_str(), files.heatmap.c_str(), files.lobeImages.size());
    }
}

}  // namespace

void registerOverlapCommand(CLI::App& app) {
    static OverlapCommand cmd;
    CLI::App* sub = app.add_subcommand(
        "overlap",
        "Total flux overlap test: rank all pairs of specular BRDFs by how little their "
        "lobes overlap (paper Figures 5-9)");
    sub->add_option("--out", cmd.outDir, "output folder")->required();
    sub->add_option("--size", cmd.options.size, "lattice side in pixels")->capture_default_str();
    sub->add_option("--spp", cmd.options.samplesPerPixel, "jittered samples per pixel (16 = 4x4)")
        ->capture_default_str();
    sub->add_option("--variant", cmd.variant, "metric variant that ranks: sum or mse")
        ->capture_default_str();
    sub->add_option("--set", cmd.settings,
                    "parameter override MODEL.key=value (per band: key=a,b,c); repeatable");
    sub->add_option("--pair", cmd.pairs,
                    "also write lobes/<a>_vs_<b>.png for this pair (A red, B green); repeatable");
    sub->add_option("--threads", cmd.options.threads, "worker threads (0: all cores)")
        ->capture_default_str();
    sub->add_flag("--study", cmd.study,
                  "run the convergence study (128/256/512 x 1/4/16/64 spp; minutes) and write "
                  "study.md instead");
    sub->add_flag("--quiet", cmd.quiet, "no progress display");
    sub->callback([] { runOverlap(cmd); });
}

}  // namespace lobe
