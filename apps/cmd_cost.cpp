// `lobe cost SCENE [--models a,b,… --object NAME] [--csv FILE]`: what a render of the user's own
// scene costs — CPU time by part (surfaces, volume sampling, shading, other) and, per object, the
// BRDF evaluations and the CPU time of shading them; with --models, the same scene rendered again
// with each model on one object, side by side. Prints Markdown; --csv writes the same numbers as
// one long table. Nothing else is written. docs/cost.md explains what each number measures.
#include "analysis/cost_report.h"
#include "analysis/overlap_report.h"
#include "apps/commands.h"
#include "apps/options.h"
#include "core/error.h"
#include "core/temporary_file.h"
#include "materials/registry.h"
#include "render/render_scene.h"
#include "render/scene_file.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <sstream>

namespace lobe {
namespace {

namespace fs = std::filesystem;

struct CostCommand {
    std::string scene;
    SceneOverrides overrides;
    std::string models;  // comma list of registry names
    std::string object;  // the object the models go on
    std::string csv;
    int repeat = 1;
    int threads = 0;
    bool quiet = false;
};

std::vector<std::string> splitList(const std::string& text) {
    std::vector<std::string> items;
    std::stringstream ss(text);
    std::string item;
    while (std::getline(ss, item, ',')) {
        item.erase(0, item.find_first_not_of(" \t"));
        item.erase(item.find_last_not_of(" \t") + 1);
        if (!item.empty()) items.push_back(item);
    }
    return items;
}

// The object the models go on: --object by name, or the scene's only object.
int objectIndex(const SceneSpec& spec, const std::string& name) {
    if (name.empty()) {
        if (spec.objects.size() == 1) return 0;
        std::string names;
        for (const ObjectSpec& o : spec.objects) names += (names.empty() ? "" : ", ") + o.name;
        throw Error("--models needs --object NAME: the scene has " +
                    std::to_string(spec.objects.size()) + " objects (" + names + ")");
    }
    for (size_t i = 0; i < spec.objects.size(); ++i)
        if (spec.objects[i].name == name) return int(i);
    std::string names;
    for (const ObjectSpec& o : spec.objects) names += (names.empty() ? "" : ", ") + o.name;
    throw Error("--object: " + spec.path + " has no object '" + name + "' (objects: " + names +
                ")");
}

void runCost(const CostCommand& cmd) {
    cmd.overrides.validate();
    if (cmd.repeat < 1 || cmd.repeat > 100) throw Error("--repeat must be in [1, 100]");
    if (!cmd.object.empty() && cmd.models.empty())
        throw Error("--object names the object for --models; give --models too");
    SceneSpec spec = loadSceneFile(cmd.scene);
    cmd.overrides.apply(spec);

    // The runs: the scene as written, then each model of --models on the chosen object (with the
    // model's default parameters; the object's kd and colour stay).
    std::vector<CostRun> runs;
    runs.push_back({"scene", spec, {}});
    int target = -1;
    if (!cmd.models.empty()) {
        target = objectIndex(spec, cmd.object);
        const std::vector<std::string> names = splitList(cmd.models);
        if (names.empty())
            throw Error("--models: expected a comma list of models (lobe brdf list)");
        for (const std::string& name : names) {
            SceneSpec s = spec;
            ObjectSpec& o = s.objects[size_t(target)];
            try {
                o.material.specular = makeBrdf(name);
            } catch (const Error& e) {
                throw Error(std::string("--models: ") + e.what());
            }
            o.brdfModel = name;
            o.material.specularOn = true;
            runs.push_back({name, std::move(s), {}});
        }
    }

    // Rounds over all runs (a, b, c, a, b, c, …) so that a machine's changing load falls on every
    // model alike; each run keeps its fastest round (the counts are the same in every round).
    VolumeCache volumes;
    for (int round = 0; round < cmd.repeat; ++round)
        for (CostRun& run : runs) {
            const RenderScene scene(run.spec, false, &volumes);
            RenderOptions options;
            options.threads = cmd.threads;
            options.progress = !cmd.quiet;
            options.label = "cost: " + run.label;
            RenderCost cost;
            options.cost = &cost;
            scene.render(options);
            if (round == 0 || cost.cpuSeconds < run.cost.cpuSeconds) run.cost = cost;
        }
    if (!cmd.quiet) std::fprintf(stderr, "\n");

    std::string md = costMarkdown(runs, target, cmd.threads, cmd.repeat);
    std::fputs(md.c_str(), stdout);
    if (!cmd.csv.empty()) writeTextFileAtomic(cmd.csv, costCsv(runs));
}

}  // namespace

void registerCostCommand(CLI::App& app) {
    static CostCommand cmd;
    CLI::App* sub = app.add_subcommand(
        "cost",
        "What rendering a scene costs: CPU time by part (surfaces, volume sampling, "
        "shading) and per object its BRDF evaluations and their time; with --models, the "
        "same scene with each model on one object (docs/cost.md)");
    sub->add_option("scene", cmd.scene, "a scene file (docs/scene-format.md)")->required();
    addOverrideOptions(*sub, cmd.overrides);
    sub->add_option("--models", cmd.models,
                    "comma list of models (lobe brdf list, default parameters) to render the "
                    "scene with, one after another, on --object");
    sub->add_option("--object", cmd.object,
                    "the object --models go on (its name in the scene; not needed for a scene of "
                    "one object)");
    sub->add_option("--csv", cmd.csv, "also write the numbers as CSV to this file");
    sub->add_option("--repeat", cmd.repeat,
                    "render every run N times in alternation and keep each run's fastest (times "
                    "on a busy machine)")
        ->capture_default_str();
    sub->add_option("--threads", cmd.threads, "worker threads (0: all cores)")
        ->capture_default_str()
        ->check(CLI::Range(0, 1024));
    sub->add_flag("--quiet", cmd.quiet, "no progress display");
    sub->footer(
        "Example: lobe cost assets/scenes/paper/rendering-01.json --width 128 --spp 1 "
        "--object cortex --models ward,he_torrance,cook_torrance --csv cost.csv");
    sub->callback([] { runCost(cmd); });
}

}  // namespace lobe
