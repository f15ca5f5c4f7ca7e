// `lobe render SCENE... [--out DIR]`, `lobe merge` and `lobe contact-sheet`: their options. The
// batch they run — checks, preloading, shards, orbits, posters in bands, MPI — is batch/batch.h;
// the files each image becomes, figure/figure_output.h.
#include "apps/commands.h"
#include "apps/options.h"
#include "batch/batch.h"
#include "core/error.h"
#include "core/image_output.h"
#include "figure/figure_output.h"

#include <CLI/CLI.hpp>

#include <filesystem>

namespace lobe {

namespace {

namespace fs = std::filesystem;

struct SheetCommand {
    std::string out;
    std::vector<std::string> images;  // IMAGE or IMAGE=CAPTION
    int columns = 3;
    int thumb = 256;
};

void runSheet(const SheetCommand& cmd) {
    if (cmd.columns < 1 || cmd.thumb < 16) throw Error("--columns must be >= 1 and --thumb >= 16");
    std::vector<ContactSheetEntry> entries;
    for (const std::string& item : cmd.images) {
        const auto eq = item.find('=');
        const std::string path = item.substr(0, eq);
        const std::string caption =
            eq == std::string::npos ? fs::path(path).stem().string() : item.substr(eq + 1);
        entries.push_back({readImage(path), caption});
    }
    writeContactSheet(cmd.out, entries, cmd.columns, cmd.thumb);
}

}  // namespace

void registerRenderCommand(CLI::App& app) {
    static SheetCommand sheet;
    CLI::App* sheetSub = app.add_subcommand(
        "contact-sheet", "Put existing images side by side with captions (as render batches do)");
    sheetSub->add_option("--out", sheet.out, "the sheet to write (.png, .jpg, .exr)")->required();
    sheetSub->add_option("images", sheet.images, "IMAGE or IMAGE=CAPTION, in order")->required();
    sheetSub->add_option("--columns", sheet.columns, "images per row")->capture_default_str();
    sheetSub->add_option("--thumb", sheet.thumb, "thumbnail width in pixels")
        ->capture_default_str()
        ->check(CLI::Range(16, 4096));
    sheetSub->callback([] { runSheet(sheet); });

    static BatchOptions cmd;
    CLI::App* sub = app.add_subcommand(
        "render",
        "Render scene files (JSON) to EXR and PNG; several scenes or a folder make a "
        "batch with contact sheets per scene group");
    sub->add_option("scenes", cmd.inputs, "scene files or folders of them");
    sub->add_option("--list", cmd.listFile, "a file listing scene files, one per line");
    sub->add_option("--out", cmd.outDir, "output folder")->capture_default_str();
    addOverrideOptions(*sub, cmd.overrides);
    sub->add_option("--threads", cmd.threads, "worker threads (0: all cores)")
        ->capture_default_str()
        ->check(CLI::Range(0, 1024));
    sub->add_option("--sheet-thumb", cmd.sheetThumb, "contact sheet thumbnail width")
        ->capture_default_str()
        ->check(CLI::Range(16, 4096));
    sub->add_flag("--no-contact-sheets", cmd.noContactSheets, "write no contact sheets");
    sub->add_flag("--check", cmd.check,
                  "read and check every scene, print every error, render nothing");
    sub->add_flag("--skip-existing", cmd.skipExisting,
                  "do not render scenes whose .exr and .png exist (resume a batch)");
    sub->add_flag("--keep-going", cmd.keepGoing,
                  "report a failing scene and go on with the others (exit 1 at the end)");
    sub->add_option("--shard", cmd.shard,
                    "I/N: render part I (0-based) of N — every N-th scene of a batch, or a band of "
                    "rows of one image written as NAME.part-I-of-N.exr; `lobe merge` joins them "
                    "(docs/cluster.md)");
    sub->add_option(
        "--aov", cmd.aov,
        "extra EXR passes: all, or a comma list of objects (each object's lambert and "
        "specular contribution), backdrop, depth, normal, id (object contributing most)");
    sub->add_option("--orbit", cmd.orbit,
                    "N: a turntable of each scene, N frames turned 360/N degrees apart about the "
                    "camera's up axis through the objects' centre, lights turning with the camera; "
                    "writes NAME-orbit-000.exr/.png ... and contact-sheet-NAME-orbit.png")
        ->check(CLI::Range(1, 3600));
    addFigureOptions(*sub, cmd.figure);
    sub->add_flag("--quiet", cmd.quiet, "no progress display or summary");
    sub->add_flag("--stats", cmd.stats,
                  "after each scene, print its CPU time by part and each object's BRDF "
                  "evaluations and shading time (as `lobe cost`; docs/cost.md)");
    sub->callback([] { renderScenes(cmd); });

    static BatchOptions merge;
    CLI::App* mergeSub = app.add_subcommand(
        "merge",
        "Join what `lobe render --shard I/N` wrote (parts of one image, or a batch's "
        "scenes) into the files of one run, and write the contact sheets");
    mergeSub->add_option("scenes", merge.inputs, "the scene files given to the sharded renders");
    mergeSub->add_option("--list", merge.listFile, "a file listing scene files, one per line");
    mergeSub->add_option("--out", merge.outDir, "the output folder of the sharded renders")
        ->capture_default_str();
    addOverrideOptions(*mergeSub, merge.overrides);
    mergeSub->add_option("--aov", merge.aov, "the --aov the parts were rendered with");
    mergeSub->add_option("--sheet-thumb", merge.sheetThumb, "contact sheet thumbnail width")
        ->capture_default_str()
        ->check(CLI::Range(16, 4096));
    mergeSub->add_flag("--no-contact-sheets", merge.noContactSheets, "write no contact sheets");
    mergeSub->add_flag("--quiet", merge.quiet, "no summary");
    mergeSub->footer("Give it the same scene files and overrides as the sharded renders.");
    mergeSub->callback([] { mergeShards(merge); });
}

}  // namespace lobe
