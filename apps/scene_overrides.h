// Command-line overrides of a scene's image and sampling settings, shared by `lobe render`,
// `lobe separation` and `lobe assign`: --width/--height/--spp/--step/--seed/--roulette/--preview.
#pragma once

#include "render/scene_overrides.h"

#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace lobe {

// The settings, their check and how they apply: render/scene_overrides.h; the command line adds
// clipping and shadows.
struct SceneOverrides : RenderOverrides {
    // --clip plane:x,y,z,nx,ny,nz | box:x0,y0,z0,x1,y1,z1 [:invert] [:cap], repeatable: replaces
    // every scene's top-level clip shapes (core/clip.h).
    std::vector<std::string> clip;
    std::string shadows;  // --shadows off|exact|cached: "" keeps the scenes'

    // RenderOverrides' checks and changes, then those of --clip and --shadows.
    void validate() const;
    void apply(SceneSpec& spec) const;
    // Adds the options to a subcommand.
    void addOptions(CLI::App& sub);
};

}  // namespace lobe
