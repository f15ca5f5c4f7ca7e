#include "analysis/study.h"

#include "core/error.h"
#include "core/rng.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

namespace lobe {

namespace {

constexpr double kSqrt2 = 1.41421356237309504880;
constexpr double kInvSqrt2Pi = 0.39894228040143267794;

double normalPdf(double x) { return kInvSqrt2Pi * std::exp(-0.5 * x * x); }

// log Φ(x) and λ(x) = φ(x)/Φ(x) (d/dx log Φ), stable for very negative x: there Φ(x) underflows,
// and the continued-fraction asymptote Φ(x) ≈ φ(x)/|x| · (1 − 1/x² + 3/x⁴) is used instead
// (Abramowitz & Stegun 26.2.12).
double logNormalCdf(double x) {
    if (x > -30.0) return std::log(normalCdf(x));
    const double x2 = x * x;
    return -0.5 * x2 - std::log(-x) - 0.5 * std::log(2.0 * M_PI) +
           std::log1p(-1.0 / x2 + 3.0 / (x2 * x2));
}
double millsRatio(double x) {
    if (x > -30.0) return normalPdf(x) / normalCdf(x);
    const double x2 = x * x;
    return -x / (1.0 - 1.0 / x2 + 3.0 / (x2 * x2));
}

// Connected components over the pairs compared at least once: every condition must be reached.
bool connected(const PairCounts& counts) {
    if (counts.n <= 1) return true;
    std::vector<bool> seen(size_t(counts.n), false);
    std::vector<int> stack{0};
    seen[0] = true;
    while (!stack.empty()) {
        const int i = stack.back();
        stack.pop_back();
        for (int j = 0; j < counts.n; ++j)
            if (!seen[size_t(j)] && counts.at(i, j) + counts.at(j, i) > 0) {
                seen[size_t(j)] = true;
                stack.push_back(j);
            }
    }
    return std::all_of(seen.begin(), seen.end(), [](bool s) { return s; });
}

// Solves A x = b (m × m, symmetric negative definite here) by Gaussian elimination with partial
// pivoting; the systems are as small as the number of conditions.
std::vector<double> solve(std::vector<double> a, std::vector<double> b) {
    const size_t m = b.size();
    for (size_t k = 0; k < m; ++k) {
        size_t p = k;
        for (size_t r = k + 1; r < m; ++r)
            if (std::fabs(a[r * m + k]) > std::fabs(a[p * m + k])) p = r;
        if (p != k) {
            for (size_t c = 0; c < m; ++c) std::swap(a[k * m + c], a[p * m + c]);
            std::swap(b[k], b[p]);
        }
        const double pivot = a[k * m + k];
        if (pivot == 0.0) throw Error("JOD scaling: singular Hessian (conditions not connected)");
        for (size_t r = k + 1; r < m; ++r) {
            const double f = a[r * m + k] / pivot;
            for (size_t c = k; c < m; ++c) a[r * m + c] -= f * a[k * m + c];
            b[r] -= f * b[k];
        }
    }
    std::vector<double> x(m);
    for (size_t k = m; k-- > 0;) {
        double s = b[k];
        for (size_t c = k + 1; c < m; ++c) s -= a[k * m + c] * x[c];
        x[k] = s / a[k * m + k];
    }
    return x;
}

}  // namespace

double normalCdf(double x) { return 0.5 * std::erfc(-x / kSqrt2); }

double normalQuantile(double p) {
    if (!(p > 0.0 && p < 1.0)) throw Error("normal quantile: probability must be in (0, 1)");
    // Bracket, bisect to a good start, then Newton steps on Φ(x) − p (Φ' = φ > 0, Φ monotone).
    double lo = -40.0, hi = 40.0;
    for (int k = 0; k < 60; ++k) {
        const double mid = 0.5 * (lo + hi);
        (normalCdf(mid) < p ? lo : hi) = mid;
    }
    double x = 0.5 * (lo + hi);
    for (int k = 0; k < 4; ++k) {
        const double f = normalPdf(x);
        if (f <= 0.0) break;
        const double step = (normalCdf(x) - p) / f;
        if (!std::isfinite(step)) break;
        x -= step;
    }
    return x;
}

double jodSigma() { return 1.0 / normalQuantile(0.75); }

PairCounts& PairCounts::operator+=(const PairCounts& o) {
    if (o.n != n) throw Error("pair counts of different sizes");
    for (size_t k = 0; k < c.size(); ++k) c[k] += o.c[k];
    return *this;
}

PairCounts withPrior(const PairCounts& counts, double priorCount) {
    PairCounts w = counts;
    for (int i = 0; i < counts.n; ++i)
        for (int j = i + 1; j < counts.n; ++j) {
            const double a = counts.at(i, j), b = counts.at(j, i);
            if (a + b > 0 && (a == 0 || b == 0)) {
                w.at(i, j) += priorCount;
                w.at(j, i) += priorCount;
            }
        }
    return w;
}

double jodLogLikelihood(const PairCounts& w, const std::vector<double>& q,
                        std::vector<double>* gradient) {
    const double sigma = jodSigma();
    if (gradient) gradient->assign(size_t(w.n), 0.0);
    double sum = 0.0;
    for (int i = 0; i < w.n; ++i)
        for (int j = 0; j < w.n; ++j) {
            const double c = w.at(i, j);
            if (i == j || c == 0.0) continue;
            const double d = (q[size_t(i)] - q[size_t(j)]) / sigma;
            sum += c * logNormalCdf(d);
            if (gradient) {
                const double g = c * millsRatio(d) / sigma;
                (*gradient)[size_t(i)] += g;
                (*gradient)[size_t(j)] -= g;
            }
        }
    return sum;
}

std::vector<double> scaleJod(const PairCounts& counts, double priorCount) {
    const int n = counts.n;
    if (n < 1) throw Error("JOD scaling: no conditions");
    if (!connected(counts))
        throw Error(
            "JOD scaling: the compared pairs do not connect every condition, so their "
            "qualities cannot be put on one scale");
    const PairCounts w = withPrior(counts, priorCount);
    const double sigma = jodSigma();
    std::vector<double> q(size_t(n), 0.0);
    if (n == 1) return q;
    const size_t m = size_t(n - 1);  // free parameters q_1 … q_{n−1}
    double value = jodLogLikelihood(w, q);
    for (int iteration = 0; iteration < 100; ++iteration) {
        std::vector<double> grad;
        jodLogLikelihood(w, q, &grad);
        // Hessian of L: for each term c·log Φ(d), d²/dd² log Φ = −λ(d)(d + λ(d)).
        std::vector<double> h(m * m, 0.0);
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j) {
                const double c = w.at(i, j);
                if (i == j || c == 0.0) continue;
                const double d = (q[size_t(i)] - q[size_t(j)]) / sigma;
                const double lambda = millsRatio(d);
                const double second = -c * lambda * (d + lambda) / (sigma * sigma);
                // ∂²/∂q_i² += second, ∂²/∂q_j² += second, ∂²/∂q_i∂q_j −= second.
                if (i > 0) h[size_t(i - 1) * m + size_t(i - 1)] += second;
                if (j > 0) h[size_t(j - 1) * m + size_t(j - 1)] += second;
                if (i > 0 && j > 0) {
                    h[size_t(i - 1) * m + size_t(j - 1)] -= second;
                    h[size_t(j - 1) * m + size_t(i - 1)] -= second;
                }
            }
        std::vector<double> g(grad.begin() + 1, grad.end());
        double gnorm = 0.0;
        for (double v : g) gnorm = std::max(gnorm, std::fabs(v));
        if (gnorm < 1e-12) break;
        // Newton direction: H·step = −g (H negative definite: an ascent direction).
        std::vector<double> minusG(g);
        for (double& v : minusG) v = -v;
        const std::vector<double> step = solve(h, minusG);
        double t = 1.0;
        bool improved = false;
        for (int k = 0; k < 60; ++k, t *= 0.5) {
            std::vector<double> trial = q;
            for (size_t r = 0; r < m; ++r) trial[r + 1] += t * step[r];
            const double v = jodLogLikelihood(w, trial);
            if (v >= value) {
                improved = v > value || t == 1.0;
                q = trial;
                value = v;
                break;
            }
        }
        if (!improved) break;
    }
    return q;
}

