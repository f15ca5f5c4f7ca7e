// What a render's tiles cost, and what handing one out across processes costs — the inputs of
// the scaling simulation in docs/cluster.md (scripts/simulate_scaling.py).
//
//   lobe_bench_tiles SCENE [--width W] [--spp S] [--threads T] --csv FILE
//       renders the scene (a width other than the scene's keeps its aspect) and writes one line
//       per tile: x0, y0, x1, y1 and the seconds the worker spent on it;
//   mpirun -n 2 lobe_bench_tiles --message-cost [--tiles N]
//       hands out N tiles through the cluster's tile source (cluster/cluster.h) twice and prints
//       what a tile costs rank 1 beyond its work: with 1 ms of busy work per tile on both ranks
//       (the wait a render sees), and with none on rank 1 (the whole round trip to rank 0,
//       its polling included); then the time of one request and its answer between two
//       spinning processes (MPI_Send + MPI_Recv both ways): what rank 0 spends on a request.
#include "bench/bench_common.h"
#include "cluster/cluster.h"
#include "core/progress.h"
#include "core/tile_scheduler.h"
#include "render/render_scene.h"
#include "render/scene_file.h"

#ifdef LOBE_HAVE_MPI
#include <mpi.h>
#endif

#include <chrono>
#include <cstdio>
#include <fstream>
#include <mutex>
#include <vector>

using namespace lobe;

namespace {

// The local tile source, timing each tile from the moment a worker takes it to the moment the
// same worker asks for the next.
class TimedTiles : public TileSource {
public:
    void begin(const std::vector<Tile>& tiles, ProgressReporter& progress) override {
        tiles_ = tiles;
        seconds_.assign(tiles.size(), 0.0);
        local_.begin(tiles_, progress);
    }
    int next(int slot, int finished) override {
        const double now = bench::wallSeconds();
        std::lock_guard<std::mutex> lock(mutex_);
        if (started_.size() <= size_t(slot)) started_.resize(size_t(slot) + 1, 0.0);
        if (finished >= 0) seconds_[size_t(finished)] = now - started_[size_t(slot)];
        const int i = local_.next(slot, finished);
        started_[size_t(slot)] = now;
        return i;
    }
    void end() override { local_.end(); }

    const std::vector<Tile>& tiles() const { return tiles_; }
    const std::vector<double>& seconds() const { return seconds_; }

private:
    LocalTileSource local_;
    std::vector<Tile> tiles_;
    std::vector<double> seconds_, started_;
    std::mutex mutex_;
};

int tileCosts(const std::string& scenePath, int width, int spp, int threads,
              const std::string& csv) {
    SceneSpec spec = loadSceneFile(scenePath);
    if (width > 0) {
        spec.height = int(double(spec.height) * width / spec.width + 0.5);
        spec.width = width;
    }
    if (spp > 0) spec.samplesPerPixel = spp;
    const RenderScene scene(spec, false);
    TimedTiles timed;
    RenderOptions options;
    options.threads = threads;
    options.progress = false;
    options.tileSource = &timed;
    const bench::Stopwatch clock;
    scene.render(options);
    const double wall = clock.wall(), cpu = clock.cpu();
    std::ofstream out(csv);
    out << "x0,y0,x1,y1,seconds\n";
    double sum = 0.0, most = 0.0;
    for (size_t i = 0; i < timed.tiles().size(); ++i) {
        const Tile& t = timed.tiles()[i];
        out << t.x0 << ',' << t.y0 << ',' << t.x1 << ',' << t.y1 << ',' << timed.seconds()[i]
            << '\n';
        sum += timed.seconds()[i];
        most = std::max(most, timed.seconds()[i]);
    }
    std::printf(
        "%s: %dx%d, %d spp, %zu tiles: %.2f s wall, %.2f CPU s; tile seconds sum %.2f, "
        "mean %.2f ms, max %.2f ms -> %s\n",
        scenePath.c_str(), spec.width, spec.height, spec.samplesPerPixel, timed.tiles().size(),
        wall, cpu, sum, 1e3 * sum / double(timed.tiles().size()), 1e3 * most, csv.c_str());
    return out ? 0 : 1;
}

int messageCost(int tileCount) {
    if (!cluster::distributed()) {
        std::fprintf(stderr, "--message-cost runs under mpirun -n 2 (or more)\n");
        return 1;
    }
    const std::unique_ptr<TileSource> source = cluster::sharedTiles();
    SchedulerOptions options;
    options.threads = 1;
    options.tileSize = 1;
    options.progress = false;
    options.tileSource = source.get();
    for (const bool workOnRank1 : {true, false}) {
        constexpr double kWork = 1e-3;  // seconds of busy work per tile
        const bool work = workOnRank1 || cluster::rank() != 1;
        std::atomic<long> mine{0};
        const bench::Stopwatch clock;
        forEachTile(tileCount, 1, options, [&](const Tile&) {
            ++mine;
            const double until = bench::wallSeconds() + (work ? kWork : 0.0);
            while (bench::wallSeconds() < until) {
            }
        });
        const double wall = clock.wall();
        if (cluster::rank() == 1)
            std::printf(
                "rank 1 of %d, tiles of %s: %ld of %d tiles in %.3f s: %.1f us per tile "
                "beyond its work\n",
                cluster::size(), workOnRank1 ? "1 ms" : "0 ms", mine.load(), tileCount, wall,
                1e6 * (wall / double(mine.load()) - (work ? kWork : 0.0)));
        std::fflush(stdout);
    }
#ifdef LOBE_HAVE_MPI
    MPI_Barrier(MPI_COMM_WORLD);
    const int rounds = 20000;
    int message[2] = {0, 0};
    const bench::Stopwatch clock;
    for (int i = 0; i < rounds && cluster::rank() < 2; ++i) {
        if (cluster::rank() == 1) {
            MPI_Send(message, 2, MPI_INT, 0, 7, MPI_COMM_WORLD);
            MPI_Recv(message, 1, MPI_INT, 0, 8, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        } else {
            MPI_Recv(message, 2, MPI_INT, 1, 7, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
            MPI_Send(message, 1, MPI_INT, 1, 8, MPI_COMM_WORLD);
        }
    }
    if (cluster::rank() == 1)
        std::printf("request and answer between two spinning processes: %.2f us\n",
                    1e6 * clock.wall() / rounds);
#endif
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    cluster::start(&argc, &argv);
    std::string scene, csv = "tile-costs.csv";
    int width = 0, spp = 0, threads = 0, tiles = 4000;
    bool message = false;
    for (int i = 1; i < argc; ++i) {
        bench::Args a(argc, argv, i);
        if (a.flag() == "--width")
            width = a.integer();
        else if (a.flag() == "--spp")
            spp = a.integer();
        else if (a.flag() == "--threads")
            threads = a.integer();
        else if (a.flag() == "--csv")
            csv = a.text();
        else if (a.flag() == "--tiles")
            tiles = a.integer();
        else if (a.flag() == "--message-cost")
            message = true;
        else
            scene = a.flag();
    }
    int code = 0;
    try {
        if (message)
            code = messageCost(tiles);
        else if (scene.empty()) {
            std::fprintf(stderr,
                         "usage: lobe_bench_tiles SCENE [--width W] [--spp S] --csv FILE\n"
                         "       mpirun -n 2 lobe_bench_tiles --message-cost\n");
            code = 1;
        } else
            code = tileCosts(scene, width, spp, threads, csv);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "lobe_bench_tiles: %s\n", e.what());
        code = 1;
    }
    cluster::stop();
    return code;
}
