#include "cluster/cluster.h"

#include "core/error.h"
#include "core/progress.h"

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>

#ifdef LOBE_HAVE_MPI
#include <mpi.h>
#include <sys/prctl.h>

#include <chrono>
#include <mutex>
#include <thread>
#endif

namespace lobe::cluster {

bool faultInjectedHere() {
    const char* value = std::getenv("LOBE_FAULT_RANK");
    return value && std::string(value) == std::to_string(rank());
}

void everywhere(const std::function<void()>& step) {
    if (!distributed()) {
        step();
        return;
    }
    std::string message;
    bool failed = false;
    try {
        step();
    } catch (const Error& e) {
        failed = true;
        message = e.what();
    }
    const int first = firstFailed(failed);
    if (first < 0) return;
    // A failure on some ranks only (a file missing on one node) names the rank that found it.
    const bool everyRank = countTrue(failed) == size();
    if (first == rank())
        throw CollectiveError(everyRank ? message
                                        : "on rank " + std::to_string(rank()) + " of " +
                                              std::to_string(size()) + " only: " + message,
                              true);
    throw CollectiveError("a scene failed on rank " + std::to_string(first), false);
}

#ifndef LOBE_HAVE_MPI

void start(int*, char***) {
    // Under mpirun, every copy of a lobe without MPI would render everything and write the same
    // files at once.
    const char* size = std::getenv("OMPI_COMM_WORLD_SIZE");
    if (size && std::atoi(size) > 1)
        throw Error(
            "this lobe was built without MPI: run it without mpirun, or install "
            "libopenmpi-dev (scripts/setup.sh) and rebuild");
}
void stop() {}
[[noreturn]] void abort(int code) { std::exit(code); }
int rank() { return 0; }
int size() { return 1; }
int firstFailed(bool failed) { return failed ? 0 : -1; }
bool broadcast(bool value) { return value; }
std::string broadcast(const std::string& value) { return value; }
int countTrue(bool value) { return value ? 1 : 0; }
std::unique_ptr<TileSource> sharedTiles() { return std::make_unique<LocalTileSource>(); }
void gatherTiles(const TileSource&, int, const std::vector<PixelBuffer>&, int) {}

#else

namespace {

bool g_started = false;
int g_rank = 0;
int g_size = 1;
MPI_Comm g_tileComm = MPI_COMM_NULL;  // tile requests only, apart from the gathers

// Tags on g_tileComm: a request {slot, finished tile}, a process's "done with this image", and
// the reply to worker `slot` (kReply + slot). On MPI_COMM_WORLD: the gather.
constexpr int kRequest = 1;
constexpr int kDone = 2;
constexpr int kReply = 100;
constexpr int kGatherHead = 10;
constexpr int kGatherData = 11;
constexpr size_t kChunk = size_t(1) << 30;
constexpr int kPollSleepUs = 500;  // rank 0's tile server between empty polls (see serve())  // MPI
                                   // counts are int: send at most 1 GiB at a time

void check(int code, const char* what) {
    if (code == MPI_SUCCESS) return;
    char text[MPI_MAX_ERROR_STRING];
    int length = 0;
    MPI_Error_string(code, text, &length);
    throw Error(std::string("MPI ") + what + ": " + std::string(text, size_t(length)));
}

// The tiles of one image shared by every process. Rank 0 owns the counter: its own workers take
// from it directly, a server thread takes for the other processes' requests.
class ClusterTileSource : public TileSource {
public:
    void begin(const std::vector<Tile>& tiles, ProgressReporter& progress) override {
        // Row order, not the single process's shuffled tileOrder: the efficiencies docs/cluster.md
        // simulates for hundreds of ranks are for row order, whose cheap last rows fill the end;
        // one-tile hand-out over a shuffled order is not simulated. The ETA under mpirun is
        // therefore the row-order one.
        tiles_ = tiles;  // a copy: gatherTiles needs them after the render
        progress_ = &progress;
        counter_ = 0;
        rendered_.clear();
        pending_.assign(kMaxSlots, 0);
        if (g_rank == 0) server_ = std::thread([this] { serve(); });
    }

