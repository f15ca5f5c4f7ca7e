#include "apps/options.h"

#include <CLI/CLI.hpp>

namespace lobe {

void addOverrideOptions(CLI::App& sub, SceneOverrides& o) {
    // Ranges are checked when an option is given (0 / −1 defaults mean "the scene's own").
    sub.add_option("--width", o.width,
                   "image width (overrides the scenes; keeps the aspect unless "
                   "--height is given too)")
        ->check(CLI::Range(1, 16384));
    sub.add_option("--height", o.height, "image height (overrides the scenes)")
        ->check(CLI::Range(1, 16384));
    sub.add_option("--spp", o.spp, "samples per pixel (overrides the scenes)")
        ->check(CLI::Range(1, 4096));
    sub.add_option("--step", o.step, "volume step in voxels, 0.001-16 (overrides the scenes)")
        ->check(CLI::Range(0.001, 16.0));
    sub.add_option("--seed", o.seed, "random seed, 0-2147483647 (overrides the scenes)")
        ->check(CLI::Range(0LL, 2147483647LL));
    sub.add_option("--roulette", o.roulette,
                   "shading roulette threshold in [0, 0.5] (overrides the scenes; 0 shades every "
                   "volume sample, docs/scene-format.md)");
    sub.add_flag("--pre-integrated", o.preIntegrated,
                 "classify volume segments by pre-integration (the same accuracy at a coarser "
                 "step; docs/scene-format.md)");
    sub.add_option("--clip", o.clip,
                   "cut every object: plane:x,y,z,nx,ny,nz keeps the side the normal points to, "
                   "box:x0,y0,z0,x1,y1,z1 the inside (world mm); append :invert for the other "
                   "side, :cap to close cut iso-surfaces; repeatable (docs/scene-format.md, "
                   "\"Clip\")");
    sub.add_option(
           "--shadows", o.shadows,
           "shadows from every light: exact (a shadow ray per light from every shaded "
           "point), cached (every shaded point reads a per-light transmittance grid), or off "
           "(overrides the scenes; docs/scene-format.md, \"Shadows\")")
        ->check(CLI::IsMember({"off", "exact", "cached"}));
    sub.add_flag("--preview", o.preview,
                 "quick look: 512 pixels wide, 1 sample per pixel (--width/--spp still win), "
                 "He-Torrance from a table within 2 % (docs/models.md)");
    sub.add_flag("--exact-brdf", o.exactBrdf,
                 "He-Torrance from its series, not from a table (full renders read a table "
                 "within 0.5 %, previews one within 2 %; docs/models.md)");
}

void addFigureOptions(CLI::App& sub, FigureOptions& f, const std::string& outOption) {
    CLI::Option* o = sub.add_option(
        "-o,--output", f.output,
        "a single scene's image file; its extension picks the format (.png, .jpg, .tif, .exr); "
        "only that file is written (add --exr for the EXR beside it)");
    if (CLI::Option* out = sub.get_option_no_throw(outOption)) o->excludes(out);
    sub.add_flag("--exr", f.withExr,
                 "with -o FILE.png/.jpg/.tif: also write FILE.exr (linear floats)");
    sub.add_option("--png-bits", f.pngBits, "bits per channel of PNG (and TIFF) output: 8 or 16")
        ->capture_default_str()
        ->check(CLI::IsMember({8, 16}));
    sub.add_option("--band-rows", f.bandRows,
                   "render and write the image in bands of N rows, holding one band in memory "
                   "(0: only images above 2048 x 2048 pixels, in bands of about 1 M pixels)")
        ->capture_default_str()
        ->check(CLI::Range(0, 1 << 20));
    sub.add_option("--background", f.background,
                   "backdrop (the paper's), none (transparent: alpha in EXR/PNG/TIFF), or a colour "
                   "#rrggbb; overrides the scenes' \"background\" (docs/scene-format.md)");
}

}  // namespace lobe
