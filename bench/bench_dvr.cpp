// Benchmark of direct volume rendering (volume/volume_marcher.h): time against error for steps of
// 0.05, 0.1, 0.25, 0.5 and 1 voxel, with and without empty-space skipping, and pre-integrated
// (volume/pre_integration.h) up to 4 voxels, against a 0.02-voxel point-sampled reference image;
// samples per second; peak memory.
//
// Scene: the SPM12 FieldMap grey-matter prior (assets/brain/
// grey_icbm151_smooth8mm_FieldMap.nii.gz: 91×109×91, 2 mm, already 8 mm smoothed — the closest
// analogue of the paper's density maps, docs/paper-scene.md), the paper's four density-map
// ramps in one transfer function (TransferFunction::densityMaps), trilinear reconstruction and
// central-difference normals (the paper's choice for the density maps), Phong + Lambert kd 0.2,
// four point lights around the camera, 128² pixels, one jittered ray per pixel (the same jitter
// in every image, so the error is the step's, not the noise's), 2 threads.
//
// Checks before any time is reported: the image is finite and not black, and with skipping it is
// identical to the one without (the "skipDiff" counter is the largest band difference; above
// 1e-12 the benchmark reports an error instead of a time).
//
// Counters: rmse (band RMSE over all pixels against the reference), relRmse (rmse / mean band
// value of the reference, black background included), Msamples/s (reconstructed lattice points
// per second of wall time), Mlattice/s (lattice points passed, skipped ones included),
// evaluated and skipped lattice points per image, peakRssMB (getrusage ru_maxrss, whole
// process). LOBE_BENCH_DVR_PPM=<folder> also writes every image as a PPM for a look.
//
// The volume is read by the project's loader (volume/volume.h).
#include "bench/bench_common.h"
#include "core/camera.h"
#include "core/error.h"
#include "core/pixel_loop.h"
#include "core/rng.h"
#include "render/compositor.h"
#include "render/shading.h"
#include "volume/volume.h"
#include "volume/volume_marcher.h"

#include <benchmark/benchmark.h>
#include <sys/resource.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/global_control.h>
#include <zlib.h>

#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

