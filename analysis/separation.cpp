#include "analysis/separation.h"

#include "analysis/colour.h"
#include "core/error.h"
#include "core/format.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace lobe {

namespace {

double lum(const float* rgb) { return srgbLuminance(rgb[0], rgb[1], rgb[2]); }

void checkLayers(const SeparationLayers& l, bool needSpecular) {
    const size_t n = l.pixelCount(), k = l.objects.size();
    bool ok = l.lambert.size() == k && l.backdrop.size() == 3 * n &&
              (l.depth.empty() || l.depth.size() == k) && (!needSpecular || l.specular.size() == k);
    for (size_t o = 0; ok && o < k; ++o) {
        ok = l.lambert[o].size() == 3 * n && (!needSpecular || l.specular[o].size() == 3 * n) &&
             (l.depth.empty() || l.depth[o].size() == n);
    }
    if (!ok) throw Error("separation: layers do not match the image");
}

}  // namespace

std::vector<float> beautyOf(const SeparationLayers& l) {
    checkLayers(l, true);
    std::vector<float> b(l.backdrop);
    for (size_t o = 0; o < l.objects.size(); ++o)
        for (size_t i = 0; i < b.size(); ++i) b[i] += l.lambert[o][i] + l.specular[o][i];
    return b;
}

SeparationLayers mergeObjects(const SeparationLayers& layers, const std::string& name,
                              const std::vector<std::string>& members) {
    std::vector<bool> member(layers.objects.size(), false);
    for (const std::string& m : members) {
        const auto it = std::find(layers.objects.begin(), layers.objects.end(), m);
        if (it == layers.objects.end()) {
            std::string names;
            for (const std::string& o : layers.objects) names += (names.empty() ? "" : ", ") + o;
            throw Error("--merge: the scene has no object '" + m + "' (objects: " + names + ")");
        }
        member[size_t(it - layers.objects.begin())] = true;
    }
    SeparationLayers out = layers;
    out.objects.clear();
    out.lambert.clear();
    out.specular.clear();
    out.depth.clear();
    const bool hasSpecular = !layers.specular.empty(), hasDepth = !layers.depth.empty();
    int merged = -1;
    for (size_t o = 0; o < layers.objects.size(); ++o) {
        if (!member[o] || merged < 0) {
            if (member[o]) merged = int(out.objects.size());
            out.objects.push_back(member[o] ? name : layers.objects[o]);
            out.lambert.push_back(layers.lambert[o]);
            if (hasSpecular) out.specular.push_back(layers.specular[o]);
            if (hasDepth) out.depth.push_back(layers.depth[o]);
            continue;
        }
        const size_t m = size_t(merged);
        for (size_t i = 0; i < layers.lambert[o].size(); ++i) {
            out.lambert[m][i] += layers.lambert[o][i];
            if (hasSpecular) out.specular[m][i] += layers.specular[o][i];
        }
        if (hasDepth)
            for (size_t i = 0; i < layers.depth[o].size(); ++i) {
                const float d = layers.depth[o][i];
                float& to = out.depth[m][i];
                if (d > 0.0f && (to == 0.0f || d < to)) to = d;
            }
    }
    return out;
}

