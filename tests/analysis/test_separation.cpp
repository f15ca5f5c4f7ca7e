// The separation score (analysis/separation.h) and the assignment search (analysis/assign.h) on
// layers built by hand, where every value follows from the definitions:
//   contrast c = S / Y_beauty; per pair e = min(OA/areaA, OB/areaB) with
//   OA = Σ c_A where only A is above t, plus Σ (c_A − c_B) where both are and A is brighter.
#include "analysis/assign.h"
#include "analysis/separation.h"
#include "core/error.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

namespace lobe {
namespace {

// A 1-D image of `n` pixels: beauty 1 + the highlights, highlights `value` on [lo, hi).
struct Box {
    int lo, hi;
    double value;
};
std::vector<float> boxLayer(int n, const Box& b) {
    std::vector<float> v(size_t(n), 0.0f);
    for (int i = b.lo; i < b.hi; ++i) v[size_t(i)] = float(b.value);
    return v;
}

// A grey rgb layer of luminance `v` per pixel ((v, v, v) has sRGB luminance v).
std::vector<float> grey(const std::vector<float>& v) {
    std::vector<float> out;
    for (float x : v) out.insert(out.end(), {x, x, x});
    return out;
}

// Highlights only (no Lambert) over a grey backdrop of luminance 1: the highlight term alone
// decides the score (visibility, veiling and identity have no matte footprint to measure).
SeparationLayers twoObjects(int n, const Box& a, const Box& b) {
    SeparationLayers l;
    l.width = n;
    l.height = 1;
    l.objects = {"a", "b"};
    l.specular = {grey(boxLayer(n, a)), grey(boxLayer(n, b))};
    l.lambert = {grey(std::vector<float>(size_t(n), 0.0f)),
                 grey(std::vector<float>(size_t(n), 0.0f))};
    l.backdrop = grey(std::vector<float>(size_t(n), 1.0f));
    return l;
}

TEST(Separation, DisjointHighlightsScoreTheDimmerContrast) {
    // A: 0.5 on 10 px → contrast 0.5/1.5; B: 0.6 on 5 px → 0.6/1.6. Disjoint: OA/areaA is A's
    // contrast, OB/areaB B's; e = the smaller.
    const SeparationReport r = measureSeparation(twoObjects(40, {0, 10, 0.5}, {20, 25, 0.6}));
    ASSERT_EQ(r.pairs.size(), 1u);
    EXPECT_NEAR(r.highlight, 0.5 / 1.5, 1e-6);
    EXPECT_NEAR(r.pairs[0].metric.eSum, 0.5 / 1.5, 1e-6);
    EXPECT_EQ(r.pairs[0].metric.areaA, 10);
    EXPECT_EQ(r.pairs[0].metric.areaB, 5);
    EXPECT_NEAR(r.score, 0.5 / 1.5, 1e-6);
    EXPECT_NEAR(r.objects[0].specularShare, 10.0 / 40.0, 1e-12);
    EXPECT_NEAR(r.objects[1].meanSpecularContrast, 0.6 / 1.6, 1e-6);
}

TEST(Separation, OneHighlightInsideTheOtherScoresZero) {
    // Same pixels, A brighter everywhere: every B pixel is covered (OB = 0) → e = 0.
    EXPECT_EQ(measureSeparation(twoObjects(40, {0, 10, 0.5}, {2, 8, 0.3})).score, 0.0);
    // Identical highlights: nothing stands apart.
    EXPECT_EQ(measureSeparation(twoObjects(40, {0, 10, 0.5}, {0, 10, 0.5})).score, 0.0);
}

TEST(Separation, PartialOverlapByHand) {
    // A 0.5 on [0,10), B 0.2 on [5,15). Beauty: 1.5 on [0,5), 1.7 on [5,10), 1.2 on [10,15).
    // OA = 5·0.5/1.5 + 5·(0.5 − 0.2)/1.7; OB = 5·0.2/1.2 (B is dimmer where both are).
    const SeparationReport r = measureSeparation(twoObjects(40, {0, 10, 0.5}, {5, 15, 0.2}));
    const double OA = 5 * 0.5 / 1.5 + 5 * (0.5 - 0.2) / 1.7, OB = 5 * 0.2 / 1.2;
    EXPECT_NEAR(r.pairs[0].metric.OA, OA, 1e-6);
    EXPECT_NEAR(r.pairs[0].metric.OB, OB, 1e-6);
    EXPECT_NEAR(r.score, std::min(OA / 10, OB / 10), 1e-6);
}

TEST(Separation, MovingTheHighlightsApartNeverLowersTheScore) {
    double last = -1.0;
    for (int shift = 0; shift <= 12; ++shift) {
        const double s =
            measureSeparation(twoObjects(40, {0, 10, 0.5}, {shift, shift + 10, 0.4})).score;
        EXPECT_GE(s, last) << "shift " << shift;
        last = s;
    }
    EXPECT_NEAR(last, 0.4 / 1.4, 1e-6);  // apart: B's contrast is the smaller
}

TEST(Separation, BelowTheWeberThresholdAHighlightIsNotSeen) {
    // B lifts its pixels by 1 %: no visible highlight → area 0 → e = 0.
    const SeparationReport r = measureSeparation(twoObjects(40, {0, 10, 0.5}, {20, 30, 0.01}));
    EXPECT_EQ(r.pairs[0].metric.areaB, 0);
    EXPECT_EQ(r.score, 0.0);
    EXPECT_EQ(r.objects[1].specularShare, 0.0);
}

TEST(Separation, ScoreIsExposureInvariantAndTheScorerAgrees) {
    SeparationLayers l = twoObjects(40, {0, 10, 0.5}, {5, 15, 0.2});
    const double s = measureSeparation(l).score;
    std::vector<const float*> spec = {l.specular[0].data(), l.specular[1].data()};
    EXPECT_EQ(SeparationScorer(l).score(spec), s);
    for (auto* layer : {&l.specular[0], &l.specular[1], &l.lambert[0], &l.lambert[1], &l.backdrop})
        for (float& v : *layer) v *= 7.0f;
    EXPECT_NEAR(measureSeparation(l).score, s, 1e-6);
}

TEST(Separation, MergedObjectsScoreAsOne) {
    // Three objects: a, and b split into two halves b1, b2; merged, b is the whole box again.
    SeparationLayers l = twoObjects(40, {0, 10, 0.5}, {20, 30, 0.6});
    SeparationLayers split = l;
    split.objects = {"a", "b1", "b2"};
    split.specular = {l.specular[0], grey(boxLayer(40, {20, 25, 0.6})),
                      grey(boxLayer(40, {25, 30, 0.6}))};
    split.lambert = {l.lambert[0], l.lambert[0], l.lambert[0]};
    const SeparationLayers merged = mergeObjects(split, "b", {"b1", "b2"});
    EXPECT_EQ(merged.objects, (std::vector<std::string>{"a", "b"}));
    EXPECT_EQ(measureSeparation(merged).score, measureSeparation(l).score);
    EXPECT_THROW(mergeObjects(split, "b", {"b1", "c"}), Error);
}

// A translucent grey object "veil" in front of a red object "inner", on a 40-pixel image over a
// grey backdrop (luminance 0.1):
//   veil:  Lambert grey 0.05 on [0,40), depth 1;
//   inner: Lambert red (0.30, 0.03, 0.03) on [10,30), depth 2 (3 when `veilBehind`: the veil then
//          lies behind it there), its own highlight grey 0.3 on [20,25) (or, `tintedHighlight`,
//          the same luminance in its own red);
//   the veil's highlight: "narrow" grey 0.05 on [0,5), away from the inner object, or "broad"
//   grey 1.0 on [10,20) and [25,30): over the inner object, around its highlight.
enum class VeilHighlight { Narrow, Broad };
SeparationLayers veilScene(VeilHighlight h, bool veilBehind = false, bool tintedHighlight = false) {
    const int n = 40;
    SeparationLayers l;
    l.width = n;
    l.height = 1;
    l.objects = {"veil", "inner"};
    l.backdrop = grey(std::vector<float>(n, 0.1f));
    l.lambert = {grey(std::vector<float>(n, 0.05f)), std::vector<float>(3 * n, 0.0f)};
    l.depth = {std::vector<float>(n, 1.0f), std::vector<float>(n, 0.0f)};
    const float red[3] = {0.30f, 0.03f, 0.03f};
    const double redY = 0.2126 * red[0] + 0.7152 * red[1] + 0.0722 * red[2];
    std::vector<float> own(3 * n, 0.0f);
    for (int i = 10; i < 30; ++i) {
        for (int c = 0; c < 3; ++c) l.lambert[1][size_t(3 * i + c)] = red[c];
        l.depth[1][size_t(i)] = 2.0f;
        if (veilBehind) l.depth[0][size_t(i)] = 3.0f;
    }
    for (int i = 20; i < 25; ++i)
        for (int c = 0; c < 3; ++c)
            own[size_t(3 * i + c)] = tintedHighlight ? float(red[c] * 0.3 / redY) : 0.3f;
    std::vector<float> veil(3 * n, 0.0f);
    for (int i = 0; i < n; ++i) {
        const bool on =
            h == VeilHighlight::Narrow ? i < 5 : (i >= 10 && i < 20) || (i >= 25 && i < 30);
        if (on)
            for (int c = 0; c < 3; ++c)
                veil[size_t(3 * i + c)] = h == VeilHighlight::Narrow ? 0.05f : 1.0f;
    }
    l.specular = {veil, own};
    return l;
}

TEST(Separation, AHighlightThatVeilsAnotherObjectScoresLower) {
    const SeparationReport narrow = measureSeparation(veilScene(VeilHighlight::Narrow));
    const SeparationReport broad = measureSeparation(veilScene(VeilHighlight::Broad));
    // The broad highlight stands out more: the highlight term alone prefers it (0.56 vs 0.25).
    EXPECT_GT(broad.highlight, 2.0 * narrow.highlight)
        << broad.highlight << " " << narrow.highlight;
    // ... but it lies over the inner object: veiled, less of the pixel, its red washed out.
    const ObjectVisibility& in = broad.objects[1];
    const ObjectVisibility& inNarrow = narrow.objects[1];
    EXPECT_EQ(inNarrow.veiling, 0.0);
    // W by hand: the inner object's matte weight w is the same on its 20 pixels; on 15 of them the
    // veil's highlight is 1.0 of a pixel luminance 0.1 + 0.05 + Y(red) + 1.0.
    const double redY = 0.2126 * 0.30 + 0.7152 * 0.03 + 0.0722 * 0.03;
    EXPECT_NEAR(in.veiling, 15.0 / 20.0 * 1.0 / (0.15 + redY + 1.0), 1e-6);
    // V by hand: its share Y(red)/Y on the 15 veiled pixels, (Y(red) + 0.3)/Y on its highlight.
    EXPECT_NEAR(in.visibility,
                (15 * redY / (0.15 + redY + 1.0) + 5 * (redY + 0.3) / (0.15 + redY + 0.3)) / 20,
                1e-6);
    EXPECT_NEAR(in.matteVisibility, redY / (0.15 + redY), 1e-6);
    EXPECT_GE(inNarrow.visibility, inNarrow.matteVisibility);
    EXPECT_LT(in.identity, inNarrow.identity);
    EXPECT_LT(in.chroma, inNarrow.chroma);
    EXPECT_LT(broad.score, narrow.score) << broad.score << " " << narrow.score;
}

TEST(Separation, TheSameLightInFrontVeilsBehindItDoesNot) {
    // The same pixels, only the order differs: the veil's highlight in front of the inner object
    // or behind it. Visibility and identity see the same pixels; the veiling term alone differs.
    const SeparationReport front = measureSeparation(veilScene(VeilHighlight::Broad, false));
    const SeparationReport behind = measureSeparation(veilScene(VeilHighlight::Broad, true));
    EXPECT_DOUBLE_EQ(front.highlight, behind.highlight);
    EXPECT_DOUBLE_EQ(front.objects[1].visibility, behind.objects[1].visibility);
    EXPECT_DOUBLE_EQ(front.objects[1].identity, behind.objects[1].identity);
    EXPECT_GT(front.objects[1].veiling, 0.5);
    EXPECT_EQ(behind.objects[1].veiling, 0.0);
    EXPECT_LT(front.score, behind.score);
    // Without depth layers the order is unknown and nothing counts as veiling.
    SeparationLayers noDepth = veilScene(VeilHighlight::Broad);
    noDepth.depth.clear();
    EXPECT_EQ(measureSeparation(noDepth).objects[1].veiling, 0.0);
}

TEST(Separation, AWhiteHighlightThatWashesOutTheColourScoresLower) {
    // The inner object's own highlight at the same luminance, white or in its own red: the
    // highlight term cannot tell them apart, identity can.
    const SeparationReport white =
        measureSeparation(veilScene(VeilHighlight::Narrow, false, false));
    const SeparationReport tinted =
        measureSeparation(veilScene(VeilHighlight::Narrow, false, true));
    EXPECT_NEAR(white.highlight, tinted.highlight, 1e-6);
    EXPECT_TRUE(white.objects[1].chromatic);
    EXPECT_FALSE(white.objects[0].chromatic);  // the grey veil has no colour to keep
    EXPECT_EQ(white.objects[0].identity, 1.0);
    // Its red is mixed with the grey veil and backdrop everywhere (identity below 1 even tinted),
    // and the white highlight takes a quarter of its pixels further towards grey.
    EXPECT_LT(white.objects[1].identity, tinted.objects[1].identity - 0.05);
    EXPECT_LT(white.objects[1].chroma, tinted.objects[1].chroma);
    EXPECT_LT(white.score, tinted.score);
}

TEST(Separation, AnObjectAloneKeepsEverything) {
    // Only the inner object's Lambert, no highlights, a black backdrop: it is the whole of its
    // pixels, nothing veils it and its colour is its own.
    SeparationLayers l = veilScene(VeilHighlight::Narrow);
    std::fill(l.lambert[0].begin(), l.lambert[0].end(), 0.0f);
    std::fill(l.backdrop.begin(), l.backdrop.end(), 0.0f);
    for (auto& s : l.specular) std::fill(s.begin(), s.end(), 0.0f);
    SeparationReport r = measureSeparation(l);
    EXPECT_NEAR(r.objects[1].visibility, 1.0, 1e-6);
    EXPECT_NEAR(r.objects[1].identity, 1.0, 1e-6);
    EXPECT_NEAR(r.objects[1].quality, 1.0, 1e-6);
    // Over a grey backdrop of luminance 0.1 it is Y(red)/(Y(red) + 0.1) of its pixels, and its
    // red is mixed with that grey: identity falls below 1.
    std::fill(l.backdrop.begin(), l.backdrop.end(), 0.1f);
    r = measureSeparation(l);
    const double redY = 0.2126 * 0.30 + 0.7152 * 0.03 + 0.0722 * 0.03;
    EXPECT_NEAR(r.objects[1].visibility, redY / (redY + 0.1), 1e-6);
    EXPECT_NEAR(r.objects[1].matteVisibility, redY / (redY + 0.1), 1e-6);
    EXPECT_EQ(r.objects[1].veiling, 0.0);
    EXPECT_LT(r.objects[1].identity, 0.6);
    EXPECT_GT(r.objects[1].identity, 0.3);
}

// Two objects, three candidates each, on a 40-pixel image with base luminance 1:
//   A: 0 → 0.5 on [0,10); 1 → 0.8 on [10,20); 2 → 0.05 everywhere (broad and dim)
//   B: 0 → 0.5 on [0,10); 1 → 0.5 on [10,20); 2 → 0.6 on [20,30)
// Disjoint pairs score the smaller contrast; the best is A1 + B2: min(0.8/1.8, 0.6/1.6) = 0.375.
AssignmentLayers handLayers() {
    AssignmentLayers l;
    l.scene = twoObjects(40, {0, 0, 0.0}, {0, 0, 0.0});
    l.scene.specular.clear();
    l.candidates = {"c0", "c1", "c2"};
    l.candidateModels = {"m0", "m1", "m2"};
    l.specular = {grey(boxLayer(40, {0, 10, 0.5})),  grey(boxLayer(40, {10, 20, 0.8})),
                  grey(boxLayer(40, {0, 40, 0.05})), grey(boxLayer(40, {0, 10, 0.5})),
                  grey(boxLayer(40, {10, 20, 0.5})), grey(boxLayer(40, {20, 30, 0.6}))};
    return l;
}

TEST(Assign, ExhaustiveSearchFindsTheBestByConstruction) {
    const AssignmentLayers l = handLayers();
    AssignOptions o;
    const AssignResult r = searchAssignments(l, o);
    EXPECT_TRUE(r.exhaustive);
    EXPECT_EQ(r.evaluated, 9u);
    ASSERT_FALSE(r.ranked.empty());
    EXPECT_EQ(r.ranked[0].assignment, (std::vector<int>{1, 2}));
    EXPECT_NEAR(r.ranked[0].score, 0.6 / 1.6, 1e-6);
    EXPECT_EQ(assignmentScore(l, {0, 0}), 0.0);  // the same highlight twice
    EXPECT_EQ(countBetter(l, o, {1, 2}), 0u);
    // (0,0) and (1,1) put one highlight inside the other (score 0); the other 7 score more.
    EXPECT_EQ(assignmentScore(l, {1, 1}), 0.0);
    EXPECT_EQ(countBetter(l, o, {0, 0}), 7u);
}

TEST(Assign, LocalSearchFindsItFromABadStartAndKeepsFixedObjects) {
    const AssignmentLayers l = handLayers();
    AssignOptions o;
    o.exhaustiveLimit = 0;  // force the local search
    o.restarts = 0;
    o.start = {0, 0};
    const AssignResult r = searchAssignments(l, o);
    EXPECT_FALSE(r.exhaustive);
    EXPECT_EQ(r.ranked[0].assignment, (std::vector<int>{1, 2}));
    // A kept at candidate 0: B's best partners are 1 and 2, both at min(1/3, …) = 1/3.
    o.fixed = {0, -1};
    const AssignResult kept = searchAssignments(l, o);
    EXPECT_EQ(kept.ranked[0].assignment[0], 0);
    EXPECT_NEAR(kept.ranked[0].score, 0.5 / 1.5, 1e-6);
    // Excluding candidate 2 for free objects: A1 + B0 = min(0.8/1.8, 0.5/1.5) = 1/3.
    AssignOptions ex;
    ex.allowed = {true, true, false};
    const AssignResult e = searchAssignments(l, ex);
    EXPECT_NEAR(e.ranked[0].score, 0.5 / 1.5, 1e-6);
    for (int c : e.ranked[0].assignment) EXPECT_NE(c, 2);
}

TEST(Assign, DistinctNeverRepeatsAModel) {
    AssignmentLayers l = handLayers();
    // Candidates 0 and 1 are two settings of one model: distinct forbids pairing them too.
    l.candidateModels = {"m0", "m0", "m2"};
    AssignOptions o;
    o.distinct = true;
    o.top = 100;
    const AssignResult r = searchAssignments(l, o);
    ASSERT_FALSE(r.ranked.empty());
    for (const ScoredAssignment& a : r.ranked)
        EXPECT_NE(l.candidateModels[size_t(a.assignment[0])],
                  l.candidateModels[size_t(a.assignment[1])]);
    // Of the 9 assignments, (0,0), (0,1), (1,0), (1,1), (2,2) repeat a model.
    EXPECT_EQ(r.rejected, 5u);
    EXPECT_EQ(r.ranked.size(), 4u);
    // With candidate 2 forbidden for both objects (objectAllowed), only m0 is left: nothing is
    // admissible.
    o.objectAllowed = {{true, true, false}, {true, true, false}};
    const AssignResult none = searchAssignments(l, o);
    EXPECT_TRUE(none.ranked.empty());  // every remaining assignment repeats model m0
    // The local search keeps the rule too.
    AssignOptions local;
    local.distinct = true;
    local.exhaustiveLimit = 0;
    local.start = {0, 0};
    for (const ScoredAssignment& a : searchAssignments(l, local).ranked)
        EXPECT_NE(l.candidateModels[size_t(a.assignment[0])],
                  l.candidateModels[size_t(a.assignment[1])]);
}

TEST(Assign, BoundsRejectAssignmentsThatLoseAnObject) {
    // The veil scene as assignment layers: the veil may take the narrow or the broad highlight.
    const SeparationLayers narrow = veilScene(VeilHighlight::Narrow);
    const SeparationLayers broad = veilScene(VeilHighlight::Broad);
    AssignmentLayers l;
    l.scene = narrow;
    l.scene.specular.clear();
    l.candidates = {"narrow", "broad"};
    l.candidateModels = {"n", "b"};
    l.specular = {narrow.specular[0], broad.specular[0], narrow.specular[1], narrow.specular[1]};
    const SeparationReport input = measureSeparation(narrow);
    AssignOptions o;
    o.fixed = {-1, 0};
    o.minVisibility = {0.8 * input.objects[0].visibility, 0.8 * input.objects[1].visibility};
    o.minChroma = {0.8 * input.objects[0].chroma, 0.8 * input.objects[1].chroma};
    const AssignResult r = searchAssignments(l, o);
    ASSERT_EQ(r.ranked.size(), 1u);
    EXPECT_EQ(r.ranked[0].assignment[0], 0);  // the broad veil loses the inner object
    EXPECT_EQ(r.rejected, 1u);
    EXPECT_TRUE(withinBounds(input, o));
    EXPECT_FALSE(withinBounds(measureSeparation(broad), o));
    // Brightness band: the veil's own light where it shows is 0.05 (Lambert) plus its highlight;
    // the broad highlight adds 1.0 on 15 of its 40 pixels, the narrow one 0.05 on 5: the broad
    // one more than doubles its mean luminance and leaves a band of ×1/2 … ×2.
    const double narrowY = input.objects[0].meanLuminance;
    const double broadY = measureSeparation(broad).objects[0].meanLuminance;
    EXPECT_GT(broadY, 2.0 * narrowY);
    AssignOptions band;
    band.fixed = {-1, 0};
    band.minLuminance = {narrowY / 2.0, 0.0};
    band.maxLuminance = {narrowY * 2.0, 1e9};
    const AssignResult b = searchAssignments(l, band);
    ASSERT_EQ(b.ranked.size(), 1u);
    EXPECT_EQ(b.ranked[0].assignment[0], 0);  // the broad highlight leaves the band
}

TEST(Assign, SparkleIsSpecksNotBroadHighlights) {
    const int w = 16, h = 16;
    std::vector<float> speck(3 * w * h, 0.0f), blob(3 * w * h, 0.0f);
    for (int c = 0; c < 3; ++c) speck[size_t(3 * (5 * w + 5) + c)] = 1.0f;  // one pixel
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const double r2 = (x - 8) * (x - 8) + (y - 8) * (y - 8);
            for (int c = 0; c < 3; ++c)
                blob[size_t(3 * (y * w + x) + c)] = float(std::exp(-r2 / 8.0));
        }
    EXPECT_EQ(sparkleShare(speck.data(), w, h), 1.0);
    EXPECT_EQ(sparkleShare(blob.data(), w, h), 0.0);
    // Two specks among a faint broad highlight: their share of the light.
    std::vector<float> mixed = blob;
    for (int c = 0; c < 3; ++c) mixed[size_t(3 * (1 * w + 1) + c)] = 2.0f;
    double total = 0.0;
    for (size_t i = 0; i < mixed.size(); i += 3) total += mixed[i];
    EXPECT_NEAR(sparkleShare(mixed.data(), w, h), 2.0 / total, 1e-6);
}

// Glints: specks that change between two seeds' layers, seen against the pixel. Hand-counted.
TEST(Assign, GlintsAreSpecksThatChangeBetweenSeeds) {
    const int w = 32, h = 32;
    const size_t n = size_t(w) * size_t(h);
    const std::vector<double> matte(n, 1.0);
    const auto grey = [&](const std::function<double(int, int)>& f) {
        std::vector<float> v(3 * n);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x)
                for (int c = 0; c < 3; ++c)
                    v[3 * (size_t(y) * w + size_t(x)) + size_t(c)] = float(f(x, y));
        return v;
    };
    const auto inSquare = [](int x, int y) { return x >= 6 && x < 26 && y >= 6 && y < 26; };
    // The same broad highlight at both seeds: nothing glints.
    const std::vector<float> smooth =
        grey([&](int x, int y) { return inSquare(x, y) ? 0.125 : 0.0; });
    EXPECT_EQ(glintShare(smooth.data(), smooth.data(), w, h, matte), 0.0);
    // A faint base (0.1 on 400 pixels, each seen: 0.1 ≥ 2 % of 1.1) with 10 specks of 1 whose
    // places differ between the seeds: 20 of the 400 seen pixels change by ≥ 20 % (|Δ| = 1 against
    // Y = 1 + 0.6) and are specks at one seed (1.1 against neighbours of 0.1) → 5 %.
    const auto speckled = [&](int row0, int row1) {
        return grey([&](int x, int y) {
            if (!inSquare(x, y)) return 0.0;
            const bool speck = (y == row0 || y == row1) && x >= 8 && x < 23 && (x - 8) % 3 == 0;
            return 0.1 + (speck ? 1.0 : 0.0);
        });
    };
    const std::vector<float> a = speckled(10, 20), b = speckled(14, 23);
    EXPECT_NEAR(glintShare(a.data(), b.data(), w, h, matte), 20.0 / 400.0, 1e-12);
    // The same specks against a pixel 10× brighter: seen (0.6 ≥ 2 % of 10.6), but they change it
    // by 1 < 20 % of 10.6: no glint.
    EXPECT_EQ(glintShare(a.data(), b.data(), w, h, std::vector<double>(n, 10.0)), 0.0);
    // Grain of a broad lobe over the whole image: every pixel changes by ±50 % between the seeds,
    // but no pixel stands out of its neighbours (at most 3× them): no glint.
    const std::vector<float> g0 = grey([&](int x, int y) { return (x + y) % 2 ? 1.5 : 0.5; });
    const std::vector<float> g1 = grey([&](int x, int y) { return (x + y) % 2 ? 0.5 : 1.5; });
    EXPECT_EQ(glintShare(g0.data(), g1.data(), w, h, std::vector<double>(n, 0.0)), 0.0);
    // A black layer is never seen.
    const std::vector<float> black(3 * n, 0.0f);
    EXPECT_EQ(glintShare(black.data(), black.data(), w, h, matte), 0.0);
}

