#include "analysis/assign.h"

#include "analysis/separation.h"
#include "core/error.h"
#include "core/rng.h"

#include <algorithm>
#include <limits>
#include <set>

namespace lobe {

double assignmentScore(const AssignmentLayers& layers, const std::vector<int>& assignment) {
    const size_t n = layers.pixelCount();
    std::vector<float> beauty(layers.base);
    std::vector<const float*> specular;
    for (size_t o = 0; o < assignment.size(); ++o) {
        const std::vector<float>& s = layers.layer(int(o), assignment[o]);
        for (size_t i = 0; i < n; ++i) beauty[i] += s[i];
        specular.push_back(s.data());
    }
    return separationScore(specular, beauty.data(), n);
}

namespace {

// Keeps the `top` best distinct assignments seen.
struct Ranking {
    size_t top;
    std::vector<ScoredAssignment> best;
    void offer(const std::vector<int>& a, double score) {
        for (const ScoredAssignment& s : best)
            if (s.assignment == a) return;
        if (best.size() == top && !(score > best.back().score)) return;
        best.push_back({a, score});
        std::stable_sort(best.begin(), best.end(), [](const ScoredAssignment& x,
                                                      const ScoredAssignment& y) {
            return x.score > y.score;
        });
        if (best.size() > top) best.pop_back();
    }
};

std::vector<std::vector<int>> choicesPerObject(const AssignmentLayers& layers,
                                               const AssignOptions& o) {
    const size_t k = layers.objects.size(), m = layers.candidates.size();
    std::vector<std::vector<int>> choices(k);
    for (size_t i = 0; i < k; ++i) {
        const int fixed = i < o.fixed.size() ? o.fixed[i] : -1;
        if (fixed >= 0) {
            choices[i] = {fixed};
            continue;
        }
        for (size_t c = 0; c < m; ++c)
            if (o.allowed.empty() || o.allowed[c]) choices[i].push_back(int(c));
        if (choices[i].empty())
            throw Error("assign: no candidate BRDF left for object '" + layers.objects[i] + "'");
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
    if (layers.objects.empty()) throw Error("assign: the scene has no objects");
    const std::vector<std::vector<int>> choices = choicesPerObject(layers, options);
    AssignResult result;
    result.space = spaceSize(choices);
    Ranking ranking{size_t(std::max(1, options.top)), {}};
    if (result.space <= options.exhaustiveLimit) {
        result.exhaustive = true;
        forEachAssignment(choices, [&](const std::vector<int>& a) {
            ranking.offer(a, assignmentScore(layers, a));
            ++result.evaluated;
        });
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
            s[i] = choices[i][size_t(rng.uniform() * double(choices[i].size())) % choices[i].size()];
        starts.push_back(s);
    }
    for (std::vector<int> a : starts) {
        double score = assignmentScore(layers, a);
        ++result.evaluated;
        ranking.offer(a, score);
        for (bool changed = true; changed;) {
            changed = false;
            for (size_t i = 0; i < a.size(); ++i) {
                const int keep = a[i];
                for (int c : choices[i]) {
                    if (c == keep) continue;
                    a[i] = c;
                    const double s = assignmentScore(layers, a);
                    ++result.evaluated;
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
    const double mine = assignmentScore(layers, assignment);
    uint64_t better = 0;
    forEachAssignment(choicesPerObject(layers, options), [&](const std::vector<int>& a) {
        better += assignmentScore(layers, a) > mine;
    });
    return better;
}

}  // namespace lobe
