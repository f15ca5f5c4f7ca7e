// What `lobe overlap` writes (docs/flux-overlap.md, "What the tool reports"): the ranked
// table as CSV and Markdown, a heat map of the pair scores, and lobe images in the style of the
// paper's Figures 8 and 9 (A in red, B in green, overlap yellow). Everything is built in memory
// first and each file is written under a temporary name and renamed, so an error never leaves a
// partial file.
#pragma once

#include "analysis/overlap_ranking.h"
#include "core/rgb_image.h"

#include <string>
#include <utility>
#include <vector>

namespace lobe {

// Header: rank,score,model_a,model_b,score_mse,sphere,torus,superquadric. `score` and the
// per-primitive columns are of the ranking variant; score_mse is always the mse variant.
std::string overlapCsv(const std::vector<PairScore>& pairs);

// The same table in Markdown, after a short header naming the settings (`settingsLine`).
std::string overlapMarkdown(const std::vector<PairScore>& pairs, const std::string& settingsLine,
                            OverlapVariant variant);

// n×n heat map of the pair scores (symmetric; the diagonal is grey, a model is not paired with
// itself), with row names, column numbers and each cell's score.
RgbImage overlapHeatmap(const std::vector<PairScore>& pairs,
                        const std::vector<std::string>& models);

// Rows: the three primitives; columns: A (red), B (green), both (red + green = yellow where the
// lobes overlap). Each lattice is the band mean, pixels ≤ threshold black, scaled by its own 99th
// percentile of lit pixels.
RgbImage lobeImage(const LatticeSet& lattices, int modelA, int modelB, double threshold);

// The convergence study as a Markdown table (one row per lattice size × samples per pixel).
std::string studyMarkdown(const std::vector<StudyRow>& rows);

// writeTextFileAtomic (text via a temporary sibling and rename): core/temporary_file.h.

struct OverlapReportFiles {
    std::string csv, markdown, heatmap;
    std::vector<std::string> lobeImages;
};

// Writes overlap.csv, overlap.md, overlap-heatmap.png and lobes/<a>_vs_<b>.png for the best and
// the worst pair and each of `extraPairs` (model names) into `outDir` (created if missing).
OverlapReportFiles writeOverlapReport(
    const std::string& outDir, const LatticeSet& lattices, const std::vector<PairScore>& pairs,
    const std::vector<std::pair<std::string, std::string>>& extraPairs, double threshold,
    OverlapVariant variant, const std::string& settingsLine);

}  // namespace lobe
