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
//  - posters in bands of rows (FigureWriter below): an image of more than kBandThresholdPixels
//    pixels (2048²), or any image with --band-rows N, is rendered a band at a time and each band
//    written to every output file as it is finished, so memory follows the band, not the image;
//  - warnings on stderr: a volume object whose transfer function gives opacity 0 to every voxel
//    of its volume (it cannot be seen), and an image in which no pixel is covered by any object.
#pragma once

#include "core/film.h"
#include "core/image_output.h"
#include "core/rgb_image.h"
#include "figure/contact_sheet.h"
#include "render/scene_description.h"

#include <memory>
#include <string>
#include <vector>

namespace lobe {

class RenderScene;
struct Gallery;
struct GalleryOptions;

struct FigureOptions {
    std::string output;      // -o FILE ("" : NAME.png and NAME.exr in --out)
    bool withExr = false;    // --exr: with -o FILE.png/.jpg/.tif, FILE.exr too
    int pngBits = 8;         // --png-bits
    std::string background;  // --background ("" : each scene's own)
    int bandRows = 0;        // --band-rows (0: bands only above kBandThresholdPixels)

    // Throws lobe::Error naming the option: -o with several scenes or with --shard, an
    // unsupported extension or a missing folder, --exr without -o, a bad --background.
    void validate(size_t sceneCount, bool sharded) const;
    // The --background override; throws lobe::Error naming the scene for a transparent
    // background with -o FILE.jpg.
    void apply(SceneSpec& spec) const;
    // The files a scene writes: `base` is NAME in --out (without extension).
    std::vector<std::string> outputPaths(const std::string& base) const;
};

// Posters. Unbanded, a render holds about 73 bytes a pixel at once (the film, the EXR's
// floats, the display image and its 8-bit copy, the coverage): 1.34 GiB at 4096², ~19 GiB at
// 16384² (docs/performance.md, "Posters"). Above kBandThresholdPixels the image is rendered in
// bands of about kBandPixels pixels (whole tiles: a multiple of 16 rows), each written to the
// files as it is finished, so a render holds one band — ~75 MB — whatever the image's size.
// Below it, one band: small renders keep one pass over the tiles (no wait for a band's last
// tile). The pixels are the same either way.
constexpr long long kBandThresholdPixels = 2048LL * 2048;
constexpr long long kBandPixels = 1LL << 20;
// Rows per band for `spec`: `requested` (--band-rows) when > 0, else as above; the image's
// height when it is not banded.
int bandRowsFor(const SceneSpec& spec, int requested);

// Every output of one render, written band by band: the rows of each band, top first, go to
// every file as they come (EXR: linear floats with the passes; PNG/JPEG/TIFF: the display
// encoding), each file under a temporary name opened with the first band; finish() puts all of
// them in place at once. Destroyed unfinished (a failed render, an error), or on SIGINT/SIGTERM,
// it removes them: no partial file under a final name, and no file replaced. With a colour
// background each band's film is composited over it (the film is changed).
struct FigureResult {
    RgbImage display;      // the contact-sheet thumbnail (empty without one)
    std::string written;   // "out/a.png/.exr" or the -o paths
    bool covered = false;  // some pixel has coverage > 0 (when the coverage was rendered)
};
class FigureWriter {
public:
    // `thumbWidth` > 0: keep the display image box-filtered to that width (what
    // makeContactSheet(…, thumbWidth) makes of the whole image, the same floats).
    FigureWriter(const FigureOptions& options, const SceneSpec& spec, const std::string& base,
                 int thumbWidth = 0);
    ~FigureWriter();
    // The next film.height() rows: their film, coverage (when the background needs it, else
    // empty) and pass channels (the same names every band).
    void write(Film& band, const std::vector<float>& alpha, const ImageChannels& extra);
    FigureResult finish();

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// compositeBackground: render/background.h.
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
void writeGalleryFiles(const std::string& base, const Gallery& gallery,
                       const GalleryOptions& options);
// A contact sheet's: lobe:sheet_captions, its cells' captions one a line.
ImageAttributes sheetProvenance(const std::vector<std::string>& captions);

// makeContactSheet (figure/contact_sheet.h) written to `path` (temporary name, then renamed) with
// sheetProvenance.
void writeContactSheet(const std::string& path, const std::vector<ContactSheetEntry>& entries,
                       int columns, int thumbSize);
// This process's command line, arguments quoted for a POSIX shell where needed.
std::string commandLine();

// One line on stderr for every volume object whose transfer function gives opacity 0 to every
// voxel of its volume; returns how many.
int warnInvisibleObjects(const RenderScene& scene);
// One line on stderr when no pixel is covered by any object (`covered` false: every alpha 0
// when the coverage was rendered, otherwise no surface hit and no volume sample composited);
// returns whether it warned.
bool warnIfEmpty(const SceneSpec& spec, bool covered);

}  // namespace lobe
