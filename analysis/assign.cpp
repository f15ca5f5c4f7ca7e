#include "analysis/assign.h"

#include "analysis/colour.h"
#include "analysis/separation.h"
#include "core/error.h"
#include "core/rng.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <set>

namespace lobe {

namespace {

// Whether pixel (px, py) of luminance image y is a speck: above kSparklePeak × the mean of its
// (up to 8) neighbours.
bool isSpeck(const std::vector<double>& y, int width, int height, int px, int py) {
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
    return count > 0 &&
           y[size_t(py) * size_t(width) + size_t(px)] > kSparklePeak * neighbour / count;
}

}  // namespace

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
            if (v > 0.01 * maxY && isSpeck(y, width, height, px, py)) specks += v;
        }
    return specks / total;
}

double glintShare(const float* rgbA, const float* rgbB, int width, int height,
                  const std::vector<double>& matteY) {
    const size_t n = size_t(width) * size_t(height);
    if (matteY.size() != n) throw Error("internal: glintShare: one matte luminance per pixel");
    std::vector<double> ya(n), yb(n);
    for (size_t i = 0; i < n; ++i) {
        ya[i] = srgbLuminance(rgbA[3 * i], rgbA[3 * i + 1], rgbA[3 * i + 2]);
        yb[i] = srgbLuminance(rgbB[3 * i], rgbB[3 * i + 1], rgbB[3 * i + 2]);
    }
    double seen = 0.0, glints = 0.0;
    for (int py = 0; py < height; ++py)
        for (int px = 0; px < width; ++px) {
            const size_t i = size_t(py) * size_t(width) + size_t(px);
            const double s = 0.5 * (ya[i] + yb[i]), y = matteY[i] + s;
            if (!(y > 0.0) || !(s >= kWeberContrast * y)) continue;
            seen += 1.0;
            if (std::abs(ya[i] - yb[i]) >= kGlintContrast * y &&
                (isSpeck(ya, width, height, px, py) || isSpeck(yb, width, height, px, py)))
                glints += 1.0;
        }
    return seen > 0.0 ? glints / seen : 0.0;
}

