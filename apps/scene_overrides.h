// Command-line overrides of a scene's image and sampling settings, shared by `lobe render`,
// `lobe separation` and `lobe assign`: --width/--height/--spp/--step/--seed/--roulette/--preview.
#pragma once

#include "render/scene_overrides.h"

#include <string>

namespace CLI {
class App;
}

namespace lobe {

// The settings, their check and how they apply: render/scene_overrides.h.
struct SceneOverrides : RenderOverrides {
    // Adds the options to a subcommand.
    void addOptions(CLI::App& sub);
};

}  // namespace lobe