SeparationScorer::SeparationScorer(const SeparationLayers& l, double threshold,
                                   SeparationMetric metric)
    : layers_(l), threshold_(threshold), metric_(metric) {
    checkLayers(l, false);
    n_ = l.pixelCount();
    k_ = l.objects.size();
    const bool shoulder = toneIsShoulder(l.tone);
    base_ = l.backdrop;
    for (size_t o = 0; o < k_; ++o)
        for (size_t i = 0; i < 3 * n_; ++i) base_[i] += l.lambert[o][i];
    lambertY_.assign(n_ * k_, 0.0f);
    weight_.assign(n_ * k_, 0.0f);
    ownA_.assign(n_ * k_, 0.0f);
    ownB_.assign(n_ * k_, 0.0f);
    ownC_.assign(n_ * k_, 0.0f);
    weightSum_.assign(k_, 0.0);
    matteShare_.assign(k_, 0.0);
    matteIdentity_.assign(k_, 1.0);
    std::vector<double> idSum(k_, 0.0), idWeight(k_, 0.0);
    for (size_t i = 0; i < n_; ++i) {
        const double yBase = lum(&base_[3 * i]);
        const Rgb3 baseLab = srgbToLab({displayedShoulder(base_[3 * i], shoulder),
                                        displayedShoulder(base_[3 * i + 1], shoulder),
                                        displayedShoulder(base_[3 * i + 2], shoulder)});
        for (size_t o = 0; o < k_; ++o) {
            const float* L = &l.lambert[o][3 * i];
            const double y = lum(L);
            const size_t j = i * k_ + o;
            lambertY_[j] = float(y);
            if (!(yBase > 0.0) || !(y > 0.0)) continue;
            const double w = std::clamp(y / yBase, 0.0, 1.0);
            weight_[j] = float(w);
            weightSum_[o] += w;
            matteShare_[o] += w * w;
            // The object's own colour at the matte pixel's luminance, as displayed.
            const double s = yBase / y;
            const Rgb3 own = srgbToLab({displayedShoulder(L[0] * s, shoulder),
                                        displayedShoulder(L[1] * s, shoulder),
                                        displayedShoulder(L[2] * s, shoulder)});
            const double c = std::hypot(own[1], own[2]);
            if (c >= kAchromaticChroma) {
                ownA_[j] = float(own[1] / c);
                ownB_[j] = float(own[2] / c);
                ownC_[j] = float(c);
                const double along = baseLab[1] * ownA_[j] + baseLab[2] * ownB_[j];
                idSum[o] += w * std::clamp(along / ownC_[j], 0.0, 1.0);
                idWeight[o] += w;
            }
        }
    }
    for (size_t o = 0; o < k_; ++o)
        if (idWeight[o] > 0.0) matteIdentity_[o] = idSum[o] / idWeight[o];
}

SeparationScorer::Sums SeparationScorer::emptySums() const {
    Sums s;
    s.area.assign(k_, 0);
    s.seen.assign(k_, 0);
    s.idCount.assign(k_, 0);
    for (std::vector<double>* v : {&s.seenSum, &s.contrastSum, &s.shareSum, &s.veilSum, &s.idSum,
                                   &s.idWeight, &s.chromaSum, &s.lumSum})
        v->assign(k_, 0.0);
    s.together.assign(k_ * k_, 0.0);
    return s;
}

