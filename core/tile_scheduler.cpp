#include "core/tile_scheduler.h"

#include "core/progress.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <pmmintrin.h>
#include <xmmintrin.h>

#include <algorithm>
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
    const int y0 = std::max(0, options.rowBegin);
    const int y1 = options.rowEnd < 0 ? height : std::min(height, options.rowEnd);
    std::vector<Tile> tiles;
    for (int y = y0; y < y1; y += size)
        for (int x = 0; x < width; x += size)
            tiles.push_back({x, y, std::min(x + size, width), std::min(y + size, y1)});

    ProgressReporter own(options.label, int64_t(width) * std::max(0, y1 - y0),
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
