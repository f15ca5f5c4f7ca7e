// The paper's Table 7 regenerated (Koldenhof 2003, "Timings"; docs/paper-scene.md): render
// time of the CThead skull alone at 512×512, one specular BRDF at a time, beside the paper's
// minutes on a 666 MHz Pentium III, and the share of the time spent evaluating the BRDF.
//
// Scenes: assets/scenes/skull/skull-<model>.json (the paper's skull: iso 0.5 of value/3272, exact
// iso-surface, opaque, the model's default parameters plus Lambert kd 0.2, four point lights
// behind the camera, the backdrop), resized to 512² with the paper's 8 jittered samples per
// pixel, on 2 threads (--threads). All nine models are measured in one run, so the ratios between
// them are meaningful even on a shared, noisy machine.
//
// The BRDF's share, measured two independent ways:
//  (a) difference: the same render with the specular BRDF switched off (Material::specularOn =
//      false: Lambert only, no BRDF call) is the cost of everything else (camera rays, Embree,
//      normals, frames, lights, backdrop); (model − Lambert-only) / model. Measured in process
//      CPU seconds (less sensitive than wall time to other jobs taking a core), and the
//      Lambert-only render is timed before and after the models to show the drift.
//  (b) count × unit cost: the shading directions (wi, wo) that the render evaluates are collected
//      on a lattice of pixel centres (every --stride-th pixel, the renderer's frame and lighting
//      rules: two-sided, tangent field, lights and viewer above the surface;
//      materials/material.cpp), giving the evaluations per camera ray; each model is then timed on
//      exactly those pairs (ns per evaluation on the real direction distribution, one thread), and
//      evaluations in the render × ns/eval is the BRDF's CPU time.
//
// Checks before anything is reported: every image finite; the skull covers 10–80 % of the camera
// rays (surface hits / rays) and the same rays hit it for every model (same geometry, same
// samples); each model adds light over the Lambert-only image (its BRDF is really evaluated);
// the collected pairs give a positive number of evaluations per ray.
// Output: a Markdown report on stdout.
#include "bench/bench_common.h"
#include "core/camera.h"
#include "core/error.h"
#include "core/frame.h"
#include "render/render_scene.h"
#include "render/scene_file.h"
#include "render/shading.h"
#include "surface/iso_exact.h"
#include "surface/surface_scene.h"
#include "volume/volume.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <memory>
#include <string>
#include <utility>
#include <vector>

using namespace lobe;

