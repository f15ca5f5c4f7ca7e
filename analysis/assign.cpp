#include "analysis/assign.h"

#include "analysis/colour.h"
#include "analysis/separation.h"
#include "core/error.h"
#include "core/rng.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

namespace lobe {

double sparkleShare(const float* rgb, int width, int height) {
    const size_t n = size_t(width) * size_t(height);
    std::vector<double> y(n);
    double maxY = 0.0, total = 0.0;
    for (size_t i = 0; i < n; ++i) {
        y[i] = srgbLuminance(rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2]);
        maxY = std::max(maxY, y[i]);
        total += y[i];
    }
    if (!(total > 0.0)) return 0.0;
    double specks = 0.0;
    for (int py = 0; py < height; ++py)
        for (int px = 0; px < width; ++px) {
            const double v = y[size_t(py) * size_t(width) + size_t(px)];
            if (!(v > 0.01 * maxY)) continue;
            double neighbour = 0.0;
            int count = 0;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int x = px + dx, yy = py + dy;
                    if ((dx || dy) && x >= 0 && yy >= 0 && x < width && yy < height) {
                        neighbour += y[size_t(yy) * size_t(width) + size_t(x)];
                        ++count;
                    }
                }
            if (count > 0 && v > kSparklePeak * neighbour / count) specks += v;
        }
    return specks / total;
}

AssignmentLayers mergeAssignmentObjects(const AssignmentLayers& in, const std::string& name,
                                        const std::vector<std::string>& members) {
    AssignmentLayers out;
    out.scene = mergeObjects(in.scene, name, members);  // throws for an unknown member
    out.candidates = in.candidates;
    out.candidateModels = in.candidateModels;
    const size_t m = in.candidates.size();
    out.specular.resize(out.scene.objects.size() * m);
    for (size_t o = 0; o < in.scene.objects.size(); ++o) {
        const bool member =
            std::find(members.begin(), members.end(), in.scene.objects[o]) != members.end();
        const std::string& target = member ? name : in.scene.objects[o];
        const size_t t =
            size_t(std::find(out.scene.objects.begin(), out.scene.objects.end(), target) -
                   out.scene.objects.begin());
        for (size_t c = 0; c < m; ++c) {
            std::vector<float>& dst = out.specular[t * m + c];
            const std::vector<float>& src = in.layer(int(o), int(c));
            if (dst.empty()) {
                dst = src;
                continue;
            }
            for (size_t i = 0; i < src.size(); ++i) dst[i] += src[i];
        }
    }
    return out;
}

SeparationReport assignmentReport(const SeparationScorer& scorer, const AssignmentLayers& layers,
                                  const std::vector<int>& assignment) {
    std::vector<const float*> specular;
    for (size_t o = 0; o < assignment.size(); ++o)
        specular.push_back(layers.layer(int(o), assignment[o]).data());
    return scorer.evaluate(specular);
}

double assignmentScore(const AssignmentLayers& layers, const std::vector<int>& assignment) {
    const SeparationScorer scorer(layers.scene);
    return assignmentReport(scorer, layers, assignment).score;
}

bool withinBounds(const SeparationReport& r, const AssignOptions& o) {
    for (size_t i = 0; i < r.objects.size(); ++i) {
        const ObjectVisibility& v = r.objects[i];
        if (i < o.minVisibility.size() && v.visibility < o.minVisibility[i]) return false;
        if (i < o.minChroma.size() && v.chroma < o.minChroma[i]) return false;
        if (i < o.minLuminance.size() && v.meanLuminance < o.minLuminance[i]) return false;
        if (i < o.maxLuminance.size() && v.meanLuminance > o.maxLuminance[i]) return false;
    }
    return true;
}

