// The batch engine (batch/batch.h): `lobe render`, `lobe merge` and renderBatch.
#include "batch/batch.h"

#include "analysis/cost_report.h"
#include "batch/batch_eta.h"
#include "cluster/cluster.h"
#include "core/error.h"
#include "core/image_output.h"
#include "core/output_folder.h"
#include "core/progress.h"
#include "figure/contact_sheet.h"
#include "figure/figure_output.h"
#include "render/framing.h"
#include "render/render_scene.h"
#include "render/scene_file.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <tuple>

namespace lobe {
namespace {

namespace fs = std::filesystem;

using RenderCommand = BatchOptions;

// --shard i/N → (i, N); N = 0 when not sharding.
std::pair<int, int> parseShard(const std::string& text) {
    if (text.empty()) return {0, 0};
    const auto slash = text.find('/');
    int i = -1, n = 0;
    try {
        size_t used = 0;
        i = std::stoi(text.substr(0, slash), &used);
        if (used != slash) i = -1;
        n = std::stoi(text.substr(slash + 1), &used);
        if (slash + 1 + used != text.size()) n = 0;
    } catch (const std::exception&) {
        i = -1;
    }
    if (slash == std::string::npos || n < 1 || n > 100000 || i < 0 || i >= n)
        throw Error("--shard: expected I/N with 0 <= I < N <= 100000, got '" + text + "'");
    return {i, n};
}

// FNV-1a 64 of a text, in hex: identifies a scene file's content and a run's settings in the
// header of every shard part, so `lobe merge` joins only parts of the same scene and settings.
std::string fingerprint(const std::string& text) {
    uint64_t h = 1469598103934665603ull;
    for (unsigned char c : text) h = (h ^ c) * 1099511628211ull;
    char buf[17];
    std::snprintf(buf, sizeof buf, "%016llx", (unsigned long long)h);
    return buf;
}

std::string fileText(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

// What a part's pixels depend on besides the scene file: size, sampling and everything the
// overrides and --aov set.
std::string settingsText(const SceneSpec& spec, const std::string& aov) {
    char buf[256];
    std::snprintf(buf, sizeof buf, "%dx%d spp %d seed %llu step %.17g%s roulette %.17g aov ",
                  spec.width, spec.height, spec.samplesPerPixel, (unsigned long long)spec.seed,
                  spec.volumeStepVoxels, spec.volumePreIntegrated ? " pre-integrated" : "",
                  spec.shadingRoulette);
    return buf + aov;
}

std::string partPath(const std::string& base, int i, int n) {
    return base + ".part-" + std::to_string(i) + "-of-" + std::to_string(n) + ".exr";
}

// Scene files named by the inputs: files as given, folders' *.json in name order, list files'
// lines (relative to the list's folder).
std::vector<std::string> collectScenes(const RenderCommand& cmd) {
    std::vector<std::string> scenes;
    for (const std::string& input : cmd.inputs) {
        std::error_code ec;
        if (fs::is_directory(input, ec)) {
            std::vector<std::string> found;
            for (const auto& entry : fs::directory_iterator(input))
                if (entry.path().extension() == ".json") found.push_back(entry.path().string());
            std::sort(found.begin(), found.end());
            if (found.empty()) throw Error("folder '" + input + "' holds no .json scene files");
            scenes.insert(scenes.end(), found.begin(), found.end());
        } else {
            if (!fs::exists(input, ec))
                throw Error(
                    "scene file '" + input + "' " +
                    (ec ? "cannot be read: " + ec.message() : std::string("does not exist")));
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
            std::error_code ec;
            if (!fs::exists(p, ec))
                throw Error(
                    cmd.listFile + ":" + std::to_string(n) + ": scene file '" + p.string() + "' " +
                    (ec ? "cannot be read: " + ec.message() : std::string("does not exist")));
            scenes.push_back(p.string());
        }
    }
    if (scenes.empty()) throw Error("no scene given (a scene file, a folder or --list FILE)");
    return scenes;
}

// The display image of a written EXR: its R, G, B floats (what the render had before writing)
// through the scene's tone curve — the same pixels a render puts in its contact sheet.
RgbImage displayFromExr(const std::string& path, const std::string& tone,
                        std::vector<float>* alpha = nullptr) {
    const FloatImage image = readFloatImage(path);
    const auto& names = image.channels.names;
    const size_t k = names.size();
    const size_t pixels = size_t(image.width) * image.height;
    RgbImage rgb(image.width, image.height);
    for (int c = 0; c < 3; ++c) {
        const auto it = std::find(names.begin(), names.end(), std::string(1, "RGB"[c]));
        if (it == names.end()) throw Error(path + ": no channel " + std::string(1, "RGB"[c]));
        const size_t ch = size_t(it - names.begin());
        for (size_t p = 0; p < pixels; ++p)
            rgb.rgb[p * 3 + size_t(c)] = image.channels.data[p * k + ch];
    }
    // The coverage, when asked for and present (a transparent background's channel A).
    const auto a = std::find(names.begin(), names.end(), std::string("A"));
    if (alpha && a != names.end()) {
        alpha->resize(pixels);
        for (size_t p = 0; p < pixels; ++p)
            (*alpha)[p] = image.channels.data[p * k + size_t(a - names.begin())];
    }
    applyDisplayTone(rgb, alpha && !alpha->empty() ? alpha : nullptr, tone);
    return rgb;
}

// The contact-sheet thumbnail of a written EXR — what makeContactSheet(…, thumbWidth) makes of
// displayFromExr's image, the same floats — read a band at a time, so that a poster already on
// disk (--skip-existing, lobe merge) is never whole in memory.
RgbImage thumbnailFromExr(const std::string& path, const std::string& tone, int thumbWidth) {
    std::unique_ptr<BoxResizer> resizer;
    forEachRgbBand(path, kBandPixels, [&](RgbImage& band, int height) {
        if (!resizer) {
            const int h = int(std::lround(double(thumbWidth) * height / std::max(1, band.width)));
            resizer = std::make_unique<BoxResizer>(band.width, height, thumbWidth, std::max(1, h));
        }
        applyTone(band, tone);
        resizer->addRows(band);
    });
    return resizer->result();
}

// The EXR channels of the requested per-object passes (none when no pass was asked for).
ImageChannels passChannels(const AovRequest& aov, const AovImage& aovs, const SceneSpec& spec) {
    ImageChannels extra;
    if (!aov.any()) return extra;
    std::vector<std::string> names;
    for (const ObjectSpec& o : spec.objects) names.push_back(o.name);
    appendAovChannels(aov, aovs, names, spec.exposure, extra);
    return extra;
}

// The per-pixel buffers of a render, for gathering the pixels other processes rendered.
std::vector<PixelBuffer> pixelBuffers(Film& film, AovImage& aovs) {
    std::vector<PixelBuffer> buffers{
        {reinterpret_cast<unsigned char*>(film.data()), sizeof(Spectrum)}};
    const size_t pixels = size_t(film.width()) * size_t(film.height());
    for (std::vector<float>* pass :
         {&aovs.lambert, &aovs.specular, &aovs.backdrop, &aovs.depth, &aovs.normal, &aovs.topObject,
          &aovs.modelSpecular, &aovs.alpha, &aovs.objectDepth})
        if (!pass->empty())
            buffers.push_back({reinterpret_cast<unsigned char*>(pass->data()),
                               pass->size() / pixels * sizeof(float)});
    return buffers;
}

// Renders a loaded scene's image (or its rows [y0, y1)) with the tiles shared among the processes
// of an mpirun; on rank 0 the result holds every process's pixels.
// With `bandOnly`, the film holds rows [y0, y1) alone (RenderOptions::bandOnly).
Film renderShared(const RenderScene& scene, const RenderCommand& cmd, const AovRequest& aov,
                  AovImage& aovs, RenderStats* stats, ProgressReporter* progress, int y0 = 0,
                  int y1 = -1, RenderCost* cost = nullptr, bool bandOnly = false) {
    const std::unique_ptr<TileSource> tiles = cluster::sharedTiles();
    RenderOptions options;
    options.threads = cmd.threads;
    options.progress = !cmd.quiet && cluster::isRoot();
    options.sharedProgress = progress;
    options.rowBegin = y0;
    options.rowEnd = y1;
    options.tileSource = tiles.get();
    options.cost = cost;
    options.bandOnly = bandOnly;
    Film film = scene.render(options, stats, &aov, &aovs);
    cluster::gatherTiles(*tiles, film.width(), pixelBuffers(film, aovs), bandOnly ? y0 : 0);
    return film;
}

// Output file names (without extension): the scene file's name in --out, with "-preview" for
// --preview renders so that a quick look never replaces a full render.
std::string outputBase(const RenderCommand& cmd, const SceneSpec& spec) {
    const std::string stem = fs::path(spec.path).stem().string() + spec.outputSuffix +
                             (cmd.overrides.preview ? "-preview" : "");
    return (fs::path(cmd.outDir) / stem).string();
}

void runRender(const RenderCommand& cmd, std::vector<RenderedImage>* rendered) {
    // Under mpirun every process reads the scenes and renders; rank 0 alone prints and writes.
    const bool root = cluster::isRoot();
    const bool quiet = cmd.quiet || !root;
    if (cmd.check && !root) return;
    int shardIndex = 0, shardCount = 0;
    AovRequest aov;
    std::vector<std::string> files;
    // Every scene is read and checked before anything renders; --check prints every error.
    std::vector<SceneSpec> specs;
    std::vector<std::string> errors;
    std::map<std::string, std::string> writerOf;  // output base → scene file
    VolumeCache volumes;  // each distinct source loaded once for the whole batch
    const auto validate = [&] {
        cmd.overrides.validate();
        std::tie(shardIndex, shardCount) = parseShard(cmd.shard);
        if (!cmd.aov.empty()) aov = AovRequest::parse(cmd.aov);
        files = collectScenes(cmd);
        cmd.figure.validate(files.size() * size_t(std::max(cmd.orbit, 1)), shardCount > 0);
        for (const std::string& f : files) {
            try {
                SceneSpec loaded = loadSceneFile(f);
                cmd.overrides.apply(loaded);
                cmd.figure.apply(loaded);
                for (SceneSpec& spec : orbitFrames(loaded, cmd.orbit)) {
                    const std::string base = outputBase(cmd, spec);
                    const auto [it, fresh] = writerOf.emplace(base, f);
                    if (!fresh)
                        throw Error("scenes '" + it->second + "' and '" + f +
                                    "' would both write " + base +
                                    ".exr/.png: rename one, or render them into different "
                                    "--out folders");
                    specs.push_back(std::move(spec));
                }
            } catch (const Error& e) {
                if (!cmd.check && !cmd.keepGoing) throw;
                errors.push_back(e.what());
                if (!cmd.check && root)
                    std::fprintf(stderr, "lobe: error: %s (skipped)\n", e.what());
            }
        }
    };
    // Every volume of the scenes to render loaded now (each distinct file once), so that a later
    // scene's bad file is found before the first scene renders.
    const auto loadVolumes = [&] {
        std::vector<const SceneSpec*> all;
        for (const SceneSpec& spec : specs) all.push_back(&spec);
        // Its own phase on the display, before the render's progress and apart from its ETA.
        ProgressReporter loading("load volumes", 1, !quiet && !cmd.check);
        const std::vector<std::string> volumeErrors = volumes.preload(all);
        loading.advance();
        loading.finish();
        std::vector<SceneSpec> loadable;
        for (size_t k = 0; k < specs.size(); ++k) {
            // Fitted cameras, zooms and rigs checked too (render/framing.h): none fails later.
            // And transfer-function values given as percentiles of the data.
            std::string error = volumeErrors[k];
            if (error.empty()) error = computedViewError(specs[k], volumes);
            if (error.empty()) error = transferError(specs[k], volumes);
            if (error.empty()) {
                loadable.push_back(std::move(specs[k]));
                continue;
            }
            if (!cmd.check && !cmd.keepGoing) throw Error(error);
            errors.push_back(error);
            if (!cmd.check && root)
                std::fprintf(stderr, "lobe: error: %s (skipped)\n", error.c_str());
        }
        specs = std::move(loadable);
        // How a volume was read, when the image depends on it and nothing else says so (a single
        // DICOM slice drawn as a slab): one warning per volume.
        if (root) {
            std::set<std::string> said;
            for (const SceneSpec& spec : specs)
                for (const ObjectSpec& object : spec.objects) {
                    const std::string& note = volumes.get(object.source)->note;
                    if (!note.empty() && said.insert(note).second)
                        std::fprintf(stderr, "lobe: warning: %s\n", note.c_str());
                }
        }
        if (root && !cmd.check && cmd.figure.output.empty()) createOutputFolder(cmd.outDir);
    };
    if (cmd.check) {  // rank 0 alone (the others returned)
        validate();
        loadVolumes();
        for (const std::string& e : errors) std::fprintf(stderr, "lobe: error: %s\n", e.c_str());
        if (!errors.empty())
            throw Error(std::to_string(errors.size()) + " of " + std::to_string(files.size()) +
                        " scenes have errors");
        std::printf("%zu scene%s valid\n", files.size(), files.size() == 1 ? "" : "s");
        return;
    }
    cluster::everywhere(validate);
    // Sharding: a batch deals its scenes out (scene k goes to part k mod N); one scene is cut
    // into N bands of rows, each written as a part file for `lobe merge`.
    const bool rowShards = shardCount > 0 && specs.size() == 1;
    if (shardCount > 0 && !rowShards) {
        std::vector<SceneSpec> mine;
        for (size_t k = 0; k < specs.size(); ++k)
            if (int(k % size_t(shardCount)) == shardIndex) mine.push_back(std::move(specs[k]));
        specs = std::move(mine);
    }
    cluster::everywhere(loadVolumes);
    // Every rank's volumes the same as rank 0's (node-local copies that differ would mix two
    // data sets in one image): compared by content hash before anything renders.
    if (cluster::distributed())
        cluster::everywhere([&] {
            std::string first;  // thrown after the loop: every rank makes every broadcast
            for (const SceneSpec& spec : specs) {
                const std::string mine = volumes.contentHashes(spec);
                const std::string differs = contentHashDifference(cluster::broadcast(mine), mine);
                if (!differs.empty() && first.empty())
                    first =
                        spec.path + ": this rank loaded other volume data than rank 0: " + differs;
            }
            if (!first.empty()) throw Error(first);
        });
    int64_t totalPixels = 0;
    for (const SceneSpec& spec : specs) totalPixels += int64_t(spec.width) * spec.height;

    ProgressReporter progress(files.size() == 1 ? "render" : "render batch", totalPixels, !quiet);
    std::map<std::string, std::vector<ContactSheetEntry>> sheets;
    std::unique_ptr<RenderScene> assembled;  // the last scene assembled (an orbit keeps it)
    // The display's ETA from the measured cost of the work (batch/batch_eta.h) when the work
    // comes in parts (scenes, frames, bands) whose cost per pixel can differ: the first scene
    // profiled now, the others as they are assembled. Its time is loading, apart from the ETA.
    std::unique_ptr<BatchPilot> pilot;
    if (!quiet && !rowShards && needsCostSchedule(specs, cmd.figure.bandRows)) {
        progress.pause();
        pilot = std::make_unique<BatchPilot>(
            specs, cmd.figure.bandRows, cmd.threads, [&](const SceneSpec& spec) {
                const std::vector<std::string> outputs =
                    cmd.figure.outputPaths(outputBase(cmd, spec));
                return cmd.skipExisting &&
                       std::all_of(outputs.begin(), outputs.end(),
                                   [](const std::string& p) { return fs::exists(p); });
            });
        pilot->profileFirst(volumes, assembled);
        progress.setSchedule(&pilot->schedule());
        // The loads to come are in the ETA too: one per scene assembled (an orbit's frames share
        // one; the pilot's pause is the first scene's). With --skip-existing some never come.
        if (!cmd.skipExisting) {
            int loads = 1;
            for (size_t i = 1; i < specs.size(); ++i)
                if (!(cmd.orbit > 0 && specs[i].path == specs[i - 1].path &&
                      specs[i].group == specs[i - 1].group))
                    ++loads;
            progress.expectLoads(loads);
        }
        progress.resume();
    }
    for (size_t i = 0; i < specs.size(); ++i) {
        const SceneSpec& spec = specs[i];
        const std::string base = outputBase(cmd, spec);
        const bool inSheet = !spec.group.empty() && !cmd.noContactSheets && shardCount == 0 &&
                             cmd.figure.output.empty();
        const std::vector<std::string> outputs = cmd.figure.outputPaths(base);
        if (rowShards) {
            // Rows [y0, y1) of part i: floor(i·H/N) to floor((i+1)·H/N).
            const int y0 = int(int64_t(shardIndex) * spec.height / shardCount);
            const int y1 = int(int64_t(shardIndex + 1) * spec.height / shardCount);
            const std::string part = partPath(base, shardIndex, shardCount);
            if (cluster::broadcast(cmd.skipExisting && fs::exists(part))) continue;
            std::unique_ptr<RenderScene> scene;
            cluster::everywhere(
                [&] { scene = std::make_unique<RenderScene>(spec, false, &volumes); });
            AovImage aovs;
            AovRequest withAlpha = aov;  // the coverage, for a background other than the backdrop
            withAlpha.alpha = spec.background.needsAlpha();
            Film film = renderShared(*scene, cmd, withAlpha, aovs, nullptr, nullptr, y0, y1);
            if (!root) continue;
            const ImageChannels extra = passChannels(aov, aovs, spec);
            // The part's rows as a single run writes them (writeFigure): a colour composited
            // per pixel, with none the coverage as channel A; `lobe merge` joins the rows.
            compositeBackground(film, aovs.alpha, spec.background, spec.exposure);
            ImageWriteOptions write;
            write.attributes = {
                {"lobe:shard", std::to_string(shardIndex) + "/" + std::to_string(shardCount)},
                {"lobe:rows", std::to_string(y0) + " " + std::to_string(y1)},
                {"lobe:scene", fingerprint(fileText(spec.path))},
                {"lobe:settings", fingerprint(settingsText(spec, cmd.aov))},
                {"lobe:volumes", volumes.contentHashes(spec)},
                {"lobe:background", spec.background.text}};
            if (spec.background.mode == Background::Mode::None) write.alpha = &aovs.alpha;
            writeFilmPending(part, film, spec.exposure, extra, write).commit();
            if (!quiet)
                std::fprintf(stderr, "\nrows %d-%d of %s -> %s\n", y0, y1 - 1, spec.title.c_str(),
                             part.c_str());
            continue;
        }
        if (cluster::broadcast(cmd.skipExisting &&
                               std::all_of(outputs.begin(), outputs.end(),
                                           [](const std::string& p) { return fs::exists(p); }))) {
            progress.advance(int64_t(spec.width) * spec.height);
            if (inSheet && root)
                sheets[spec.group].push_back(
                    {thumbnailFromExr(base + ".exr", spec.tone, cmd.sheetThumb), spec.title});
            if (!quiet)
                std::fprintf(stderr, "\n[%zu/%zu] %s: exists, skipped\n", i + 1, specs.size(),
                             base.c_str());
            continue;
        }
        try {
            // Assembling the scene (surfaces, volume structures) is shown as a phase of its own
            // and kept out of the render's ETA. An orbit's frames share one assembled scene,
            // turned to each frame's view (Scene::setView): rendering 1's structures took ~0.3 s
            // a frame to build again.
            // The pilot's scene (batch_eta.h) is the first frame's: kept, not built again.
            const bool sameOrbit = (cmd.orbit > 0 || i == 0) && assembled &&
                                   assembled->spec().path == spec.path &&
                                   assembled->spec().group == spec.group;
            if (sameOrbit) {
                cluster::everywhere([&] { assembled->setView(spec); });
            } else {
                assembled.reset();
                progress.pause();
                cluster::everywhere(
                    [&] { assembled = std::make_unique<RenderScene>(spec, !quiet, &volumes); });
                if (pilot) pilot->profile(i, *assembled);
                progress.resume();
            }
            RenderScene* const scene = assembled.get();
            if (root && hasComputedView(scene->spec()))  // fitted numbers, to freeze into the scene
                std::printf("%s%s: fitted view:\n%s\n", quiet ? "" : "\n", spec.title.c_str(),
                            frozenViewJson(scene->spec()).c_str());
            if (root) warnInvisibleObjects(*scene);
            RenderStats stats;
            // The coverage only for a background other than the backdrop: rendering it costs
            // about a third more render time (rendering 1, 512² × 2 spp: 2.27 -> 3.10 s).
            AovRequest withAlpha = aov;
            withAlpha.alpha = spec.background.needsAlpha();
            RenderCost cost;  // --stats (a process's own share under mpirun: not printed)
            const bool withCost = cmd.stats && !cluster::distributed();
            // In bands of rows (a poster: figure/figure_output.h), each written as it is done;
            // one band for an image up to 2048².
            std::unique_ptr<FigureWriter> writer;
            if (root)
                writer = std::make_unique<FigureWriter>(cmd.figure, spec, base,
                                                        inSheet ? cmd.sheetThumb : 0);
            const int bandRows = bandRowsFor(spec, cmd.figure.bandRows);
            for (int y0 = 0; y0 < spec.height; y0 += bandRows) {
                const int y1 = std::min(spec.height, y0 + bandRows);
                AovImage aovs;
                RenderStats bandStats;
                RenderCost bandCost;
                Film band = renderShared(*scene, cmd, withAlpha, aovs, &bandStats, &progress, y0,
                                         y1, withCost ? &bandCost : nullptr, true);
                stats += bandStats;
                stats.seconds += bandStats.seconds;
                cost += bandCost;
                if (root) writer->write(band, aovs.alpha, passChannels(aov, aovs, spec));
            }
            if (!root) continue;
            const FigureResult figure = writer->finish();
            // Without the coverage: no hit and no sample anywhere (under mpirun rank 0's counts
            // are only its share, so it does not judge).
            warnIfEmpty(spec, withAlpha.alpha ? figure.covered
                                              : cluster::distributed() || stats.surfaceHits > 0 ||
                                                    stats.volumeSamples > 0);
            const RgbImage& rgb = figure.display;
            if (!quiet && cluster::distributed())  // rank 0's counts are only its share
                std::fprintf(stderr,
                             "\n[%zu/%zu] %s: %dx%d, %d spp, %.2f s on %d processes -> "
                             "%s\n",
                             i + 1, specs.size(), spec.title.c_str(), spec.width, spec.height,
                             spec.samplesPerPixel, stats.seconds, cluster::size(),
                             figure.written.c_str());
            else if (!quiet)
                std::fprintf(stderr,
                             "\n[%zu/%zu] %s: %dx%d, %d spp, %.2f s, %.2f M rays, %.1f M volume "
                             "samples (%.1f M shaded) -> %s\n",
                             i + 1, specs.size(), spec.title.c_str(), spec.width, spec.height,
                             spec.samplesPerPixel, stats.seconds, stats.rays * 1e-6,
                             stats.volumeSamples * 1e-6, stats.volumeShaded * 1e-6,
                             figure.written.c_str());
            if (withCost) {
                std::fflush(stderr);
                std::printf("%s: %s", spec.title.c_str(), costSummary(spec, cost).c_str());
                std::fflush(stdout);
            }
            if (inSheet) sheets[spec.group].push_back({rgb, spec.title});
            if (rendered) rendered->push_back({spec.path, spec.title, base});
        } catch (const cluster::CollectiveError& e) {
            // A scene that failed to load on some process: every process skips it.
            if (!cmd.keepGoing) throw;
            errors.push_back(e.what());
            if (e.reportHere()) std::fprintf(stderr, "\nlobe: error: %s (skipped)\n", e.what());
        } catch (const Error& e) {
            if (!cmd.keepGoing || cluster::distributed()) throw;
            errors.push_back(e.what());
            std::fprintf(stderr, "\nlobe: error: %s (skipped)\n", e.what());
        }
    }
    progress.finish();
    if (root)
        for (const auto& [group, entries] : sheets) {
            const std::string path =
                (fs::path(cmd.outDir) / ("contact-sheet-" + group + ".png")).string();
            writeContactSheet(path, entries, 3, cmd.sheetThumb);
            if (!quiet) std::fprintf(stderr, "contact sheet %s\n", path.c_str());
        }
    if (!errors.empty()) {
        const std::string message = std::to_string(errors.size()) + " of " +
                                    std::to_string(files.size()) +
                                    " scenes failed (--keep-going rendered the others)";
        if (cluster::distributed()) throw cluster::CollectiveError(message, root);
        throw Error(message);
    }
}

// `lobe merge SCENES… [--out DIR]`: joins what `--shard` renders wrote into the files one
// unsharded run writes — the part files of a sharded image (checked: every part present, all
// from this scene file and the same settings) into NAME.exr and NAME.png, the same floats bit for
// bit — and writes the contact sheets of the batch.
void runMerge(const RenderCommand& cmd) {
    cmd.overrides.validate();
    const std::vector<std::string> files = collectScenes(cmd);
    std::map<std::string, std::vector<ContactSheetEntry>> sheets;
    for (const std::string& f : files) {
        SceneSpec spec = loadSceneFile(f);
        cmd.overrides.apply(spec);
        const std::string base = outputBase(cmd, spec);
        const std::string stem = fs::path(base).filename().string();
        // Part files of this scene: STEM.part-I-of-N.exr.
        std::map<int, std::string> parts;
        int count = 0;
        if (fs::is_directory(cmd.outDir))
            for (const auto& entry : fs::directory_iterator(cmd.outDir)) {
                const std::string name = entry.path().filename().string();
                const std::string prefix = stem + ".part-";
                if (name.rfind(prefix, 0) != 0 || entry.path().extension() != ".exr") continue;
                int i = -1, n = -1;
                char tail[8] = {0};
                if (std::sscanf(name.c_str() + prefix.size(), "%d-of-%d.%4s", &i, &n, tail) != 3 ||
                    std::string(tail) != "exr")
                    continue;
                if (count && n != count)
                    throw Error(spec.path + ": parts of different shard counts in " + cmd.outDir +
                                " (" + parts.begin()->second + " and " + name + ")");
                count = n;
                parts[i] = entry.path().string();
            }
        if (!parts.empty()) {
            for (int i = 0; i < count; ++i)
                if (!parts.count(i))
                    throw Error(spec.path + ": part " + std::to_string(i) + " of " +
                                std::to_string(count) + " is missing (" + partPath(base, i, count) +
                                ")");
            const std::string sceneId = fingerprint(fileText(spec.path));
            const std::string settingsId = fingerprint(settingsText(spec, cmd.aov));
            FloatImage merged;
            std::string volumesId;   // part 0's lobe:volumes
            std::string background;  // the parts' (--background is given to the renders)
            for (const auto& [i, path] : parts) {
                FloatImage part = readFloatImage(path);
                const std::string own = part.attributes.count("lobe:background")
                                            ? part.attributes["lobe:background"]
                                            : "backdrop";
                if (i > 0 && own != background)
                    throw Error(path + ": rendered with --background " + own + ", part 0 with " +
                                background);
                background = own;
                if (part.attributes["lobe:scene"] != sceneId)
                    throw Error(path + ": rendered from a different scene file than " + spec.path);
                // The volumes as each part's render loaded them (a file re-exported between
                // two array tasks gives another image): every part's against part 0's.
                if (i == 0) volumesId = part.attributes["lobe:volumes"];
                const std::string differs =
                    contentHashDifference(volumesId, part.attributes["lobe:volumes"]);
                if (!differs.empty())
                    throw Error(path + ": rendered from other volume data than " +
                                parts.begin()->second + ": " + differs +
                                "; render the parts again");
                if (part.attributes["lobe:settings"] != settingsId)
                    throw Error(path +
                                ": rendered with other settings (size, samples, seed, step, "
                                "roulette or --aov) than asked for " +
                                spec.path);
                const int y0 = int(int64_t(i) * spec.height / count);
                const int y1 = int(int64_t(i + 1) * spec.height / count);
                if (part.attributes["lobe:rows"] != std::to_string(y0) + " " + std::to_string(y1) ||
                    part.width != spec.width || part.height != spec.height)
                    throw Error(path + ": not part " + std::to_string(i) + " of " +
                                std::to_string(count) + " of a " + std::to_string(spec.width) +
                                "x" + std::to_string(spec.height) + " image");
                if (i == 0) {
                    merged = std::move(part);
                    continue;
                }
                if (part.channels.names != merged.channels.names)
                    throw Error(path + ": other channels than " + parts.begin()->second);
                const size_t k = merged.channels.names.size();
                std::copy(part.channels.data.begin() + long(size_t(y0) * spec.width * k),
                          part.channels.data.begin() + long(size_t(y1) * spec.width * k),
                          merged.channels.data.begin() + long(size_t(y0) * spec.width * k));
            }
            spec.background = parseBackground(background, spec.path + ": the parts' background");
            merged.attributes = provenance(spec);  // the shards' own tags go; the merge's come
            writeFloatImage(base + ".exr", merged);
            // The display image from the merged floats, as a single run makes it from its own
            // (with none, the coverage the parts kept as channel A).
            std::vector<float> alpha;
            ImageWriteOptions png;
            png.attributes = merged.attributes;
            const RgbImage display = displayFromExr(base + ".exr", spec.tone, &alpha);
            if (!alpha.empty()) png.alpha = &alpha;
            writeImagePending(base + ".png", display, png).commit();
            if (!cmd.quiet)
                std::fprintf(stderr, "%s: %d parts -> %s.exr/.png\n", spec.title.c_str(), count,
                             base.c_str());
        } else if (!(fs::exists(base + ".exr") && fs::exists(base + ".png"))) {
            throw Error(spec.path + ": neither " + base + ".exr/.png nor part files " + stem +
                        ".part-I-of-N.exr in " + cmd.outDir);
        }
        if (!spec.group.empty() && !cmd.noContactSheets)
            sheets[spec.group].push_back(
                {thumbnailFromExr(base + ".exr", spec.tone, cmd.sheetThumb), spec.title});
    }
    for (const auto& [group, entries] : sheets) {
        const std::string path =
            (fs::path(cmd.outDir) / ("contact-sheet-" + group + ".png")).string();
        writeContactSheet(path, entries, 3, cmd.sheetThumb);
        if (!cmd.quiet) std::fprintf(stderr, "contact sheet %s\n", path.c_str());
    }
}

}  // namespace

void renderScenes(const BatchOptions& options, std::vector<RenderedImage>* rendered) {
    runRender(options, rendered);
}

void mergeShards(const BatchOptions& options) { runMerge(options); }

std::vector<RenderedImage> renderBatch(const RenderBatchRequest& request) {
    BatchOptions cmd;
    cmd.inputs = request.scenes;
    cmd.outDir = request.outDir;
    cmd.overrides = request.overrides;
    cmd.orbit = request.orbit;
    cmd.aov = request.aov;
    cmd.quiet = request.quiet;
    cmd.noContactSheets = true;
    std::vector<RenderedImage> rendered;
    runRender(cmd, &rendered);
    return rendered;
}

}  // namespace lobe