namespace {

double wallNow() { return bench::wallSeconds(); }
double cpuNow() { return bench::cpuSeconds(); }

// The paper's Table 7 (666 MHz Pentium III, one core, 512², CThead only): minutes:seconds.
struct PaperRow {
    const char* model;
    int minutes, seconds;
};
const PaperRow kPaperTable7[] = {
    {"ward", 57, 42},          {"ashikhmin_shirley", 55, 54}, {"he_torrance", 56, 12},
    {"cook_torrance", 56, 12}, {"schlick_lewis", 55, 1},      {"phong", 55, 12},
    {"strauss", 55, 25},       {"poulin_fournier", 54, 42},   {"lafortune", 56, 7}};

struct Timed {
    double wall = 0.0, cpu = 0.0;
    RenderStats stats;
    double meanRadiance = 0.0;
};

Timed renderTimed(const SceneSpec& spec, int threads, const std::string& what) {
    const RenderScene scene(spec, false);  // load + Embree build: not timed
    RenderOptions options;
    options.threads = threads;
    options.progress = false;
    Timed t;
    const double w0 = wallNow(), c0 = cpuNow();
    const Film film = scene.render(options, &t.stats);
    t.cpu = cpuNow() - c0;
    t.wall = wallNow() - w0;
    double sum = 0.0;
    for (const Spectrum& s : film.pixels()) {
        if (!s.isFinite()) throw Error(what + ": non-finite pixel");
        sum += s[0] + s[1] + s[2];
    }
    t.meanRadiance = sum / (3.0 * film.pixels().size());
    const double coverage = double(t.stats.surfaceHits) / double(t.stats.rays);
    if (!(coverage > 0.10 && coverage < 0.80))
        throw Error(what + ": the skull covers " + std::to_string(coverage) +
                    " of the rays, expected 0.1-0.8 (wrong scene or camera?)");
    return t;
}

// The shading directions the renderer evaluates the BRDF on, in the local frame, collected on a
// lattice of pixel centres; `rays` counts the lattice's camera rays.
struct DirectionSample {
    std::vector<std::pair<Vec3, Vec3>> pairs;  // (wi, wo)
    long long rays = 0;
};

DirectionSample collectDirections(const SceneSpec& spec, int stride) {
    const ObjectSpec& object = spec.objects.at(0);
    const auto& L = object.transform.linear;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            if (L[i][j] != (i == j ? 1.0 : 0.0) || object.transform.translation[i] != 0.0)
                throw Error("the skull scene has an object transform; this bench assumes none");
    LoadOptions options;
    options.normalize = object.source.divideBy;
    options.background = object.source.background;
    const Volume volume = loadVolume(object.source.path, options);
    SurfaceScene surfaces;
    surfaces.add(std::make_shared<IsoExactSurface>(*volume.grid, object.iso, object.name));
    surfaces.commit();
    // The tangent field as render/render_scene.cpp (worldAxes) builds it, identity transform.
    const Vec3 axis = normalized(object.tangentAxis);
    const Vec3 fallback = std::abs(axis.x) < 0.9 ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
    const PinholeCamera camera(spec.cameraPosition, spec.cameraTarget, spec.cameraUp,
                               spec.fovDegrees, double(spec.width) / spec.height, spec.crop);
    DirectionSample out;
    for (int y = stride / 2; y < spec.height; y += stride)
        for (int x = stride / 2; x < spec.width; x += stride) {
            ++out.rays;
            const Ray ray = camera.generateRay((x + 0.5) / spec.width, (y + 0.5) / spec.height);
            const auto hit = surfaces.intersect(ray);
            if (!hit) continue;
            // The directions render/shading.cpp's directLighting evaluates: two-sided, the
            // frame turned to the viewer, then the one light loop.
            const Vec3 toViewer = -ray.d;
            const Frame frame =
                facingViewer(Frame::fromNormalAndAxis(hit->normal, axis, fallback), toViewer);
            forEachLightInFrame(spec.lights, frame, hit->position, toViewer,
                                [&](const PointLight&, const Vec3& wi, const Vec3& wo, double) {
                                    out.pairs.emplace_back(wi, wo);
                                });
        }
    if (out.pairs.empty()) throw Error("no BRDF evaluations found on the skull");
    return out;
}

// CPU nanoseconds per evalBrdf on the collected pairs (one thread; at least 0.2 s of work).
double nsPerEval(const Brdf& brdf, const DirectionSample& d, double& checksum) {
    long long evals = 0;
    const double c0 = cpuNow();
    double elapsed = 0.0;
    do {
        for (const auto& [wi, wo] : d.pairs) {
            const Spectrum f = evalBrdf(brdf, wi, wo);
            checksum += f[0] + f[1] + f[2];
        }
        evals += (long long)d.pairs.size();
        elapsed = cpuNow() - c0;
    } while (elapsed < 0.2);
    return 1e9 * elapsed / double(evals);
}

}  // namespace