JodScale scaleJodWithIntervals(const std::vector<PairCounts>& observers, int bootstrapSamples,
                               uint64_t seed, double level, double priorCount) {
    if (observers.empty()) throw Error("JOD scaling: no observers");
    if (!(level > 0.0 && level < 1.0)) throw Error("confidence level must be in (0, 1)");
    const int n = observers.front().n;
    PairCounts total(n);
    for (const PairCounts& o : observers) total += o;
    JodScale result;
    result.level = level;
    result.samples = bootstrapSamples;
    result.q = scaleJod(total, priorCount);
    result.low = result.high = result.q;
    if (bootstrapSamples <= 0) return result;
    std::vector<std::vector<double>> draws{size_t(n)};
    Rng rng(mixBits(seed), 0x5eed);
    const uint32_t count = uint32_t(observers.size());
    for (int b = 0; b < bootstrapSamples; ++b) {
        PairCounts sample(n);
        for (uint32_t k = 0; k < count; ++k)
            sample +=
                observers[size_t(std::min<uint32_t>(count - 1, uint32_t(rng.uniform() * count)))];
        std::vector<double> q;
        try {
            q = scaleJod(sample, priorCount);
        } catch (const Error&) {
            continue;  // a resample that leaves a condition unconnected says nothing of its scale
        }
        for (int i = 0; i < n; ++i) draws[size_t(i)].push_back(q[size_t(i)]);
    }
    // Percentiles by the nearest-rank rule on the sorted draws.
    const double tail = 0.5 * (1.0 - level);
    for (int i = 0; i < n; ++i) {
        std::vector<double>& d = draws[size_t(i)];
        if (d.empty()) continue;
        std::sort(d.begin(), d.end());
        const auto rank = [&](double p) {
            const double r = std::ceil(p * double(d.size())) - 1.0;
            return d[size_t(std::clamp(r, 0.0, double(d.size() - 1)))];
        };
        result.low[size_t(i)] = rank(tail);
        result.high[size_t(i)] = rank(1.0 - tail);
    }
    return result;
}

