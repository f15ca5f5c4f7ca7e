// lobe_bench_hybrid: direct volume rendering of the paper scene's brain objects through the
// hybrid renderer (render/render_scene.h) — time against error for steps of 0.05, 0.1,
// 0.25, 0.5 and 1 voxel, with and without empty-space skipping, against a 0.02-voxel reference;
// lattice points per second; peak memory. (bench/bench_dvr.cpp measures the bare marcher on the
// density maps alone; this one runs the real objects with their BRDFs, as `lobe render` does.)
//
// Scene: assets/scenes/paper/rendering-01.json without the skull — the cortex (MNI ICBM152 2009a
// T1 / 255, the cortex ramp 0.001 → 0.2 around 0.47, cubic B-spline values and gradients,
// Ashikhmin-Shirley + Lambert 0.2) and the density maps (SPM12 grey FieldMap, the four
// density_maps ramps, trilinear + central differences, He-Torrance + Lambert 0.2), both placed by
// scale (0.87, −0.87, −0.87) + (102, 127.6, 85) in the CThead world; the camera and four lights of
// docs/paper-scene.md "A placement that works". Backdrop off, so the error is the volumes'.
// One jittered sample per pixel with the same seed in every image: the pixel positions and
// lattice jitters are the same, so the differences are the step's, not noise.
//
// Checks before a time is reported: every image is finite and not black; with and without
// skipping the image is the same (largest band difference ≤ 1e-9 of the reference's largest
// value; volume_marcher.h "Empty-space skipping" says they differ by rounding only).
//
// Error: relative RMSE = RMSE of the band values over all pixels / mean band value of the
// reference (black pixels included), as in bench_dvr. Samples/s: lattice points reconstructed
// per second of render wall time (RenderStats::volumeEvaluated; skipped points are not counted)
// and per CPU-second (user + system, getrusage: less sensitive to other processes on the machine).
// Peak memory: getrusage ru_maxrss of the whole process (after loading, and at the end).
//
// Usage: lobe_bench_hybrid [--size N (128)] [--threads N (2)] [--reps N (2: best of)]
//                          [--out DIR: EXR images of the reference and each step]
// Output: a Markdown report on stdout.
#include "bench/bench_common.h"
#include "core/error.h"
#include "core/image_output.h"
#include "render/render_scene.h"
#include "render/scene_file.h"

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

using namespace lobe;

