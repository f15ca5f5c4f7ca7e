// The study analysis (analysis/study.h): Thurstone case V scaling to JOD against closed forms
// and its likelihood's gradient against finite differences; planted qualities recovered from
// simulated observers; Wilson intervals and attention-check exclusion against hand values.
// Reference numbers computed with Python's statistics.NormalDist (an independent Φ⁻¹):
//   σ = 1/NormalDist().inv_cdf(0.75), σ·inv_cdf(0.35), σ·inv_cdf(0.5/11), Wilson for 8 of 10.
#include "analysis/study.h"
#include "core/error.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>

namespace lobe {
namespace {

TEST(StudyNormal, QuantilesMatchAnIndependentImplementation) {
    EXPECT_NEAR(normalQuantile(0.975), 1.9599639845400536, 1e-13);
    EXPECT_NEAR(normalQuantile(0.5), 0.0, 1e-15);
    EXPECT_NEAR(normalQuantile(1e-10), -6.361340902404056, 1e-9);
    EXPECT_NEAR(jodSigma(), 1.482602218505602, 1e-13);
    EXPECT_NEAR(normalCdf(1.0 / jodSigma()), 0.75, 1e-15);  // 1 JOD ↔ 75 %
    EXPECT_THROW(normalQuantile(0.0), Error);
    EXPECT_THROW(normalQuantile(1.0), Error);
}

// Two conditions: L = c01·log Φ(−q1/σ) + c10·log Φ(q1/σ) is maximal where Φ(q1/σ) = c10/(c01+c10),
// so q1 = σ·Φ⁻¹(c10 / (c01 + c10)).
TEST(StudyJod, TwoConditionsHaveTheClosedForm) {
    PairCounts c(2);
    c.at(0, 1) = 13;
    c.at(1, 0) = 7;
    const std::vector<double> q = scaleJod(c);
    EXPECT_EQ(q[0], 0.0);
    EXPECT_NEAR(q[1], -0.5712769783314731, 1e-9);  // σ·Φ⁻¹(0.35)
    // 75 % for condition 1: exactly +1 JOD.
    c.at(0, 1) = 10;
    c.at(1, 0) = 30;
    EXPECT_NEAR(scaleJod(c)[1], 1.0, 1e-9);
}

TEST(StudyJod, UnanimousPairGetsHalfAChoiceEachWay) {
    PairCounts c(2);
    c.at(0, 1) = 10;  // every observer chose condition 0: the plain ML estimate is −∞
    const std::vector<double> q = scaleJod(c);
    EXPECT_TRUE(std::isfinite(q[1]));
    EXPECT_NEAR(q[1], -2.5065193786761255, 1e-9);  // σ·Φ⁻¹(0.5 / 11)
    // Without the prior the likelihood only grows as q1 → −∞.
    EXPECT_GT(jodLogLikelihood(c, {0.0, -20.0}), jodLogLikelihood(c, {0.0, -10.0}));
}

TEST(StudyJod, GradientMatchesFiniteDifferences) {
    PairCounts c(4);
    const double counts[4][4] = {{0, 7, 3, 0}, {5, 0, 9, 2}, {1, 4, 0, 6}, {0, 8, 3, 0}};
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) c.at(i, j) = counts[i][j];
    for (const std::vector<double>& q :
         {std::vector<double>{0.0, 0.3, -1.2, 2.5}, std::vector<double>{0.0, -4.0, 1.0, 0.5},
          std::vector<double>{0.0, 0.0, 0.0, 0.0}}) {
        std::vector<double> grad;
        jodLogLikelihood(c, q, &grad);
        for (size_t k = 0; k < q.size(); ++k) {
            const double h = 1e-6;
            std::vector<double> up = q, down = q;
            up[k] += h;
            down[k] -= h;
            const double numeric = (jodLogLikelihood(c, up) - jodLogLikelihood(c, down)) / (2 * h);
            EXPECT_NEAR(grad[k], numeric, 1e-6 * std::max(1.0, std::fabs(numeric))) << "q_" << k;
        }
    }
    // At the estimate the gradient of the free parameters vanishes.
    const std::vector<double> q = scaleJod(c);
    std::vector<double> grad;
    jodLogLikelihood(withPrior(c), q, &grad);
    for (size_t k = 1; k < q.size(); ++k) EXPECT_NEAR(grad[k], 0.0, 1e-8);
}

TEST(StudyJod, DisconnectedConditionsAreAnError) {
    PairCounts c(4);
    c.at(0, 1) = 3;
    c.at(1, 0) = 2;
    c.at(2, 3) = 4;
    EXPECT_THROW(scaleJod(c), Error);
}

// A study file of `n` conditions where each observer compares every pair `repeats` times.
std::string pairStudy(int n, int repeats) {
    nlohmann::json s;
    s["study"] = "test-study";
    s["conditions"] = nlohmann::json::array();
    for (int i = 0; i < n; ++i) s["conditions"].push_back({{"name", "c" + std::to_string(i)}});
    s["trials"] = nlohmann::json::array();
    for (int r = 0; r < repeats; ++r)
        for (int i = 0; i < n; ++i)
            for (int j = i + 1; j < n; ++j)
                s["trials"].push_back({{"kind", "pair"}, {"a", i}, {"b", j}});
    s["trials"].push_back({{"kind", "attention"}, {"instructed", "left"}});
    s["trials"].push_back({{"kind", "marker"},
                           {"condition", 1},
                           {"object", "skull"},
                           {"options", {"skull", "cortex"}}});
    return s.dump();
}

// Issue 29's acceptance test: a planted difference of 1 JOD between two conditions (a third at
// 0.4) is recovered within ±0.3 JOD in every one of 40 simulated studies of 30 observers, each
// comparing every pair 20 times; the simulations go through the answers files' text, so the
// parser and analyseStudy are the ones `lobe study analyse` runs.
TEST(StudyJod, PlantedOneJodDifferenceIsRecovered) {
    const std::string study = pairStudy(3, 20);
    SimulatedObserverModel model;
    model.jod = {0.0, 1.0, 0.4};
    StudyAnalysisOptions options;
    options.bootstrapSamples = 200;
    int covered = 0, oneOverZero = 0, zeroOneTrials = 0;
    double meanError = 0.0;
    const int studies = 40;
    for (int s = 0; s < studies; ++s) {
        std::vector<StudyAnswers> answers;
        for (int o = 0; o < 30; ++o)
            answers.push_back(
                parseStudyAnswers(simulateStudyAnswers(study, model, o, 1000 + uint64_t(s)),
                                  "sim" + std::to_string(o)));
        for (const StudyAnswers& o : answers)
            for (const auto& p : o.pairs)
                if (p.a == 0 && p.b == 1) {
                    oneOverZero += p.chosen == 1;
                    zeroOneTrials += 1;
                }
        const StudyAnalysis a = analyseStudy(answers, options);
        ASSERT_EQ(a.included.size(), 30u);
        const double d = a.jod.q[1] - a.jod.q[0];
        EXPECT_NEAR(d, 1.0, 0.3) << "simulated study " << s;
        EXPECT_NEAR(a.jod.q[2], 0.4, 0.3) << "simulated study " << s;
        meanError += (d - 1.0) / studies;
        covered += a.jod.low[1] <= 1.0 && 1.0 <= a.jod.high[1];
    }
    EXPECT_NEAR(meanError, 0.0, 0.05);  // no bias beyond the simulations' noise
    EXPECT_GE(covered, 34);             // a 95 % interval holds the truth in most studies
    // The simulated observers follow the JOD definition: 1 JOD apart, 75 % choose the better
    // (24 000 choices: standard error 0.003).
    EXPECT_EQ(zeroOneTrials, 40 * 30 * 20);
    EXPECT_NEAR(double(oneOverZero) / zeroOneTrials, 0.75, 0.01);
}

TEST(StudyJod, BootstrapIsDeterministicAndBracketsTheEstimate) {
    const std::string study = pairStudy(3, 4);
    SimulatedObserverModel model;
    model.jod = {0.0, 1.0, -0.5};
    std::vector<PairCounts> observers;
    for (int o = 0; o < 12; ++o) {
        const StudyAnswers a = parseStudyAnswers(simulateStudyAnswers(study, model, o, 7), "x");
        PairCounts c(3);
        for (const auto& p : a.pairs) c.at(p.chosen, p.chosen == p.a ? p.b : p.a) += 1;
        observers.push_back(c);
    }
    const JodScale a = scaleJodWithIntervals(observers, 300, 42);
    const JodScale b = scaleJodWithIntervals(observers, 300, 42);
    EXPECT_EQ(a.low, b.low);
    EXPECT_EQ(a.high, b.high);
    EXPECT_EQ(a.low[0], 0.0);
    EXPECT_EQ(a.high[0], 0.0);
    for (int i = 1; i < 3; ++i) {
        EXPECT_LE(a.low[size_t(i)], a.q[size_t(i)]);
        EXPECT_GE(a.high[size_t(i)], a.q[size_t(i)]);
        EXPECT_LT(a.low[size_t(i)], a.high[size_t(i)]);
    }
}

TEST(StudyAccuracy, WilsonIntervalMatchesHandValues) {
    const Proportion p = wilsonInterval(8, 10);
    EXPECT_DOUBLE_EQ(p.p, 0.8);
    EXPECT_NEAR(p.low, 0.49016247153664183, 1e-12);
    EXPECT_NEAR(p.high, 0.9433178485456247, 1e-12);
    // All right: the upper end is 1 and the lower n/(n + z²).
    const Proportion all = wilsonInterval(20, 20);
    EXPECT_DOUBLE_EQ(all.high, 1.0);
    EXPECT_NEAR(all.low, 20.0 / (20.0 + 1.9599639845400536 * 1.9599639845400536), 1e-12);
    const Proportion none = wilsonInterval(0, 0);
    EXPECT_EQ(none.low, 0.0);
    EXPECT_EQ(none.high, 1.0);
}

TEST(StudyAnswersFile, AttentionFailuresAreExcludedAndMarkersScored) {
    const std::string study = pairStudy(3, 2);
    SimulatedObserverModel good;
    good.jod = {0.0, 0.5, 1.0};
    good.markerAccuracy = {1.0, 1.0, 1.0};
    SimulatedObserverModel careless = good;
    careless.attentionPass = 0.0;
    careless.markerAccuracy = {0.0, 0.0, 0.0};
    std::vector<StudyAnswers> answers;
    for (int o = 0; o < 3; ++o)
        answers.push_back(parseStudyAnswers(simulateStudyAnswers(study, good, o, 3), "g"));
    answers.push_back(parseStudyAnswers(simulateStudyAnswers(study, careless, 9, 3), "bad.json"));
    const StudyAnalysis a = analyseStudy(answers);
    EXPECT_EQ(a.included.size(), 3u);
    ASSERT_EQ(a.excluded.size(), 1u);
    EXPECT_NE(a.excluded[0].find("sim-9 (bad.json): failed 1 of 1"), std::string::npos)
        << a.excluded[0];
    EXPECT_EQ(a.pairTrials, 3 * 6);
    // The careless observer's wrong marker answer is not counted: 3 of 3 right on condition 1.
    EXPECT_EQ(a.markerAccuracy[1].trials, 3);
    EXPECT_EQ(a.markerAccuracy[1].successes, 3);
    EXPECT_EQ(a.markerAccuracy[0].trials, 0);
}

// Two objects on a 20×12 image: A bright at (6, 5) where B is as bright (no marker there), A
// dimmer but alone at (14, 6); B alone at (3, 1) — too near the edge — and at (10, 8).
TEST(StudyStimuli, MarkerGoesWhereTheObjectsHighlightDominates) {
    const int w = 20, h = 12;
    std::vector<std::vector<float>> s(2, std::vector<float>(size_t(w * h), 0.0f));
    const auto put = [&](int o, int x, int y, float v) { s[size_t(o)][size_t(y * w + x)] = v; };
    put(0, 6, 5, 5.0f);
    put(1, 6, 5, 5.0f);
    put(0, 14, 6, 2.0f);
    put(1, 3, 1, 9.0f);
    put(1, 10, 8, 1.0f);
    const MarkerSpot a = highlightMarker(s, w, h, 0);
    ASSERT_TRUE(a.found);
    EXPECT_EQ(a.x, 13);  // the 3×3 sums tie on the 9 pixels around (14, 6): the first in row order
    EXPECT_EQ(a.y, 5);
    EXPECT_DOUBLE_EQ(a.share, 1.0);
    const MarkerSpot b = highlightMarker(s, w, h, 1);
    ASSERT_TRUE(b.found);
    EXPECT_EQ(b.x, 9);
    EXPECT_EQ(b.y, 7);
    // With a share of 0.5 allowed, the shared spot (sum 10 against 2) wins for A.
    const MarkerSpot shared = highlightMarker(s, w, h, 0, 0.5);
    EXPECT_EQ(shared.x, 5);
    EXPECT_EQ(shared.y, 4);
    EXPECT_DOUBLE_EQ(shared.share, 0.5);
    // An object with no highlight anywhere gets no marker.
    s[0].assign(size_t(w * h), 0.0f);
    EXPECT_FALSE(highlightMarker(s, w, h, 0).found);
}

TEST(StudyAnswersFile, BadFilesNameTheFileAndKey) {
    const auto message = [](const std::string& text) {
        try {
            parseStudyAnswers(text, "p1.json");
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string("(no error)");
    };
    EXPECT_NE(message("{").find("p1.json: not JSON"), std::string::npos);
    EXPECT_NE(message("{\"format\":\"x\"}").find("lobe-study-answers-1"), std::string::npos);
    EXPECT_NE(message(R"({"format":"lobe-study-answers-1","study":"s","participant":"p",
        "conditions":["a","b"],"trials":[{"kind":"pair","a":0,"b":2,"chosen":0}]})")
                  .find("'b' = 2 is not one of the 2 conditions"),
              std::string::npos);
    EXPECT_NE(message(R"({"format":"lobe-study-answers-1","study":"s","participant":"p",
        "conditions":["a","b"],"trials":[{"kind":"pair","a":0,"b":1}]})")
                  .find("missing key 'chosen'"),
              std::string::npos);
    // Two files of different studies.
    StudyAnswers a, b;
    a.study = "one";
    b.study = "two";
    a.path = "a.json";
    b.path = "b.json";
    EXPECT_THROW(analyseStudy({a, b}), Error);
}

}  // namespace
}  // namespace lobe
