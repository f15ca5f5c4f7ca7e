#include "core/film.h"
#include "core/progress.h"
#include "core/rng.h"
#include "core/sampling.h"
#include "core/tile_scheduler.h"

#include <gtest/gtest.h>

#include <algorithm>
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
                             [&](const Tile&) {
                                 // The first tile taken, wherever the shuffled order puts it.
                                 if (rendered++ == 0) throw std::runtime_error("first");
                                 std::this_thread::sleep_for(std::chrono::milliseconds(1));
                             }),
                 std::runtime_error);
    // Not the 10 000 tiles (10 s) of the image: the other worker stops within a second.
    EXPECT_LT(rendered.load(), 1000);
}

// The visiting order: a fixed permutation (the same on every call, so every process of a cluster
// agrees), row-major when asked.
TEST(TileScheduler, TileOrderIsAFixedPermutation) {
    const std::vector<int> order = tileOrder(1000);
    EXPECT_EQ(order, tileOrder(1000));
    std::vector<int> sorted = order;
    std::sort(sorted.begin(), sorted.end());
    for (int i = 0; i < 1000; ++i) ASSERT_EQ(sorted[size_t(i)], i);
    int inPlace = 0;
    for (int i = 0; i < 1000; ++i) inPlace += order[size_t(i)] == i;
    EXPECT_LT(inPlace, 10);  // a random permutation fixes one point on average
    EXPECT_EQ(tileOrder(5, false), (std::vector<int>{0, 1, 2, 3, 4}));
    EXPECT_TRUE(tileOrder(0).empty());
    EXPECT_EQ(tileOrder(1), std::vector<int>{0});
}

// Why the order is shuffled: on an image whose top half costs nothing (backdrop) and whose
// bottom half costs 1 per tile, the cost done when half the tiles are done should be half the
// total (an honest ETA). Row-major it is 0, and the ETA at 50 % says "as long again" for a
// render that has all its work still ahead. The first k tiles of a random order are a simple
// random sample: the dear tiles among them are hypergeometric, mean k·K/N = 256 of the K = 512,
// standard deviation sqrt(k·(K/N)·(1 − K/N)·(N − k)/(N − 1)) = 8.0 tiles at N = 1024, k = 512, a
// share of 0.016; the bound 0.05 is 3 sd (the permutation is fixed, so the test is too).
TEST(TileScheduler, ShuffledOrderSamplesTheCostEvenly) {
    const int width = 32 * 32, height = 32 * 32;  // 32 × 32 = 1024 tiles of 32²
    SchedulerOptions options;
    options.tileSize = 32;
    options.progress = false;
    options.threads = 1;  // the visiting order exactly as tileOrder gives it
    for (const bool shuffled : {true, false}) {
        options.shuffleTiles = shuffled;
        std::vector<int> visited;
        forEachTile(width, height, options, [&](const Tile& t) { visited.push_back(t.y0); });
        ASSERT_EQ(visited.size(), 1024u);
        double costOfFirstHalf = 0.0;
        for (size_t i = 0; i < 512; ++i) costOfFirstHalf += visited[i] >= height / 2 ? 1.0 : 0.0;
        const double share = costOfFirstHalf / 512.0;  // of the 512 dear tiles
        if (shuffled)
            EXPECT_NEAR(share, 0.5, 0.05);
        else
            EXPECT_EQ(share, 0.0);
    }
}

}  // namespace lobe

namespace lobe {

// Paused time (a batch assembling its next scene) is not counted towards the ETA, and the final
// line shows it apart. Sleeps of 30 ms running and 300 ms paused: the bound 0.25 s leaves 220 ms
// for a loaded machine's scheduling delays, and no run can measure less than the 30 ms.
TEST(Progress, PausedTimeIsNotTheUnitsTime) {
    ::testing::internal::CaptureStderr();
    {
        ProgressReporter progress("work", 2, true);  // stderr is captured: not a terminal
        std::this_thread::sleep_for(std::chrono::milliseconds(30));
        progress.pause();
        std::this_thread::sleep_for(std::chrono::milliseconds(300));
        const double whilePaused = progress.elapsedSeconds();
        progress.resume();
        const double elapsed = progress.elapsedSeconds();
        EXPECT_GE(elapsed, 0.03);
        EXPECT_LT(elapsed, 0.25);
        EXPECT_NEAR(whilePaused, elapsed, 0.05);
        progress.advance();  // half done within the first second: no line yet, only the last
        progress.advance();
        progress.finish();
    }
    const std::string err = ::testing::internal::GetCapturedStderr();
    EXPECT_EQ(err.find("50%"), std::string::npos) << err;
    EXPECT_EQ(err.rfind("work: 100%  done in 0.", 0), 0u) << err;
    EXPECT_NE(err.find(" s (+ 0."), std::string::npos) << err;  // 0.3 s and the delays
    EXPECT_NE(err.find(" s loading)\n"), std::string::npos) << err;
}

}  // namespace lobe