    int next(int slot, int finished) override {
        if (finished < 0 && faultInjectedHere())
            throw Error("fault injected on rank " + std::to_string(g_rank) + " (LOBE_FAULT_RANK)");
        if (g_rank == 0) {
            if (finished >= 0) progress_->advance(tilePixels(tiles_[size_t(finished)]));
            return take();
        }
        // Another process: the answer to the request sent when this worker took its previous
        // tile, then at once the request for the tile after (so the round trip to rank 0 is
        // hidden behind the render of this one).
        if (slot < 0 || size_t(slot) >= pending_.size())
            throw Error("MPI tile source: worker slot " + std::to_string(slot) + " out of range");
        if (!pending_[size_t(slot)]) request(slot, finished);
        int index = -1;
        check(MPI_Recv(&index, 1, MPI_INT, 0, kReply + slot, g_tileComm, MPI_STATUS_IGNORE),
              "receive");
        pending_[size_t(slot)] = 0;
        if (index >= 0) {
            record(index);
            request(slot, finished);
            pending_[size_t(slot)] = 1;
        } else if (finished >= 0) {
            request(-1, finished);  // no tile left: only the last one's pixels to count
        }
        return index;
    }

    void end() override {
        if (g_rank == 0) {
            server_.join();
            if (!serverError_.empty()) throw Error(serverError_);
        } else {
            check(MPI_Send(nullptr, 0, MPI_INT, 0, kDone, g_tileComm), "send");
        }
    }

    const std::vector<int>& rendered() const { return rendered_; }

    static constexpr size_t kMaxSlots = 4096;
    const std::vector<Tile>& tiles() const { return tiles_; }

private:
    void request(int slot, int finished) {
        const int message[2] = {slot, finished};
        check(MPI_Send(message, 2, MPI_INT, 0, kRequest, g_tileComm), "send");
    }

    int take() {
        const int i = counter_.fetch_add(1);
        if (i >= int(tiles_.size())) return -1;
        record(i);
        return i;
    }
    void record(int i) {
        std::lock_guard<std::mutex> lock(mutex_);
        rendered_.push_back(i);
    }

    // Rank 0: answers requests until every other process said it is done. A blocking receive
    // in Open MPI spins a core the renderer needs, so it polls, and sleeps 500 µs after a poll
    // that found nothing (timer slack 1 µs, or Linux stretches each sleep by 50 µs). Every poll
    // costs: at 20 µs the polls took a third of the render's CPU on 2 ranks (512² × 8 spp,
    // 14.9 s against 9.8 s in one process), at 500 µs 3.5 % (10.2 s). The wait they add is
    // hidden, as each worker asks for its next tile while it renders one.
    void serve() {
        prctl(PR_SET_TIMERSLACK, 1000UL, 0UL, 0UL, 0UL);
        try {
            int done = 0;
            while (done < g_size - 1) {
                int ready = 0;
                MPI_Status status;
                check(MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, g_tileComm, &ready, &status),
                      "probe");
                if (!ready) {
                    std::this_thread::sleep_for(std::chrono::microseconds(kPollSleepUs));
                    continue;
                }
                if (status.MPI_TAG == kDone) {
                    check(MPI_Recv(nullptr, 0, MPI_INT, status.MPI_SOURCE, kDone, g_tileComm,
                                   MPI_STATUS_IGNORE),
                          "receive");
                    ++done;
                    continue;
                }
                int request[2] = {0, -1};
                check(MPI_Recv(request, 2, MPI_INT, status.MPI_SOURCE, kRequest, g_tileComm,
                               MPI_STATUS_IGNORE),
                      "receive");
                if (request[1] >= 0) progress_->advance(tilePixels(tiles_[size_t(request[1])]));
                if (request[0] < 0) continue;  // a count only, no tile asked for
                const int i = counter_.fetch_add(1);
                const int reply = i < int(tiles_.size()) ? i : -1;
                check(MPI_Send(&reply, 1, MPI_INT, status.MPI_SOURCE, kReply + request[0],
                               g_tileComm),
                      "send");
            }
        } catch (const std::exception& e) {
            serverError_ = e.what();
        }
    }

