// The analysis of a perception study made with `lobe study` (docs/study.md): paired comparisons
// scaled to JOD units, marker-task accuracy with binomial intervals, attention-check exclusion,
// and the simulated observers the tests and the worked example use.
//
// Scaling (Thurstone's law of comparative judgment, case V: L. L. Thurstone, "A law of
// comparative judgment", Psychological Review 34(4), 1927; the maximum-likelihood form and the
// JOD unit as in M. Pérez-Ortiz & R. K. Mantiuk, "A practical guide and software for analysing
// pairwise comparison experiments", arXiv:1712.03686, 2017):
//   P(i chosen over j) = Φ((q_i − q_j) / σ),   σ = 1 / Φ⁻¹(0.75) ≈ 1.4826,
// so that a difference of 1 JOD means 75 % of the choices go to the better condition. The
// qualities q maximise  L(q) = Σ_{i≠j} w_ij · log Φ((q_i − q_j) / σ)  with q_0 = 0 fixed, where
// w_ij = c_ij (times i was chosen over j) plus the prior below. L is concave (log Φ is), so
// Newton's method with a backtracking line search finds the maximum.
//
// Prior (ours, weak): a pair compared only one way — every observer chose the same side, so the
// ML difference is infinite — gets half a pseudo-choice each way, w_ij = c_ij + ½ and
// w_ji = c_ji + ½ (the log-likelihood of one extra observer split evenly; it pulls that pair's
// difference towards 0 by the weight of one answer out of c_ij + c_ji + 1). Pairs with choices
// both ways get no prior, so their estimate is the plain ML one. (pwcmp, the software of
// Pérez-Ortiz & Mantiuk, uses a different, distance-based prior; this one is the simplest that
// keeps every estimate finite.)
//
// Confidence intervals: percentile bootstrap over observers (B. Efron & R. Tibshirani, "An
// Introduction to the Bootstrap", 1993, ch. 13): observers resampled with replacement, the counts
// summed and scaled again; the interval holds the middle `level` of the B estimates. The random
// draws come from core/rng.h seeded with `seed`, so the same answers give the same interval.
//
// Binomial intervals: Wilson score interval (E. B. Wilson, "Probable inference, the law of
// succession, and statistical inference", JASA 22(158), 1927):
//   centre = (p̂ + z²/2n) / (1 + z²/n),  half-width = z·√(p̂(1−p̂)/n + z²/4n²) / (1 + z²/n),
// z = Φ⁻¹(1 − (1−level)/2).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace lobe {

// The standard normal distribution function Φ (through std::erfc) and its inverse (Newton's
// method on Φ from a bisection bracket; accurate to a few ulp). normalQuantile throws lobe::Error
// outside (0, 1).
double normalCdf(double x);
double normalQuantile(double p);
// σ of the JOD scale: 1 / Φ⁻¹(0.75).
double jodSigma();

// Choices between n conditions: count(i, j) = times condition i was chosen over condition j.
struct PairCounts {
    int n = 0;
    std::vector<double> c;  // row-major n × n
    explicit PairCounts(int conditions = 0)
        : n(conditions), c(size_t(conditions) * size_t(conditions), 0.0) {}
    double& at(int i, int j) { return c[size_t(i) * size_t(n) + size_t(j)]; }
    double at(int i, int j) const { return c[size_t(i) * size_t(n) + size_t(j)]; }
    PairCounts& operator+=(const PairCounts& o);
};

// The weights w_ij the likelihood uses: the counts plus the unanimous-pair prior above.
PairCounts withPrior(const PairCounts& counts, double priorCount = 0.5);
// L(w; q) as above for weights `w` (no prior added here); `gradient` (when not null) receives
// ∂L/∂q_k for every k (including k = 0).
double jodLogLikelihood(const PairCounts& w, const std::vector<double>& q,
                        std::vector<double>* gradient = nullptr);
// The ML qualities in JOD with q_0 = 0 for `counts` (the prior added). Throws lobe::Error when
// the conditions compared do not form one connected set (the scale would not be defined).
std::vector<double> scaleJod(const PairCounts& counts, double priorCount = 0.5);

