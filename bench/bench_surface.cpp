// Benchmark of the two iso-surface methods (surface/iso_exact.h, surface/iso_mesh.h) on the
// CThead skull: rays per second of each, and time against error.
//
// Scene: shared/data/cthead (256×256×113 int16, spacing 1,1,2) through the volume loader, value/3272,
// iso 0.5 (the paper's skull, shared/docs/paper-scene.md); the camera of "A placement that works":
// 560 units from the skull's centre (110, 131, 116) at 45° azimuth from straight-front (front =
// −y), up = −z, 30° vertical field of view; 256² pixels, 2 threads.
//
// Image: a headlight shading |n·d| of the first hit (0 for a miss), so the image carries the hit
// position's silhouette and the normal — the two things the methods differ in. Pixel value =
// mean over spp stratified jittered samples (n×n strata, pixelSampleRng).
//
// Reference: the exact method at 64 samples per pixel (8×8 strata). Each benchmark renders one
// method at 1, 4 or 16 spp and reports: rmse (image RMSE against the reference; values in [0,1]),
// Mrays/s (primary rays per second of wall time on 2 threads), hitFraction. The exact method's
// error falls with spp (pixel integration only); the mesh method's error levels off at its bias.
//
// LOBE_BENCH_SURFACE_PGM=<folder> also writes each image as a PGM for a look.
//
// Checks before any time is reported: the reference is finite, hits between 10 % and 90 % of the
// pixels; each image is finite and its hit fraction is within 2 % of the reference's.
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "core/camera.h"
#include "core/error.h"
#include "core/rng.h"
#include "core/tile_scheduler.h"
#include "surface/iso_exact.h"
#include "surface/iso_mesh.h"
#include "surface/surface_scene.h"
#include "volume/volume.h"

