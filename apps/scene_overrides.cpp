#include "apps/scene_overrides.h"

#include "core/error.h"

#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdlib>

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

void SceneOverrides::addOptions(CLI::App& sub) {
    // Ranges are checked when an option is given (0 / −1 defaults mean "the scene's own").
    sub.add_option("--width", width,
                   "image width (overrides the scenes; keeps the aspect unless "
                   "--height is given too)")
        ->check(CLI::Range(1, 16384));
    sub.add_option("--height", height, "image height (overrides the scenes)")
        ->check(CLI::Range(1, 16384));
    sub.add_option("--spp", spp, "samples per pixel (overrides the scenes)")
        ->check(CLI::Range(1, 4096));
    sub.add_option("--step", step, "volume step in voxels, 0.001-16 (overrides the scenes)")
        ->check(CLI::Range(0.001, 16.0));
    sub.add_option("--seed", seed, "random seed, 0-2147483647 (overrides the scenes)")
        ->check(CLI::Range(0LL, 2147483647LL));
    sub.add_option("--roulette", roulette,
                   "shading roulette threshold in [0, 0.5] (overrides the scenes; 0 shades every "
                   "volume sample, docs/scene-format.md)");
    sub.add_flag("--pre-integrated", preIntegrated,
                 "classify volume segments by pre-integration (the same accuracy at a coarser "
                 "step; docs/scene-format.md)");
    sub.add_option("--clip", clip,
                   "cut every object: plane:x,y,z,nx,ny,nz keeps the side the normal points to, "
                   "box:x0,y0,z0,x1,y1,z1 the inside (world mm); append :invert for the other "
                   "side, :cap to close cut iso-surfaces; repeatable (docs/scene-format.md, "
                   "\"Clip\")");
    sub.add_option(
           "--shadows", shadows,
           "shadows from every light: exact (a shadow ray per light from every shaded "
           "point), cached (every shaded point reads a per-light transmittance grid), or off "
           "(overrides the scenes; docs/scene-format.md, \"Shadows\")")
        ->check(CLI::IsMember({"off", "exact", "cached"}));
    sub.add_flag("--preview", preview,
                 "quick look: 512 pixels wide, 1 sample per pixel (--width/--spp still win)");
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