Proportion wilsonInterval(int successes, int trials, double level) {
    Proportion r;
    r.successes = successes;
    r.trials = trials;
    if (trials <= 0) return r;
    const double n = trials;
    const double p = successes / n;
    const double z = normalQuantile(1.0 - 0.5 * (1.0 - level));
    const double z2 = z * z;
    const double denom = 1.0 + z2 / n;
    const double centre = (p + z2 / (2.0 * n)) / denom;
    const double half = z * std::sqrt(p * (1.0 - p) / n + z2 / (4.0 * n * n)) / denom;
    r.p = p;
    r.low = std::max(0.0, centre - half);
    r.high = std::min(1.0, centre + half);
    return r;
}

int StudyAnswers::failedChecks() const {
    int failed = 0;
    for (const Attention& a : attention) failed += a.instructed != a.answer;
    return failed;
}

StudyAnswers parseStudyAnswers(const std::string& text, const std::string& path) {
    using nlohmann::json;
    json doc;
    try {
        doc = json::parse(text);
    } catch (const json::exception& e) {
        throw Error(path + ": not JSON (" + e.what() + ")");
    }
    const auto need = [&](const json& obj, const char* key, const char* what) -> const json& {
        if (!obj.is_object() || !obj.contains(key))
            throw Error(path + ": missing key '" + key + "' (expected " + what + ")");
        return obj.at(key);
    };
    if (!doc.is_object() || doc.value("format", "") != "lobe-study-answers-1")
        throw Error(path +
                    ": not a lobe study answers file (expected \"format\": "
                    "\"lobe-study-answers-1\")");
    StudyAnswers a;
    a.path = path;
    try {
        a.study = need(doc, "study", "the study's fingerprint").get<std::string>();
        a.participant = need(doc, "participant", "a participant id").get<std::string>();
        a.conditions =
            need(doc, "conditions", "a list of condition names").get<std::vector<std::string>>();
        const json& trials = need(doc, "trials", "a list of trials");
        if (!trials.is_array()) throw Error(path + ": 'trials' must be a list");
        const int n = int(a.conditions.size());
        const auto condition = [&](const json& t, const char* key) {
            const int c = need(t, key, "a condition index").get<int>();
            if (c < 0 || c >= n)
                throw Error(path + ": trial condition '" + key + "' = " + std::to_string(c) +
                            " is not one of the " + std::to_string(n) + " conditions");
            return c;
        };
        for (const json& t : trials) {
            const std::string kind =
                need(t, "kind", "pair, marker or attention").get<std::string>();
            if (kind == "pair") {
                StudyAnswers::Pair p;
                p.a = condition(t, "a");
                p.b = condition(t, "b");
                p.chosen = condition(t, "chosen");
                if (p.a == p.b || (p.chosen != p.a && p.chosen != p.b))
                    throw Error(path + ": a pair trial's 'chosen' must be its 'a' or 'b'");
                a.pairs.push_back(p);
            } else if (kind == "marker") {
                StudyAnswers::Marker m;
                m.condition = condition(t, "condition");
                m.object = need(t, "object", "the marked object's name").get<std::string>();
                m.answer = need(t, "answer", "the object named").get<std::string>();
                a.markers.push_back(m);
            } else if (kind == "attention") {
                a.attention.push_back(
                    {need(t, "instructed", "the instructed answer").get<std::string>(),
                     need(t, "answer", "the answer given").get<std::string>()});
            } else {
                throw Error(path + ": unknown trial kind '" + kind +
                            "' (expected pair, marker or attention)");
            }
        }
    } catch (const json::exception& e) {
        throw Error(path + ": a value of the wrong type (" + e.what() + ")");
    }
    return a;
}