namespace {

using bench::cpuSeconds;
using bench::relativeRmse;
double peakRssMB() { return bench::peakRssMb(); }

struct Run {
    Film film;
    RenderStats stats;
    double build = 0.0;   // seconds: loading, brick tables
    double render = 0.0;  // seconds: best of the repetitions
    double cpu = 0.0;     // CPU seconds (user + system) of that repetition
};

SceneSpec brainScene(int size) {
    SceneSpec spec =
        // The brain's volume objects: the cortex and the four density maps as DVR objects (the
        // paper scenes now draw the maps as iso-surfaces; this scene keeps them as volumes).
        loadSceneFile(std::string(LOBE_SOURCE_DIR) + "/assets/scenes/assign/six-objects.json");
    std::vector<ObjectSpec> volumes;
    for (const ObjectSpec& o : spec.objects)
        if (o.kind == ObjectSpec::Kind::Volume) volumes.push_back(o);
    if (volumes.size() < 2) throw Error("six-objects.json: expected the cortex and density maps");
    spec.objects = volumes;
    spec.backdrop.enabled = false;
    spec.width = spec.height = size;
    spec.samplesPerPixel = 1;
    // Every sample shaded: this bench measures the step's error, and the shading roulette's
    // noise (one draw per ray at 1 spp) would hide it; lobe_bench_scene measures the roulette.
    spec.shadingRoulette = 0.0;
    // The paper camera frames the whole head; the brain fills the middle of the view. Render
    // only that square (same camera, same rays as the full frame at 1/0.52 of the size).
    spec.crop = CropWindow{0.24, 0.14, 0.76, 0.66};
    return spec;
}

Run run(SceneSpec spec, double step, bool skip, int threads, int reps) {
    spec.volumeStepVoxels = step;
    spec.emptySpaceSkipping = skip;
    Run r;
    const auto t0 = std::chrono::steady_clock::now();
    const RenderScene scene(spec, false);
    r.build = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    RenderOptions options;
    options.threads = threads;
    options.progress = false;
    r.render = 1e300;
    for (int i = 0; i < reps; ++i) {
        RenderStats stats;
        const double c0 = cpuSeconds();
        Film film = scene.render(options, &stats);
        const double cpu = cpuSeconds() - c0;
        if (stats.seconds < r.render) {
            r.cpu = cpu;
            r.render = stats.seconds;
            r.stats = stats;
            r.film = std::move(film);
        }
    }
    for (const Spectrum& p : r.film.pixels())
        if (!p.isFinite()) throw Error("non-finite pixel at step " + std::to_string(step));
    return r;
}

double maxValue(const Film& f) {
    double m = 0;
    for (const Spectrum& p : f.pixels()) m = std::max(m, p.maxValue());
    return m;
}

double maxDiff(const Film& a, const Film& b) {
    double m = 0;
    for (size_t i = 0; i < a.pixels().size(); ++i)
        for (int k = 0; k < kBandCount; ++k)
            m = std::max(m, std::abs(a.pixels()[i][k] - b.pixels()[i][k]));
    return m;
}

int runBench(int size, int threads, int reps, const std::string& out) {
    const SceneSpec spec = brainScene(size);
    const double kReferenceStep = 0.02;
    const Run ref = run(spec, kReferenceStep, true, threads, 1);
    const double refMax = maxValue(ref.film);
    if (!(refMax > 0)) throw Error("the reference image is black");
    const double rssAfterReference = peakRssMB();
    if (!out.empty()) writeFilm(out + "/brain-ref.exr", ref.film, spec.exposure);
    std::printf(
        "# DVR of the paper scene's brain objects (lobe_bench_hybrid)\n\n"
        "%d², 1 spp, %d threads, best of %d; cortex (B-spline) + density maps "
        "(trilinear), no skull, no backdrop, the brain's square of the paper view (crop "
        "[0.24, 0.14, 0.76, 0.66]). Reference: step %.2f voxel, %.1f s (%.1f CPU-s), "
        "%.1f M lattice points evaluated, %.1f M skipped, %.1f M composited. "
        "Evaluated: lattice points reconstructed; composited: those with opacity > 0, "
        "shaded with the BRDF.\n\n",
        size, threads, reps, kReferenceStep, ref.render, ref.cpu, ref.stats.volumeEvaluated * 1e-6,
        ref.stats.volumeSkipped * 1e-6, ref.stats.volumeSamples * 1e-6);
    std::printf(
        "| step (voxel) | skipping | render (s) | CPU (s) | build (s) | rel. RMSE | "
        "evaluated (M) | skipped (M) | composited (M) | M evaluated/s | "
        "M evaluated/CPU-s | skip diff / max |\n"
        "|---:|:---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    for (double step : {0.05, 0.1, 0.25, 0.5, 1.0}) {
        const Run on = run(spec, step, true, threads, reps);
        const Run off = run(spec, step, false, threads, reps);
        // Skipping must not change the image (checked before any time is reported).
        const double diff = maxDiff(on.film, off.film) / refMax;
        if (diff > 1e-9)
            throw Error("skipping changed the image at step " + std::to_string(step) +
                        " (max difference " + std::to_string(diff) + " of the maximum)");
        if (!(maxValue(on.film) > 0)) throw Error("black image at step " + std::to_string(step));
        for (const Run* r : {&on, &off})
            std::printf(
                "| %.2f | %s | %.2f | %.2f | %.2f | %.2e | %.1f | %.1f | %.1f | %.2f | %.2f | "
                "%.0e |\n",
                step, r == &on ? "on" : "off", r->render, r->cpu, r->build,
                relativeRmse(r->film, ref.film), r->stats.volumeEvaluated * 1e-6,
                r->stats.volumeSkipped * 1e-6, r->stats.volumeSamples * 1e-6,
                r->stats.volumeEvaluated * 1e-6 / r->render,
                r->stats.volumeEvaluated * 1e-6 / r->cpu, diff);
        if (!out.empty()) {
            char name[64];
            std::snprintf(name, sizeof name, "/brain-step%.2f.exr", step);
            writeFilm(out + name, on.film, spec.exposure);
        }
        std::fflush(stdout);
    }
    std::printf(
        "\nPeak memory (getrusage ru_maxrss, whole process): %.0f MB after the reference "
        "(both volumes loaded, brick tables built), %.0f MB at the end.\n",
        rssAfterReference, peakRssMB());
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    int size = 128, threads = 2, reps = 2;
    std::string out;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto value = [&]() -> std::string {
            if (i + 1 >= argc) {
                std::fprintf(stderr, "lobe_bench_hybrid: %s needs a value\n", a.c_str());
                std::exit(2);
            }
            return argv[++i];
        };
        if (a == "--size")
            size = std::atoi(value().c_str());
        else if (a == "--threads")
            threads = std::atoi(value().c_str());
        else if (a == "--reps")
            reps = std::atoi(value().c_str());
        else if (a == "--out")
            out = value();
        else {
            std::fprintf(stderr,
                         "usage: lobe_bench_hybrid [--size N] [--threads N] [--reps N] "
                         "[--out DIR]\n");
            return 2;
        }
    }
    if (size < 8 || size > 4096 || threads < 0 || reps < 1) {
        std::fprintf(stderr,
                     "lobe_bench_hybrid: --size in [8, 4096], --threads >= 0, --reps >= 1\n");
        return 2;
    }
    try {
        return runBench(size, threads, reps, out);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "lobe_bench_hybrid: %s\n", e.what());
        return 1;
    }
}
