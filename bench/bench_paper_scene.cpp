// lobe_bench_scene: the paper scene's speed and error (issue "The paper's renderings").
//
//  1. One full scene (default: assets/scenes/paper/rendering-01.json: skull, cortex, density maps)
//     at 1024² × 8 spp on the given threads: wall time of building the scene (loading, Embree,
//     brick tables) and of rendering, and of writing EXR + PNG.
//  2. Its error: a reference with a 0.02-voxel step and 64 samples per pixel is rendered on an
//     N × N lattice of the image's pixels (every 1024/N-th pixel, the same pixel footprints), and
//     the full render's relative RMSE over those pixels is reported (RMSE of the band values over
//     the mean reference value).
//  3. The 512² one-sample preview time.
//  4. Where the time goes, from renders of the same scene at a smaller size with parts switched
//     off, all in this one run: full; every BRDF replaced by its Lambert term only (the BRDF
//     evaluation's share is the difference); no volumes (the volume sampling's share); no
//     surfaces and no volumes (what is left: camera rays, backdrop, scheduling); --no-split
//     leaves it out. --step S renders the scene at another volume step (the reference stays).
// Output: a Markdown report on stdout. Checks before reporting: images finite, the scene covers
// a plausible part of the image (not just backdrop).
#include "bench/bench_common.h"
#include "core/error.h"
#include "core/image_output.h"
#include "core/tile_scheduler.h"
#include "render/render_scene.h"
#include "render/scene_file.h"

#include <sys/resource.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

using namespace lobe;

namespace {

// CPU seconds of this process (bench_common.h): on a shared machine the render's CPU time over
// the thread count estimates its wall time when it has the cores alone.
double now() { return bench::wallSeconds(); }
using bench::cpuSeconds;

struct Timed {
    double build = 0.0, render = 0.0, renderCpu = 0.0;
    Film film;
    RenderStats stats;
};

Timed renderTimed(const SceneSpec& spec, int threads) {
    Timed t;
    const double t0 = now();
    RenderScene scene(spec, false);
    const double t1 = now();
    RenderOptions options;
    options.threads = threads;
    options.progress = false;
    const double c1 = cpuSeconds();
    t.film = scene.render(options, &t.stats);
    t.render = now() - t1;
    t.renderCpu = cpuSeconds() - c1;
    t.build = t1 - t0;
    return t;
}

bool finite(const Film& f) {
    for (const Spectrum& s : f.pixels())
        if (!s.isFinite()) return false;
    return true;
}

// Fraction of pixels with any light from the objects, rendered with the backdrop off.
double coverage(const Film& objectsOnly) {
    size_t lit = 0;
    for (const Spectrum& s : objectsOnly.pixels())
        if (s.maxValue() > 0.0) ++lit;
    return double(lit) / objectsOnly.pixels().size();
}

}  // namespace

