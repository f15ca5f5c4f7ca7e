#include "render/scene_overrides.h"

#include "core/error.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

namespace lobe {

namespace {

// "plane:x,y,z,nx,ny,nz" or "box:x0,y0,z0,x1,y1,z1", then optional ":invert" and ":cap".
ClipShape parseClipOption(const std::string& text) {
    const std::string form =
        "--clip: expected plane:x,y,z,nx,ny,nz or box:x0,y0,z0,x1,y1,z1, "
        "optionally followed by :invert and :cap; got '" +
        text + "'";
    std::vector<std::string> parts;
    size_t start = 0;
    for (size_t i = 0; i <= text.size(); ++i)
        if (i == text.size() || text[i] == ':') {
            parts.push_back(text.substr(start, i - start));
            start = i + 1;
        }
    if (parts.size() < 2 || (parts[0] != "plane" && parts[0] != "box")) throw Error(form);
    std::vector<double> v;
    size_t pos = 0;
    const std::string& numbers = parts[1];
    while (pos <= numbers.size()) {
        const size_t comma = std::min(numbers.find(',', pos), numbers.size());
        const std::string item = numbers.substr(pos, comma - pos);
        char* end = nullptr;
        const double x = std::strtod(item.c_str(), &end);
        if (item.empty() || end != item.c_str() + item.size() || !std::isfinite(x))
            throw Error(form);
        v.push_back(x);
        pos = comma + 1;
    }
    if (v.size() != 6) throw Error(form);
    ClipShape s;
    if (parts[0] == "plane") {
        s.kind = ClipShape::Kind::Plane;
        s.point = Vec3(v[0], v[1], v[2]);
        s.normal = Vec3(v[3], v[4], v[5]);
        if (!(s.normal.length() > 0.0))
            throw Error("--clip: the plane's normal must not be zero ('" + text + "')");
        s.normal.normalize();
    } else {
        s.kind = ClipShape::Kind::Box;
        s.lo = Vec3(v[0], v[1], v[2]);
        s.hi = Vec3(v[3], v[4], v[5]);
        if (!(s.lo.x < s.hi.x && s.lo.y < s.hi.y && s.lo.z < s.hi.z))
            throw Error("--clip: the box needs x0 < x1, y0 < y1, z0 < z1 ('" + text + "')");
    }
    for (size_t i = 2; i < parts.size(); ++i) {
        if (parts[i] == "invert")
            s.invert = true;
        else if (parts[i] == "cap")
            s.cap = true;
        else
            throw Error(form);
    }
    return s;
}

}  // namespace

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
    if (exactBrdf) spec.exactBrdf = true;        // … or from its series
    if (roulette >= 0.0) spec.shadingRoulette = roulette;
    if (step > 0.0) spec.volumeStepVoxels = step;
    if (preIntegrated) spec.volumePreIntegrated = true;
    if (seed >= 0) spec.seed = uint64_t(seed);
}

void SceneOverrides::validate() const {
    RenderOverrides::validate();
    if (clip.size() > size_t(kMaxClipShapes))
        throw Error("--clip: at most " + std::to_string(kMaxClipShapes) + " shapes");
    for (const std::string& c : clip) parseClipOption(c);
    if (!shadows.empty() && shadows != "off" && shadows != "exact" && shadows != "cached")
        throw Error("--shadows: expected off, exact or cached, got '" + shadows + "'");
}

void SceneOverrides::apply(SceneSpec& spec) const {
    RenderOverrides::apply(spec);
    if (!shadows.empty()) spec.shadows = shadows;
    if (!clip.empty()) {
        // Replaces the scene's own shapes: the command line's cut wins (and the count stays in
        // the format's limit).
        spec.clip.clear();
        for (const std::string& c : clip) spec.clip.push_back(parseClipOption(c));
    }
}

}  // namespace lobe
