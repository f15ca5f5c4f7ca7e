#include "core/tile_scheduler.h"

#include "core/progress.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <pmmintrin.h>
#include <xmmintrin.h>

#include <vector>

namespace lobe {

void setFlushToZero() {
    _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
    _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
}

void runWithThreads(int threads, const std::function<void()>& fn) {
    tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
    arena.execute([&] {
        setFlushToZero();
        fn();
    });
}

void forEachTile(int width, int height, const SchedulerOptions& options,
                 const std::function<void(const Tile&)>& renderTile) {
    const int size = options.tileSize > 0 ? options.tileSize : 32;
    std::vector<Tile> tiles;
    for (int y = 0; y < height; y += size)
        for (int x = 0; x < width; x += size)
            tiles.push_back({x, y, std::min(x + size, width), std::min(y + size, height)});

    ProgressReporter own(options.label, int64_t(width) * height,
                         options.progress && !options.sharedProgress);
    ProgressReporter& progress = options.sharedProgress ? *options.sharedProgress : own;
    runWithThreads(options.threads, [&] {
        tbb::parallel_for(tbb::blocked_range<size_t>(0, tiles.size(), 1),
                          [&](const tbb::blocked_range<size_t>& range) {
                              setFlushToZero();
                              for (size_t i = range.begin(); i != range.end(); ++i) {
                                  const Tile& tile = tiles[i];
                                  renderTile(tile);
                                  progress.advance(int64_t(tile.x1 - tile.x0) *
                                                   (tile.y1 - tile.y0));
                              }
                          });
    });
    own.finish();
}

}  // namespace lobe