int main(int argc, char** argv) {
    std::string scenePath = std::string(LOBE_SOURCE_DIR) + "/assets/scenes/paper/rendering-01.json";
    int threads = 2, size = 1024, spp = 8, lattice = 32, splitSize = 256;
    double roulette = -1.0;  // < 0: the scene's own
    double step = -1.0;      // < 0: the scene's own
    bool split = true;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto next = [&] { return i + 1 < argc ? std::string(argv[++i]) : std::string(); };
        if (a == "--scene")
            scenePath = next();
        else if (a == "--threads")
            threads = std::atoi(next().c_str());
        else if (a == "--size")
            size = std::atoi(next().c_str());
        else if (a == "--spp")
            spp = std::atoi(next().c_str());
        else if (a == "--lattice")
            lattice = std::atoi(next().c_str());
        else if (a == "--split-size")
            splitSize = std::atoi(next().c_str());
        else if (a == "--roulette")
            roulette = std::atof(next().c_str());
        else if (a == "--step")
            step = std::atof(next().c_str());
        else if (a == "--no-split")
            split = false;
        else {
            std::fprintf(stderr,
                         "usage: %s [--scene F] [--threads N] [--size N] [--spp N] "
                         "[--lattice N] [--split-size N] [--roulette W] [--step S] "
                         "[--no-split]\n",
                         argv[0]);
            return 2;
        }
    }
    try {
        SceneSpec spec = loadSceneFile(scenePath);
        spec.width = spec.height = size;
        spec.samplesPerPixel = spp;
        if (roulette >= 0.0) spec.shadingRoulette = roulette;
        if (step > 0.0) spec.volumeStepVoxels = step;
        std::printf("# Paper scene benchmark\n\nscene `%s`, %d threads, volume step %.3g voxel\n\n",
                    scenePath.c_str(), threads, spec.volumeStepVoxels);

        // 1. Full scene.
        const Timed full = renderTimed(spec, threads);
        const auto out = std::filesystem::temp_directory_path() / "lobe_bench_scene";
        std::filesystem::create_directories(out);
        const double o0 = now();
        writeFilm((out / "full.exr").string(), full.film, spec.exposure);
        writeImage((out / "full.png").string(), filmToRgb(full.film, spec.exposure));
        const double outputSeconds = now() - o0;
        if (!finite(full.film)) throw Error("the full render has non-finite pixels");

        // 2. Error against the 0.02-voxel, 64-spp reference on an N×N pixel lattice.
        SceneSpec refSpec = spec;
        refSpec.volumeStepVoxels = 0.02;
        refSpec.samplesPerPixel = 64;
        refSpec.shadingRoulette = 0.0;  // every sample shaded
        refSpec.exactBrdf = true;       // He–Torrance from its series (no table)
        const RenderScene reference(refSpec, false);
        std::vector<Spectrum> ref(size_t(lattice) * lattice), got(ref.size());
        const int stride = size / lattice;
        const double r0 = now();
        runWithThreads(threads, [&] {
            tbb::parallel_for(0, lattice * lattice, [&](int i) {
                const int x = (i % lattice) * stride + stride / 2,
                          y = (i / lattice) * stride + stride / 2;
                ref[i] = reference.renderPixel(x, y);
                got[i] = full.film.at(x, y);
            });
        });
        const double refSeconds = now() - r0;
        double se = 0.0, mean = 0.0;
        for (size_t i = 0; i < ref.size(); ++i)
            for (int c = 0; c < 3; ++c) {
                se += (got[i][c] - ref[i][c]) * (got[i][c] - ref[i][c]);
                mean += ref[i][c];
            }
        const double n = 3.0 * ref.size();
        const double relRmse = std::sqrt(se / n) / (mean / n);

        // 3. Preview.
        SceneSpec preview = spec;
        preview.width = preview.height = 512;
        preview.samplesPerPixel = 1;
        const Timed pre = renderTimed(preview, threads);

        std::printf("| what | wall time | note |\n|---|---|---|\n");
        std::printf("| build (load volumes, Embree, bricks) | %.2f s | |\n", full.build);
        std::printf(
            "| render %d² × %d spp | **%.2f s** | %.2f CPU s (%.2f s per thread); %.1f µs "
            "of CPU per camera ray |\n",
            size, spp, full.render, full.renderCpu, full.renderCpu / threads,
            full.renderCpu / (double(size) * size * spp) * 1e6);
        std::printf("| write EXR + PNG | %.2f s | |\n", outputSeconds);
        std::printf(
            "| volume lattice points skipped / reconstructed | %.1f M / %.1f M | "
            "%.1f / %.1f per camera ray |\n",
            full.stats.volumeSkipped * 1e-6, full.stats.volumeEvaluated * 1e-6,
            double(full.stats.volumeSkipped) / full.stats.rays,
            double(full.stats.volumeEvaluated) / full.stats.rays);
        std::printf(
            "| volume samples composited / shaded (roulette %.3g) | %.1f M / %.1f M | "
            "%.1f / %.1f per camera ray |\n",
            spec.shadingRoulette, full.stats.volumeSamples * 1e-6, full.stats.volumeShaded * 1e-6,
            double(full.stats.volumeSamples) / full.stats.rays,
            double(full.stats.volumeShaded) / full.stats.rays);
        std::printf(
            "| preview 512² × 1 spp (render only / with build) | **%.2f s** / %.2f s | "
            "%.2f CPU s |\n",
            pre.render, pre.render + pre.build, pre.renderCpu);
        std::printf("| reference (step 0.02, 64 spp) on %d×%d pixels | %.2f s | |\n\n", lattice,
                    lattice, refSeconds);
        std::printf(
            "Error of the %d² × %d spp render against the reference on those pixels: "
            "relative RMSE **%.2f %%**.\n\n",
            size, spp, relRmse * 100.0);

        // 4. Where the time goes (at splitSize², same spp).
        if (!split) return 0;
        SceneSpec base = spec;
        base.width = base.height = splitSize;
        SceneSpec lambert = base;
        for (ObjectSpec& o : lambert.objects) o.material.specularOn = false;
        SceneSpec noVolumes = lambert;
        noVolumes.objects.erase(
            std::remove_if(noVolumes.objects.begin(), noVolumes.objects.end(),
                           [](const ObjectSpec& o) { return o.kind == ObjectSpec::Kind::Volume; }),
            noVolumes.objects.end());
        SceneSpec nothing = base;
        nothing.objects.clear();
        const Timed tFull = renderTimed(base, threads), tLambert = renderTimed(lambert, threads),
                    tNoVol = renderTimed(noVolumes, threads),
                    tNothing = renderTimed(nothing, threads);
        SceneSpec objectsOnly = base;
        objectsOnly.backdrop.enabled = false;
        objectsOnly.width = objectsOnly.height = 64;
        objectsOnly.samplesPerPixel = 1;
        const double cover = coverage(renderTimed(objectsOnly, threads).film);
        if (cover < 0.05) throw Error("the scene covers under 5 % of the image: wrong placement?");
        const double total = tFull.render;
        std::printf(
            "Where the render time goes (%d² × %d spp, one run; objects cover %.0f %% of the "
            "image):\n\n| part | seconds | share |\n|---|---|---|\n",
            splitSize, spp, cover * 100.0);
        std::printf("| BRDF evaluation (full − Lambert only) | %.2f | %.0f %% |\n",
                    total - tLambert.render, 100.0 * (total - tLambert.render) / total);
        std::printf(
            "| volume sampling (reconstruction, gradients, transfer functions, Lambert "
            "shading) | %.2f | %.0f %% |\n",
            tLambert.render - tNoVol.render, 100.0 * (tLambert.render - tNoVol.render) / total);
        std::printf("| surfaces (Embree, exact iso-surface, Lambert shading) | %.2f | %.0f %% |\n",
                    tNoVol.render - tNothing.render,
                    100.0 * (tNoVol.render - tNothing.render) / total);
        std::printf("| camera rays, backdrop, scheduling | %.2f | %.0f %% |\n", tNothing.render,
                    100.0 * tNothing.render / total);
        std::printf("| output (EXR + PNG at %d²) | %.2f | (beside the %.2f s render) |\n", size,
                    outputSeconds, full.render);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "lobe_bench_scene: %s\n", e.what());
        return 1;
    }
    return 0;
}