namespace {

bool repeatsAModel(const AssignmentLayers& layers, const std::vector<int>& a) {
    std::set<std::string> used;
    for (int c : a)
        if (!used.insert(layers.candidateModels[size_t(c)]).second) return true;
    return false;
}

// Scores assignments under the options' metric and constraints; an inadmissible one scores
// −∞ (never ranked, never taken by the local search).
struct Judge {
    const AssignmentLayers& layers;
    const AssignOptions& options;
    SeparationScorer scorer;
    AssignResult& result;
    Judge(const AssignmentLayers& l, const AssignOptions& o, AssignResult& r)
        : layers(l),
          options(o),
          scorer(l.scene, o.metric == SeparationMetric::Itp ? kItpThreshold : kWeberContrast,
                 o.metric),
          result(r) {}
    double operator()(const std::vector<int>& a) {
        ++result.evaluated;
        if (options.distinct && repeatsAModel(layers, a)) {
            ++result.rejected;
            return -std::numeric_limits<double>::infinity();
        }
        const SeparationReport r = assignmentReport(scorer, layers, a);
        if (!withinBounds(r, options)) {
            ++result.rejected;
            return -std::numeric_limits<double>::infinity();
        }
        return r.score;
    }
};

// Keeps the `top` best distinct assignments seen.
struct Ranking {
    size_t top;
    std::vector<ScoredAssignment> best;
    void offer(const std::vector<int>& a, double score) {
        if (!(score > -std::numeric_limits<double>::infinity())) return;
        for (const ScoredAssignment& s : best)
            if (s.assignment == a) return;
        if (best.size() == top && !(score > best.back().score)) return;
        best.push_back({a, score});
        std::stable_sort(
            best.begin(), best.end(),
            [](const ScoredAssignment& x, const ScoredAssignment& y) { return x.score > y.score; });
        if (best.size() > top) best.pop_back();
    }
};

std::vector<std::vector<int>> choicesPerObject(const AssignmentLayers& layers,
                                               const AssignOptions& o) {
    const size_t k = layers.objects().size(), m = layers.candidates.size();
    std::vector<std::vector<int>> choices(k);
    for (size_t i = 0; i < k; ++i) {
        const int fixed = i < o.fixed.size() ? o.fixed[i] : -1;
        if (fixed >= 0) {
            choices[i] = {fixed};
            continue;
        }
        for (size_t c = 0; c < m; ++c)
            if ((o.allowed.empty() || o.allowed[c]) &&
                (i >= o.objectAllowed.size() || o.objectAllowed[i].empty() ||
                 o.objectAllowed[i][c]))
                choices[i].push_back(int(c));
        if (choices[i].empty())
            throw Error("assign: no candidate BRDF left for object '" + layers.objects()[i] + "'");
    }
    return choices;
}

uint64_t spaceSize(const std::vector<std::vector<int>>& choices) {
    uint64_t total = 1;
    for (const auto& c : choices) {
        if (total > std::numeric_limits<uint64_t>::max() / c.size())
            return std::numeric_limits<uint64_t>::max();
        total *= c.size();
    }
    return total;
}

// Calls fn(assignment) for every assignment of the product space, odometer order.
template <class Fn>
void forEachAssignment(const std::vector<std::vector<int>>& choices, Fn&& fn) {
    std::vector<size_t> digit(choices.size(), 0);
    std::vector<int> a(choices.size());
    for (;;) {
        for (size_t i = 0; i < choices.size(); ++i) a[i] = choices[i][digit[i]];
        fn(a);
        size_t i = 0;
        while (i < choices.size() && ++digit[i] == choices[i].size()) digit[i++] = 0;
        if (i == choices.size()) return;
    }
}

}  // namespace

AssignResult searchAssignments(const AssignmentLayers& layers, const AssignOptions& options) {
    if (layers.objects().empty()) throw Error("assign: the scene has no objects");
    const std::vector<std::vector<int>> choices = choicesPerObject(layers, options);
    AssignResult result;
    result.space = spaceSize(choices);
    Judge judge(layers, options, result);
    Ranking ranking{size_t(std::max(1, options.top)), {}};
    if (result.space <= options.exhaustiveLimit) {
        result.exhaustive = true;
        forEachAssignment(choices, [&](const std::vector<int>& a) { ranking.offer(a, judge(a)); });
        result.ranked = ranking.best;
        return result;
    }
    // Local search: coordinate ascent from several starts.
    Rng rng(options.seed, 0xa551);
    std::vector<std::vector<int>> starts;
    if (options.start.size() == choices.size()) {
        std::vector<int> s = options.start;
        for (size_t i = 0; i < s.size(); ++i)
            if (std::find(choices[i].begin(), choices[i].end(), s[i]) == choices[i].end())
                s[i] = choices[i][0];
        starts.push_back(s);
    }
    for (int r = 0; r < options.restarts; ++r) {
        std::vector<int> s(choices.size());
        for (size_t i = 0; i < s.size(); ++i)
            s[i] =
                choices[i][size_t(rng.uniform() * double(choices[i].size())) % choices[i].size()];
        starts.push_back(s);
    }
    for (std::vector<int> a : starts) {
        double score = judge(a);
        ranking.offer(a, score);
        for (bool changed = true; changed;) {
            changed = false;
            for (size_t i = 0; i < a.size(); ++i) {
                const int keep = a[i];
                for (int c : choices[i]) {
                    if (c == keep) continue;
                    a[i] = c;
                    const double s = judge(a);
                    ranking.offer(a, s);
                    if (s > score) {
                        score = s;
                        changed = true;
                        break;  // take the improvement; the sweep goes on from here
                    }
                    a[i] = keep;
                }
                if (changed) break;
            }
        }
    }
    result.ranked = ranking.best;
    return result;
}

uint64_t countBetter(const AssignmentLayers& layers, const AssignOptions& options,
                     const std::vector<int>& assignment) {
    AssignResult scratch;
    Judge judge(layers, options, scratch);
    const SeparationReport mine = assignmentReport(judge.scorer, layers, assignment);
    uint64_t better = 0;
    forEachAssignment(choicesPerObject(layers, options),
                      [&](const std::vector<int>& a) { better += judge(a) > mine.score; });
    return better;
}

}  // namespace lobe