std::vector<std::string> excludeSparkle(const AssignmentLayers& layers,
                                        const std::vector<bool>& reference, AssignOptions& options,
                                        const AssignmentLayers* nextSeed) {
    const size_t k = layers.objects().size(), m = layers.candidates.size();
    if (reference.size() != m) throw Error("internal: excludeSparkle: one flag per candidate");
    const int width = layers.scene.width, height = layers.scene.height;
    if (nextSeed && (nextSeed->objects() != layers.objects() || nextSeed->candidates.size() != m ||
                     nextSeed->scene.width != width || nextSeed->scene.height != height))
        throw Error("internal: excludeSparkle: the second seed's layers differ in shape");
    // The pixels' luminance without any highlight (every Lambert term and the backdrop), the
    // same for every assignment: what a glint must stand out against.
    std::vector<double> matte;
    if (nextSeed) {
        const size_t n = layers.pixelCount();
        matte.assign(n, 0.0);
        for (size_t i = 0; i < n; ++i) {
            if (!layers.scene.backdrop.empty()) {
                const float* b = &layers.scene.backdrop[3 * i];
                matte[i] = srgbLuminance(b[0], b[1], b[2]);
            }
            for (const std::vector<float>& l : layers.scene.lambert)
                matte[i] += srgbLuminance(l[3 * i], l[3 * i + 1], l[3 * i + 2]);
        }
    }
    if (options.objectAllowed.size() != k) options.objectAllowed.assign(k, {});
    std::vector<std::string> notes;
    for (size_t o = 0; o < k; ++o) {
        if (o < options.fixed.size() && options.fixed[o] >= 0) continue;
        std::vector<bool>& allowed = options.objectAllowed[o];
        if (allowed.size() != m) allowed.assign(m, true);
        std::vector<double> share(m), glint(m, 0.0), referenceGlints;
        double least = 1.0;
        for (size_t c = 0; c < m; ++c) {
            const std::vector<float>& layer = layers.layer(int(o), int(c));
            share[c] = sparkleShare(layer.data(), width, height);
            if (nextSeed)
                glint[c] = glintShare(layer.data(), nextSeed->layer(int(o), int(c)).data(), width,
                                      height, matte);
            if (reference[c]) {
                least = std::min(least, share[c]);
                referenceGlints.push_back(glint[c]);
            }
        }
        // The typical default's glint share (the lower median): a count of a few pixels on a
        // small structure or coarse layers, where the least of nine is often 0 by chance.
        double typicalGlint = 1.0;
        if (!referenceGlints.empty()) {
            std::sort(referenceGlints.begin(), referenceGlints.end());
            typicalGlint = referenceGlints[(referenceGlints.size() - 1) / 2];
        }
        for (size_t c = 0; c < m; ++c) {
            const bool specks = share[c] > kSparkleLimit && share[c] > 2.0 * least;
            const bool glints = glint[c] > kGlintLimit && glint[c] > 2.0 * typicalGlint;
            if (allowed[c] && (specks || glints)) {
                allowed[c] = false;
                char buf[160];
                if (nextSeed)
                    std::snprintf(buf, sizeof buf,
                                  " (%.0f %% in specks, %.1f %% glints; the least specky "
                                  "default %.0f %%, the median default %.1f %% glints)",
                                  100.0 * share[c], 100.0 * glint[c], 100.0 * least,
                                  100.0 * typicalGlint);
                else
                    std::snprintf(buf, sizeof buf,
                                  " (%.0f %% in specks; the least default %.0f %%)",
                                  100.0 * share[c], 100.0 * least);
                notes.push_back(layers.objects()[o] + ": " + layers.candidates[c] + buf);
            }
        }
    }
    return notes;
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

// How many objects use a model an earlier object uses.
int repeatedModels(const AssignmentLayers& layers, const std::vector<int>& a) {
    std::set<std::string> used;
    int repeats = 0;
    for (int c : a) repeats += !used.insert(layers.candidateModels[size_t(c)]).second;
    return repeats;
}

// How far `report` is from the bounds of `options`: the sum of the relative shortfalls (0 when
// within them).
double boundsViolation(const SeparationReport& r, const AssignOptions& o) {
    const auto below = [](double v, double bound) {
        return v < bound ? (bound - v) / std::max(bound, 1e-12) : 0.0;
    };
    double sum = 0.0;
    for (size_t i = 0; i < r.objects.size(); ++i) {
        const ObjectVisibility& v = r.objects[i];
        if (i < o.minVisibility.size()) sum += below(v.visibility, o.minVisibility[i]);
        if (i < o.minChroma.size()) sum += below(v.chroma, o.minChroma[i]);
        if (i < o.minLuminance.size()) sum += below(v.meanLuminance, o.minLuminance[i]);
        if (i < o.maxLuminance.size() && v.meanLuminance > o.maxLuminance[i])
            sum += (v.meanLuminance - o.maxLuminance[i]) / std::max(o.maxLuminance[i], 1e-12);
    }
    return sum;
}

// Scores assignments under the options' metric and constraints. Scores are ≥ 0; an
// inadmissible assignment gets −1 − (how far it is from admissible: the relative shortfalls of
// the bounds plus the repeated models under `distinct`), so it is never ranked but the local
// search, started somewhere inadmissible, climbs towards the admissible ones.
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
    double judge(const SeparationReport& r, const std::vector<int>& a) {
        ++result.evaluated;
        const double violation = (options.distinct ? double(repeatedModels(layers, a)) : 0.0) +
                                 boundsViolation(r, options);
        if (violation > 0.0) {
            ++result.rejected;
            return -1.0 - violation;
        }
        return r.score;
    }
    double operator()(const std::vector<int>& a) {
        return judge(assignmentReport(scorer, layers, a), a);
    }
    double operator()(const SeparationScorer::Sums& sums, const std::vector<int>& a) {
        return judge(scorer.report(sums, false), a);
    }
};

bool nonZero(const std::vector<float>& layer, size_t i) {
    return layer[3 * i] != 0.0f || layer[3 * i + 1] != 0.0f || layer[3 * i + 2] != 0.0f;
}

// Where an assignment can change anything: per pixel the objects with a matte weight or a
// non-zero layer for any of their choices (ascending), per object the pixels where any of its
// choices is non-zero. An object swapped for another candidate changes only its own pixels.
struct Support {
    std::vector<uint32_t> start, objects;       // pixel i: objects[start[i] .. start[i + 1])
    std::vector<std::vector<uint32_t>> pixels;  // per object
};

