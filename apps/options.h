// Options several subcommands share: the scene overrides (render/scene_overrides.h: --width,
// --height, --spp, --step, --seed, --roulette, --preview, --pre-integrated, --clip, --shadows) and
// the figure output of `lobe render` (figure/figure_output.h: -o, --exr, --png-bits, --band-rows,
// --background). What they mean and how they are checked lives with those structs.
#pragma once

#include "figure/figure_output.h"
#include "render/scene_overrides.h"

#include <string>

namespace CLI {
class App;
}

namespace lobe {

void addOverrideOptions(CLI::App& sub, SceneOverrides& overrides);
// -o excludes `outOption`.
void addFigureOptions(CLI::App& sub, FigureOptions& figure, const std::string& outOption = "--out");

}  // namespace lobe