// A speckled highlight whose specks are a minority of its light (22 %: the speck rule alone keeps
// it, as it kept Cook–Torrance on rendering 1's skull) but come and go between seeds is not
// offered when the second seed's layers are given; a smooth highlight of the same total light is.
TEST(Assign, GlintingCandidateIsNotOfferedThoughFewSpecks) {
    const int w = 32, h = 32;
    const size_t n = size_t(w) * size_t(h);
    const auto layersAt = [&](int row0, int row1) {
        AssignmentLayers l;
        l.scene.width = w;
        l.scene.height = h;
        l.scene.objects = {"skull"};
        l.scene.lambert = {std::vector<float>(3 * n, 0.0f)};
        l.scene.backdrop.assign(3 * n, 1.0f);
        l.candidates = {"smooth", "glints"};
        l.candidateModels = {"m0", "m1"};
        std::vector<float> smooth(3 * n, 0.0f), glints(3 * n, 0.0f);
        for (int y = 6; y < 26; ++y)
            for (int x = 6; x < 26; ++x) {
                const bool speck = (y == row0 || y == row1) && x >= 8 && x < 23 && (x - 8) % 3 == 0;
                for (int c = 0; c < 3; ++c) {
                    smooth[3 * (size_t(y) * w + size_t(x)) + size_t(c)] = 0.125f;
                    glints[3 * (size_t(y) * w + size_t(x)) + size_t(c)] = speck ? 1.1f : 0.1f;
                }
            }
        l.specular = {smooth, glints};
        return l;
    };
    const AssignmentLayers a = layersAt(10, 20), b = layersAt(14, 23);
    double total[2] = {0.0, 0.0};
    for (int c = 0; c < 2; ++c)
        for (size_t i = 0; i < 3 * n; i += 3) total[c] += a.layer(0, c)[i];
    EXPECT_NEAR(total[0], total[1], 1e-3);  // the same light, 50 in both
    EXPECT_NEAR(sparkleShare(a.layer(0, 1).data(), w, h), 11.0 / 50.0, 1e-6);
    // The speck rule alone (one seed) keeps both.
    AssignOptions oneSeed;
    EXPECT_TRUE(excludeSparkle(a, {true, true}, oneSeed).empty());
    // With the second seed the glinting one is not offered; the smooth one stays.
    AssignOptions twoSeeds;
    const std::vector<std::string> notes = excludeSparkle(a, {true, true}, twoSeeds, &b);
    ASSERT_EQ(notes.size(), 1u);
    EXPECT_NE(notes[0].find("skull: glints"), std::string::npos) << notes[0];
    EXPECT_EQ(twoSeeds.objectAllowed[0], (std::vector<bool>{true, false}));
    // Where the typical (median) default glints as much — here the only reference — it stays.
    AssignOptions typical;
    EXPECT_TRUE(excludeSparkle(a, {false, true}, typical, &b).empty());
    // Layers of another shape are refused.
    AssignmentLayers other = b;
    other.candidates.push_back("third");
    AssignOptions bad;
    EXPECT_THROW(excludeSparkle(a, {true, true}, bad, &other), Error);
}

