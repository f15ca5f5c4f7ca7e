// Renders an image as square tiles in parallel on a TBB arena of a chosen size. Each tile is
// handed to the caller's function; pixels must depend only on their coordinates and the seed
// (core/rng.h) so that the image is the same for any thread count.
#pragma once

#include <functional>
#include <string>

namespace lobe {

class ProgressReporter;

struct Tile {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // pixel range [x0,x1) × [y0,y1)
};

struct SchedulerOptions {
    int threads = 0;      // 0: all hardware threads
    int tileSize = 32;    // pixels per tile side
    bool progress = true; // show a progress display on stderr
    std::string label = "render";
    // When set, pixels are reported to this reporter (one display over a batch of renders)
    // instead of a reporter of the scheduler's own.
    ProgressReporter* sharedProgress = nullptr;
    // Only the rows [rowBegin, rowEnd) (rowEnd < 0: to the bottom): one shard of an image.
    int rowBegin = 0;
    int rowEnd = -1;
};

// Calls renderTile once for every tile, in parallel. An exception thrown by renderTile stops the
// render and is rethrown here.
void forEachTile(int width, int height, const SchedulerOptions& options,
                 const std::function<void(const Tile&)>& renderTile);

// Runs fn inside an arena of `threads` workers (0: all), with flush-to-zero set on each worker.
// For parallel work that is not tiled (the flux-overlap test, property sweeps).
void runWithThreads(int threads, const std::function<void()>& fn);

// Flush-to-zero and denormals-are-zero for the calling thread (Embree asks for it, and denormal
// arithmetic in long BRDF tails is 100× slower).
void setFlushToZero();

}  // namespace lobe
