// The overhead of `lobe cost` / `lobe render --stats` (RenderOptions::cost, render/render_cost.h):
// the same scene rendered with counting and timing off and on, alternated (off, on, off, on, …)
// in one process so that a shared machine's changing load falls on both alike. Prints each run's
// wall and process CPU seconds and the ratio on/off of the medians; first checks that the images
// are identical bit for bit (counting must not change a pixel).
//
//   lobe_bench_cost [--scene FILE] [--width 128] [--spp 1] [--rounds 5] [--threads 0]
#include "bench_common.h"
#include "render/render_scene.h"
#include "render/scene_file.h"

#include <algorithm>
#include <cstdio>
#include <vector>

using namespace lobe;

namespace {

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace

int main(int argc, char** argv) {
    std::string scenePath = std::string(LOBE_SOURCE_DIR) + "/assets/scenes/paper/rendering-01.json";
    int width = 128, spp = 1, rounds = 5, threads = 0;
    for (int i = 1; i < argc; ++i) {
        bench::Args a(argc, argv, i);
        if (a.flag() == "--scene")
            scenePath = a.text();
        else if (a.flag() == "--width")
            width = a.integer();
        else if (a.flag() == "--spp")
            spp = a.integer();
        else if (a.flag() == "--rounds")
            rounds = a.integer();
        else if (a.flag() == "--threads")
            threads = a.integer();
        else {
            std::fprintf(stderr, "unknown option %s\n", argv[i]);
            return 2;
        }
    }
    SceneSpec spec = loadSceneFile(scenePath);
    spec.height = std::max(1, int(double(width) * spec.height / spec.width + 0.5));
    spec.width = width;
    spec.samplesPerPixel = spp;
    const RenderScene scene(spec, false);
    RenderOptions off;
    off.progress = false;
    off.threads = threads;
    RenderOptions on = off;
    RenderCost cost;
    on.cost = &cost;

    const Film reference = scene.render(off);  // also warms caches
    const Film counted = scene.render(on);
    for (size_t i = 0; i < reference.pixels().size(); ++i)
        for (int k = 0; k < kBandCount; ++k)
            if (reference.pixels()[i][k] != counted.pixels()[i][k]) {
                std::fprintf(stderr, "FAIL: pixel %zu differs with counting on\n", i);
                return 1;
            }

    std::printf("%s, %dx%d, %d spp, %d rounds (off, on alternated)\n", scenePath.c_str(),
                spec.width, spec.height, spec.samplesPerPixel, rounds);
    std::vector<double> wall[2], cpu[2];
    for (int r = 0; r < rounds; ++r)
        for (int k = 0; k < 2; ++k) {
            const bench::Stopwatch sw;
            scene.render(k ? on : off);
            wall[k].push_back(sw.wall());
            cpu[k].push_back(sw.cpu());
            std::printf("  round %d stats %-3s  wall %.3f s  CPU %.3f s\n", r, k ? "on" : "off",
                        wall[k].back(), cpu[k].back());
        }
    std::printf("median: off wall %.3f s CPU %.3f s; on wall %.3f s CPU %.3f s\n", median(wall[0]),
                median(cpu[0]), median(wall[1]), median(cpu[1]));
    std::printf("ratio on/off: wall %.3f, CPU %.3f\n", median(wall[1]) / median(wall[0]),
                median(cpu[1]) / median(cpu[0]));
    std::printf(
        "last on-run: CPU %.3f s = surfaces %.3f + volumes %.3f + shading %.3f + other "
        "%.3f; %lld BRDF evaluations\n",
        cost.cpuSeconds, cost.surfaces, cost.volumes, cost.shading, cost.other,
        cost.brdfEvaluations());
    return 0;
}