void SeparationScorer::addPixel(size_t i, const std::vector<const float*>& specular,
                                const uint32_t* active, size_t count, double sign, Sums& s) const {
    if (count == 0) return;
    const SeparationLayers& l = layers_;
    const bool shoulder = toneIsShoulder(l.tone);
    const bool itp = metric_ == SeparationMetric::Itp;
    const bool hasDepth = !l.depth.empty();
    thread_local std::vector<double> c, ys;
    thread_local std::vector<uint32_t> lit;
    c.resize(count);
    ys.resize(count);
    lit.clear();
    double B[3] = {base_[3 * i], base_[3 * i + 1], base_[3 * i + 2]};
    for (size_t u = 0; u < count; ++u)
        for (int b = 0; b < 3; ++b) B[b] += specular[active[u]][3 * i + size_t(b)];
    const double Y = srgbLuminance(B[0], B[1], B[2]);
    const Rgb3 shown = {displayedShoulder(B[0], shoulder), displayedShoulder(B[1], shoulder),
                        displayedShoulder(B[2], shoulder)};
    const Rgb3 lab = srgbToLab(shown);
    const double chroma = std::sqrt(lab[1] * lab[1] + lab[2] * lab[2]);
    Rgb3 ictcp{};
    if (itp) ictcp = srgbToIctcp(shown, l.peakLuminance);
    for (size_t u = 0; u < count; ++u) {
        const size_t o = active[u];
        const float* S = specular[o] + 3 * i;
        ys[u] = lum(S);
        if (itp) {  // detection map: the pixel with and without the object's specular pass
            if (S[0] == 0.0f && S[1] == 0.0f && S[2] == 0.0f) {
                c[u] = 0.0;
            } else {
                const Rgb3 off = {displayedShoulder(B[0] - S[0], shoulder),
                                  displayedShoulder(B[1] - S[1], shoulder),
                                  displayedShoulder(B[2] - S[2], shoulder)};
                c[u] = deltaEItp(ictcp, srgbToIctcp(off, l.peakLuminance));
            }
        } else {
            c[u] = Y > 0.0 ? double(float(ys[u] / Y)) : 0.0;
        }
        if (c[u] > threshold_) {
            s.area[o] += sign > 0.0 ? 1 : -1;
            s.seenSum[o] += sign * c[u];
            lit.push_back(uint32_t(u));
        }
        if (c[u] >= threshold_) s.contrastSum[o] += sign * c[u];
    }
    for (size_t u = 0; u < count; ++u) {
        const size_t o = active[u];
        const size_t j = i * k_ + o;
        const double share = Y > 0.0 ? (lambertY_[j] + ys[u]) / Y : 0.0;
        if (share >= kWeberContrast) s.seen[o] += sign > 0.0 ? 1 : -1;
        const double w = weight_[j];
        if (w == 0.0) continue;
        s.shareSum[o] += sign * w * std::min(share, 1.0);
        s.chromaSum[o] += sign * w * chroma;
        s.lumSum[o] += sign * w * (lambertY_[j] + ys[u]);
        if (hasDepth && Y > 0.0) {
            const float d = l.depth[o][i];
            double veil = 0.0;
            for (size_t v = 0; v < count; ++v) {
                const float da = l.depth[active[v]][i];
                if (v != u && da > 0.0f && d > 0.0f && da < d) veil += ys[v];
            }
            s.veilSum[o] += sign * w * std::min(1.0, veil / Y);
        }
        if (ownC_[j] > 0.0f) {
            const double along = lab[1] * ownA_[j] + lab[2] * ownB_[j];
            s.idSum[o] += sign * w * std::clamp(along / ownC_[j], 0.0, 1.0);
            s.idWeight[o] += sign * w;
            s.idCount[o] += sign > 0.0 ? 1 : -1;
        }
    }
    for (size_t x = 0; x < lit.size(); ++x)
        for (size_t y = x + 1; y < lit.size(); ++y)
            s.together[size_t(active[lit[x]]) * k_ + active[lit[y]]] +=
                sign * std::min(c[lit[x]], c[lit[y]]);
}

SeparationReport SeparationScorer::report(const Sums& s, bool withPairs) const {
    const SeparationLayers& l = layers_;
    const bool itp = metric_ == SeparationMetric::Itp;
    SeparationReport r;
    r.metric = metric_;
    r.threshold = threshold_;
    r.objects.resize(k_);
    for (size_t o = 0; o < k_; ++o) {
        ObjectVisibility& v = r.objects[o];
        v.name = l.objects[o];
        v.visibleShare = n_ ? double(s.seen[o]) / double(n_) : 0.0;
        v.specularShare = n_ ? double(s.area[o]) / double(n_) : 0.0;
        v.meanSpecularContrast = s.area[o] > 0 ? s.contrastSum[o] / double(s.area[o]) : 0.0;
        const double W = weightSum_[o];
        if (W > 0.0) {
            v.visibility = s.shareSum[o] / W;
            v.matteVisibility = matteShare_[o] / W;
            v.veiling = s.veilSum[o] / W;
            v.chroma = s.chromaSum[o] / W;
            v.meanLuminance = s.lumSum[o] / W;
        }
        v.chromatic = s.idCount[o] > 0;
        v.identity = v.chromatic ? s.idSum[o] / s.idWeight[o] : 1.0;
        v.matteIdentity = matteIdentity_[o];
        const double keptColour =
            v.matteIdentity > 0.0 ? std::min(1.0, v.identity / v.matteIdentity) : 1.0;
        // An object never seen in the matte image has nothing to lose: kept 1, W 0, I 1.
        const double kept =
            v.matteVisibility > 0.0 ? std::min(1.0, v.visibility / v.matteVisibility) : 1.0;
        v.quality = kept * (1.0 - v.veiling) * keptColour;
    }
    const size_t pairs = k_ * (k_ - 1) / 2;
    if (withPairs) r.pairs.reserve(pairs);
    for (size_t a = 0; a < k_; ++a)
        for (size_t b = a + 1; b < k_; ++b) {
            FluxOverlap m;
            m.areaA = s.area[a];
            m.areaB = s.area[b];
            const double both = s.together[a * k_ + b];
            m.OA = std::max(0.0, s.seenSum[a] - both);
            m.OB = std::max(0.0, s.seenSum[b] - both);
            m.eSum = (m.areaA > 0 && m.areaB > 0)
                         ? std::min(m.OA / double(m.areaA), m.OB / double(m.areaB))
                         : 0.0;
            const double score =
                itp ? m.eSum : m.eSum * r.objects[a].quality * r.objects[b].quality;
            r.highlight += m.eSum;
            r.score += score;
            if (withPairs) {
                PairSeparation ps;
                ps.a = int(a);
                ps.b = int(b);
                ps.metric = m;
                ps.score = score;
                r.pairs.push_back(ps);
            }
        }
    if (pairs > 0) {
        r.highlight /= double(pairs);
        r.score /= double(pairs);
    }
    return r;
}

