#include "core/tile_scheduler.h"

#include "core/progress.h"
#include "core/rng.h"

#include <pmmintrin.h>
#include <tbb/global_control.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <xmmintrin.h>

#include <algorithm>
#include <memory>
#include <vector>

namespace lobe {

void setFlushToZero() {
    _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
    _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
}

void runWithThreads(int threads, const std::function<void()>& fn) {
    // More threads than the machine's cores, asked for: TBB's limit raised to that many for
    // the run, so they are given — otherwise TBB prints "TBB Warning: The number of workers is
    // currently limited to N" on stderr (even under --quiet) and gives fewer.
    std::unique_ptr<tbb::global_control> raised;
    if (threads > tbb::info::default_concurrency())
        raised = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                       size_t(threads));
    tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
    arena.execute([&] {
        setFlushToZero();
        fn();
    });
}

std::vector<Tile> imageTiles(int width, int height, const SchedulerOptions& options) {
    const int size = options.tileSize > 0 ? options.tileSize : 32;
    const int y0 = std::max(0, options.rowBegin);
    const int y1 = options.rowEnd < 0 ? height : std::min(height, options.rowEnd);
    std::vector<Tile> tiles;
    for (int y = y0; y < y1; y += size)
        for (int x = 0; x < width; x += size)
            tiles.push_back({x, y, std::min(x + size, width), std::min(y + size, y1)});
    return tiles;
}

std::vector<int> tileOrder(int count, bool shuffled) {
    std::vector<int> order(size_t(std::max(0, count)));
    for (int i = 0; i < count; ++i) order[size_t(i)] = i;
    if (!shuffled) return order;
    Rng rng(0x7469'6c65'6f72'6465ULL);  // fixed: the same order in every run and process
    for (int i = count - 1; i > 0; --i) {
        // j uniform in [0, i] (to within 2^-32, which does not matter for a visiting order).
        const int j = std::min(i, int(rng.uniform() * double(i + 1)));
        std::swap(order[size_t(i)], order[size_t(j)]);
    }
    return order;
}

void LocalTileSource::begin(const std::vector<Tile>& tiles, ProgressReporter& progress) {
    tiles_ = &tiles;
    order_ = tileOrder(int(tiles.size()), shuffled_);
    progress_ = &progress;
    counter_ = 0;
}

int LocalTileSource::next(int /*slot*/, int finished) {
    if (finished >= 0) progress_->advance(tilePixels((*tiles_)[size_t(finished)]));
    const int i = counter_.fetch_add(1);
    return i < int(order_.size()) ? order_[size_t(i)] : -1;
}

void forEachTile(int width, int height, const SchedulerOptions& options,
                 const std::function<void(const Tile&)>& renderTile) {
    const std::vector<Tile> tiles = imageTiles(width, height, options);
    int64_t pixels = 0;
    for (const Tile& t : tiles) pixels += tilePixels(t);
    ProgressReporter own(options.label, pixels, options.progress && !options.sharedProgress);
    ProgressReporter& progress = options.sharedProgress ? *options.sharedProgress : own;
    LocalTileSource local(options.shuffleTiles);
    TileSource& source = options.tileSource ? *options.tileSource : local;
    source.begin(tiles, progress);
    // One loop per worker: each asks the source for tiles until none is left. A tile that
    // throws stops every loop; the exception reaches the caller.
    std::atomic<bool> failed{false};
    runWithThreads(options.threads, [&] {
        const int workers = tbb::this_task_arena::max_concurrency();
        tbb::parallel_for(0, workers, 1, [&](int slot) {
            setFlushToZero();
            for (int i = source.next(slot, -1); i >= 0 && !failed; i = source.next(slot, i)) {
                try {
                    renderTile(tiles[size_t(i)]);
                } catch (...) {
                    failed = true;
                    throw;
                }
            }
        });
    });
    source.end();
    own.finish();
}

}  // namespace lobe
