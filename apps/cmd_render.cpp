// `lobe render SCENE... [--out DIR]`: renders scene files (docs/scene-format.md) to EXR and PNG.
// Given several scenes, a folder of them or a list file, it validates every scene first (so a
// typo in the 20th file is reported before hours of rendering), renders them one after another
// with one progress display over the whole batch, and writes a contact sheet per scene group.
#include "apps/commands.h"
#include "apps/contact_sheet.h"
#include "apps/scene_overrides.h"
#include "render/render_scene.h"
#include "render/scene_file.h"
#include "core/error.h"
#include "core/image_output.h"
#include "core/progress.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>

namespace lobe {
namespace {

namespace fs = std::filesystem;

struct RenderCommand {
    std::vector<std::string> inputs;
    std::string listFile;
    std::string outDir = "out";
    SceneOverrides overrides;
    int threads = 0;
    bool quiet = false;
    bool noContactSheets = false;
    int sheetThumb = 256;
    std::string aov;  // --aov LIST: per-object passes as extra EXR channels
};

// Scene files named by the inputs: files as given, folders' *.json in name order, list files'
// lines (relative to the list's folder).
std::vector<std::string> collectScenes(const RenderCommand& cmd) {
    std::vector<std::string> scenes;
    for (const std::string& input : cmd.inputs) {
        if (fs::is_directory(input)) {
            std::vector<std::string> found;
            for (const auto& entry : fs::directory_iterator(input))
                if (entry.path().extension() == ".json") found.push_back(entry.path().string());
            std::sort(found.begin(), found.end());
            if (found.empty()) throw Error("folder '" + input + "' holds no .json scene files");
            scenes.insert(scenes.end(), found.begin(), found.end());
        } else {
            if (!fs::exists(input)) throw Error("scene file '" + input + "' does not exist");
            scenes.push_back(input);
        }
    }
    if (!cmd.listFile.empty()) {
        std::ifstream in(cmd.listFile);
        if (!in) throw Error("cannot open list file '" + cmd.listFile + "'");
        std::string line;
        int n = 0;
        while (std::getline(in, line)) {
            ++n;
            line.erase(0, line.find_first_not_of(" \t\r"));
            line.erase(line.find_last_not_of(" \t\r") + 1);
            if (line.empty() || line[0] == '#') continue;
            const fs::path p = fs::path(line).is_absolute()
                                   ? fs::path(line)
                                   : fs::path(cmd.listFile).parent_path() / line;
            if (!fs::exists(p))
                throw Error(cmd.listFile + ":" + std::to_string(n) + ": scene file '" + p.string() +
                            "' does not exist");
            scenes.push_back(p.string());
        }
    }
    if (scenes.empty()) throw Error("no scene given (a scene file, a folder or --list FILE)");
    return scenes;
}

void runRender(const RenderCommand& cmd) {
    cmd.overrides.validate();
    AovRequest aov;
    if (!cmd.aov.empty()) aov = AovRequest::parse(cmd.aov);
    const std::vector<std::string> files = collectScenes(cmd);
    std::vector<SceneSpec> specs;
    int64_t totalPixels = 0;
    for (const std::string& f : files) {
        specs.push_back(loadSceneFile(f));
        cmd.overrides.apply(specs.back());
        totalPixels += int64_t(specs.back().width) * specs.back().height;
    }
    fs::create_directories(cmd.outDir);

    ProgressReporter progress(files.size() == 1 ? "render" : "render batch", totalPixels, !cmd.quiet);
    std::map<std::string, std::vector<ContactSheetEntry>> sheets;
    for (size_t i = 0; i < specs.size(); ++i) {
        const SceneSpec& spec = specs[i];
        const RenderScene scene(spec, false);
        RenderOptions options;
        options.threads = cmd.threads;
        options.progress = !cmd.quiet;
        options.sharedProgress = &progress;
        RenderStats stats;
        AovImage aovs;
        const Film film = scene.render(options, &stats, &aov, &aovs);
        const std::string base = (fs::path(cmd.outDir) / fs::path(spec.path).stem()).string();
        ImageChannels extra;
        if (aov.any()) {
            std::vector<std::string> names;
            for (const ObjectSpec& o : spec.objects) names.push_back(o.name);
            appendAovChannels(aov, aovs, names, spec.exposure, extra);
        }
        writeFilm(base + ".exr", film, spec.exposure, extra);
        RgbImage rgb = filmToRgb(film, spec.exposure);
        applyTone(rgb, spec.tone);
        writeImage(base + ".png", rgb);
        if (!cmd.quiet)
            std::fprintf(stderr, "\n[%zu/%zu] %s: %dx%d, %d spp, %.2f s, %.2f M rays, %.1f M volume "
                                 "samples (%.1f M shaded) -> %s.png/.exr\n",
                         i + 1, specs.size(), spec.title.c_str(), spec.width, spec.height,
                         spec.samplesPerPixel, stats.seconds, stats.rays * 1e-6,
                         stats.volumeSamples * 1e-6, stats.volumeShaded * 1e-6, base.c_str());
        if (!spec.group.empty() && !cmd.noContactSheets) sheets[spec.group].push_back({rgb, spec.title});
    }
    progress.finish();
    for (const auto& [group, entries] : sheets) {
        const std::string path = (fs::path(cmd.outDir) / ("contact-sheet-" + group + ".png")).string();
        writeImage(path, makeContactSheet(entries, 3, cmd.sheetThumb));
        if (!cmd.quiet) std::fprintf(stderr, "contact sheet %s\n", path.c_str());
    }
}

}  // namespace

namespace {

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
    writeImage(cmd.out, makeContactSheet(entries, cmd.columns, cmd.thumb));
}

}  // namespace

void registerRenderCommand(CLI::App& app) {
    static SheetCommand sheet;
    CLI::App* sheetSub = app.add_subcommand(
        "contact-sheet", "Put existing images side by side with captions (as render batches do)");
    sheetSub->add_option("--out", sheet.out, "the sheet to write (.png, .jpg, .exr)")->required();
    sheetSub->add_option("images", sheet.images, "IMAGE or IMAGE=CAPTION, in order")->required();
    sheetSub->add_option("--columns", sheet.columns, "images per row")->capture_default_str();
    sheetSub->add_option("--thumb", sheet.thumb, "thumbnail width in pixels")->capture_default_str();
    sheetSub->callback([] { runSheet(sheet); });

    static RenderCommand cmd;
    CLI::App* sub = app.add_subcommand(
        "render", "Render scene files (JSON) to EXR and PNG; several scenes or a folder make a "
                  "batch with contact sheets per scene group");
    sub->add_option("scenes", cmd.inputs, "scene files or folders of them");
    sub->add_option("--list", cmd.listFile, "a file listing scene files, one per line");
    sub->add_option("--out", cmd.outDir, "output folder")->capture_default_str();
    cmd.overrides.addOptions(*sub);
    sub->add_option("--threads", cmd.threads, "worker threads (0: all cores)")->capture_default_str();
    sub->add_option("--sheet-thumb", cmd.sheetThumb, "contact sheet thumbnail width")
        ->capture_default_str();
    sub->add_flag("--no-contact-sheets", cmd.noContactSheets, "write no contact sheets");
    sub->add_option("--aov", cmd.aov,
                    "extra EXR passes: all, or a comma list of objects (each object's lambert and "
                    "specular contribution), backdrop, depth, normal, id (object contributing most)");
    sub->add_flag("--quiet", cmd.quiet, "no progress display or summary");
    sub->callback([] { runRender(cmd); });
}

}  // namespace lobe