SeparationReport SeparationScorer::evaluate(const std::vector<const float*>& specular) const {
    if (specular.size() != k_) throw Error("separation: one specular layer per object expected");
    Sums s = emptySums();
    std::vector<uint32_t> active;
    active.reserve(k_);
    for (size_t i = 0; i < n_; ++i) {
        // Objects neither in the matte image nor lit by a highlight here add nothing (c = 0,
        // w = 0); a pixel without any adds nothing to any sum.
        active.clear();
        for (size_t o = 0; o < k_; ++o) {
            const float* S = specular[o] + 3 * i;
            if (weight_[i * k_ + o] != 0.0f || S[0] != 0.0f || S[1] != 0.0f || S[2] != 0.0f)
                active.push_back(uint32_t(o));
        }
        addPixel(i, specular, active.data(), active.size(), 1.0, s);
    }
    return report(s);
}

SeparationReport measureSeparation(const SeparationLayers& layers, double threshold,
                                   SeparationMetric metric) {
    checkLayers(layers, true);
    const SeparationScorer scorer(layers, threshold, metric);
    std::vector<const float*> specular;
    for (const std::vector<float>& s : layers.specular) specular.push_back(s.data());
    return scorer.evaluate(specular);
}

SeparationMetric parseSeparationMetric(const std::string& name) {
    if (name == "weber") return SeparationMetric::Weber;
    if (name == "itp") return SeparationMetric::Itp;
    throw Error("--metric: expected weber or itp, got '" + name + "'");
}

const char* separationMetricName(SeparationMetric metric) {
    return metric == SeparationMetric::Itp ? "itp" : "weber";
}

std::string separationCsv(const SeparationReport& r, const std::vector<std::string>& objects) {
    std::string out =
        "kind,a,b,score,visible_share,specular_share,mean_specular_contrast,area_a,area_b,"
        "visibility,matte_visibility,veiling,identity,matte_identity,chroma,quality,highlight\n";
    for (const ObjectVisibility& v : r.objects)
        out += "object," + v.name + ",,," + formatNumber("%.6g", v.visibleShare) + "," +
               formatNumber("%.6g", v.specularShare) + "," +
               formatNumber("%.6g", v.meanSpecularContrast) + ",,," +
               formatNumber("%.6g", v.visibility) + "," + formatNumber("%.6g", v.matteVisibility) +
               "," + formatNumber("%.6g", v.veiling) + "," +
               (v.chromatic ? formatNumber("%.6g", v.identity) : "") + "," +
               (v.chromatic ? formatNumber("%.6g", v.matteIdentity) : "") + "," +
               formatNumber("%.6g", v.chroma) + "," + formatNumber("%.6g", v.quality) + ",\n";
    for (const PairSeparation& p : r.pairs)
        out += "pair," + objects[size_t(p.a)] + "," + objects[size_t(p.b)] + "," +
               formatNumber("%.6g", p.score) + ",,,," + std::to_string(p.metric.areaA) + "," +
               std::to_string(p.metric.areaB) + ",,,,,,,," + formatNumber("%.6g", p.metric.eSum) +
               "\n";
    out += "scene,,," + formatNumber("%.6g", r.score) + ",,,,,,,,,,,,," +
           formatNumber("%.6g", r.highlight) + "\n";
    return out;
}