// Random layers for k objects and m candidates on a w × h image: each object a coloured Lambert
// disc at its own depth, each candidate a highlight blob of random place, width and strength
// (some broad, some narrow) inside it. Enough overlap that every term of the score matters.
AssignmentLayers randomLayers(int k, int m, int w, int h, uint32_t seed) {
    uint32_t x = seed;
    const auto next = [&x] {
        x = x * 1664525u + 1013904223u;
        return double(x >> 8) / double(1u << 24);
    };
    AssignmentLayers l;
    SeparationLayers& s = l.scene;
    s.width = w;
    s.height = h;
    const size_t n = size_t(w) * size_t(h);
    s.backdrop.assign(3 * n, 0.1f);
    for (int c = 0; c < m; ++c) {
        l.candidates.push_back("c" + std::to_string(c));
        l.candidateModels.push_back("m" + std::to_string(c));
    }
    for (int o = 0; o < k; ++o) {
        s.objects.push_back("o" + std::to_string(o));
        const double cx = next() * w, cy = next() * h, r = 3.0 + next() * w / 3.0;
        const float colour[3] = {float(0.1 + 0.3 * next()), float(0.1 + 0.3 * next()),
                                 float(0.1 + 0.3 * next())};
        std::vector<float> lambert(3 * n, 0.0f), depth(n, 0.0f);
        const float d = float(1.0 + next());
        for (int y = 0; y < h; ++y)
            for (int px = 0; px < w; ++px)
                if (std::hypot(px - cx, y - cy) < r) {
                    const size_t i = size_t(y) * size_t(w) + size_t(px);
                    for (int c = 0; c < 3; ++c) lambert[3 * i + size_t(c)] = colour[c];
                    depth[i] = d;
                }
        s.lambert.push_back(lambert);
        s.depth.push_back(depth);
        for (int c = 0; c < m; ++c) {
            const double hx = cx + (next() - 0.5) * r, hy = cy + (next() - 0.5) * r;
            const double sigma = 0.5 + next() * 4.0, peak = 0.05 + next();
            std::vector<float> spec(3 * n, 0.0f);
            for (int y = 0; y < h; ++y)
                for (int px = 0; px < w; ++px) {
                    const size_t i = size_t(y) * size_t(w) + size_t(px);
                    if (depth[i] == 0.0f) continue;
                    const double r2 = (px - hx) * (px - hx) + (y - hy) * (y - hy);
                    const double v = peak * std::exp(-r2 / (2 * sigma * sigma));
                    if (v > 1e-3)
                        for (int b = 0; b < 3; ++b) spec[3 * i + size_t(b)] = float(v);
                }
            l.specular.push_back(spec);
        }
    }
    return l;
}

