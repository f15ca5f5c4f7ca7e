// Overrides of a scene's image and sampling settings — what `lobe render --width/--height/--spp/
// --step/--seed/--roulette/--preview/--pre-integrated` and the Python module's
// Scene.render(width=, …) change — and how they apply (a width alone keeps the aspect). The
// command-line options are added in apps/scene_overrides.h.
#pragma once

#include "render/scene_description.h"

namespace lobe {

struct RenderOverrides {
    int width = 0, height = 0, spp = 0;  // 0: the scene's own
    double step = 0.0;                   // 0: the scene's own
    double roulette = -1.0;              // < 0: the scenes' own
    long long seed = -1;                 // < 0: the scene's own
    bool preview = false;
    bool preIntegrated = false;  // --pre-integrated: on for every scene

    // Throws lobe::Error for a value out of range, naming the setting.
    void validate() const;
    void apply(SceneSpec& spec) const;
};

}  // namespace lobe
