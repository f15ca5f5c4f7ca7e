#include "render/scene_overrides.h"

#include "core/error.h"

#include <algorithm>
#include <cmath>

namespace lobe {

void RenderOverrides::validate() const {
    if (width < 0 || width > 16384 || height < 0 || height > 16384)
        throw Error("width and height must be in [1, 16384]");
    if (spp < 0 || spp > 4096) throw Error("spp must be in [1, 4096]");
    // NaN passes CLI11's range checks (every comparison with it is false): refuse it here.
    if (!std::isfinite(step) || step < 0.0 || step > 16.0)
        throw Error("step must be in [0.001, 16] voxels");
    if (!std::isfinite(roulette)) throw Error("roulette must be in [0, 0.5]");
    if (roulette != -1.0 && !(roulette >= 0.0 && roulette <= 0.5))
        throw Error("roulette must be in [0, 0.5]");
    if (seed < -1 || seed > 2147483647LL) throw Error("seed must be in [0, 2147483647]");
}

void RenderOverrides::apply(SceneSpec& spec) const {
    // --preview: 512 pixels wide and one sample per pixel, unless --width / --spp say otherwise.
    const int w = width > 0 ? width : preview && height <= 0 ? 512 : 0;
    if (w > 0 && height <= 0) {
        spec.height = std::max(1, int(std::lround(double(w) * spec.height / spec.width)));
        spec.width = w;
    } else if (w > 0) {
        spec.width = w;
    }
    if (height > 0) spec.height = height;
    if (spp > 0)
        spec.samplesPerPixel = spp;
    else if (preview)
        spec.samplesPerPixel = 1;
    if (preview) spec.previewBrdfTables = true;  // He–Torrance from a table (render/scene.cpp)
    if (roulette >= 0.0) spec.shadingRoulette = roulette;
    if (step > 0.0) spec.volumeStepVoxels = step;
    if (preIntegrated) spec.volumePreIntegrated = true;
    if (seed >= 0) spec.seed = uint64_t(seed);
}

}  // namespace lobe
