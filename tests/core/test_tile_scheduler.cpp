#include "core/film.h"
#include "core/rng.h"
#include "core/sampling.h"
#include "core/tile_scheduler.h"

#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>

namespace lobe {
namespace {

// A noisy "render": each pixel averages random samples from its own RNG streams.
Film noisyRender(int threads, int tileSize) {
    Film film(97, 61);  // not a multiple of the tile size
    SchedulerOptions options;
    options.threads = threads;
    options.tileSize = tileSize;
    options.progress = false;
    forEachTile(film.width(), film.height(), options, [&](const Tile& tile) {
        for (int y = tile.y0; y < tile.y1; ++y)
            for (int x = tile.x0; x < tile.x1; ++x) {
                Spectrum sum;
                const StrataGrid grid = strataFor(8);
                for (int s = 0; s < 8; ++s) {
                    Rng rng = pixelSampleRng(1234, x, y, s);
                    const Vec2 p = jitteredSample(grid, s, rng);
                    sum += Spectrum(p.x, p.y, rng.uniform());
                }
                film.at(x, y) = sum * (1.0 / 8.0);
            }
    });
    return film;
}

}  // namespace

TEST(TileScheduler, ImageIsIdenticalForAnyThreadCountAndTileSize) {
    const Film one = noisyRender(1, 32);
    const Film two = noisyRender(2, 16);
    const Film many = noisyRender(8, 7);
    for (size_t i = 0; i < one.pixels().size(); ++i)
        for (int c = 0; c < 3; ++c) {
            ASSERT_EQ(one.pixels()[i][c], two.pixels()[i][c]);
            ASSERT_EQ(one.pixels()[i][c], many.pixels()[i][c]);
        }
}

TEST(TileScheduler, EveryPixelIsVisitedExactlyOnce) {
    std::vector<std::atomic<int>> visits(50 * 33);
    SchedulerOptions options;
    options.tileSize = 8;
    options.progress = false;
    forEachTile(50, 33, options, [&](const Tile& t) {
        for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x) visits[y * 50 + x]++;
    });
    for (auto& v : visits) ASSERT_EQ(v.load(), 1);
}

TEST(TileScheduler, ExceptionInATileReachesTheCaller) {
    SchedulerOptions options;
    options.progress = false;
    EXPECT_THROW(forEachTile(64, 64, options,
                             [](const Tile& t) {
                                 if (t.x0 == 32) throw std::runtime_error("tile failed");
                             }),
                 std::runtime_error);
}

}  // namespace lobe
