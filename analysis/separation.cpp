#include "analysis/separation.h"

#include "core/error.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace lobe {

std::vector<float> contrastLattice(const std::vector<float>& layer,
                                   const std::vector<float>& beauty) {
    std::vector<float> c(layer.size(), 0.0f);
    for (size_t i = 0; i < layer.size(); ++i)
        if (beauty[i] > 0.0f) c[i] = layer[i] / beauty[i];
    return c;
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
    SeparationLayers out;
    out.width = layers.width;
    out.height = layers.height;
    out.beauty = layers.beauty;
    int merged = -1;
    for (size_t o = 0; o < layers.objects.size(); ++o) {
        if (!member[o]) {
            out.objects.push_back(layers.objects[o]);
            out.specular.push_back(layers.specular[o]);
            out.total.push_back(layers.total[o]);
            continue;
        }
        if (merged < 0) {
            merged = int(out.objects.size());
            out.objects.push_back(name);
            out.specular.push_back(layers.specular[o]);
            out.total.push_back(layers.total[o]);
            continue;
        }
        for (size_t i = 0; i < layers.beauty.size(); ++i) {
            out.specular[size_t(merged)][i] += layers.specular[o][i];
            out.total[size_t(merged)][i] += layers.total[o][i];
        }
    }
    return out;
}

SeparationReport measureSeparation(const SeparationLayers& layers, double threshold) {
    const size_t n = size_t(layers.width) * layers.height;
    const size_t k = layers.objects.size();
    if (layers.specular.size() != k || layers.total.size() != k || layers.beauty.size() != n)
        throw Error("separation: layers do not match the image");
    SeparationReport report;
    report.threshold = threshold;
    std::vector<std::vector<float>> contrast(k);
    for (size_t o = 0; o < k; ++o) {
        contrast[o] = contrastLattice(layers.specular[o], layers.beauty);
        const std::vector<float> visible = contrastLattice(layers.total[o], layers.beauty);
        ObjectVisibility v;
        v.name = layers.objects[o];
        size_t seen = 0, shiny = 0;
        double sum = 0.0;
        for (size_t i = 0; i < n; ++i) {
            seen += visible[i] >= threshold;
            if (contrast[o][i] >= threshold) {
                ++shiny;
                sum += contrast[o][i];
            }
        }
        v.visibleShare = n ? double(seen) / double(n) : 0.0;
        v.specularShare = n ? double(shiny) / double(n) : 0.0;
        v.meanSpecularContrast = shiny ? sum / double(shiny) : 0.0;
        report.objects.push_back(v);
    }
    for (size_t a = 0; a < k; ++a)
        for (size_t b = a + 1; b < k; ++b) {
            PairSeparation p;
            p.a = int(a);
            p.b = int(b);
            p.metric = fluxOverlap(contrast[a].data(), contrast[b].data(), n, threshold);
            report.score += p.metric.eSum;
            report.pairs.push_back(p);
        }
    if (!report.pairs.empty()) report.score /= double(report.pairs.size());
    return report;
}

double separationScore(const std::vector<const float*>& specular, const float* beauty,
                       size_t count, double threshold) {
    const size_t k = specular.size();
    if (k < 2) return 0.0;
    // Per pair: areas and OA/OB of the contrast lattices (flux_overlap.h), summed in one pass.
    const size_t pairs = k * (k - 1) / 2;
    std::vector<double> OA(pairs, 0.0), OB(pairs, 0.0);
    std::vector<int64_t> area(k, 0);
    std::vector<double> c(k);
    for (size_t i = 0; i < count; ++i) {
        const double y = beauty[i];
        for (size_t o = 0; o < k; ++o) {
            c[o] = y > 0.0 ? double(float(specular[o][i] / y)) : 0.0;
            area[o] += c[o] > threshold;
        }
        size_t p = 0;
        for (size_t a = 0; a < k; ++a)
            for (size_t b = a + 1; b < k; ++b, ++p) {
                const OverlapContribution cd = overlapContribution(c[a], c[b], threshold);
                OA[p] += cd.c;
                OB[p] += cd.d;
            }
    }
    double score = 0.0;
    size_t p = 0;
    for (size_t a = 0; a < k; ++a)
        for (size_t b = a + 1; b < k; ++b, ++p)
            if (area[a] > 0 && area[b] > 0)
                score += std::min(OA[p] / double(area[a]), OB[p] / double(area[b]));
    return score / double(pairs);
}

namespace {

std::string fmt(const char* f, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, f, v);
    return buf;
}

}  // namespace

std::string separationCsv(const SeparationReport& r, const std::vector<std::string>& objects) {
    std::string out = "kind,a,b,score,visible_share,specular_share,mean_specular_contrast,area_a,area_b\n";
    for (const ObjectVisibility& v : r.objects)
        out += "object," + v.name + ",," + ",," + fmt("%.6g", v.visibleShare) + "," +
               fmt("%.6g", v.specularShare) + "," + fmt("%.6g", v.meanSpecularContrast) + ",,\n";
    for (const PairSeparation& p : r.pairs)
        out += "pair," + objects[size_t(p.a)] + "," + objects[size_t(p.b)] + "," +
               fmt("%.6g", p.metric.eSum) + ",,,," + std::to_string(p.metric.areaA) + "," +
               std::to_string(p.metric.areaB) + "\n";
    out += "scene,,," + fmt("%.6g", r.score) + ",,,,,\n";
    return out;
}

std::string separationMarkdown(const SeparationReport& r, const std::vector<std::string>& objects,
                               const std::string& title) {
    std::string out = "# Separation: " + title + "\n\nScene score (mean over pairs): **" +
                      fmt("%.4g", r.score) + "**; threshold: Weber contrast " +
                      fmt("%.3g", r.threshold) + " (docs/separation.md).\n\n" +
                      "| object | visible | highlight visible | mean highlight contrast |\n"
                      "|---|---:|---:|---:|\n";
    for (const ObjectVisibility& v : r.objects)
        out += "| " + v.name + " | " + fmt("%.1f %%", 100 * v.visibleShare) + " | " +
               fmt("%.1f %%", 100 * v.specularShare) + " | " +
               fmt("%.3f", v.meanSpecularContrast) + " |\n";
    out += "\n| pair | score | highlight pixels A | highlight pixels B |\n|---|---:|---:|---:|\n";
    for (const PairSeparation& p : r.pairs)
        out += "| " + objects[size_t(p.a)] + " / " + objects[size_t(p.b)] + " | " +
               fmt("%.4g", p.metric.eSum) + " | " + std::to_string(p.metric.areaA) + " | " +
               std::to_string(p.metric.areaB) + " |\n";
    return out;
}

RgbImage separationMap(const SeparationLayers& layers, int a, int b, double threshold) {
    const std::vector<float> ca = contrastLattice(layers.specular[size_t(a)], layers.beauty);
    const std::vector<float> cb = contrastLattice(layers.specular[size_t(b)], layers.beauty);
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
