#include "apps/scene_overrides.h"

#include <CLI/CLI.hpp>

namespace lobe {

void SceneOverrides::addOptions(CLI::App& sub) {
    // Ranges are checked when an option is given (0 / −1 defaults mean "the scene's own").
    sub.add_option("--width", width, "image width (overrides the scenes; keeps the aspect unless "
                                     "--height is given too)")
        ->check(CLI::Range(1, 16384));
    sub.add_option("--height", height, "image height (overrides the scenes)")
        ->check(CLI::Range(1, 16384));
    sub.add_option("--spp", spp, "samples per pixel (overrides the scenes)")->check(CLI::Range(1, 4096));
    sub.add_option("--step", step, "volume step in voxels, 0.001-16 (overrides the scenes)")
        ->check(CLI::Range(0.001, 16.0));
    sub.add_option("--seed", seed, "random seed, 0-2147483647 (overrides the scenes)")
        ->check(CLI::Range(0LL, 2147483647LL));
    sub.add_option("--roulette", roulette,
                   "shading roulette threshold in [0, 0.5] (overrides the scenes; 0 shades every "
                   "volume sample, docs/scene-format.md)");
    sub.add_flag("--pre-integrated", preIntegrated,
                 "classify volume segments by pre-integration (the same accuracy at a coarser "
                 "step; docs/scene-format.md)");
    sub.add_flag("--preview", preview,
                 "quick look: 512 pixels wide, 1 sample per pixel (--width/--spp still win)");
}

}  // namespace lobe
