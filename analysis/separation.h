// The separation score of a rendering: can a viewer tell the objects apart? docs/separation.md
// defines it and argues each choice; in short, for objects o of one rendering with per-object
// passes (render/aov.h) in display-linear sRGB (× the scene's exposure):
//
//  Highlight separation (the paper's idea): the total-flux-overlap metric (eqs. 1.21–1.25,
//  analysis/flux_overlap.h) applied to the objects' specular contributions in the image, as
//  Weber contrast lattices c_o = Y(S_o) / Y(pixel) with threshold t = 0.02 — the Weber fraction
//  of photopic luminance discrimination (Blackwell 1946, "Contrast thresholds of the human eye";
//  Wyszecki & Stiles, Color Science, §7.10). Pair term e_ab = min(OA/areaA, OB/areaB).
//
//  What the viewer keeps of each object, averaged over the pixels where it shows in the matte
//  image (weight w_o = Y(L_o)/Y(Σ L + backdrop): its share of the image without highlights, which
//  no BRDF changes):
//   - visibility V_o: the object's share Y(L_o + S_o)/Y(pixel) of what the pixel shows; v_o =
//     min(1, V_o / V0_o) against the matte image's share V0_o — other objects' highlights laid
//     over it lower it, its own cannot raise it above 1 (they count in the highlight term);
//   - veiling W_o: the share of the pixel that is highlight light of objects in front of it
//     (per-object first-event depth): a veil lowers the contrast of everything behind it,
//     ΔY/(Y + Y_veil) (veiling luminance: Moon & Spencer 1945; transparency perception: Metelli
//     1974), and is seen as a layer over the object, not as part of it;
//   - identity I_o: its colour recognisable where it shows — the CIELAB (CIE 15:2004) chroma of
//     the displayed pixel along the hue of the object's own colour, over that colour's chroma at
//     the matte pixel's luminance, clamped to [0, 1]; i_o = min(1, I_o / I0_o) against the matte
//     image's I0_o (what translucent Lambert layers already mix in is not the assignment's
//     doing); 1 for an achromatic object (own C* < 5 everywhere).
//   q_o = v_o · (1 − W_o) · i_o.
//  Scene score = mean over pairs of e_ab · q_a · q_b: a highlight that stands apart counts only as
//  far as both objects stay seen and recognisable, so raising highlight contrast by veiling an
//  object or washing out its colour scores lower.
//
// A second, independent measure (`--metric itp`): per object a detection map ΔE_ITP (ITU-R
// BT.2124) between the displayed pixel with and without its specular pass, through the display
// model of analysis/colour.h; pair score the flux-overlap metric on those maps with threshold 1
// (about one just-noticeable difference); scene score the mean over pairs.
#pragma once

#include "analysis/flux_overlap.h"
#include "core/rgb_image.h"

#include <cstdint>
#include <string>
#include <vector>

namespace lobe {

constexpr double kWeberContrast = 0.02;
// ΔE_ITP of one just-noticeable difference (ITU-R BT.2124, §2): the threshold of the itp metric.
constexpr double kItpThreshold = 1.0;
// CIELAB chroma below which an object's own colour counts as achromatic (no identity to keep).
constexpr double kAchromaticChroma = 5.0;

enum class SeparationMetric { Weber, Itp };

// Per-object passes of one rendering (width × height each, row-major), display-linear sRGB
// triples (the scene's exposure applied, no tone curve).
struct SeparationLayers {
    int width = 0, height = 0;
    std::vector<std::string> objects;
    std::vector<std::vector<float>> lambert;   // per object, rgb triples
    std::vector<std::vector<float>> specular;  // per object, rgb triples
    // Per object: distance along the ray of its first event (0: not on this pixel's rays). Empty:
    // order unknown, no veiling measured.
    std::vector<std::vector<float>> depth;
    std::vector<float> backdrop;   // rgb triples
    std::string tone = "clip";     // the display's tone curve (core/rgb_image.h)
    double peakLuminance = 100.0;  // cd/m² of display white (1, 1, 1), for ΔE_ITP
    size_t pixelCount() const { return size_t(width) * size_t(height); }
};

struct ObjectVisibility {
    std::string name;
    double visibleShare = 0.0;  // share of the image where (L + S)/Y ≥ kWeberContrast
    double specularShare =
        0.0;  // share of the image where its highlight (S/Y, or ΔE_ITP) ≥ threshold
    double meanSpecularContrast = 0.0;  // over the pixels of specularShare
    double visibility = 0.0;            // V_o
    double matteVisibility = 0.0;       // V0_o
    double veiling = 0.0;               // W_o
    double identity = 1.0;              // I_o
    double matteIdentity = 1.0;         // I0_o
    bool chromatic = false;      // own colour's chroma ≥ kAchromaticChroma somewhere it shows
    double chroma = 0.0;         // mean CIELAB C* of the displayed pixels where it shows (w_o)
    double quality = 0.0;        // q_o = min(1, V/V0) · (1 − W) · min(1, I/I0)
    double meanLuminance = 0.0;  // mean Y of its own light L + S where it shows (w_o)
};

struct PairSeparation {
    int a = 0, b = 0;
    FluxOverlap metric;  // on the contrast (or ΔE_ITP) lattices; metric.eSum is the pair's e
    double score = 0.0;  // Weber: e · q_a · q_b; itp: e
};

struct SeparationReport {
    SeparationMetric metric = SeparationMetric::Weber;
    double threshold = kWeberContrast;
    std::vector<ObjectVisibility> objects;
    std::vector<PairSeparation> pairs;  // (0,1), (0,2), …, in object order
    double highlight = 0.0;             // mean over pairs of e (the highlight term alone)
    double score = 0.0;  // mean over pairs of PairSeparation::score (0 with < 2 objects)
};

// Display-linear rgb of `layers`' beauty: Σ lambert + specular + backdrop.
std::vector<float> beautyOf(const SeparationLayers& layers);

// The layers with `members` summed into one object called `name` (at the first member's place;
// depth: the nearest member's). Throws lobe::Error naming a member that is not an object.
SeparationLayers mergeObjects(const SeparationLayers& layers, const std::string& name,
                              const std::vector<std::string>& members);

// Scores any set of specular layers over fixed Lambert, backdrop and depth layers: what
// measureSeparation does for one rendering and `lobe assign` for every candidate assignment.
// Everything that does not depend on the specular layers is computed once here.
class SeparationScorer {
public:
    // Uses `fixed`'s objects, lambert, depth, backdrop, tone and peak; its specular is ignored.
    explicit SeparationScorer(const SeparationLayers& fixed, double threshold = kWeberContrast,
                              SeparationMetric metric = SeparationMetric::Weber);
    // specular[o]: object o's rgb triples (pixelCount · 3 floats).
    SeparationReport evaluate(const std::vector<const float*>& specular) const;
    double score(const std::vector<const float*>& specular) const {
        return evaluate(specular).score;
    }

