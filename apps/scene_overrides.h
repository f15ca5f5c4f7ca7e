// Command-line overrides of a scene's image and sampling settings, shared by `lobe render`,
// `lobe separation` and `lobe assign`: --width/--height/--spp/--step/--seed/--roulette/--preview.
#pragma once

#include "render/scene_description.h"

#include <string>
#include <vector>

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
    // --clip plane:x,y,z,nx,ny,nz | box:x0,y0,z0,x1,y1,z1 [:invert] [:cap], repeatable: added
    // to every scene's clip shapes (core/clip.h).
    std::vector<std::string> clip;
    std::string shadows;  // --shadows off|exact|cached: "" keeps the scenes'

    // Adds the options to a subcommand.
    void addOptions(CLI::App& sub);
    // Throws lobe::Error for a value out of range, naming the option.
    void validate() const;
    void apply(SceneSpec& spec) const;
};

}  // namespace lobe
