// `lobe demo`: the README's first command. Renders the default scene — the paper's rendering 1
// (skull Ward, cortex Ashikhmin–Shirley, density maps He–Torrance) from the data shipped in
// assets/ — and the BRDF gallery into --out, as EXR and PNG. The default size (512², 4 spp)
// keeps a first run short; --size 1024 --spp 8 gives the paper's settings.
#include "apps/commands.h"
#include "apps/data_dir.h"
#include "core/error.h"
#include "core/image_output.h"
#include "core/output_folder.h"
#include "figure/figure_output.h"
#include "render/gallery.h"
#include "render/render_scene.h"
#include "render/scene_file.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <filesystem>

namespace lobe {
namespace {

namespace fs = std::filesystem;

struct DemoCommand {
    std::string outDir = "out";
    std::string assets;  // "" : findAssetsDir()
    int size = 512;
    int spp = 4;
    int threads = 0;
    bool quiet = false;
};

void runDemo(const DemoCommand& cmd) {
    if (cmd.size < 16 || cmd.size > 16384) throw Error("--size must be in [16, 16384]");
    if (cmd.spp < 1 || cmd.spp > 4096) throw Error("--spp must be in [1, 4096]");
    const std::string assets = cmd.assets.empty() ? findAssetsDir() : cmd.assets;
    if (assets.empty())
        throw Error(
            "cannot find Lobe's assets folder next to the executable (installed: "
            "PREFIX/share/lobe/assets; in a build tree: the repository's assets/); give it "
            "with --assets");
    const fs::path scenePath = fs::path(assets) / "scenes" / "paper" / "rendering-01.json";
    if (!fs::exists(scenePath))
        throw Error("cannot find the demo scene '" + scenePath.string() +
                    "' (give the repository's assets folder with --assets)");
    createOutputFolder(cmd.outDir);

    SceneSpec spec = loadSceneFile(scenePath.string());
    spec.width = spec.height = cmd.size;
    spec.samplesPerPixel = cmd.spp;
    const RenderScene scene(spec, !cmd.quiet);
    RenderOptions options;
    options.threads = cmd.threads;
    options.progress = !cmd.quiet;
    options.label = "rendering 1";
    RenderStats stats;
    const Film film = scene.render(options, &stats);
    const std::string base = (fs::path(cmd.outDir) / "rendering-01").string();
    // With the provenance `lobe render` records (figure/figure_output.h).
    ImageWriteOptions write;
    write.attributes = provenance(spec);
    RgbImage rgb = filmToRgb(film, spec.exposure);
    applyTone(rgb, spec.tone);
    std::vector<PendingImage> files;
    files.push_back(writeImagePending(base + ".png", rgb, write));
    files.push_back(writeFilmPending(base + ".exr", film, spec.exposure, {}, write));
    PendingImage::commitAll(files);

    GalleryOptions gallery;
    gallery.threads = cmd.threads;
    gallery.progress = !cmd.quiet;
    const Gallery g = renderGallery(gallery);
    const std::string galleryBase = (fs::path(cmd.outDir) / "gallery").string();
    writeGalleryFiles(galleryBase, g, gallery);
    if (!cmd.quiet)
        std::printf(
            "rendering 1 (%s): %dx%d, %d spp in %.1f s -> %s.png / .exr\n"
            "BRDF gallery -> %s.png / .exr\n",
            spec.title.c_str(), spec.width, spec.height, spec.samplesPerPixel, stats.seconds,
            base.c_str(), galleryBase.c_str());
}

}  // namespace

void registerDemoCommand(CLI::App& app) {
    static DemoCommand cmd;
    CLI::App* sub = app.add_subcommand(
        "demo",
        "Render the default scene (the paper's rendering 1) and the BRDF gallery into --out");
    sub->add_option("--out", cmd.outDir, "output folder")->capture_default_str();
    sub->add_option("--size", cmd.size, "image width and height")->capture_default_str();
    sub->add_option("--spp", cmd.spp, "samples per pixel")->capture_default_str();
    sub->add_option("--threads", cmd.threads, "worker threads (0: all cores)")
        ->capture_default_str();
    sub->add_option("--assets", cmd.assets,
                    "the assets folder (default: found next to the executable, apps/data_dir.h)");
    sub->add_flag("--quiet", cmd.quiet, "no progress display");
    sub->callback([] { runDemo(cmd); });
}

}  // namespace lobe