// The sums behind a report can be changed pixel by pixel (what the search does when it swaps an
// object's candidate): taking out the pixels of one layer and adding them back with another
// gives the report of the new layers, to rounding.
TEST(Assign, SumsUpdatedByDifferencesEqualAFullPass) {
    const AssignmentLayers l = randomLayers(4, 3, 24, 20, 7);
    for (SeparationMetric metric : {SeparationMetric::Weber, SeparationMetric::Itp}) {
        const SeparationScorer scorer(
            l.scene, metric == SeparationMetric::Itp ? kItpThreshold : kWeberContrast, metric);
        std::vector<const float*> before, after;
        for (int o = 0; o < 4; ++o) before.push_back(l.layer(o, 0).data());
        after = before;
        after[2] = l.layer(2, 1).data();
        const std::vector<uint32_t> all = {0, 1, 2, 3};
        SeparationScorer::Sums sums = scorer.emptySums();
        for (size_t i = 0; i < l.pixelCount(); ++i)
            scorer.addPixel(i, before, all.data(), all.size(), 1.0, sums);
        for (size_t i = 0; i < l.pixelCount(); ++i) {
            scorer.addPixel(i, before, all.data(), all.size(), -1.0, sums);
            scorer.addPixel(i, after, all.data(), all.size(), 1.0, sums);
        }
        const SeparationReport full = scorer.evaluate(after), diff = scorer.report(sums);
        EXPECT_GT(full.score, 0.0);
        EXPECT_NEAR(diff.score, full.score, 1e-12);
        EXPECT_NEAR(diff.highlight, full.highlight, 1e-12);
        for (size_t o = 0; o < 4; ++o) {
            EXPECT_NEAR(diff.objects[o].visibility, full.objects[o].visibility, 1e-12);
            EXPECT_NEAR(diff.objects[o].veiling, full.objects[o].veiling, 1e-12);
            EXPECT_NEAR(diff.objects[o].identity, full.objects[o].identity, 1e-12);
            EXPECT_NEAR(diff.objects[o].chroma, full.objects[o].chroma, 1e-9);
        }
    }
}