std::string separationMarkdown(const SeparationReport& r, const std::vector<std::string>& objects,
                               const std::string& title) {
    const bool itp = r.metric == SeparationMetric::Itp;
    std::string out = "# Separation: " + title + "\n\nScene score (mean over pairs): **" +
                      formatNumber("%.4g", r.score) + "**";
    if (itp)
        out += "; metric: ΔE_ITP detection maps (BT.2124), threshold " +
               formatNumber("%.3g", r.threshold) + " (docs/separation.md).\n\n";
    else
        out += " (highlight term alone " + formatNumber("%.4g", r.highlight) +
               "); threshold: Weber contrast " + formatNumber("%.3g", r.threshold) +
               " (docs/separation.md).\n\n";
    out +=
        "| object | visibility V | matte V0 | veiling W | identity I | matte I0 | chroma C* | "
        "quality q | highlight seen | mean highlight " +
        std::string(itp ? "ΔE_ITP" : "contrast") +
        " |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const ObjectVisibility& v : r.objects)
        out += "| " + v.name + " | " + formatNumber("%.3f", v.visibility) + " | " +
               formatNumber("%.3f", v.matteVisibility) + " | " + formatNumber("%.3f", v.veiling) +
               " | " +
               (v.chromatic ? formatNumber("%.3f", v.identity) : std::string("— (achromatic)")) +
               " | " + (v.chromatic ? formatNumber("%.3f", v.matteIdentity) : std::string("—")) +
               " | " + formatNumber("%.1f", v.chroma) + " | " + formatNumber("%.3f", v.quality) +
               " | " + formatNumber("%.1f %%", 100 * v.specularShare) + " | " +
               formatNumber("%.3f", v.meanSpecularContrast) + " |\n";
    out +=
        "\n| pair | score | highlight e | highlight pixels A | highlight pixels B |\n"
        "|---|---:|---:|---:|---:|\n";
    for (const PairSeparation& p : r.pairs)
        out += "| " + objects[size_t(p.a)] + " / " + objects[size_t(p.b)] + " | " +
               formatNumber("%.4g", p.score) + " | " + formatNumber("%.4g", p.metric.eSum) + " | " +
               std::to_string(p.metric.areaA) + " | " + std::to_string(p.metric.areaB) + " |\n";
    return out;
}

RgbImage separationMap(const SeparationLayers& layers, int a, int b, double threshold) {
    const std::vector<float> beauty = beautyOf(layers);
    const size_t n = layers.pixelCount();
    auto contrast = [&](int o) {
        std::vector<float> c(n, 0.0f);
        for (size_t i = 0; i < n; ++i) {
            const double y = lum(&beauty[3 * i]);
            if (y > 0.0) c[i] = float(lum(&layers.specular[size_t(o)][3 * i]) / y);
        }
        return c;
    };
    const std::vector<float> ca = contrast(a), cb = contrast(b);
    auto scaleOf = [&](const std::vector<float>& c) {
        std::vector<float> lit;
        for (float v : c)
            if (v > threshold) lit.push_back(v);
        if (lit.empty()) return 1.0;
        const size_t k = std::min(lit.size() - 1, size_t(0.99 * double(lit.size())));
        std::nth_element(lit.begin(), lit.begin() + long(k), lit.end());
        return lit[k] > 0.0f ? 1.0 / lit[k] : 1.0;
    };
    const double sa = scaleOf(ca), sb = scaleOf(cb);
    RgbImage img(layers.width, layers.height);
    for (int y = 0; y < layers.height; ++y)
        for (int x = 0; x < layers.width; ++x) {
            const size_t i = size_t(y) * layers.width + x;
            const double r = ca[i] > threshold ? std::min(1.0, ca[i] * sa) : 0.0;
            const double g = cb[i] > threshold ? std::min(1.0, cb[i] * sb) : 0.0;
            img.set(x, y, {r, g, 0.0});
        }
    return img;
}

}  // namespace lobe