Support supportOf(const AssignmentLayers& layers, const SeparationScorer& scorer,
                  const std::vector<std::vector<int>>& choices) {
    const size_t n = layers.pixelCount(), k = choices.size();
    std::vector<std::vector<char>> lit(k, std::vector<char>(n, 0));
    Support s;
    s.pixels.resize(k);
    for (size_t o = 0; o < k; ++o) {
        for (int c : choices[o]) {
            const std::vector<float>& layer = layers.layer(int(o), c);
            for (size_t i = 0; i < n; ++i)
                if (nonZero(layer, i)) lit[o][i] = 1;
        }
        for (size_t i = 0; i < n; ++i)
            if (lit[o][i]) s.pixels[o].push_back(uint32_t(i));
    }
    s.start.assign(n + 1, 0);
    for (size_t i = 0; i < n; ++i) {
        for (size_t o = 0; o < k; ++o)
            if (lit[o][i] || scorer.inMatte(i, o)) s.objects.push_back(uint32_t(o));
        s.start[i + 1] = uint32_t(s.objects.size());
    }
    return s;
}

// The score's sums for the current assignment, updated pixel by pixel as objects change
// candidate (SeparationScorer::Sums): a trial costs the changed object's pixels, not the image.
class IncrementalSums {
public:
    IncrementalSums(const AssignmentLayers& layers, const SeparationScorer& scorer,
                    const Support& support)
        : layers_(layers), scorer_(scorer), support_(support) {}

    void reset(const std::vector<int>& a) {
        assignment_ = a;
        specular_.resize(a.size());
        for (size_t o = 0; o < a.size(); ++o) specular_[o] = layers_.layer(int(o), a[o]).data();
        sums_ = scorer_.emptySums();
        const size_t n = layers_.pixelCount();
        for (size_t i = 0; i < n; ++i) add(i, specular_, 1.0, sums_);
    }
    const SeparationScorer::Sums& sums() const { return sums_; }
    const std::vector<int>& assignment() const { return assignment_; }

    // `out`: the sums with object o at candidate c, the others as now.
    void trial(size_t o, int c, SeparationScorer::Sums& out) {
        out = sums_;
        if (c == assignment_[o]) return;
        const std::vector<float>& before = layers_.layer(int(o), assignment_[o]);
        const std::vector<float>& after = layers_.layer(int(o), c);
        scratch_ = specular_;
        scratch_[o] = after.data();
        for (uint32_t i : support_.pixels[o]) {
            if (!nonZero(before, i) && !nonZero(after, i)) continue;
            add(i, specular_, -1.0, out);
            add(i, scratch_, 1.0, out);
        }
    }
    void accept(size_t o, int c, SeparationScorer::Sums& sums) {
        assignment_[o] = c;
        specular_[o] = layers_.layer(int(o), c).data();
        std::swap(sums_, sums);
    }

private:
    void add(size_t i, const std::vector<const float*>& specular, double sign,
             SeparationScorer::Sums& s) const {
        const uint32_t b = support_.start[i], e = support_.start[i + 1];
        scorer_.addPixel(i, specular, support_.objects.data() + b, e - b, sign, s);
    }
    const AssignmentLayers& layers_;
    const SeparationScorer& scorer_;
    const Support& support_;
    std::vector<int> assignment_;
    std::vector<const float*> specular_, scratch_;
    SeparationScorer::Sums sums_;
};

// Keeps the `top` best distinct assignments seen.
struct Ranking {
    size_t top;
    std::vector<ScoredAssignment> best;
    ScoredAssignment closest{{}, -std::numeric_limits<double>::infinity()};
    void offer(const std::vector<int>& a, double score) {
        if (score < 0.0) {  // inadmissible (Judge)
            if (score > closest.score) closest = {a, score};
            return;
        }
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

// Calls fn(assignment, score) for every assignment of the product space, the sums updated by
// differences from one assignment to the next.
template <class Fn>
void forEachScored(const std::vector<std::vector<int>>& choices, const Support& support,
                   IncrementalSums& state, Judge& judge, Fn&& fn) {
    const size_t k = choices.size();
    // The odometer's fastest digit changes at every step: give it the object with the fewest
    // pixels to update (a small region rather than a hull over the whole image).
    std::vector<size_t> order(k);
    for (size_t i = 0; i < k; ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](size_t x, size_t y) {
        return support.pixels[x].size() < support.pixels[y].size();
    });
    std::vector<std::vector<int>> permuted(k);
    for (size_t i = 0; i < k; ++i) permuted[i] = choices[order[i]];
    std::vector<int> a(k);
    SeparationScorer::Sums trial;
    uint64_t step = 0;
    forEachAssignment(permuted, [&](const std::vector<int>& p) {
        for (size_t i = 0; i < k; ++i) a[order[i]] = p[i];
        // Differences accumulate rounding: start afresh now and then.
        if (step++ % 8192 == 0) {
            state.reset(a);
        } else {
            for (size_t i = 0; i < k; ++i)
                if (a[i] != state.assignment()[i]) {
                    state.trial(i, a[i], trial);
                    state.accept(i, a[i], trial);
                }
        }
        fn(a, judge(state.sums(), a));
    });
}

}  // namespace

