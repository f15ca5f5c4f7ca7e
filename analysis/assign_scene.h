// What `lobe assign SCENE --out BEST.json` does: chooses each object's BRDF so that the objects'
// highlights stay apart in the rendering — the paper's proposed "adaptive BRDF". One render at a
// reduced size (default 256 wide, 2 spp) gives every object's specular layer for every candidate
// BRDF (render/aov.h); every assignment is then scored from the layers without rendering again
// (analysis/assign.h explains why that is exact). Writes BEST.json (the scene with the chosen
// models; image settings and everything else as in the input, data paths made relative to
// BEST.json's folder) and BEST-assign.md (the ranked table, the scene's own assignment and its
// rank). Objects can be kept (--keep NAME) and models excluded (--exclude MODEL); --tune adds the
// documented parameter variants of every model (analysis/properties.h) as candidates.
#pragma once

#include "render/scene_overrides.h"

#include <string>
#include <vector>

namespace lobe {

struct AssignRequest {
    std::string scene;
    std::string out;
    std::vector<std::string> keep, exclude;
    SceneOverrides overrides;
    bool tune = false;
    bool force = false;
    bool quiet = false;
    bool distinct = false;
    std::string equalAlbedo;      // the albedo at normal incidence as given ("": every lobe as is)
    double keepFraction = 0.8;    // least visibility and chroma against the input's (0: no bound)
    double brightnessBand = 0.0;  // > 1: each object's mean luminance within [1/b, b] × the input's
    std::string metric = "weber";
    int top = 10;
    int threads = 0;
};

// Checks the request (lobe::Error naming the option), renders the layers, searches and writes
// BEST.json and BEST-assign.md (nothing is written when no assignment qualifies).
void assignScene(const AssignRequest& request);

}  // namespace lobe
