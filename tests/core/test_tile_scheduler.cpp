#include "core/film.h"
#include "core/rng.h"
#include "core/sampling.h"
#include "core/tile_scheduler.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>

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

// A tile source decides which tiles this process renders (as the cluster's does): here every
// other tile; each worker reports the tile it finished when it asks for the next.
class EveryOtherTile : public TileSource {
public:
    void begin(const std::vector<Tile>& tiles, ProgressReporter&) override {
        count = int(tiles.size());
        next_ = 0;
    }
    int next(int, int finished) override {
        if (finished >= 0) ++finishedReports;
        const int i = 2 * next_.fetch_add(1);
        return i < count ? i : -1;
    }
    void end() override { ended = true; }

    int count = 0;
    std::atomic<int> finishedReports{0};
    bool ended = false;

private:
    std::atomic<int> next_{0};
};

TEST(TileScheduler, ATileSourceChoosesTheTiles) {
    EveryOtherTile source;
    SchedulerOptions options;
    options.tileSize = 8;
    options.progress = false;
    options.threads = 2;
    options.tileSource = &source;
    std::vector<std::atomic<int>> visits(40 * 24);
    forEachTile(40, 24, options, [&](const Tile& t) {
        for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x) visits[size_t(y * 40 + x)]++;
    });
    ASSERT_EQ(source.count, 15);  // 5 × 3 tiles of 8 × 8
    EXPECT_TRUE(source.ended);
    EXPECT_EQ(source.finishedReports.load(), 8);  // tiles 0, 2, …, 14
    for (int y = 0; y < 24; ++y)
        for (int x = 0; x < 40; ++x)
            ASSERT_EQ(visits[size_t(y * 40 + x)].load(), ((y / 8) * 5 + x / 8) % 2 == 0 ? 1 : 0)
                << x << "," << y;
}

TEST(TileScheduler, ATileThatThrowsStopsTheOtherWorkers) {
    SchedulerOptions options;
    options.tileSize = 1;
    options.progress = false;
    options.threads = 2;
    std::atomic<int> rendered{0};
    EXPECT_THROW(forEachTile(100, 100, options,
                             [&](const Tile& t) {
                                 rendered++;
                                 if (t.x0 == 0 && t.y0 == 0) throw std::runtime_error("first");
                                 std::this_thread::sleep_for(std::chrono::milliseconds(1));
                             }),
                 std::runtime_error);
    // Not the 10 000 tiles (10 s) of the image: the other worker stops within a second.
    EXPECT_LT(rendered.load(), 1000);
}

}  // namespace lobe