namespace lobe {
namespace {

constexpr int kSize = 256;
constexpr int kThreads = 2;
constexpr int kReferenceStrata = 8;  // 64 spp
constexpr double kIso = 0.5;
const char* kDataPath = LOBE_SHARED_DATA "/cthead/cthead.nhdr";

double seconds(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

struct Setup {
    PinholeCamera camera;
    std::unique_ptr<SurfaceScene> exact, mesh;
};

const Setup& setup() {
    static const Setup s = [] {
        Setup r;
        LoadOptions opts;
        opts.normalize = 3272.0;
        auto t0 = std::chrono::steady_clock::now();
        const Volume vol = loadNrrd(kDataPath, opts);
        std::printf("CThead loaded in %.2f s\n", seconds(t0));
        t0 = std::chrono::steady_clock::now();
        auto exact = std::make_shared<IsoExactSurface>(*vol.grid, kIso, "CThead");
        r.exact = std::make_unique<SurfaceScene>();
        r.exact->add(exact);
        r.exact->commit();
        std::printf("exact: %zu of %zu bricks kept, %.1f MB, built in %.2f s (with BVH)\n",
                    exact->brickCount(), exact->candidateBrickCount(),
                    exact->memoryBytes() / 1048576.0, seconds(t0));
        t0 = std::chrono::steady_clock::now();
        auto mesh = std::make_shared<IsoMeshSurface>(*vol.grid, kIso, "CThead");
        r.mesh = std::make_unique<SurfaceScene>();
        r.mesh->add(mesh);
        r.mesh->commit();
        std::printf("mesh: %zu quads (%zu triangles), %zu vertices, %.1f MB, built in %.2f s "
                    "(volumeToMesh + BVH)\n",
                    mesh->quadCount(), mesh->triangleCount(), mesh->vertexCount(),
                    mesh->memoryBytes() / 1048576.0, seconds(t0));
        // paper-scene.md, "A placement that works".
        const Vec3 centre(110, 131, 116);
        const double az = radians(45.0);
        const Vec3 position = centre + Vec3(std::sin(az), -std::cos(az), 0.0) * 560.0;
        r.camera = PinholeCamera(position, centre, Vec3(0, 0, -1), 30.0, 1.0);
        return r;
    }();
    return s;
}

struct Image {
    std::vector<double> pixels;
    double hitFraction = 0.0;
    double seconds = 0.0;
    long long rays = 0;
};

Image render(const SurfaceScene& scene, int strata) {
    const PinholeCamera& cam = setup().camera;
    Image img;
    img.pixels.assign(std::size_t(kSize) * kSize, 0.0);
    std::atomic<long long> hits{0};
    const auto t0 = std::chrono::steady_clock::now();
    tbb::parallel_for(0, kSize, [&](int y) {
        setFlushToZero();
        long long rowHits = 0;
        for (int x = 0; x < kSize; ++x) {
            double sum = 0.0;
            for (int s = 0; s < strata * strata; ++s) {
                Rng rng = pixelSampleRng(7, x, y, s);
                const double jx = (s % strata + rng.uniform()) / strata;
                const double jy = (s / strata + rng.uniform()) / strata;
                const Ray ray = cam.generateRay((x + jx) / kSize, (y + jy) / kSize);
                if (const auto hit = scene.intersect(ray)) {
                    sum += std::abs(hit->normal.dot(ray.d));
                    ++rowHits;
                }
            }
            img.pixels[std::size_t(y) * kSize + x] = sum / (strata * strata);
        }
        hits += rowHits;
    });
    img.seconds = seconds(t0);
    img.rays = (long long)kSize * kSize * strata * strata;
    img.hitFraction = double(hits) / img.rays;
    return img;
}

bool finite(const Image& img) {
    for (double p : img.pixels)
        if (!std::isfinite(p)) return false;
    return true;
}

void writePgm(const Image& img, const std::string& name) {
    const char* dir = std::getenv("LOBE_BENCH_SURFACE_PGM");
    if (!dir) return;
    FILE* f = std::fopen((std::string(dir) + "/" + name + ".pgm").c_str(), "wb");
    if (!f) return;
    std::fprintf(f, "P5\n%d %d\n255\n", kSize, kSize);
    for (double p : img.pixels) std::fputc(int(std::lround(255.0 * std::min(1.0, std::max(0.0, p)))), f);
    std::fclose(f);
}

const Image& reference() {
    static const Image ref = [] {
        Image r = render(*setup().exact, kReferenceStrata);
        if (!finite(r)) throw Error("reference image is not finite");
        if (r.hitFraction < 0.1 || r.hitFraction > 0.9)
            throw Error("reference hit fraction " + std::to_string(r.hitFraction) +
                        " outside [0.1, 0.9]: wrong camera or data");
        std::printf("reference: exact, %d spp, %.2f s, %.2f Mrays/s, hit fraction %.3f\n",
                    kReferenceStrata * kReferenceStrata, r.seconds, r.rays * 1e-6 / r.seconds,
                    r.hitFraction);
        writePgm(r, "surface_reference");
        return r;
    }();
    return ref;
}

double rmse(const Image& a, const Image& b) {
    double s = 0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i) {
        const double d = a.pixels[i] - b.pixels[i];
        s += d * d;
    }
    return std::sqrt(s / double(a.pixels.size()));
}

void benchSurface(benchmark::State& state) {
    const bool exact = state.range(0) != 0;
    const int strata = static_cast<int>(state.range(1));
    const SurfaceScene& scene = exact ? *setup().exact : *setup().mesh;
    const Image& ref = reference();
    Image img;
    double total = 0;
    long long rays = 0;
    for (auto _ : state) {
        img = render(scene, strata);
        total += img.seconds;
        rays += img.rays;
        state.SetIterationTime(img.seconds);
    }
    if (!finite(img)) state.SkipWithError("image is not finite");
    if (std::abs(img.hitFraction - ref.hitFraction) > 0.02)
        state.SkipWithError("hit fraction differs from the reference by more than 0.02");
    state.counters["rmse"] = rmse(img, ref);
    state.counters["Mrays/s"] = rays * 1e-6 / total;
    state.counters["hitFraction"] = img.hitFraction;
    state.counters["spp"] = strata * strata;
    writePgm(img, std::string(exact ? "surface_exact_" : "surface_mesh_") +
                      std::to_string(strata * strata));
}

}  // namespace
}  // namespace lobe

int main(int argc, char** argv) {
    tbb::global_control threads(tbb::global_control::max_allowed_parallelism, lobe::kThreads);
    openvdb::initialize();
    try {
        lobe::reference();
    } catch (const std::exception& e) {
        std::fprintf(stderr, "lobe_bench_surface: %s\n", e.what());
        return 1;
    }
    for (int exact : {1, 0})
        for (int strata : {1, 2, 4})
            benchmark::RegisterBenchmark((std::string(exact ? "surface/exact" : "surface/mesh") +
                                          "/spp:" + std::to_string(strata * strata))
                                             .c_str(),
                                         lobe::benchSurface)
                ->Args({exact, strata})
                ->UseManualTime()
                ->Iterations(2)
                ->Unit(benchmark::kMillisecond);
    benchmark::Initialize(&argc, argv);
    benchmark::RunSpecifiedBenchmarks();
    return 0;
}
