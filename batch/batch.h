// `lobe render`'s batch (apps/cmd_render.cpp) for other commands that need rendered images, so
// there is one render path: `lobe study` renders its stimuli through it.
#pragma once

#include "apps/scene_overrides.h"

#include <string>
#include <vector>

namespace lobe {

struct RenderBatchRequest {
    std::vector<std::string> scenes;  // scene files (as `lobe render SCENE…`)
    std::string outDir;
    SceneOverrides overrides;  // --width, --spp, …
    int orbit = 0;             // --orbit N
    std::string aov;           // --aov LIST
    bool quiet = false;
};
// One image rendered: its scene file, title and output name (BASE.png, BASE.exr).
struct RenderedImage {
    std::string scene, title, base;
};
// Renders like `lobe render` (no contact sheets) and returns the images in render order (an
// orbit's frames one after another). Throws lobe::Error as `lobe render` would.
std::vector<RenderedImage> renderBatch(const RenderBatchRequest& request);

}  // namespace lobe
