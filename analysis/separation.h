// The separation score of a rendering: how far the highlights of each pair of objects stay
// apart where both are seen — the paper's total-flux-overlap metric (eqs. 1.21–1.25 as fixed by
// docs/flux-overlap.md, analysis/flux_overlap.h) applied not to lobes on test primitives
// but to the two objects' specular contributions in the rendered image (render/aov.h) — and, per
// object, the share of the image where it is visible. docs/separation.md argues the choices:
//  - lattices in Weber contrast: an object's specular luminance over the pixel's luminance,
//    c = S_o / Y_beauty, so the score does not depend on exposure or light intensity and a
//    highlight counts where it changes what the eye sees, not where its radiance is large;
//  - luminance (CIE Y) rather than bands: the question is whether a viewer can tell the
//    highlights apart, and luminance contrast carries that (colour is discussed in the doc);
//  - linear values before any display transform (a tone curve is a choice of the viewer; the
//    clip of today's PNGs would hide contrast the EXR still holds);
//  - threshold t = 0.02: a highlight is "seen" where it lifts the pixel by 2 % — the Weber
//    fraction of photopic luminance discrimination (about 1–2 %: Blackwell 1946, "Contrast
//    thresholds of the human eye"; Wyszecki & Stiles, Color Science, §7.10).
// Pair score e = min(OA/areaA, OB/areaB) on the two contrast lattices: the mean contrast by which
// each object's highlight stands out where the other's does not. 0 when either object shows no
// highlight above t or when one highlight lies inside the other (flux-overlap.md). The scene's
// score is the mean over all pairs of objects.
#pragma once

#include "analysis/flux_overlap.h"
#include "core/rgb_image.h"

#include <string>
#include <vector>

namespace lobe {

constexpr double kWeberContrast = 0.02;

// Luminance layers of one rendering (width × height each, row-major).
struct SeparationLayers {
    int width = 0, height = 0;
    std::vector<std::string> objects;
    std::vector<std::vector<float>> specular;  // per object: specular luminance
    std::vector<std::vector<float>> total;     // per object: lambert + specular luminance
    std::vector<float> beauty;                 // the pixel's luminance
};

struct ObjectVisibility {
    std::string name;
    double visibleShare = 0.0;   // share of the image where the object's contrast ≥ t
    double specularShare = 0.0;  // share where its specular contrast ≥ t
    double meanSpecularContrast = 0.0;  // over the pixels of specularShare
};

struct PairSeparation {
    int a = 0, b = 0;
    FluxOverlap metric;  // on the contrast lattices; metric.eSum is the pair's score
};

struct SeparationReport {
    double threshold = kWeberContrast;
    std::vector<ObjectVisibility> objects;
    std::vector<PairSeparation> pairs;  // (0,1), (0,2), …, in object order
    double score = 0.0;                 // mean of the pairs' eSum (0 with fewer than 2 objects)
};

// The layers with `members` summed into one object called `name` (at the first member's place):
// to score several objects as one, e.g. the four density maps against the paper's single
// "density maps" object. Throws lobe::Error naming a member that is not an object.
SeparationLayers mergeObjects(const SeparationLayers& layers, const std::string& name,
                              const std::vector<std::string>& members);

// Contrast lattice of one layer: layer / beauty, 0 where the beauty is 0.
std::vector<float> contrastLattice(const std::vector<float>& layer, const std::vector<float>& beauty);

SeparationReport measureSeparation(const SeparationLayers& layers,
                                   double threshold = kWeberContrast);

// The scene score alone from specular luminance layers and the beauty luminance (all
// `count` long): what `lobe assign` evaluates for every candidate assignment.
double separationScore(const std::vector<const float*>& specular, const float* beauty,
                       size_t count, double threshold = kWeberContrast);

// CSV (object rows, then pair rows) and Markdown of a report.
std::string separationCsv(const SeparationReport& report, const std::vector<std::string>& objects);
std::string separationMarkdown(const SeparationReport& report,
                               const std::vector<std::string>& objects, const std::string& title);

// The paper's Figures 8–9 on the scene: A's contrast in red, B's in green (yellow where both are
// above the threshold), each scaled by its own 99th percentile of pixels above the threshold.
RgbImage separationMap(const SeparationLayers& layers, int a, int b,
                       double threshold = kWeberContrast);

}  // namespace lobe