int main(int argc, char** argv) {
    int threads = 2, size = 512, spp = 8, stride = 2;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto next = [&] { return i + 1 < argc ? std::atoi(argv[++i]) : 0; };
        if (a == "--threads")
            threads = next();
        else if (a == "--size")
            size = next();
        else if (a == "--spp")
            spp = next();
        else if (a == "--stride")
            stride = next();
        else {
            std::fprintf(stderr, "usage: %s [--threads N] [--size N] [--spp N] [--stride N]\n",
                         argv[0]);
            return 2;
        }
    }
    if (threads < 1 || size < 16 || spp < 1 || stride < 1) {
        std::fprintf(stderr, "bad arguments\n");
        return 2;
    }
    try {
        auto skull = [&](const std::string& model) {
            SceneSpec spec = loadSceneFile(std::string(LOBE_SOURCE_DIR) +
                                           "/assets/scenes/skull/skull-" + model + ".json");
            spec.width = spec.height = size;
            spec.samplesPerPixel = spp;
            if (spec.objects.size() != 1 || spec.objects[0].brdfModel != model)
                throw Error(spec.path + ": expected the skull alone with BRDF " + model);
            return spec;
        };
        const double t0 = wallNow();
        SceneSpec lambertSpec = skull("ward");
        lambertSpec.objects[0].material.specularOn = false;
        const Timed lambertBefore = renderTimed(lambertSpec, threads, "Lambert only");

        std::vector<SceneSpec> specs;
        std::vector<Timed> timed;
        for (const PaperRow& row : kPaperTable7) {
            specs.push_back(skull(row.model));
            timed.push_back(renderTimed(specs.back(), threads, row.model));
            const Timed& t = timed.back();
            if (t.stats.rays != lambertBefore.stats.rays ||
                t.stats.surfaceHits != lambertBefore.stats.surfaceHits)
                throw Error(std::string(row.model) + ": different rays or hits than Lambert only");
            if (!(t.meanRadiance > lambertBefore.meanRadiance))
                throw Error(std::string(row.model) + ": adds no light over Lambert only");
        }
        const Timed lambertAfter = renderTimed(lambertSpec, threads, "Lambert only (again)");
        const double lambertCpu = 0.5 * (lambertBefore.cpu + lambertAfter.cpu);
        const double lambertWall = 0.5 * (lambertBefore.wall + lambertAfter.wall);

        const DirectionSample dirs = collectDirections(specs[0], stride);
        const double evalsPerRay = double(dirs.pairs.size()) / double(dirs.rays);
        const double renderEvals = evalsPerRay * double(lambertBefore.stats.rays);
        const double coverage =
            double(lambertBefore.stats.surfaceHits) / double(lambertBefore.stats.rays);

        std::printf(
            "# The paper's Table 7, regenerated\n\n"
            "%d×%d, %d jittered samples per pixel, the CThead skull alone (exact "
            "iso-surface, opaque), %d threads, all models in one run. Paper: 666 MHz "
            "Pentium III, one core.\n\n",
            size, size, spp, threads);
        std::printf(
            "| BRDF | paper (1 core) | Lobe wall (%d threads) | Lobe CPU | speed-up per "
            "core | CPU × Lambert-only | ns/eval | BRDF share (a) difference | BRDF share "
            "(b) count × ns |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|\n",
            threads);
        double checksum = 0.0;
        for (size_t i = 0; i < timed.size(); ++i) {
            const PaperRow& row = kPaperTable7[i];
            const Timed& t = timed[i];
            const double paperSeconds = 60.0 * row.minutes + row.seconds;
            const double ns = nsPerEval(specs[i].objects[0].material.specular, dirs, checksum);
            const double shareA = std::max(0.0, t.cpu - lambertCpu) / t.cpu;
            const double shareB = std::min(1.0, renderEvals * ns * 1e-9 / t.cpu);
            std::printf(
                "| %s | %d min %02d s | %.2f s | %.2f s | %.0f× | %.2f | %.0f | %.0f %% | "
                "%.0f %% |\n",
                row.model, row.minutes, row.seconds, t.wall, t.cpu, paperSeconds / t.cpu,
                t.cpu / lambertCpu, ns, 100.0 * shareA, 100.0 * shareB);
        }
        std::printf("| (Lambert only) | | %.2f s | %.2f s | | 1.00 | | | |\n\n", lambertWall,
                    lambertCpu);
        std::printf(
            "Lambert-only render before / after the models: %.2f / %.2f s wall, %.2f / "
            "%.2f s CPU (drift on this machine). Skull coverage %.1f %% of the camera "
            "rays; %.2f BRDF evaluations per camera ray (%zu pairs from %lld lattice rays, "
            "stride %d), %.3g in each render. CPU = process CPU seconds of the render (all "
            "threads: a single-core equivalent, so the speed-up is per core against the "
            "paper's one core; wall time inflates when other jobs share the cores). Share "
            "(a) = (CPU − Lambert-only CPU) / CPU; (b) = evaluations × ns/eval (one "
            "thread, on the collected directions) / CPU. Load + Embree build per scene not "
            "included. Whole run "
            "%.0f s. (checksum %.3g)\n",
            lambertBefore.wall, lambertAfter.wall, lambertBefore.cpu, lambertAfter.cpu,
            100.0 * coverage, evalsPerRay, dirs.pairs.size(), dirs.rays, stride, renderEvals,
            wallNow() - t0, checksum);
        return 0;
    } catch (const Error& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 1;
    }
}
