// Overrides of a scene's image and sampling settings — what `lobe render --width/--height/--spp/
// --step/--seed/--roulette/--preview/--pre-integrated/--exact-brdf` and the Python module's
// Scene.render(width=, …) change — and how they apply (a width alone keeps the aspect); the
// command line adds clipping and shadows (SceneOverrides). The options themselves are added in
// apps/options.h.
#pragma once

#include "render/scene_description.h"

#include <string>
#include <vector>

namespace lobe {

struct RenderOverrides {
    int width = 0, height = 0, spp = 0;  // 0: the scene's own
    double step = 0.0;                   // 0: the scene's own
    double roulette = -1.0;              // < 0: the scenes' own
    long long seed = -1;                 // < 0: the scene's own
    bool preview = false;
    bool preIntegrated = false;  // --pre-integrated: on for every scene
    bool exactBrdf = false;  // --exact-brdf: He–Torrance from its series (SceneSpec::exactBrdf)

    // Throws lobe::Error for a value out of range, naming the setting.
    void validate() const;
    void apply(SceneSpec& spec) const;
};

// What `lobe render`, `separation`, `assign`, `cost` and `study` override: the above, then
// clipping and shadows.
struct SceneOverrides : RenderOverrides {
    // --clip plane:x,y,z,nx,ny,nz | box:x0,y0,z0,x1,y1,z1 [:invert] [:cap], repeatable: replaces
    // every scene's top-level clip shapes (core/clip.h).
    std::vector<std::string> clip;
    std::string shadows;  // --shadows off|exact|cached: "" keeps the scenes'

    // RenderOverrides' checks and changes, then those of --clip and --shadows.
    void validate() const;
    void apply(SceneSpec& spec) const;
};

}  // namespace lobe