// The search scores assignments from sums updated object by object; its ranking must be the one
// of scoring every assignment from scratch.
TEST(Assign, SearchRanksAsScoringEveryAssignmentFromScratch) {
    const int k = 4, m = 4;
    const AssignmentLayers l = randomLayers(k, m, 32, 24, 11);
    std::vector<ScoredAssignment> all;
    for (int a = 0; a < m * m * m * m; ++a) {
        std::vector<int> as = {a % m, a / m % m, a / (m * m) % m, a / (m * m * m)};
        all.push_back({as, assignmentScore(l, as)});
    }
    std::stable_sort(all.begin(), all.end(),
                     [](const auto& x, const auto& y) { return x.score > y.score; });
    AssignOptions o;
    o.top = 5;
    const AssignResult r = searchAssignments(l, o);
    ASSERT_TRUE(r.exhaustive);
    ASSERT_EQ(r.ranked.size(), 5u);
    for (size_t i = 0; i < 5; ++i) {
        EXPECT_EQ(r.ranked[i].score, all[i].score) << i;
        EXPECT_EQ(r.ranked[i].assignment, all[i].assignment) << i;
    }
    // The local search from every start agrees with itself and reaches a local optimum: no
    // single object's change improves its best.
    o.exhaustiveLimit = 0;
    const AssignResult local = searchAssignments(l, o);
    ASSERT_FALSE(local.ranked.empty());
    const std::vector<int> best = local.ranked[0].assignment;
    EXPECT_EQ(local.ranked[0].score, assignmentScore(l, best));
    for (int i = 0; i < k; ++i)
        for (int c = 0; c < m; ++c) {
            std::vector<int> other = best;
            other[size_t(i)] = c;
            EXPECT_LE(assignmentScore(l, other), local.ranked[0].score + 1e-12);
        }
}

