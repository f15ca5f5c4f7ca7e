// `lobe gallery` renders the BRDF gallery (the nine models on spheres).
#include "apps/commands.h"
#include "core/error.h"
#include "core/image_output.h"
#include "core/output_folder.h"
#include "figure/figure_output.h"
#include "render/gallery.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <filesystem>

namespace lobe {
namespace {

struct GalleryCommand {
    GalleryOptions options;
    std::string outDir = "out";
    bool quiet = false;
};

void runGallery(const GalleryCommand& cmd) {
    GalleryOptions options = cmd.options;
    options.progress = !cmd.quiet;
    createOutputFolder(cmd.outDir);
    const Gallery gallery = renderGallery(options);
    const std::string base = (std::filesystem::path(cmd.outDir) / "gallery").string();
    writeGalleryFiles(base, gallery, options);
    if (!cmd.quiet) std::printf("wrote %s.exr and %s.png\n", base.c_str(), base.c_str());
}

void addGalleryOptions(CLI::App* sub, GalleryCommand& cmd) {
    sub->add_option("--out", cmd.outDir, "output folder (gallery.exr and gallery.png)")
        ->capture_default_str();
    sub->add_option("--cell", cmd.options.cellSize, "pixels per sphere cell")
        ->capture_default_str();
    sub->add_option("--spp", cmd.options.samplesPerPixel, "jittered samples per pixel")
        ->capture_default_str();
    sub->add_option("--threads", cmd.options.threads, "worker threads (0: all cores)")
        ->capture_default_str();
    sub->add_option("--seed", cmd.options.seed, "random seed")->capture_default_str();
    sub->add_option("--set", cmd.options.settings,
                    "parameter override MODEL.key=value (per band: key=a,b,c); repeatable");
    sub->add_flag("--quiet", cmd.quiet, "no progress display");
}

}  // namespace

void registerGalleryCommands(CLI::App& app) {
    static GalleryCommand gallery;
    CLI::App* sub = app.add_subcommand(
        "gallery", "Render the nine BRDFs side by side on spheres (the paper's Figure 3)");
    addGalleryOptions(sub, gallery);
    sub->callback([] { runGallery(gallery); });
}

}  // namespace lobe
