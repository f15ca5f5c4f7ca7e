#include "render/render_scene.h"

#include "core/camera_rays.h"
#include "core/memory.h"
#include "core/pixel_loop.h"
#include "core/rng.h"
#include "surface/surface_scene.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <optional>

namespace lobe {

namespace {

PixelSampling samplingOf(const SceneSpec& spec) { return {spec.samplesPerPixel, spec.seed}; }

// Sample j of pixel (x, y): its camera ray, and the jitter of its volume lattice drawn next from
// its stream.
struct CameraSample {
    Ray ray;
    double jitter = 0.0;
};
CameraSample cameraSample(const Scene& scene, int x, int y, const Vec2& j, Rng& rng) {
    const SceneSpec& spec = scene.spec();
    CameraSample c;
    c.ray = scene.camera().generateRay((x + j.x) / spec.width, (y + j.y) / spec.height);
    c.jitter = rng.uniform();
    return c;
}

// Pixel (x, y): the mean of the integrator's radiance over the pixel's samples; `aov`, when
// given, collects the same samples' passes.
Spectrum pixelValue(const Scene& scene, const Integrator& integrator, const PixelSamples& samples,
                    TraceState& state, RenderStats& stats, AovAccumulator* aov = nullptr) {
    if (aov) aov->beginPixel();
    return samples.mean([&](const Vec2& j, Rng& rng) {
        const CameraSample c = cameraSample(scene, samples.x(), samples.y(), j, rng);
        if (aov) aov->beginSample(-c.ray.d);
        return integrator.trace(c.ray, c.jitter, rng, state, stats, aov);
    });
}

// A camera sample whose ray is made before any sample of its tile row is traced.
struct PreparedSample {
    CameraSample camera;
    Rng rng;
};

// The pixels [x0, x1) of row y, each exactly as pixelValue makes it: first every sample's
// stream, jitter and camera ray (independent chains of hashes, divisions and a square root that
// the processor overlaps when they are not separated by a trace each: about 50 ns a pixel of
// latency otherwise; the divisions and square roots several samples at a time with SIMD,
// cameraRayDirections, core/camera_rays.h), then the traces in the same order, each pixel's sum
// in sample order.
template <class Store>
void renderRow(const Scene& scene, const Integrator& integrator, const PixelSampling& sampling,
               const StrataGrid& strata, int y, int x0, int x1, TraceState& state,
               RenderStats& stats, std::vector<PreparedSample>& buffer, const Store& store) {
    const int spp = sampling.samplesPerPixel;
    const size_t n = size_t(x1 - x0) * size_t(spp);
    buffer.resize(n);
    // The samples' pixels and stratum points, then their rays' directions (SIMD).
    thread_local std::vector<double> points;
    points.resize(7 * n);
    double* px = points.data();
    double* py = px + n;
    double* sx = py + n;
    double* sy = sx + n;
    double* dx = sy + n;
    double* dy = dx + n;
    double* dz = dy + n;
    PreparedSample* p = buffer.data();
    size_t i = 0;
    for (int x = x0; x < x1; ++x) {
        const PixelSamples samples(sampling, strata, x, y);
        for (int s = 0; s < spp; ++s, ++p, ++i) {
            // cameraSample's draws in its order: the jitter, then the lattice offset.
            const Vec2 j = samples.startInStrata(s, p->rng);
            px[i] = x;
            py[i] = y;
            sx[i] = j.x;
            sy[i] = j.y;
            p->camera.jitter = p->rng.uniform();
        }
    }
    const SceneSpec& spec = scene.spec();
    CameraSamplePoints pts;
    pts.n = int(n);
    pts.x = px;
    pts.y = py;
    pts.sx = sx;
    pts.sy = sy;
    pts.cols = strata.cols;
    pts.rows = strata.rows;
    pts.width = spec.width;
    pts.height = spec.height;
    const PinholeCamera& camera = scene.camera();
    cameraRayDirections(camera, pts, dx, dy, dz);
    for (i = 0; i < n; ++i) {
        Ray& ray = buffer[i].camera.ray;
        ray = Ray();
        ray.o = camera.position();
        ray.d = Vec3(dx[i], dy[i], dz[i]);
    }
    // Then, for opaque surface-only scenes, the first hits of 8 camera rays at a time: Embree
    // walks its tree once for the 8 neighbouring rays (SurfaceScene::intersect8, the same hits;
    // T1's exact skull: docs/performance.md).
    const bool packets = integrator.firstHitsInPackets();
    thread_local std::vector<std::optional<SurfaceHit>> firstHits;
    if (packets) {
        const double t0 = state.cost.enabled ? steadySeconds() : 0.0;
        const int count = int(buffer.size());
        firstHits.resize(buffer.size());
        const bool cutAtBackdrop = scene.backdrop().enabled();
        for (int i = 0; i < count; i += 8) {
            const int n = std::min(8, count - i);
            Ray segments[8];
            const Ray* rays[8];
            for (int k = 0; k < n; ++k) {
                const Ray& ray = buffer[size_t(i + k)].camera.ray;
                if (!cutAtBackdrop) {  // then the segment is the ray itself
                    rays[k] = &ray;
                    continue;
                }
                segments[k] = integrator.firstSurfaceSegment(ray);
                rays[k] = &segments[k];
            }
            scene.surfaces()->intersect8(rays, n, &firstHits[size_t(i)]);
        }
        if (state.cost.enabled) state.cost.surfaceSeconds += steadySeconds() - t0;
    }
    p = buffer.data();
    const std::optional<SurfaceHit>* firstHit = packets ? firstHits.data() : nullptr;
    // A packet ray that met no surface, without a backdrop, is trace()'s at once: no call.
    const bool missesEmpty = packets && !scene.backdrop().enabled();
    for (int x = x0; x < x1; ++x) {
        Spectrum sum;
        for (int s = 0; s < spp; ++s, ++p) {
            if (missesEmpty && !firstHit->has_value())
                sum += integrator.traceMissedPacketRay(stats);
            else
                sum += integrator.trace(p->camera.ray, p->camera.jitter, p->rng, state, stats,
                                        nullptr, firstHit);
            if (firstHit) ++firstHit;
        }
        store(x, PixelSamples(sampling, strata, x, y).meanOf(sum));
    }
}

}  // namespace

Spectrum RenderScene::traceRay(const Ray& ray, double jitter, uint64_t seed) const {
    TraceState state = integrator_.newState();
    RenderStats stats;
    Rng rng(seed);
    return integrator_.trace(ray, jitter, rng, state, stats);
}

Spectrum RenderScene::renderPixel(int x, int y) const {
    TraceState state = integrator_.newState();
    RenderStats stats;
    const PixelSampling sampling = samplingOf(spec());
    const StrataGrid strata = strataFor(sampling.samplesPerPixel);
    return pixelValue(scene_, integrator_, PixelSamples(sampling, strata, x, y), state, stats);
}

std::vector<double> RenderScene::costProfile(int stride, int threads) const {
    const SceneSpec& spec = scene_.spec();
    stride = std::max(1, stride);
    std::vector<double> rowSeconds(size_t(spec.height), 0.0);
    const int first = stride / 2;
    const int rows = (spec.height - first + stride - 1) / stride;
    if (rows <= 0 || spec.width <= first) return rowSeconds;
    tbb::enumerable_thread_specific<TraceState> states([&] { return integrator_.newState(); });
    PixelSampling one = samplingOf(spec);
    one.samplesPerPixel = 1;
    const StrataGrid strata = strataFor(1);
    const double scale = double(stride) * double(stride) * double(spec.samplesPerPixel);
    // A pilot row is one task, timed by its thread's CPU clock: a thread the machine's other work
    // pre-empts does not charge its wait to the row it was tracing (a wall clock per ray did, and
    // mispredicted bands by a factor of 5 on a loaded machine).
    tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
    arena.execute([&] {
        tbb::parallel_for(0, rows, [&](int r) {
            setFlushToZero();
            TraceState& state = states.local();
            RenderStats stats;
            const int y = first + r * stride;
            const double t0 = threadCpuSeconds();
            for (int x = first; x < spec.width; x += stride)
                pixelValue(scene_, integrator_, PixelSamples(one, strata, x, y), state, stats);
            rowSeconds[size_t(y)] = (threadCpuSeconds() - t0) * scale;
        });
    });
    return rowSeconds;
}

Film RenderScene::render(const RenderOptions& options, RenderStats* statsOut, const AovRequest* aov,
                         AovImage* aovs) const {
    const auto start = std::chrono::steady_clock::now();
    const SceneSpec& spec = scene_.spec();
    // The film (3 doubles a pixel), its display copy and the EXR's floats (6 + 3 floats), and
    // the passes asked for (about 6 floats an object, 8 more, and one per object and model).
    double bytesPerPixel = 3 * 8 + 9 * 4;
    if (aov && aov->alpha) bytesPerPixel += 4.0 * 2;  // coverage, and its copy in the EXR
    if (aov && (aov->objects || aov->backdrop || aov->depth || aov->normal || aov->topObject ||
                !aov->models.empty()))
        bytesPerPixel += 4.0 * (8 + double(spec.objects.size()) * (6 + 10));
    // A band: rows [rowBegin, rowEnd) alone, film row 0 = image row `firstRow`.
    const int firstRow = options.bandOnly ? std::clamp(options.rowBegin, 0, spec.height) : 0;
    const int lastRow = options.bandOnly && options.rowEnd >= 0
                            ? std::clamp(options.rowEnd, firstRow, spec.height)
                            : spec.height;
    const int filmRows = options.bandOnly ? lastRow - firstRow : spec.height;
    checkFits(double(spec.width) * filmRows * bytesPerPixel,
              spec.path + ": a " + std::to_string(spec.width) + " x " + std::to_string(filmRows) +
                  (options.bandOnly ? " band" : " image"));
    Film film(spec.width, filmRows);
    const int objectCount = int(spec.objects.size());
    tbb::enumerable_thread_specific<TraceState> states([&] {
        TraceState st = integrator_.newState();
        if (options.cost) st.cost.enable(objectCount);
        return st;
    });
    tbb::enumerable_thread_specific<RenderStats> stats;
    const bool withAovs = aov && aovs && aov->any();
    if (withAovs) *aovs = makeAovImage(*aov, spec.width, filmRows, objectCount);
    static const AovRequest kNoPasses;
    const AovRequest& request = withAovs ? *aov : kNoPasses;
    tbb::enumerable_thread_specific<AovAccumulator> accumulators(
        [&] { return AovAccumulator(request, objectCount, spec.lights); });

    SchedulerOptions scheduler;
    scheduler.threads = options.threads;
    scheduler.progress = options.progress;
    scheduler.label = options.label;
    // 32² tiles: T1's exact skull at 2048² 3.03 -> 2.98 process CPU s against 16² (longer rows
    // for renderRow, a quarter of the tile hand-outs; docs/performance.md); rendering 1 the same.
    // Pixels do not depend on the tiles (core/pixel_loop.h).
    scheduler.tileSize = 32;
    scheduler.sharedProgress = options.sharedProgress;
    scheduler.rowBegin = options.rowBegin;
    scheduler.rowEnd = options.rowEnd;
    scheduler.tileSource = options.tileSource;
    // The thread's state, counters and passes are looked up once per tile (a lookup per pixel
    // cost about 2 % of an opaque 1-spp render).
    const PixelSampling sampling = samplingOf(spec);
    const StrataGrid strata = strataFor(sampling.samplesPerPixel);
    forEachPixelByTile(
        spec.width, spec.height, sampling, scheduler, [&](const Tile& tile, auto&& pixels) {
            TraceState& st = states.local();
            RenderStats& rs = stats.local();
            // With options.cost the pixels are timed, for their thread's CPU/wall ratio.
            if (options.cost && !st.cost.started()) st.cost.start();
            if (!withAovs) {
                // Row by row, the camera rays made first (renderRow): the same pixels.
                std::vector<PreparedSample> buffer;
                for (int y = tile.y0; y < tile.y1; ++y) {
                    const double wall0 = options.cost ? steadySeconds() : 0.0;
                    renderRow(
                        scene_, integrator_, sampling, strata, y, tile.x0, tile.x1, st, rs, buffer,
                        [&](int x, const Spectrum& value) { film.at(x, y - firstRow) = value; });
                    if (options.cost) st.cost.pixelSeconds += steadySeconds() - wall0;
                }
                return;
            }
            AovAccumulator* acc = &accumulators.local();
            pixels([&](const PixelSamples& samples) {
                const double wall0 = options.cost ? steadySeconds() : 0.0;
                const int row = samples.y() - firstRow;
                film.at(samples.x(), row) = pixelValue(scene_, integrator_, samples, st, rs, acc);
                acc->finishPixel(samples.count(), size_t(row) * spec.width + size_t(samples.x()),
                                 *aovs);
                if (options.cost) st.cost.pixelSeconds += steadySeconds() - wall0;
            });
        });
    if (options.cost) {
        *options.cost = RenderCost();
        options.cost->objects.resize(size_t(objectCount));
        for (TraceState& st : states) {
            st.cost.stop();
            options.cost->add(st.cost);
        }
        options.cost->wallSeconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    if (statsOut) {
        *statsOut = RenderStats();
        for (const RenderStats& s : stats) *statsOut += s;
        for (const TraceState& st : states)
            for (const VolumeRaySampler& sampler : st.samplers) {
                statsOut->volumeEvaluated += sampler.samplesEvaluated();
                statsOut->volumeSkipped += sampler.samplesSkipped();
            }
        statsOut->seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    return film;
}

}  // namespace lobe
