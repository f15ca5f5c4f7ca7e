// Reports of the flux-overlap test: CSV, Markdown, heat map, lobe images (flux-overlap.md,
// "What the tool reports"; the paper's Figures 7–9).
#include "analysis/overlap_report.h"

#include "core/error.h"
#include "core/format.h"
#include "core/image_output.h"
#include "core/math.h"
#include "core/spectrum.h"
#include "core/temporary_file.h"
#include "figure/image_text.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>

namespace lobe {
namespace {

namespace fs = std::filesystem;

// Linear-sRGB value of an sRGB-encoded 8-bit component (IEC 61966-2-1 inverse transfer).
double srgbDecode(double c) {
    c /= 255.0;
    return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

// Viridis (van der Walt & Smith, matplotlib) sampled at 5 stops, interpolated in sRGB: a
// perceptually ordered scale that reads in grey print too.
std::array<double, 3> viridis(double x) {
    static const double stops[5][3] = {
        {68, 1, 84}, {59, 82, 139}, {33, 145, 140}, {94, 201, 98}, {253, 231, 37}};
    x = clamp01(x) * 4.0;
    const int i = std::min(3, int(x));
    const double f = x - i;
    std::array<double, 3> out;
    for (int c = 0; c < 3; ++c) out[c] = srgbDecode(stops[i][c] * (1.0 - f) + stops[i + 1][c] * f);
    return out;
}

void fillRect(RgbImage& img, int x0, int y0, int x1, int y1, const std::array<double, 3>& c) {
    for (int y = std::max(0, y0); y < std::min(img.height, y1); ++y)
        for (int x = std::max(0, x0); x < std::min(img.width, x1); ++x) img.set(x, y, c);
}

// Band mean of a model's lattice, pixels ≤ threshold set to 0, scaled to [0,1] by the 99th
// percentile of the remaining (lit) pixels.
std::vector<float> lobeIntensity(const LatticeSet& set, int model, int primitive,
                                 double threshold) {
    const size_t n = set.latticeSize();
    std::vector<float> v(n, 0.0f);
    std::vector<float> lit;
    for (size_t i = 0; i < n; ++i) {
        const double mean =
            (double(set.lattice(model, primitive, 0)[i]) + set.lattice(model, primitive, 1)[i] +
             set.lattice(model, primitive, 2)[i]) /
            3.0;
        if (mean > threshold) {
            v[i] = float(mean);
            lit.push_back(float(mean));
        }
    }
    if (lit.empty()) return v;
    const size_t k = std::min(lit.size() - 1, size_t(0.99 * double(lit.size())));
    std::nth_element(lit.begin(), lit.begin() + k, lit.end());
    const float scale = lit[k] > 0.0f ? 1.0f / lit[k] : 0.0f;
    for (float& x : v) x = std::min(1.0f, x * scale);
    return v;
}

}  // namespace

std::string overlapCsv(const std::vector<PairScore>& pairs) {
    std::string out = "rank,score,model_a,model_b,score_mse";
    for (const char* p : kStandardPrimitiveNames) out += std::string(",") + p;
    out += "\n";
    for (const PairScore& p : pairs) {
        out += std::to_string(p.rank) + "," + formatNumber("%.9g", p.score) + "," + p.modelA + "," +
               p.modelB + "," + formatNumber("%.9g", p.scoreMse);
        for (double v : p.perPrimitive) out += "," + formatNumber("%.9g", v);
        out += "\n";
    }
    return out;
}

std::string overlapMarkdown(const std::vector<PairScore>& pairs, const std::string& settingsLine,
                            OverlapVariant variant) {
    std::string out = "# Total flux overlap: ranking of BRDF pairs\n\n";
    out += settingsLine + "\n\n";
    out += std::string("Score: variant `") + overlapVariantName(variant) +
           "`, mean over 3 primitives × 3 bands; high = lobes stay apart (a good pair). "
           "Per-primitive columns: the same variant, mean over the bands.\n\n";
    out += "| rank | score | model A | model B | score (mse) | sphere | torus | superquadric |\n";
    out += "|---:|---:|---|---|---:|---:|---:|---:|\n";
    for (const PairScore& p : pairs) {
        out += "| " + std::to_string(p.rank) + " | " + formatNumber("%.4g", p.score) + " | " +
               p.modelA + " | " + p.modelB + " | " + formatNumber("%.4g", p.scoreMse);
        for (double v : p.perPrimitive) out += " | " + formatNumber("%.4g", v);
        out += " |\n";
    }
    return out;
}

RgbImage overlapHeatmap(const std::vector<PairScore>& pairs,
                        const std::vector<std::string>& models) {
    const int n = int(models.size());
    constexpr int kCell = 64, kLeft = 200, kTop = 40, kBottom = 56, kRight = 16;
    RgbImage img(kLeft + n * kCell + kRight, kTop + n * kCell + kBottom);
    fillRect(img, 0, 0, img.width, img.height, {1.0, 1.0, 1.0});
    double lo = 0.0, hi = 0.0;
    if (!pairs.empty()) {
        lo = hi = pairs.front().score;
        for (const PairScore& p : pairs) {
            lo = std::min(lo, p.score);
            hi = std::max(hi, p.score);
        }
    }
    std::vector<double> grid(size_t(n) * n, -1.0);
    for (const PairScore& p : pairs)
        grid[size_t(p.a) * n + p.b] = grid[size_t(p.b) * n + p.a] = p.score;
    const std::array<float, 3> black{0.0f, 0.0f, 0.0f}, white{1.0f, 1.0f, 1.0f};
    for (int r = 0; r < n; ++r) {
        drawText(img, 8, kTop + r * kCell + kCell / 2 + 6, std::to_string(r + 1) + " " + models[r],
                 16, black);
        drawText(img, kLeft + r * kCell + kCell / 2, kTop - 12, std::to_string(r + 1), 16, black,
                 true);
        for (int c = 0; c < n; ++c) {
            const int x0 = kLeft + c * kCell, y0 = kTop + r * kCell;
            const double v = grid[size_t(r) * n + c];
            if (r == c || v < 0.0) {
                fillRect(img, x0 + 1, y0 + 1, x0 + kCell - 1, y0 + kCell - 1, {0.5, 0.5, 0.5});
                continue;
            }
            const double x = hi > lo ? (v - lo) / (hi - lo) : 0.5;
            fillRect(img, x0 + 1, y0 + 1, x0 + kCell - 1, y0 + kCell - 1, viridis(x));
            drawText(img, x0 + kCell / 2, y0 + kCell / 2 + 5, formatNumber("%.3g", v), 13,
                     x > 0.6 ? black : white, true);
        }
    }
    // Colour bar: low (much overlap) to high (lobes apart).
    const int barY = kTop + n * kCell + 12, barW = n * kCell;
    for (int x = 0; x < barW; ++x)
        fillRect(img, kLeft + x, barY, kLeft + x + 1, barY + 14, viridis(double(x) / (barW - 1)));
    drawText(img, kLeft, barY + 34, formatNumber("%.3g", lo) + " (much overlap)", 13, black);
    drawText(img, kLeft + barW - 150, barY + 34, formatNumber("%.3g", hi) + " (apart)", 13, black);
    return img;
}

RgbImage lobeImage(const LatticeSet& set, int modelA, int modelB, double threshold) {
    const int s = set.size;
    constexpr int kHeader = 28, kGap = 4;
    RgbImage img(3 * s + 2 * kGap,
                 kHeader + kStandardPrimitiveCount * s + (kStandardPrimitiveCount - 1) * kGap);
    for (int p = 0; p < kStandardPrimitiveCount; ++p) {
        const std::vector<float> a = lobeIntensity(set, modelA, p, threshold);
        const std::vector<float> b = lobeIntensity(set, modelB, p, threshold);
        const int y0 = kHeader + p * (s + kGap);
        for (int y = 0; y < s; ++y)
            for (int x = 0; x < s; ++x) {
                const size_t i = size_t(y) * s + x;
                img.set(x, y0 + y, {a[i], 0.0, 0.0});
                img.set(s + kGap + x, y0 + y, {0.0, b[i], 0.0});
                img.set(2 * (s + kGap) + x, y0 + y, {a[i], b[i], 0.0});
            }
    }
    const int fontSize = std::max(10, std::min(18, s / 12));
    drawText(img, s / 2, 20, set.models[modelA], fontSize, {1.0f, 0.3f, 0.3f}, true);
    drawText(img, s + kGap + s / 2, 20, set.models[modelB], fontSize, {0.3f, 1.0f, 0.3f}, true);
    drawText(img, 2 * (s + kGap) + s / 2, 20, "combined", fontSize, {1.0f, 1.0f, 0.3f}, true);
    return img;
}

std::string studyMarkdown(const std::vector<StudyRow>& rows) {
    std::string out =
        "| lattice | spp | time (s) | CPU (s) | mean rel. score change | max rel. score change | "
        "Kendall tau | discordant pairs of pairs | same best | same worst |\n"
        "|---:|---:|---:|---:|---:|---:|---:|---:|:-:|:-:|\n";
    for (const StudyRow& r : rows) {
        out += "| " + std::to_string(r.size) + "² | " + std::to_string(r.samplesPerPixel) + " | " +
               formatNumber("%.2f", r.seconds) + " | " + formatNumber("%.2f", r.cpuSeconds) +
               " | " + formatNumber("%.2e", r.meanRelChange) + " | " +
               formatNumber("%.2e", r.maxRelChange) + " | " +
               formatNumber("%.4f", r.agreement.kendallTau) + " | " +
               std::to_string(r.agreement.discordant) + " / " +
               std::to_string(r.agreement.comparable) + " | " + (r.sameBest ? "yes" : "no") +
               " | " + (r.sameWorst ? "yes" : "no") + " |\n";
    }
    return out;
}

OverlapReportFiles writeOverlapReport(
    const std::string& outDir, const LatticeSet& lattices, const std::vector<PairScore>& pairs,
    const std::vector<std::pair<std::string, std::string>>& extraPairs, double threshold,
    OverlapVariant variant, const std::string& settingsLine) {
    if (pairs.empty()) throw Error("flux-overlap report: no pairs");
    // Which lobe images: best, worst, then the requested pairs (A red in the order given).
    std::vector<std::pair<int, int>> lobePairs = {{pairs.front().a, pairs.front().b},
                                                  {pairs.back().a, pairs.back().b}};
    for (const auto& [a, b] : extraPairs) {
        const int ia = lattices.modelIndex(a), ib = lattices.modelIndex(b);
        if (ia < 0 || ib < 0 || ia == ib)
            throw Error("--pair " + a + "," + b + ": expected two different models of the test");
        lobePairs.push_back({ia, ib});
    }
    // Build everything before writing anything.
    const std::string csv = overlapCsv(pairs);
    const std::string md = overlapMarkdown(pairs, settingsLine, variant);
    const RgbImage heat = overlapHeatmap(pairs, lattices.models);
    std::vector<std::pair<std::string, RgbImage>> lobes;
    std::set<std::pair<int, int>> seen;
    for (const auto& [a, b] : lobePairs) {
        if (!seen.insert({a, b}).second) continue;
        lobes.push_back({lattices.models[a] + "_vs_" + lattices.models[b] + ".png",
                         lobeImage(lattices, a, b, threshold)});
    }

    std::error_code ec;
    const fs::path dir(outDir), lobeDir = fs::path(outDir) / "lobes";
    fs::create_directories(lobeDir, ec);
    if (ec || !fs::is_directory(lobeDir))
        throw Error("--out: cannot create folder '" + lobeDir.string() + "'" +
                    (ec ? ": " + ec.message() : ""));
    OverlapReportFiles files;
    files.csv = (dir / "overlap.csv").string();
    files.markdown = (dir / "overlap.md").string();
    files.heatmap = (dir / "overlap-heatmap.png").string();
    writeTextFileAtomic(files.csv, csv);
    writeTextFileAtomic(files.markdown, md);
    writeImage(files.heatmap, heat);
    for (const auto& [name, image] : lobes) {
        files.lobeImages.push_back((lobeDir / name).string());
        writeImage(files.lobeImages.back(), image);
    }
    return files;
}

}  // namespace lobe
