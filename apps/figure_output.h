// What `lobe render` writes for a rendered scene (issue 12, "Figure output"):
//  - where: NAME.png and NAME.exr in --out (the default), or `-o FILE` for a single scene, the
//    format following FILE's extension (.png, .jpg/.jpeg, .tif, .exr), with `--exr` also the
//    EXR beside it (FILE's name with .exr);
//  - integer depth: --png-bits 8 (default) or 16;
//  - the background (render/background.h; scene key "background", --background): with none,
//    an alpha channel A in the EXR and RGBA in PNG/TIFF (JPEG refuses it); with a colour, the
//    objects composited over it by their coverage;
//  - provenance in every EXR header and PNG text chunk (readable with `oiiotool --info -v`):
//      lobe:version          the Lobe version that rendered it
//      lobe:command_line     the command line, arguments quoted for a POSIX shell
//      lobe:scene_file       the scene file's path as given
//      lobe:scene_json       the scene file's text
//      lobe:seed             the seed used (after --seed)
//      lobe:render_settings  size, samples, seed, step, roulette, background after every override
//    Non-ASCII characters are written as JSON escapes \uXXXX (the JSON stays the same JSON), so
//    every value is plain ASCII, as PNG's tEXt chunks require;
//  - warnings on stderr: a volume object whose transfer function gives opacity 0 to every voxel
//    of its volume (it cannot be seen), and an image in which no pixel is covered by any object.
#pragma once

#include "core/film.h"
#include "core/image_output.h"
#include "core/rgb_image.h"
#include "render/scene_description.h"

#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace lobe {

class RenderScene;
struct Gallery;
struct GalleryOptions;

struct FigureOptions {
    std::string output;      // -o FILE ("" : NAME.png and NAME.exr in --out)
    bool withExr = false;    // --exr: with -o FILE.png/.jpg/.tif, FILE.exr too
    int pngBits = 8;         // --png-bits
    std::string background;  // --background ("" : each scene's own)

    // Adds -o, --exr, --png-bits and --background to `lobe render` (-o excludes `outOption`).
    void addOptions(CLI::App& sub, const std::string& outOption = "--out");
    // Throws lobe::Error naming the option: -o with several scenes or with --shard, an
    // unsupported extension or a missing folder, --exr without -o, a bad --background.
    void validate(size_t sceneCount, bool sharded) const;
    // The --background override; throws lobe::Error naming the scene for a transparent
    // background with -o FILE.jpg.
    void apply(SceneSpec& spec) const;
    // The files a scene writes: `base` is NAME in --out (without extension).
    std::vector<std::string> outputPaths(const std::string& base) const;
};

// Every output of one render: composites the background colour into `film` (a colour
// background), writes the files (all or none: temporary names, then renamed) with provenance,
// and returns the display image (for contact sheets) and a description of what was written.
struct FigureResult {
    RgbImage display;
    std::string written;  // "out/a.png/.exr" or the -o paths
};
FigureResult writeFigure(const FigureOptions& options, const SceneSpec& spec,
                         const std::string& base, Film& film, const std::vector<float>& alpha,
                         const ImageChannels& extra);

// Film += (1 − alpha) · colour (the background's linear sRGB in bands, divided by the exposure so
// the display shows it as given). Nothing for other backgrounds.
void compositeBackground(Film& film, const std::vector<float>& alpha, const Background& background,
                         double exposure);
// The display image: film → linear sRGB × exposure, the tone curve applied to the colour before
// premultiplication by alpha (so an edge pixel keeps its hue), premultiplied again.
RgbImage displayImage(const Film& film, const std::vector<float>* alpha, const std::string& tone,
                      double exposure);
// Its second half, on linear sRGB × exposure already converted (from a film or an EXR's R, G, B).
void applyDisplayTone(RgbImage& rgb, const std::vector<float>* alpha, const std::string& tone);

// The provenance attributes listed above.
ImageAttributes provenance(const SceneSpec& spec);
// What every image Lobe writes records, scene or not: Software, lobe:version and
// lobe:command_line, plus `more` (values written as ASCII, as above). provenance() adds the
// scene's keys to it; the BRDF gallery its settings; a contact sheet its captions.
ImageAttributes toolProvenance(const ImageAttributes& more = {});
// The gallery's: lobe:seed and lobe:render_settings (cell, samples, seed, light, --set).
ImageAttributes galleryProvenance(const GalleryOptions& options);
// BASE.exr and BASE.png of a rendered gallery, with galleryProvenance (both written, then both
// put in place). For `lobe gallery` and `lobe demo`.
void writeGalleryFiles(const std::string& base, const Gallery& gallery, const GalleryOptions& options);
// A contact sheet's: lobe:sheet_captions, its cells' captions one a line.
ImageAttributes sheetProvenance(const std::vector<std::string>& captions);
// This process's command line, arguments quoted for a POSIX shell where needed.
std::string commandLine();

// One line on stderr for every volume object whose transfer function gives opacity 0 to every
// voxel of its volume; returns how many.
int warnInvisibleObjects(const RenderScene& scene);
// One line on stderr when no pixel is covered by any object — every alpha 0 when the coverage
// was rendered, otherwise no surface hit and no volume sample composited (`objectsSeen` false);
// returns whether.
bool warnIfEmpty(const SceneSpec& spec, const std::vector<float>& alpha, bool objectsSeen);

}  // namespace lobe