namespace lobe {
namespace {

constexpr int kSize = 128;
constexpr int kThreads = 2;
constexpr double kReferenceStep = 0.02;
const char* kDataPath = LOBE_SOURCE_DIR "/assets/brain/grey_icbm151_smooth8mm_FieldMap.nii.gz";

struct Scene {
    openvdb::FloatGrid::Ptr grid;
    PinholeCamera camera;
    std::vector<PointLight> lights;
    Material material;
};

Scene& scene() {
    static Scene s = [] {
        openvdb::initialize();
        Scene sc;
        sc.grid = loadVolume(kDataPath).grid;  // the project's loader (volume/volume.h)
        // Centre of the active box in world; camera 45° from the front (+y, RAS anterior),
        // slightly above, up = +z.
        const openvdb::CoordBBox b = sc.grid->evalActiveVoxelBoundingBox();
        const openvdb::Vec3d c = sc.grid->indexToWorld(b.getCenter());
        const Vec3 centre(c.x(), c.y(), c.z());
        const Vec3 eye = centre + 260.0 * normalized(Vec3(std::sin(radians(45.0)),
                                                          std::cos(radians(45.0)), 0.35));
        sc.camera = PinholeCamera(eye, centre, Vec3(0, 0, 1), 35.0, 1.0);
        for (double sx : {-1.0, 1.0})
            for (double sy : {-1.0, 1.0})
                sc.lights.push_back(
                    {eye + 60.0 * sx * sc.camera.right() + 60.0 * sy * sc.camera.up(),
                     Spectrum(260.0 * 260.0 / 4.0)});
        return sc;
    }();
    return s;
}

struct Image {
    std::vector<Spectrum> pixels;
    long long evaluated = 0, skipped = 0;
    double seconds = 0.0;
};

Image render(double step, bool skip, bool preIntegrated = false) {
    Scene& sc = scene();
    DvrSettings set;
    set.stepVoxels = step;
    set.emptySpaceSkipping = skip;
    set.preIntegrated = preIntegrated;
    const DvrVolume vol(sc.grid, TransferFunction::densityMaps(), set, "FieldMap grey");
    Image img;
    img.pixels.assign(size_t(kSize) * kSize, Spectrum(0.0));
    // One marcher per thread; the one pixel loop (core/pixel_loop.h), 1 sample per pixel.
    tbb::enumerable_thread_specific<std::unique_ptr<VolumeRaySampler>> samplers;
    SchedulerOptions scheduler;
    scheduler.progress = false;
    const auto t0 = std::chrono::steady_clock::now();
    forEachPixel(kSize, kSize, PixelSampling{1, 1}, scheduler, [&](const PixelSamples& px) {
        std::unique_ptr<VolumeRaySampler>& sampler = samplers.local();
        if (!sampler) sampler = std::make_unique<VolumeRaySampler>(vol);
        img.pixels[size_t(px.y()) * kSize + size_t(px.x())] = px.mean([&](const Vec2& j, Rng& rng) {
            const Ray ray = sc.camera.generateRay((px.x() + j.x) / kSize, (px.y() + j.y) / kSize);
            FrontToBackCompositor comp;
            if (sampler->begin(ray, rng.uniform()))
                sampler->marchSegment(ray.tMax, [&](const VolumeSample& s) {
                    comp.add(s.alpha, shadeVolumeSample(sc.material, s, -ray.d, sc.lights));
                    return !comp.terminated();
                });
            return comp.radiance;
        });
    });
    long long evaluated = 0, skipped = 0;
    for (const auto& sampler : samplers) {
        if (!sampler) continue;
        evaluated += sampler->samplesEvaluated();
        skipped += sampler->samplesSkipped();
    }
    img.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    img.evaluated = evaluated;
    img.skipped = skipped;
    return img;
}

// Optional look at the images (LOBE_BENCH_DVR_PPM=<folder>): linear bands → sRGB 8-bit PPM,
// scaled so the reference's brightest band is white.
void writePpm(const Image& img, const std::string& path) {
    static double scale = 0.0;
    if (scale == 0.0) {
        double m = 1e-30;
        for (const Spectrum& p : img.pixels) m = std::max(m, p.maxValue());
        scale = 1.0 / m;
    }
    FILE* f = std::fopen(path.c_str(), "wb");
    if (!f) return;
    std::fprintf(f, "P6\n%d %d\n255\n", kSize, kSize);
    for (const Spectrum& p : img.pixels) {
        const auto rgb = bandsToLinearSrgb(p * scale);
        for (double c : rgb) std::fputc(int(std::lround(255.0 * srgbEncode(c))), f);
    }
    std::fclose(f);
}

double peakRssMB() { return bench::peakRssMb(); }

const Image& reference() {
    static const Image ref = [] {
        Image r = render(kReferenceStep, true);
        double mean = 0;
        for (const Spectrum& p : r.pixels) {
            if (!p.isFinite()) throw std::runtime_error("reference image is not finite");
            mean += p.average();
        }
        if (!(mean > 0)) throw std::runtime_error("reference image is black");
        std::printf(
            "reference: step %.2f voxel, %.2f s, %.1f M lattice points evaluated, "
            "%.1f M skipped\n",
            kReferenceStep, r.seconds, r.evaluated * 1e-6, r.skipped * 1e-6);
        if (const char* dir = std::getenv("LOBE_BENCH_DVR_PPM"))
            writePpm(r, std::string(dir) + "/dvr_reference.ppm");
        return r;
    }();
    return ref;
}

void benchDvr(benchmark::State& state) {
    const double step = state.range(0) / 100.0;
    const bool skip = state.range(1) != 0;
    const bool pre = state.range(2) != 0;
    const Image& ref = reference();
    // Output check: skipping must not change the image (volume_marcher.h, "Empty-space
    // skipping"; with pre-integration, by more than rounding: "Pre-integration"); compare
    // against the same step without skipping once, outside the timing.
    const Image other = render(step, !skip, pre);
    Image img;
    double seconds = 0;
    for (auto _ : state) {
        img = render(step, skip, pre);
        seconds += img.seconds;
        state.SetIterationTime(img.seconds);
    }
    double skipDiff = 0;
    for (size_t i = 0; i < img.pixels.size(); ++i)
        for (int k = 0; k < kBandCount; ++k)
            skipDiff = std::max(skipDiff, std::abs(img.pixels[i][k] - other.pixels[i][k]));
    if (skipDiff > (pre ? 1e-9 : 1e-12)) state.SkipWithError("skipping changed the image");
    double rel = 0;
    state.counters["rmse"] = bench::rmse(img.pixels, ref.pixels, &rel);
    state.counters["relRmse"] = rel;
    state.counters["skipDiff"] = skipDiff;
    state.counters["evaluated"] = double(img.evaluated);
    state.counters["skipped"] = double(img.skipped);
    state.counters["Msamples/s"] =
        benchmark::Counter(double(img.evaluated) * 1e-6 * state.iterations() / seconds);
    // Lattice points per second counts skipped ones too: the rate at which the ray advances.
    state.counters["Mlattice/s"] = benchmark::Counter(double(img.evaluated + img.skipped) * 1e-6 *
                                                      state.iterations() / seconds);
    state.counters["peakRssMB"] = peakRssMB();
    if (const char* dir = std::getenv("LOBE_BENCH_DVR_PPM"))
        writePpm(img, std::string(dir) + "/dvr_" + std::to_string(state.range(0)) + ".ppm");
}

}  // namespace
}  // namespace lobe

int main(int argc, char** argv) {
    tbb::global_control threads(tbb::global_control::max_allowed_parallelism, lobe::kThreads);
    try {
        lobe::reference();
    } catch (const std::exception& e) {
        std::fprintf(stderr, "lobe_bench_dvr: %s\n", e.what());
        return 1;
    }
    // Point-sampled with and without skipping, then pre-integrated (with skipping) at the same
    // steps and coarser ones.
    std::vector<std::array<int, 3>> runs;
    for (int step : {5, 10, 25, 50, 100})
        for (int skip : {1, 0}) runs.push_back({step, skip, 0});
    for (int step : {5, 10, 25, 50, 100, 200, 400}) runs.push_back({step, 1, 1});
    for (const auto& [step, skip, pre] : runs)
        benchmark::RegisterBenchmark(
            (std::string("dvr/step:") + std::to_string(step / 100.0).substr(0, 4) +
             (skip ? "/skip" : "/noskip") + (pre ? "/pre-integrated" : ""))
                .c_str(),
            lobe::benchDvr)
            ->Args({step, skip, pre})
            ->UseManualTime()
            ->Iterations(2)
            ->Unit(benchmark::kMillisecond);
    benchmark::Initialize(&argc, argv);
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
