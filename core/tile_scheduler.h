// Renders an image as square tiles in parallel on a TBB arena of a chosen size. Each tile is
// handed to the caller's function; pixels must depend only on their coordinates and the seed
// (core/rng.h) so that the image is the same for any thread count.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace lobe {

class ProgressReporter;

struct Tile {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // pixel range [x0,x1) × [y0,y1)
};

// Where the tiles of one image come from. Every worker thread asks for its next tile until there
// is none left; the default source counts through the image's tiles in this process. The cluster
// source (cluster/cluster.h) shares them with the other processes of an mpirun.
class TileSource {
public:
    virtual ~TileSource() = default;
    // Before any tile of an image: its tiles (row-major) and the display to advance as tiles end.
    virtual void begin(const std::vector<Tile>& tiles, ProgressReporter& progress) = 0;
    // The index of the next tile for worker `slot` to render, or -1 when none is left;
    // `finished` is the tile that worker rendered last (-1 on its first call). Thread-safe.
    virtual int next(int slot, int finished) = 0;
    // After every worker of this process got -1.
    virtual void end() = 0;
};

// The order tiles are handed out in: a fixed pseudo-random permutation of 0 … count − 1 (the
// same for every run, process and thread count), or row-major with shuffled = false.
//
// Why shuffled: the cost of a tile is very uneven (backdrop rows are cheap, rows through the
// brain dear), so in row-major order the fraction of pixels done says little about the fraction
// of time spent (a 2048² render announced 32 s and took 56 min). In a uniformly random order the
// first k of N tiles are a simple random sample without replacement, whose total cost has
// expectation k/N of the image's (Cochran, "Sampling Techniques", 3rd ed. 1977, §2.4, Theorem
// 2.1: the sample mean is unbiased), so elapsed · (1 − f)/f with f the fraction done is an
// honest ETA. Pixels depend only on their coordinates and the seed (core/pixel_loop.h), so the
// order changes no pixel. Fisher–Yates shuffle (Knuth, TAOCP vol. 2, 3rd ed., §3.4.2,
// Algorithm P) driven by core/rng.h with a fixed seed. The cluster's source (cluster/cluster.cpp)
// keeps row order (see there).
std::vector<int> tileOrder(int count, bool shuffled = true);

// The tiles of an image in tileOrder, for the threads of this process alone.
class LocalTileSource : public TileSource {
public:
    explicit LocalTileSource(bool shuffled = true) : shuffled_(shuffled) {}
    void begin(const std::vector<Tile>& tiles, ProgressReporter& progress) override;
    int next(int slot, int finished) override;
    void end() override {}

private:
    bool shuffled_;
    const std::vector<Tile>* tiles_ = nullptr;
    std::vector<int> order_;
    ProgressReporter* progress_ = nullptr;
    std::atomic<int> counter_{0};
};

// Pixels in a tile.
inline int64_t tilePixels(const Tile& t) { return int64_t(t.x1 - t.x0) * (t.y1 - t.y0); }

struct SchedulerOptions {
    int threads = 0;       // 0: all hardware threads
    int tileSize = 32;     // pixels per tile side
    bool progress = true;  // show a progress display on stderr
    std::string label = "render";
    // When set, pixels are reported to this reporter (one display over a batch of renders)
    // instead of a reporter of the scheduler's own.
    ProgressReporter* sharedProgress = nullptr;
    // Only the rows [rowBegin, rowEnd) (rowEnd < 0: to the bottom): one shard of an image.
    int rowBegin = 0;
    int rowEnd = -1;
    // Where the tiles come from (nullptr: this process renders them all, in tileOrder).
    TileSource* tileSource = nullptr;
    // The local source's order: shuffled (an honest ETA, see tileOrder) or row-major.
    bool shuffleTiles = true;
};

// The tiles forEachTile renders for an image: tileSize squares row by row, clipped to the image
// and to [rowBegin, rowEnd).
std::vector<Tile> imageTiles(int width, int height, const SchedulerOptions& options);

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
