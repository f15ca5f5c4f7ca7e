// A run of scenes (`lobe render`, `lobe merge`, and every command that needs rendered images: `lobe
// study` renders its stimuli through renderBatch, so there is one render path). It owns what a
// batch does around the renderer: every scene read and checked before anything renders (so a
// typo in the 20th file is reported before hours of rendering), each volume loaded once for the
// whole batch, shards (`--shard I/N`: every N-th scene, or a band of rows of one image), orbits
// (turntables sharing one assembled scene), posters rendered and written in bands of rows
// (figure/figure_output.h), the tiles shared among the processes of an mpirun
// (cluster/cluster.h), one progress display over the whole batch with an ETA from the measured
// cost of the work done (batch/batch_eta.h), and a contact sheet per scene group.
#pragma once

#include "figure/figure_output.h"
#include "render/scene_overrides.h"

#include <string>
#include <vector>

namespace lobe {

// What `lobe render` and `lobe merge` are asked (their options, docs in apps/cmd_render.cpp).
struct BatchOptions {
    std::vector<std::string> inputs;  // scene files or folders of them
    std::string listFile;             // --list: a file listing scene files, one per line
    std::string outDir = "out";
    SceneOverrides overrides;
    int threads = 0;
    bool quiet = false;
    bool noContactSheets = false;
    int sheetThumb = 256;
    std::string aov;            // --aov LIST: per-object passes as extra EXR channels
    bool check = false;         // validate every scene, print every error, render nothing
    bool skipExisting = false;  // resume: scenes whose EXR and PNG exist are not rendered again
    bool keepGoing = false;     // a failing scene is reported and the batch goes on
    std::string shard;          // "i/N": render part i of N (array jobs; `lobe merge` joins)
    int orbit = 0;              // --orbit N: each scene as N turntable frames (render/framing.h)
    bool stats = false;         // print CPU time by part and BRDF evaluations per object
    FigureOptions figure;       // -o, --exr, --png-bits, --background (figure/figure_output.h)
};

// One image rendered: its scene file, title and output name (BASE.png, BASE.exr).
struct RenderedImage {
    std::string scene, title, base;
};

// `lobe render`: renders the scenes (or, with `check`, checks them and renders nothing). Throws
// lobe::Error for bad input or a failed scene (after the others with keepGoing), a
// cluster::CollectiveError under mpirun. `rendered`, when given, receives the images written.
void renderScenes(const BatchOptions& options, std::vector<RenderedImage>* rendered = nullptr);

// `lobe merge`: joins what `--shard` renders wrote into the files one unsharded run writes — the
// part files of a sharded image (checked: every part present, all from this scene file and the
// same settings) into NAME.exr and NAME.png, the same floats bit for bit — and writes the
// contact sheets of the batch.
void mergeShards(const BatchOptions& options);

struct RenderBatchRequest {
    std::vector<std::string> scenes;  // scene files (as `lobe render SCENE…`)
    std::string outDir;
    SceneOverrides overrides;  // --width, --spp, …
    int orbit = 0;             // --orbit N
    std::string aov;           // --aov LIST
    bool quiet = false;
};
// Renders like `lobe render` (no contact sheets) and returns the images in render order (an
// orbit's frames one after another). Throws lobe::Error as `lobe render` would.
std::vector<RenderedImage> renderBatch(const RenderBatchRequest& request);

}  // namespace lobe