struct JodScale {
    std::vector<double> q, low, high;  // estimate and bootstrap interval per condition
    double level = 0.95;
    int samples = 0;
};
// scaleJod of the summed counts, with percentile-bootstrap intervals over the observers.
JodScale scaleJodWithIntervals(const std::vector<PairCounts>& observers, int bootstrapSamples,
                               uint64_t seed, double level = 0.95, double priorCount = 0.5);

struct Proportion {
    int successes = 0, trials = 0;
    double p = 0.0, low = 0.0, high = 1.0;  // trials == 0: p = 0, [0, 1]
};
Proportion wilsonInterval(int successes, int trials, double level = 0.95);

// --- Answers of a study (the JSON the page writes, format "lobe-study-answers-1") -----------

struct StudyAnswers {
    std::string path;         // where it was read from (for messages)
    std::string study;        // the study's fingerprint (all files of one analysis share it)
    std::string participant;  // as entered (or generated) on the page
    std::vector<std::string> conditions;
    struct Pair {
        int a = 0, b = 0;  // the two conditions (indices into `conditions`)
        int chosen = 0;    // a or b
    };
    struct Marker {
        int condition = 0;
        std::string object;  // where the marker was (the right answer)
        std::string answer;
    };
    struct Attention {
        std::string instructed, answer;  // passed when equal
    };
    std::vector<Pair> pairs;
    std::vector<Marker> markers;
    std::vector<Attention> attention;
    int trials() const { return int(pairs.size() + markers.size() + attention.size()); }
    int failedChecks() const;
};
// Parses one answers file's text; throws lobe::Error naming `path` and the key on a bad file.
StudyAnswers parseStudyAnswers(const std::string& text, const std::string& path);

struct StudyAnalysis {
    std::vector<std::string> conditions;
    std::vector<std::string> included;       // participants analysed
    std::vector<std::string> excluded;       // "participant (file): failed k of n attention checks"
    int pairTrials = 0;                      // of the included observers
    JodScale jod;                            // empty q when the study had no pair trials
    std::vector<Proportion> markerAccuracy;  // per condition (trials 0 when none)
};
struct StudyAnalysisOptions {
    int bootstrapSamples = 2000;
    uint64_t seed = 1;
    double level = 0.95;
    int maxFailedChecks = 0;  // a participant failing more is excluded
    double priorCount = 0.5;
};
// Checks that the files belong to one study (same fingerprint and conditions; throws lobe::Error
// naming the file otherwise), excludes participants failing attention checks and analyses the rest.
StudyAnalysis analyseStudy(const std::vector<StudyAnswers>& answers,
                           const StudyAnalysisOptions& options = {});

// --- Stimuli -------------------------------------------------------------------------------

// Where the marker task puts its marker for `object`: the pixel where that object's highlight is
// brightest among the pixels where it is the highlight — its specular luminance at least
// `minShare` of all objects' specular luminance there — both summed over the 3×3 neighbourhood
// (one noisy sample at 1 spp does not decide), at least `border` pixels from the image's edge so
// the marker is seen whole. `specular[o]` is object o's specular luminance, row-major
// width × height. found = false when the object's highlight dominates nowhere.
struct MarkerSpot {
    bool found = false;
    int x = 0, y = 0;
    double share = 0.0;  // its share of the specular luminance there
};
MarkerSpot highlightMarker(const std::vector<std::vector<float>>& specular, int width, int height,
                           int object, double minShare = 0.75, int border = 4);

// --- Simulated observers (tests, docs/study.md's worked example) ----------------------------

// A simulated observer's model: quality q (JOD) per condition, the probability of naming the right
// object at a marker per condition, and the probability of passing each attention check.
struct SimulatedObserverModel {
    std::vector<double> jod;
    std::vector<double> markerAccuracy;
    double attentionPass = 1.0;
};
// Answers every trial of `trials` (the study.json trial list: {"kind":"pair","a","b"} /
// {"kind":"marker","condition","object","options"} / {"kind":"attention","instructed"}) for
// observer `observer`: pair choices drawn from the Thurstone model above, marker answers right
// with markerAccuracy (else a wrong option uniformly), attention checks passed with attentionPass.
// Returns the answers file's text (the page's format). Deterministic in (seed, observer).
// `participant`: the id written ("" : "sim-<observer>").
std::string simulateStudyAnswers(const std::string& studyJson, const SimulatedObserverModel& model,
                                 int observer, uint64_t seed, const std::string& participant = "");

}  // namespace lobe
