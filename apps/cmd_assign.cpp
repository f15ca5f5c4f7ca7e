// `lobe assign SCENE --out BEST.json`: its options; the work is analysis/assign_scene.h.
#include "analysis/assign_scene.h"
#include "apps/commands.h"
#include "apps/options.h"

#include <CLI/CLI.hpp>

namespace lobe {
namespace {

struct AssignCommand {
    AssignRequest request;
    CLI::Option* equalAlbedoOption = nullptr;
};

}  // namespace

void registerAssignCommand(CLI::App& app) {
    static AssignCommand cmd;
    CLI::App* sub = app.add_subcommand(
        "assign",
        "Choose each object's BRDF so that the objects are told apart: highlights apart, "
        "every object still seen and its colour kept (the paper's adaptive BRDF); writes "
        "the scene with the chosen models");
    sub->add_option("scene", cmd.request.scene, "scene file")->required();
    sub->add_option("--out", cmd.request.out, "the scene file to write (.json)")->required();
    sub->add_option("--keep", cmd.request.keep,
                    "object whose BRDF stays as in the scene (repeatable)");
    sub->add_option("--exclude", cmd.request.exclude, "model not to choose (repeatable)");
    sub->add_flag(
        "--tune", cmd.request.tune,
        "also try each model's documented parameter variants (docs/brdf-properties.md); "
        "in every mode a candidate whose highlight on an object is mostly sub-pixel specks, or "
        "glints (specks that change between two seeds' layers), is not offered there");
    cmd.equalAlbedoOption =
        sub->add_option(
               "--equal-albedo", cmd.request.equalAlbedo,
               "scale every candidate lobe to albedo A at normal incidence (compare models "
               "by shape, not magnitude); A = 0.1 when no value is given; off by default")
            ->expected(0, 1)
            ->type_name("[A]");
    sub->add_flag("--distinct", cmd.request.distinct, "no two objects share a model");
    sub->add_option("--keep-visible", cmd.request.keepFraction,
                    "every object's visibility and chroma stay at least this fraction of the "
                    "input's (0: no bound)")
        ->capture_default_str();
    sub->add_option(
           "--brightness-band", cmd.request.brightnessBand,
           "B > 1: every object's mean luminance within [1/B, B] × the input's (0: no band)")
        ->capture_default_str();
    sub->add_option("--metric", cmd.request.metric,
                    "the score: weber (highlight separation × visibility, veiling, identity) or "
                    "itp (ΔE_ITP detection maps)")
        ->capture_default_str();
    sub->add_option("--top", cmd.request.top, "ranked assignments in the report")
        ->capture_default_str();
    addOverrideOptions(*sub, cmd.request.overrides);
    sub->add_option("--threads", cmd.request.threads, "worker threads (0: all cores)")
        ->capture_default_str()
        ->check(CLI::Range(0, 1024));
    sub->add_flag("--force", cmd.request.force, "replace --out and its report if they exist");
    sub->add_flag("--quiet", cmd.request.quiet, "no progress display or summary");
    sub->footer(
        "The layers are rendered at 256 pixels wide and 2 spp unless --width/--spp/--preview say "
        "otherwise.");
    sub->callback([] {
        if (cmd.equalAlbedoOption->count() > 0 && cmd.request.equalAlbedo.empty())
            cmd.request.equalAlbedo = "0.1";
        assignScene(cmd.request);
    });
}

}  // namespace lobe
