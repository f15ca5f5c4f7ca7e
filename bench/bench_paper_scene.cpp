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
//     surfaces and no volumes (what is left: camera rays, backdrop, scheduling).
//  With --table7: the paper's Table 7 regenerated instead — 512², 8 spp, the CThead skull alone
//  (assets/scenes/skull/skull-<model>.json), one BRDF at a time, all in one run; the BRDF's share
//  is the render time minus that of the same skull with Lambert only, over the render time.
// Output: a Markdown report on stdout. Checks before reporting: images finite, the scene covers
// a plausible part of the image (not just backdrop).
#include "apps/render/render_scene.h"
#include "apps/render/scene_file.h"
#include "core/error.h"
#include "core/image_output.h"
#include "core/tile_scheduler.h"

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

double now() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
}

struct Timed {
    double build = 0.0, render = 0.0;
    Film film;
};

Timed renderTimed(const SceneSpec& spec, int threads) {
    Timed t;
    const double t0 = now();
    RenderScene scene(spec, false);
    const double t1 = now();
    RenderOptions options;
    options.threads = threads;
    options.progress = false;
    t.film = scene.render(options);
    t.render = now() - t1;
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

// The paper's Table 7 (666 MHz Pentium III, 512², CThead only), in seconds.
const std::vector<std::pair<std::string, double>>& paperTable7() {
    static const std::vector<std::pair<std::string, double>> t = {
        {"ward", 57 * 60 + 42},          {"ashikhmin_shirley", 55 * 60 + 54},
        {"he_torrance", 56 * 60 + 12},   {"cook_torrance", 56 * 60 + 12},
        {"schlick_lewis", 55 * 60 + 1},  {"phong", 55 * 60 + 12},
        {"strauss", 55 * 60 + 25},       {"poulin_fournier", 54 * 60 + 42},
        {"lafortune", 56 * 60 + 7}};
    return t;
}

int table7(int threads, int size, int spp) {
    std::printf("# The paper's Table 7, regenerated\n\n%d², %d jittered samples per pixel, the "
                "CThead skull alone (exact iso-surface), %d threads, one run\n\n", size, spp,
                threads);
    auto skull = [&](const std::string& model) {
        SceneSpec spec = loadSceneFile(std::string(LOBE_SOURCE_DIR) +
                                       "/assets/scenes/skull/skull-" + model + ".json");
        spec.width = spec.height = size;
        spec.samplesPerPixel = spp;
        return spec;
    };
    SceneSpec lambertSpec = skull("ward");
    lambertSpec.objects[0].material.specularOn = false;
    const Timed lambert = renderTimed(lambertSpec, threads);
    if (!finite(lambert.film)) throw Error("non-finite pixels in the Lambert-only skull");
    std::printf("| BRDF | paper (666 MHz P-III) | Lobe | speed-up | BRDF share of the render |\n"
                "|---|---:|---:|---:|---:|\n");
    for (const auto& [model, paperSeconds] : paperTable7()) {
        const Timed t = renderTimed(skull(model), threads);
        if (!finite(t.film)) throw Error("non-finite pixels with " + model);
        const double share = std::max(0.0, t.render - lambert.render) / t.render;
        std::printf("| %s | %d min %02d s | %.2f s | %.0f× | %.0f %% |\n", model.c_str(),
                    int(paperSeconds) / 60, int(paperSeconds) % 60, t.render,
                    paperSeconds / t.render, 100.0 * share);
    }
    std::printf("| (Lambert only) | | %.2f s | | |\n\nBuild (load + Embree) %.2f s per scene, "
                "not included.\n", lambert.render, lambert.build);
    return 0;
}

int main(int argc, char** argv) {
    std::string scenePath = std::string(LOBE_SOURCE_DIR) + "/assets/scenes/paper/rendering-01.json";
    int threads = 2, size = 1024, spp = 8, lattice = 32, splitSize = 256;
    bool wantTable7 = false;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto next = [&] { return i + 1 < argc ? std::string(argv[++i]) : std::string(); };
        if (a == "--scene") scenePath = next();
        else if (a == "--threads") threads = std::atoi(next().c_str());
        else if (a == "--size") size = std::atoi(next().c_str());
        else if (a == "--spp") spp = std::atoi(next().c_str());
        else if (a == "--lattice") lattice = std::atoi(next().c_str());
        else if (a == "--split-size") splitSize = std::atoi(next().c_str());
        else if (a == "--table7") wantTable7 = true;
        else {
            std::fprintf(stderr, "usage: %s [--scene F] [--threads N] [--size N] [--spp N] "
                                 "[--lattice N] [--split-size N] [--table7]\n", argv[0]);
            return 2;
        }
    }
    try {
        if (wantTable7) return table7(threads, size == 1024 ? 512 : size, spp);
        SceneSpec spec = loadSceneFile(scenePath);
        spec.width = spec.height = size;
        spec.samplesPerPixel = spp;
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
        const RenderScene reference(refSpec, false);
        std::vector<Spectrum> ref(size_t(lattice) * lattice), got(ref.size());
        const int stride = size / lattice;
        const double r0 = now();
        runWithThreads(threads, [&] {
            tbb::parallel_for(0, lattice * lattice, [&](int i) {
                const int x = (i % lattice) * stride + stride / 2, y = (i / lattice) * stride + stride / 2;
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
        std::printf("| render %d² × %d spp | **%.2f s** | %.1f µs per camera ray per core |\n", size,
                    spp, full.render, full.render * threads / (double(size) * size * spp) * 1e6);
        std::printf("| write EXR + PNG | %.2f s | |\n", outputSeconds);
        std::printf("| preview 512² × 1 spp (render only / with build) | **%.2f s** / %.2f s | |\n",
                    pre.render, pre.render + pre.build);
        std::printf("| reference (step 0.02, 64 spp) on %d×%d pixels | %.2f s | |\n\n", lattice,
                    lattice, refSeconds);
        std::printf("Error of the %d² × %d spp render against the reference on those pixels: "
                    "relative RMSE **%.2f %%**.\n\n", size, spp, relRmse * 100.0);

        // 4. Where the time goes (at splitSize², same spp).
        SceneSpec base = spec;
        base.width = base.height = splitSize;
        SceneSpec lambert = base;
        for (ObjectSpec& o : lambert.objects) o.material.specularOn = false;
        SceneSpec noVolumes = lambert;
        noVolumes.objects.erase(std::remove_if(noVolumes.objects.begin(), noVolumes.objects.end(),
                                               [](const ObjectSpec& o) {
                                                   return o.kind == ObjectSpec::Kind::Volume;
                                               }),
                                noVolumes.objects.end());
        SceneSpec nothing = base;
        nothing.objects.clear();
        const Timed tFull = renderTimed(base, threads), tLambert = renderTimed(lambert, threads),
                    tNoVol = renderTimed(noVolumes, threads), tNothing = renderTimed(nothing, threads);
        SceneSpec objectsOnly = base;
        objectsOnly.backdrop.enabled = false;
        objectsOnly.width = objectsOnly.height = 64;
        objectsOnly.samplesPerPixel = 1;
        const double cover = coverage(renderTimed(objectsOnly, threads).film);
        if (cover < 0.05) throw Error("the scene covers under 5 % of the image: wrong placement?");
        const double total = tFull.render;
        std::printf("Where the render time goes (%d² × %d spp, one run; objects cover %.0f %% of the "
                    "image):\n\n| part | seconds | share |\n|---|---|---|\n", splitSize, spp,
                    cover * 100.0);
        std::printf("| BRDF evaluation (full − Lambert only) | %.2f | %.0f %% |\n",
                    total - tLambert.render, 100.0 * (total - tLambert.render) / total);
        std::printf("| volume sampling (reconstruction, gradients, transfer functions, Lambert "
                    "shading) | %.2f | %.0f %% |\n", tLambert.render - tNoVol.render,
                    100.0 * (tLambert.render - tNoVol.render) / total);
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