StudyAnalysis analyseStudy(const std::vector<StudyAnswers>& answers,
                           const StudyAnalysisOptions& options) {
    if (answers.empty()) throw Error("no answers files given");
    StudyAnalysis r;
    r.conditions = answers.front().conditions;
    const int n = int(r.conditions.size());
    std::set<std::string> seen;
    std::vector<PairCounts> observers;
    std::vector<int> correct(size_t(n), 0), total(size_t(n), 0);
    for (const StudyAnswers& a : answers) {
        if (a.study != answers.front().study || a.conditions != r.conditions)
            throw Error(a.path + ": answers of another study than " + answers.front().path +
                        " (fingerprint " + a.study + " against " + answers.front().study + ")");
        if (!seen.insert(a.participant).second)
            throw Error(a.path + ": participant '" + a.participant +
                        "' appears in two answers files");
        const int failed = a.failedChecks();
        if (failed > options.maxFailedChecks) {
            r.excluded.push_back(a.participant + " (" + a.path + "): failed " +
                                 std::to_string(failed) + " of " +
                                 std::to_string(a.attention.size()) + " attention checks");
            continue;
        }
        r.included.push_back(a.participant);
        PairCounts c(n);
        for (const StudyAnswers::Pair& p : a.pairs)
            c.at(p.chosen, p.chosen == p.a ? p.b : p.a) += 1;
        r.pairTrials += int(a.pairs.size());
        if (!a.pairs.empty()) observers.push_back(c);
        for (const StudyAnswers::Marker& m : a.markers) {
            total[size_t(m.condition)] += 1;
            correct[size_t(m.condition)] += m.answer == m.object;
        }
    }
    if (!observers.empty())
        r.jod = scaleJodWithIntervals(observers, options.bootstrapSamples, options.seed,
                                      options.level, options.priorCount);
    for (int i = 0; i < n; ++i)
        r.markerAccuracy.push_back(
            wilsonInterval(correct[size_t(i)], total[size_t(i)], options.level));
    return r;
}

