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
    bool check = false;         // validate every scene, print every error, render nothing
    bool skipExisting = false;  // resume: scenes whose EXR and PNG exist are not rendered again
    bool keepGoing = false;     // a failing scene is reported and the batch goes on
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

// Output file names (without extension): the scene file's name in --out, with "-preview" for
// --preview renders so that a quick look never replaces a full render.
std::string outputBase(const RenderCommand& cmd, const SceneSpec& spec) {
    const std::string stem =
        fs::path(spec.path).stem().string() + (cmd.overrides.preview ? "-preview" : "");
    return (fs::path(cmd.outDir) / stem).string();
}

void runRender(const RenderCommand& cmd) {
    cmd.overrides.validate();
    AovRequest aov;
    if (!cmd.aov.empty()) aov = AovRequest::parse(cmd.aov);
    const std::vector<std::string> files = collectScenes(cmd);

    // Every scene is read and checked before anything renders; --check prints every error.
    std::vector<SceneSpec> specs;
    std::vector<std::string> errors;
    std::map<std::string, std::string> writerOf;  // output base → scene file
    for (const std::string& f : files) {
        try {
            SceneSpec spec = loadSceneFile(f);
            cmd.overrides.apply(spec);
            const std::string base = outputBase(cmd, spec);
            const auto [it, fresh] = writerOf.emplace(base, f);
            if (!fresh)
                throw Error("scenes '" + it->second + "' and '" + f + "' would both write " + base +
                            ".exr/.png: rename one, or render them into different --out folders");
            specs.push_back(std::move(spec));
        } catch (const Error& e) {
            if (!cmd.check && !cmd.keepGoing) throw;
            errors.push_back(e.what());
            if (!cmd.check) std::fprintf(stderr, "lobe: error: %s (skipped)\n", e.what());
        }
    }
    if (cmd.check) {
        for (const std::string& e : errors) std::fprintf(stderr, "lobe: error: %s\n", e.c_str());
        if (!errors.empty())
            throw Error(std::to_string(errors.size()) + " of " + std::to_string(files.size()) +
                        " scenes have errors");
        std::printf("%zu scene%s valid\n", files.size(), files.size() == 1 ? "" : "s");
        return;
    }
    int64_t totalPixels = 0;
    for (const SceneSpec& spec : specs) totalPixels += int64_t(spec.width) * spec.height;
    fs::create_directories(cmd.outDir);

    ProgressReporter progress(files.size() == 1 ? "render" : "render batch", totalPixels, !cmd.quiet);
    std::map<std::string, std::vector<ContactSheetEntry>> sheets;
    for (size_t i = 0; i < specs.size(); ++i) {
        const SceneSpec& spec = specs[i];
        const std::string base = outputBase(cmd, spec);
        const bool inSheet = !spec.group.empty() && !cmd.noContactSheets;
        if (cmd.skipExisting && fs::exists(base + ".exr") && fs::exists(base + ".png")) {
            progress.advance(int64_t(spec.width) * spec.height);
            if (inSheet) sheets[spec.group].push_back({readImage(base + ".png"), spec.title});
            if (!cmd.quiet) std::fprintf(stderr, "\n[%zu/%zu] %s: exists, skipped\n", i + 1,
                                         specs.size(), base.c_str());
            continue;
        }
        try {
            const RenderScene scene(spec, false);
            RenderOptions options;
            options.threads = cmd.threads;
            options.progress = !cmd.quiet;
            options.sharedProgress = &progress;
            RenderStats stats;
            AovImage aovs;
            const Film film = scene.render(options, &stats, &aov, &aovs);
            ImageChannels extra;
            if (aov.any()) {
                std::vector<std::string> names;
                for (const ObjectSpec& o : spec.objects) names.push_back(o.name);
                appendAovChannels(aov, aovs, names, spec.exposure, extra);
            }
            RgbImage rgb = filmToRgb(film, spec.exposure);
            applyTone(rgb, spec.tone);
            // PNG first, EXR last: a resumed batch (--skip-existing) takes a scene as done only
            // when both exist.
            writeImage(base + ".png", rgb);
            writeFilm(base + ".exr", film, spec.exposure, extra);
            if (!cmd.quiet)
                std::fprintf(stderr, "\n[%zu/%zu] %s: %dx%d, %d spp, %.2f s, %.2f M rays, %.1f M volume "
                                     "samples (%.1f M shaded) -> %s.png/.exr\n",
                             i + 1, specs.size(), spec.title.c_str(), spec.width, spec.height,
                             spec.samplesPerPixel, stats.seconds, stats.rays * 1e-6,
                             stats.volumeSamples * 1e-6, stats.volumeShaded * 1e-6, base.c_str());
            if (inSheet) sheets[spec.group].push_back({rgb, spec.title});
        } catch (const Error& e) {
            if (!cmd.keepGoing) throw;
            errors.push_back(e.what());
            std::fprintf(stderr, "\nlobe: error: %s (skipped)\n", e.what());
        }
    }
    progress.finish();
    for (const auto& [group, entries] : sheets) {
        const std::string path = (fs::path(cmd.outDir) / ("contact-sheet-" + group + ".png")).string();
        writeImage(path, makeContactSheet(entries, 3, cmd.sheetThumb));
        if (!cmd.quiet) std::fprintf(stderr, "contact sheet %s\n", path.c_str());
    }
    if (!errors.empty())
        throw Error(std::to_string(errors.size()) + " of " + std::to_string(files.size()) +
                    " scenes failed (--keep-going rendered the others)");
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
    sub->add_option("--threads", cmd.threads, "worker threads (0: all cores)")
        ->capture_default_str()
        ->check(CLI::Range(0, 1024));
    sub->add_option("--sheet-thumb", cmd.sheetThumb, "contact sheet thumbnail width")
        ->capture_default_str();
    sub->add_flag("--no-contact-sheets", cmd.noContactSheets, "write no contact sheets");
    sub->add_flag("--check", cmd.check,
                  "read and check every scene, print every error, render nothing");
    sub->add_flag("--skip-existing", cmd.skipExisting,
                  "do not render scenes whose .exr and .png exist (resume a batch)");
    sub->add_flag("--keep-going", cmd.keepGoing,
                  "report a failing scene and go on with the others (exit 1 at the end)");
    sub->add_option("--aov", cmd.aov,
                    "extra EXR passes: all, or a comma list of objects (each object's lambert and "
                    "specular contribution), backdrop, depth, normal, id (object contributing most)");
    sub->add_flag("--quiet", cmd.quiet, "no progress display or summary");
    sub->callback([] { runRender(cmd); });
}

}  // namespace lobe