// No sparkle in any mode: a candidate whose highlight on an object is specks is not offered,
// whether it is a default model, a --tune variant or a lobe scaled to equal albedo — even where
// it would score best — unless the least specky default specks as much there.
TEST(Assign, SpecklyCandidatesAreNeverChosen) {
    const int w = 20, h = 20;
    const size_t n = size_t(w) * size_t(h);
    AssignmentLayers l;
    l.scene.width = w;
    l.scene.height = h;
    l.scene.objects = {"a", "b"};
    l.scene.lambert = {std::vector<float>(3 * n, 0.0f), std::vector<float>(3 * n, 0.0f)};
    l.scene.backdrop.assign(3 * n, 1.0f);
    // Candidates: 0 broad dim blob (a default), 1 specks bright (a default), 2 the specks scaled
    // ×0.3 (as --equal-albedo would), 3 a broad blob elsewhere (a --tune variant).
    l.candidates = {"broad", "specks", "specks albedo", "broad variant"};
    l.candidateModels = {"m0", "m1", "m1", "m3"};
    const auto blob = [&](double cx, double cy, double peak) {
        std::vector<float> v(3 * n, 0.0f);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const double r2 = (x - cx) * (x - cx) + (y - cy) * (y - cy);
                for (int c = 0; c < 3; ++c)
                    v[3 * (size_t(y) * w + size_t(x)) + size_t(c)] =
                        float(peak * std::exp(-r2 / 8.0));
            }
        return v;
    };
    const auto specks = [&](int first, double peak) {
        std::vector<float> v(3 * n, 0.0f);
        for (int y = first; y < h; y += 4)
            for (int x = first; x < w; x += 4)
                for (int c = 0; c < 3; ++c)
                    v[3 * (size_t(y) * w + size_t(x)) + size_t(c)] = float(peak);
        return v;
    };
    for (int o = 0; o < 2; ++o) {
        const double shift = o == 0 ? 5.0 : 14.0;
        l.specular.push_back(blob(shift, shift, 0.3));
        l.specular.push_back(specks(1 + 2 * o, o == 0 ? 2.0 : 1.5));
        l.specular.push_back(specks(1 + 2 * o, o == 0 ? 0.6 : 0.45));
        l.specular.push_back(blob(19.0 - shift, shift, 0.3));
    }
    // Without the rule the bright specks win: the two objects' specks never share a pixel.
    AssignOptions free;
    const AssignResult unruled = searchAssignments(l, free);
    ASSERT_FALSE(unruled.ranked.empty());
    EXPECT_EQ(unruled.ranked[0].assignment, (std::vector<int>{1, 1}));
    AssignOptions ruled;
    const std::vector<std::string> notes = excludeSparkle(l, {true, true, false, false}, ruled);
    EXPECT_EQ(notes.size(), 4u);  // specks and scaled specks, on both objects
    const AssignResult r = searchAssignments(l, ruled);
    ASSERT_FALSE(r.ranked.empty());
    for (const ScoredAssignment& a : r.ranked)
        for (int c : a.assignment) EXPECT_TRUE(c == 0 || c == 3) << c;
    // Where every default specks (a structure a few pixels across), nothing is taken away.
    AssignOptions tiny;
    EXPECT_TRUE(excludeSparkle(l, {false, true, true, false}, tiny).empty());
    // A kept object is not judged.
    AssignOptions kept;
    kept.fixed = {1, -1};
    EXPECT_EQ(excludeSparkle(l, {true, true, false, false}, kept).size(), 2u);
}

}  // namespace
}  // namespace lobe
