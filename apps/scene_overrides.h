// Command-line overrides of a scene's image and sampling settings, shared by `lobe render`,
// `lobe separation` and `lobe assign`: --width/--height/--spp/--step/--seed/--roulette/--preview.
#pragma once

#include "render/scene_description.h"

#include <string>

namespace CLI {
class App;
}

namespace lobe {

struct SceneOverrides {
    int width = 0, height = 0, spp = 0;
    double step = 0.0;
    double roulette = -1.0;  // < 0: the scenes' own
    long long seed = -1;
    bool preview = false;
    bool preIntegrated = false;  // --pre-integrated: on for every scene

    // Adds the options to a subcommand.
    void addOptions(CLI::App& sub);
    // Throws lobe::Error for a value out of range, naming the option.
    void validate() const;
    void apply(SceneSpec& spec) const;
};

}  // namespace lobe