MarkerSpot highlightMarker(const std::vector<std::vector<float>>& specular, int width, int height,
                           int object, double minShare, int border) {
    MarkerSpot best;
    if (object < 0 || object >= int(specular.size())) return best;
    const auto box = [&](const std::vector<float>& layer, int x, int y) {
        double sum = 0.0;
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                const int u = std::clamp(x + dx, 0, width - 1),
                          v = std::clamp(y + dy, 0, height - 1);
                sum += double(layer[size_t(v) * size_t(width) + size_t(u)]);
            }
        return sum;
    };
    double bestValue = 0.0;
    for (int y = border; y < height - border; ++y)
        for (int x = border; x < width - border; ++x) {
            const double own = box(specular[size_t(object)], x, y);
            if (!(own > bestValue)) continue;
            double all = 0.0;
            for (const std::vector<float>& layer : specular) all += box(layer, x, y);
            if (own < minShare * all) continue;
            bestValue = own;
            best = {true, x, y, own / all};
        }
    return best;
}

std::string simulateStudyAnswers(const std::string& studyJson, const SimulatedObserverModel& model,
                                 int observer, uint64_t seed, const std::string& participant) {
    using nlohmann::json;
    const json study = json::parse(studyJson);
    const json& conditions = study.at("conditions");
    const size_t n = conditions.size();
    if (model.jod.size() != n)
        throw Error("simulated observers: " + std::to_string(model.jod.size()) +
                    " JOD values for " + std::to_string(n) + " conditions");
    Rng rng(mixBits(seed ^ mixBits(uint64_t(observer) + 1)), 0x0b5e);
    const double sigma = jodSigma();
    json out;
    out["format"] = "lobe-study-answers-1";
    out["study"] = study.at("study");
    out["participant"] = participant.empty() ? "sim-" + std::to_string(observer) : participant;
    json names = json::array();
    for (const json& c : conditions) names.push_back(c.at("name"));
    out["conditions"] = names;
    json trials = json::array();
    for (const json& t : study.at("trials")) {
        json a = t;
        const std::string kind = t.at("kind");
        if (kind == "pair") {
            const int i = t.at("a"), j = t.at("b");
            const double p = normalCdf((model.jod[size_t(i)] - model.jod[size_t(j)]) / sigma);
            a["chosen"] = rng.uniform() < p ? i : j;
        } else if (kind == "marker") {
            const int c = t.at("condition");
            const double accuracy =
                c < int(model.markerAccuracy.size()) ? model.markerAccuracy[size_t(c)] : 1.0;
            const std::string right = t.at("object");
            std::vector<std::string> wrong;
            for (const json& o : t.at("options"))
                if (o.get<std::string>() != right) wrong.push_back(o);
            if (rng.uniform() < accuracy || wrong.empty())
                a["answer"] = right;
            else
                a["answer"] =
                    wrong[std::min(wrong.size() - 1, size_t(rng.uniform() * double(wrong.size())))];
        } else if (kind == "attention") {
            const std::string instructed = t.at("instructed");
            std::string other = "left";
            if (t.contains("options"))
                for (const json& o : t.at("options"))
                    if (o.get<std::string>() != instructed) other = o;
            if (instructed == "left") other = "right";
            a["answer"] = rng.uniform() < model.attentionPass ? instructed : other;
        }
        trials.push_back(a);
    }
    out["trials"] = trials;
    return out.dump(1);
}

}  // namespace lobe
