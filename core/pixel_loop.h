// The one pixel loop of Lobe: every image — scene renders (render/render_scene.h), the BRDF
// gallery, the flux-overlap lattices (analysis/overlap_ranking.h) — is made by forEachPixel.
// Tiles run in parallel (core/tile_scheduler.h). Sample s of pixel (x, y) draws from its own
// random stream pixelSampleRng(seed, x, y, s) (core/rng.h): first the stratified jitter
// j ∈ [0, 1)² of stratum s (core/sampling.h), then whatever the caller needs from the same
// stream. A pixel's value therefore depends only on its coordinates and the seed — never on the
// thread count, the tile order or which process renders the tile.
#pragma once

#include "core/film.h"
#include "core/rng.h"
#include "core/sampling.h"
#include "core/tile_scheduler.h"

#include <cmath>
#include <cstdint>

namespace lobe {

struct PixelSampling {
    int samplesPerPixel = 1;
    uint64_t seed = 0;
};

// The samples of one pixel.
class PixelSamples {
public:
    PixelSamples(const PixelSampling& sampling, const StrataGrid& strata, int x, int y)
        : sampling_(sampling), strata_(strata), x_(x), y_(y) {}

    int x() const { return x_; }
    int y() const { return y_; }
    int count() const { return sampling_.samplesPerPixel; }

    // fn(j, rng) for each sample in order: j the jitter within the pixel, rng the sample's stream
    // (already advanced past j).
    template <class Fn>
    void forEach(Fn&& fn) const {
        for (int s = 0; s < sampling_.samplesPerPixel; ++s) {
            Rng rng;
            const Vec2 j = start(s, rng);
            fn(j, rng);
        }
    }

    // Sample s's jitter, its stream left in `rng` (advanced past the jitter): what forEach hands
    // fn, for callers that prepare several samples before using any (render/render_scene.cpp).
    Vec2 start(int s, Rng& rng) const {
        rng = pixelSampleRng(sampling_.seed, uint32_t(x_), uint32_t(y_), uint32_t(s));
        return jitteredSample(strata_, s, rng);
    }
    // The same draws as start(), the jitter left in stratum units (jitteredStratumPoint): for
    // callers that divide many samples at once (render/render_scene.cpp, core/camera_rays.h).
    Vec2 startInStrata(int s, Rng& rng) const {
        rng = pixelSampleRng(sampling_.seed, uint32_t(x_), uint32_t(y_), uint32_t(s));
        return jitteredStratumPoint(strata_, s, rng);
    }

    // The mean of fn(j, rng) → Spectrum over the samples; a non-finite mean becomes 0, so no
    // NaN or Inf reaches an image.
    template <class Fn>
    Spectrum mean(Fn&& fn) const {
        Spectrum sum;
        forEach([&](const Vec2& j, Rng& rng) { sum += fn(j, rng); });
        return meanOf(sum);
    }

    // The mean given the sum of the samples' values in sample order (as mean() forms it).
    Spectrum meanOf(const Spectrum& sum) const {
        Spectrum value = sum * (1.0 / sampling_.samplesPerPixel);
        if (!value.isFinite()) value = Spectrum(0.0);
        return value;
    }

private:
    const PixelSampling& sampling_;
    const StrataGrid& strata_;
    int x_, y_;
};

// tileFn(tile, pixels) once for every tile of a width × height image, tiles in parallel;
// pixels(fn) calls fn(const PixelSamples&) for each pixel of the tile, row by row. For callers
// that look up their thread's state once per tile rather than once per pixel.
template <class TileFn>
void forEachPixelByTile(int width, int height, const PixelSampling& sampling,
                        const SchedulerOptions& scheduler, TileFn&& tileFn) {
    const StrataGrid strata = strataFor(sampling.samplesPerPixel);
    forEachTile(width, height, scheduler, [&](const Tile& tile) {
        tileFn(tile, [&](auto&& fn) {
            for (int y = tile.y0; y < tile.y1; ++y)
                for (int x = tile.x0; x < tile.x1; ++x) fn(PixelSamples(sampling, strata, x, y));
        });
    });
}

// fn(const PixelSamples&) once for every pixel of a width × height image, tiles in parallel.
template <class Fn>
void forEachPixel(int width, int height, const PixelSampling& sampling,
                  const SchedulerOptions& scheduler, Fn&& fn) {
    forEachPixelByTile(width, height, sampling, scheduler,
                       [&](const Tile&, auto&& pixels) { pixels(fn); });
}

}  // namespace lobe