    std::vector<Tile> tiles_;
    ProgressReporter* progress_ = nullptr;
    std::atomic<int> counter_{0};
    std::mutex mutex_;
    std::vector<int> rendered_;  // tiles this process rendered
    std::vector<char> pending_;  // per worker slot: a request sent and not yet answered
    std::thread server_;
    std::string serverError_;
};

void sendBytes(const unsigned char* data, size_t bytes, int to) {
    for (size_t at = 0; at < bytes; at += kChunk)
        check(MPI_Send(data + at, int(std::min(kChunk, bytes - at)), MPI_BYTE, to, kGatherData,
                       MPI_COMM_WORLD),
              "send");
}

void receiveBytes(unsigned char* data, size_t bytes, int from) {
    for (size_t at = 0; at < bytes; at += kChunk)
        check(MPI_Recv(data + at, int(std::min(kChunk, bytes - at)), MPI_BYTE, from, kGatherData,
                       MPI_COMM_WORLD, MPI_STATUS_IGNORE),
              "receive");
}

}  // namespace

void start(int* argc, char*** argv) {
    if (!std::getenv("OMPI_COMM_WORLD_SIZE")) return;  // not started by mpirun
    int provided = 0;
    check(MPI_Init_thread(argc, argv, MPI_THREAD_MULTIPLE, &provided), "init");
    g_started = true;
    if (provided < MPI_THREAD_MULTIPLE)
        throw Error("this MPI library does not support MPI_THREAD_MULTIPLE, which lobe needs");
    MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
    MPI_Comm_rank(MPI_COMM_WORLD, &g_rank);
    MPI_Comm_size(MPI_COMM_WORLD, &g_size);
    check(MPI_Comm_dup(MPI_COMM_WORLD, &g_tileComm), "communicator");
}

void stop() {
    if (!g_started) return;
    g_started = false;
    MPI_Comm_free(&g_tileComm);
    MPI_Finalize();
}

[[noreturn]] void abort(int code) {
    if (g_started && g_size > 1) MPI_Abort(MPI_COMM_WORLD, code);
    stop();
    std::exit(code);
}

int rank() { return g_rank; }
int size() { return g_size; }

int firstFailed(bool failed) {
    if (g_size == 1) return failed ? 0 : -1;
    const int mine = failed ? g_rank : g_size;
    int lowest = g_size;
    check(MPI_Allreduce(&mine, &lowest, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD), "allreduce");
    return lowest < g_size ? lowest : -1;
}

bool broadcast(bool value) {
    if (g_size == 1) return value;
    int v = value ? 1 : 0;
    check(MPI_Bcast(&v, 1, MPI_INT, 0, MPI_COMM_WORLD), "broadcast");
    return v != 0;
}

std::string broadcast(const std::string& value) {
    if (g_size == 1) return value;
    unsigned long long length = value.size();
    check(MPI_Bcast(&length, 1, MPI_UNSIGNED_LONG_LONG, 0, MPI_COMM_WORLD), "broadcast");
    std::string out = g_rank == 0 ? value : std::string(size_t(length), '\0');
    for (size_t done = 0; done < out.size(); done += kChunk)
        check(MPI_Bcast(out.data() + done, int(std::min(kChunk, out.size() - done)), MPI_CHAR, 0,
                        MPI_COMM_WORLD),
              "broadcast");
    return out;
}