AssignResult searchAssignments(const AssignmentLayers& layers, const AssignOptions& options) {
    if (layers.objects().empty()) throw Error("assign: the scene has no objects");
    const std::vector<std::vector<int>> choices = choicesPerObject(layers, options);
    AssignResult result;
    result.space = spaceSize(choices);
    Judge judge(layers, options, result);
    Ranking ranking{size_t(std::max(1, options.top)), {}};
    const Support support = supportOf(layers, judge.scorer, choices);
    IncrementalSums state(layers, judge.scorer, support);
    SeparationScorer::Sums trial, best;
    const size_t k = choices.size();
    size_t fewest = layers.pixelCount();
    for (const std::vector<uint32_t>& p : support.pixels) fewest = std::min(fewest, p.size());
    if (result.space <= options.exhaustiveLimit &&
        double(result.space) * double(std::max<size_t>(fewest, 1)) <= options.exhaustiveWork) {
        result.exhaustive = true;
        forEachScored(choices, support, state, judge,
                      [&](const std::vector<int>& a, double score) { ranking.offer(a, score); });
    } else {
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
                s[i] = choices[i][size_t(rng.uniform() * double(choices[i].size())) %
                                  choices[i].size()];
            starts.push_back(s);
        }
        for (std::vector<int> a : starts) {
            state.reset(a);
            double score = judge(state.sums(), a);
            ranking.offer(a, score);
            // Each object in turn takes the candidate that scores best with the others held;
            // done when a whole round of the objects changes none.
            for (size_t quiet = 0, i = 0; quiet < k; i = (i + 1) % k) {
                const int keep = a[i];
                int chosen = keep;
                double top = score;
                for (int c : choices[i]) {
                    if (c == keep) continue;
                    state.trial(i, c, trial);
                    a[i] = c;
                    const double s = judge(trial, a);
                    ranking.offer(a, s);
                    if (s > top) {
                        top = s;
                        chosen = c;
                        std::swap(best, trial);
                    }
                }
                a[i] = chosen;
                if (chosen != keep) {
                    state.accept(i, chosen, best);
                    score = top;
                    quiet = 0;
                } else {
                    ++quiet;
                }
            }
        }
    }
    // The ranked scores from a pass over the image, not from sums updated by differences.
    AssignResult scratch;
    Judge exact(layers, options, scratch);
    for (ScoredAssignment& r : ranking.best) r.score = exact(r.assignment);
    ranking.best.erase(std::remove_if(ranking.best.begin(), ranking.best.end(),
                                      [](const ScoredAssignment& r) { return r.score < 0.0; }),
                       ranking.best.end());
    std::stable_sort(
        ranking.best.begin(), ranking.best.end(),
        [](const ScoredAssignment& x, const ScoredAssignment& y) { return x.score > y.score; });
    result.ranked = ranking.best;
    if (result.ranked.empty()) result.closest = ranking.closest.assignment;
    return result;
}

uint64_t countBetter(const AssignmentLayers& layers, const AssignOptions& options,
                     const std::vector<int>& assignment) {
    AssignResult scratch;
    Judge judge(layers, options, scratch);
    const SeparationReport mine = assignmentReport(judge.scorer, layers, assignment);
    const std::vector<std::vector<int>> choices = choicesPerObject(layers, options);
    const Support support = supportOf(layers, judge.scorer, choices);
    IncrementalSums state(layers, judge.scorer, support);
    // Sums updated by differences carry rounding: "better" is better by more than that.
    const double margin = 1e-12 * std::max(1.0, std::abs(mine.score));
    uint64_t better = 0;
    forEachScored(choices, support, state, judge, [&](const std::vector<int>&, double score) {
        better += score > mine.score + margin;
    });
    return better;
}

}  // namespace lobe
