// The processes of one `mpirun` (Open MPI; docs/cluster.md). Every process loads the scene; the
// tiles of each image are handed out by rank 0 to the worker threads of every process as they ask
// (a tile costs from almost nothing, over the backdrop, to a hundred times more through the
// density maps, so a fixed split would leave processes idle); rank 0 gathers the pixels and alone
// writes files. A pixel's value depends only on its coordinates and the seed (core/pixel_loop.h),
// so the image is the same bit for bit for any number of processes and threads.
//
// Without mpirun, or in a build without MPI, the cluster is this one process and every call is
// local: nothing here costs a single-process run anything.
#pragma once

#include "core/error.h"
#include "core/tile_scheduler.h"

#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace lobe {

// One per-pixel image buffer (row-major, `bytesPerPixel` bytes a pixel) for gatherTiles.
struct PixelBuffer {
    unsigned char* data = nullptr;
    size_t bytesPerPixel = 0;
};

namespace cluster {

// Joins the run when this process was started by mpirun (Open MPI sets OMPI_COMM_WORLD_SIZE);
// otherwise the cluster is this process alone. Call once, first thing in main.
void start(int* argc, char*** argv);
// Leaves the run (MPI_Finalize). Call once at the end of main, on every exit path.
void stop();
// Ends every process of the run with `code` (MPI_Abort); a plain exit when not distributed.
[[noreturn]] void abort(int code);

int rank();  // 0 … size() − 1
int size();  // processes in the run (1 without mpirun)
inline bool distributed() { return size() > 1; }
inline bool isRoot() { return rank() == 0; }

// Collective calls: every process must make them, in the same order.
// The lowest rank whose `failed` is true, or −1 when none failed.
int firstFailed(bool failed);
// Rank 0's value, on every process.
bool broadcast(bool value);
std::string broadcast(const std::string& value);
// How many processes pass `value` true.
int countTrue(bool value);

// An error every process of the run knows of (see everywhere): each process ends normally with
// it, and only the process that found it prints it.
class CollectiveError : public Error {
public:
    CollectiveError(const std::string& message, bool reportHere)
        : Error(message), reportHere_(reportHere) {}
    bool reportHere() const { return reportHere_; }

private:
    bool reportHere_;
};

// Runs `step` on every process (collective). When it throws lobe::Error on any process, it
// throws CollectiveError on all: the lowest failing rank's carries its message to print, the
// others' stay silent — so bad input found while loading gives one message and no process
// renders. A failure on some ranks but not all (a file missing on one node) is prefixed "on
// rank R of N only: ". In a single process the error passes through as it is.
void everywhere(const std::function<void()>& step);

// A tile source shared by every process (collective: every process renders the same image with
// it). Rank 0 answers the other processes' requests from a thread of its own and counts their
// finished tiles in its progress display. A single process gets the local source.
std::unique_ptr<TileSource> sharedTiles();

// After an image rendered with `source` (from sharedTiles): the pixels of the tiles the other
// processes rendered are copied into rank 0's buffers (collective). `width` is the image's;
// the buffers' row 0 is image row `firstRow` (a band of a poster).
void gatherTiles(const TileSource& source, int width, const std::vector<PixelBuffer>& buffers,
                 int firstRow = 0);

// Fault injection for the tests: when LOBE_FAULT_RANK names this process's rank, its first tile
// throws, as a failing process would.
bool faultInjectedHere();

}  // namespace cluster
}  // namespace lobe
