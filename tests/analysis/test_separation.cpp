// The separation score (analysis/separation.h) and the assignment search (analysis/assign.h) on
// layers built by hand, where every value follows from the definitions:
//   contrast c = S / Y_beauty; per pair e = min(OA/areaA, OB/areaB) with
//   OA = Σ c_A where only A is above t, plus Σ (c_A − c_B) where both are and A is brighter.
#include "analysis/assign.h"
#include "analysis/separation.h"

#include "core/error.h"

#include <gtest/gtest.h>

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

SeparationLayers twoObjects(int n, const Box& a, const Box& b) {
    SeparationLayers l;
    l.width = n;
    l.height = 1;
    l.objects = {"a", "b"};
    l.specular = {boxLayer(n, a), boxLayer(n, b)};
    l.total = l.specular;
    l.beauty.assign(size_t(n), 1.0f);
    for (int i = 0; i < n; ++i) l.beauty[size_t(i)] += l.specular[0][size_t(i)] + l.specular[1][size_t(i)];
    return l;
}

TEST(Separation, DisjointHighlightsScoreTheDimmerContrast) {
    // A: 0.5 on 10 px → contrast 0.5/1.5; B: 0.6 on 5 px → 0.6/1.6. Disjoint: OA/areaA is A's
    // contrast, OB/areaB B's; e = the smaller.
    const SeparationReport r = measureSeparation(twoObjects(40, {0, 10, 0.5}, {20, 25, 0.6}));
    ASSERT_EQ(r.pairs.size(), 1u);
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
        const double s = measureSeparation(twoObjects(40, {0, 10, 0.5}, {shift, shift + 10, 0.4})).score;
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

TEST(Separation, ScoreIsExposureInvariantAndTheFastPathAgrees) {
    SeparationLayers l = twoObjects(40, {0, 10, 0.5}, {5, 15, 0.2});
    const double s = measureSeparation(l).score;
    std::vector<const float*> spec = {l.specular[0].data(), l.specular[1].data()};
    EXPECT_EQ(separationScore(spec, l.beauty.data(), 40), s);
    for (auto* layer : {&l.specular[0], &l.specular[1], &l.total[0], &l.total[1], &l.beauty})
        for (float& v : *layer) v *= 7.0f;
    EXPECT_NEAR(measureSeparation(l).score, s, 1e-6);
}

TEST(Separation, MergedObjectsScoreAsOne) {
    // Three objects: a, and b split into two halves b1, b2; merged, b is the whole box again.
    SeparationLayers l = twoObjects(40, {0, 10, 0.5}, {20, 30, 0.6});
    SeparationLayers split = l;
    split.objects = {"a", "b1", "b2"};
    split.specular = {l.specular[0], boxLayer(40, {20, 25, 0.6}), boxLayer(40, {25, 30, 0.6})};
    split.total = split.specular;
    const SeparationLayers merged = mergeObjects(split, "b", {"b1", "b2"});
    EXPECT_EQ(merged.objects, (std::vector<std::string>{"a", "b"}));
    EXPECT_EQ(measureSeparation(merged).score, measureSeparation(l).score);
    EXPECT_THROW(mergeObjects(split, "b", {"b1", "c"}), Error);
}

// Two objects, three candidates each, on a 40-pixel image with base luminance 1:
//   A: 0 → 0.5 on [0,10); 1 → 0.8 on [10,20); 2 → 0.05 everywhere (broad and dim)
//   B: 0 → 0.5 on [0,10); 1 → 0.5 on [10,20); 2 → 0.6 on [20,30)
// Disjoint pairs score the smaller contrast; the best is A1 + B2: min(0.8/1.8, 0.6/1.6) = 0.375.
AssignmentLayers handLayers() {
    AssignmentLayers l;
    l.width = 40;
    l.height = 1;
    l.objects = {"a", "b"};
    l.candidates = {"c0", "c1", "c2"};
    l.base.assign(40, 1.0f);
    l.specular = {boxLayer(40, {0, 10, 0.5}),  boxLayer(40, {10, 20, 0.8}),
                  boxLayer(40, {0, 40, 0.05}), boxLayer(40, {0, 10, 0.5}),
                  boxLayer(40, {10, 20, 0.5}), boxLayer(40, {20, 30, 0.6})};
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

}  // namespace
}  // namespace lobe