    // The report is made from sums over pixels, so a change confined to some pixels (one
    // object's specular layer swapped: `lobe assign`'s search) can be applied as the difference
    // of those pixels' terms instead of a pass over the image. The pair terms use
    //   OA_ab = Σ_{c_a>t} c_a − Σ_{c_a>t, c_b>t} min(c_a, c_b)
    // (overlapContribution summed: where only A's highlight is seen it counts c_a, where both
    // are, c_a − min), so only pairs seen together in a pixel cost anything there.
    struct Sums {
        std::vector<int64_t> area, seen;
        std::vector<int64_t> idCount;     // pixels where the object's own colour is chromatic
        std::vector<double> seenSum;      // Σ c_o over pixels where c_o > t
        std::vector<double> contrastSum;  // Σ c_o over pixels where c_o ≥ t
        std::vector<double> shareSum, veilSum, idSum, idWeight, chromaSum, lumSum;
        std::vector<double> together;  // [a · k + b], a < b: Σ min(c_a, c_b) where both > t
    };
    Sums emptySums() const;
    // Adds (sign +1) or takes away (−1) pixel i's terms. `active`: the objects (ascending) that
    // may have a non-zero weight or specular there; the others must be zero at i.
    void addPixel(size_t i, const std::vector<const float*>& specular, const uint32_t* active,
                  size_t count, double sign, Sums& sums) const;
    // Objects (every field) and, with `pairs`, the pair list; score and highlight always.
    SeparationReport report(const Sums& sums, bool pairs = true) const;
    // Whether an object has a matte weight at pixel i (the objects always active there).
    bool inMatte(size_t i, size_t object) const { return weight_[i * k_ + object] != 0.0f; }
    size_t objectCount() const { return k_; }

private:
    const SeparationLayers& layers_;
    double threshold_;
    SeparationMetric metric_;
    size_t n_ = 0, k_ = 0;
    std::vector<float> base_;         // rgb: Σ lambert + backdrop
    std::vector<float> lambertY_;     // [pixel · k + o]
    std::vector<float> weight_;       // w_o: [pixel · k + o]
    std::vector<float> ownA_, ownB_;  // unit hue of the own colour; 0 where achromatic
    std::vector<float> ownC_;         // own chroma at the matte luminance, 0 where achromatic
    std::vector<double> weightSum_, matteShare_, matteIdentity_;
};

SeparationReport measureSeparation(const SeparationLayers& layers,
                                   double threshold = kWeberContrast,
                                   SeparationMetric metric = SeparationMetric::Weber);

// Parses "weber" or "itp"; throws lobe::Error naming the expected values.
SeparationMetric parseSeparationMetric(const std::string& name);
const char* separationMetricName(SeparationMetric metric);

// CSV (object rows, then pair rows) and Markdown of a report.
std::string separationCsv(const SeparationReport& report, const std::vector<std::string>& objects);
std::string separationMarkdown(const SeparationReport& report,
                               const std::vector<std::string>& objects, const std::string& title);

// The paper's Figures 8–9 on the scene: A's highlight contrast (Weber, S/Y) in red, B's in
// green (yellow where both are above the threshold), each scaled by its own 99th percentile of
// pixels above the threshold.
RgbImage separationMap(const SeparationLayers& layers, int a, int b,
                       double threshold = kWeberContrast);

}  // namespace lobe