int countTrue(bool value) {
    if (g_size == 1) return value ? 1 : 0;
    int mine = value ? 1 : 0, total = 0;
    check(MPI_Allreduce(&mine, &total, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD), "allreduce");
    return total;
}

std::unique_ptr<TileSource> sharedTiles() {
    if (g_size == 1) return std::make_unique<LocalTileSource>();
    return std::make_unique<ClusterTileSource>();
}

// Each other process sends the indices of its tiles, then their pixels buffer by buffer, tile by
// tile, row by row; rank 0 receives from rank 1, 2, … in turn and copies them into place.
void gatherTiles(const TileSource& source, int width, const std::vector<PixelBuffer>& buffers,
                 int firstRow) {
    if (g_size == 1) return;
    const auto& shared = static_cast<const ClusterTileSource&>(source);
    const std::vector<Tile>& tiles = shared.tiles();
    size_t bytesPerPixel = 0;
    for (const PixelBuffer& b : buffers) bytesPerPixel += b.bytesPerPixel;

    // Visits the (buffer row, packed offset) pairs of the listed tiles in the packing order.
    auto forEachRow = [&](const std::vector<int>& list, auto&& fn) {
        size_t offset = 0;
        for (int i : list) {
            const Tile& t = tiles[size_t(i)];
            for (const PixelBuffer& b : buffers)
                for (int y = t.y0; y < t.y1; ++y) {
                    const size_t bytes = size_t(t.x1 - t.x0) * b.bytesPerPixel;
                    fn(b.data +
                           (size_t(y - firstRow) * size_t(width) + size_t(t.x0)) * b.bytesPerPixel,
                       offset, bytes);
                    offset += bytes;
                }
        }
    };
    auto packedSize = [&](const std::vector<int>& list) {
        size_t pixels = 0;
        for (int i : list) pixels += size_t(tilePixels(tiles[size_t(i)]));
        return pixels * bytesPerPixel;
    };

    if (g_rank != 0) {
        const std::vector<int>& mine = shared.rendered();
        const uint64_t count = mine.size();
        check(MPI_Send(&count, 1, MPI_UINT64_T, 0, kGatherHead, MPI_COMM_WORLD), "send");
        if (count == 0) return;
        check(MPI_Send(mine.data(), int(count), MPI_INT, 0, kGatherHead, MPI_COMM_WORLD), "send");
        std::vector<unsigned char> packed(packedSize(mine));
        forEachRow(mine, [&](const unsigned char* row, size_t offset, size_t bytes) {
            std::memcpy(packed.data() + offset, row, bytes);
        });
        sendBytes(packed.data(), packed.size(), 0);
        return;
    }
    for (int from = 1; from < g_size; ++from) {
        uint64_t count = 0;
        check(
            MPI_Recv(&count, 1, MPI_UINT64_T, from, kGatherHead, MPI_COMM_WORLD, MPI_STATUS_IGNORE),
            "receive");
        if (count == 0) continue;
        if (count > tiles.size())
            throw Error("MPI gather: rank " + std::to_string(from) +
                        " sent more tiles than the image has");
        std::vector<int> theirs(count);
        check(MPI_Recv(theirs.data(), int(count), MPI_INT, from, kGatherHead, MPI_COMM_WORLD,
                       MPI_STATUS_IGNORE),
              "receive");
        for (int i : theirs)
            if (i < 0 || size_t(i) >= tiles.size())
                throw Error("MPI gather: rank " + std::to_string(from) + " sent tile " +
                            std::to_string(i) + " of an image of " + std::to_string(tiles.size()));
        std::vector<unsigned char> packed(packedSize(theirs));
        receiveBytes(packed.data(), packed.size(), from);
        forEachRow(theirs, [&](unsigned char* row, size_t offset, size_t bytes) {
            std::memcpy(row, packed.data() + offset, bytes);
        });
    }
}

#endif

}  // namespace lobe::cluster
