// The tables of `lobe cost` and `lobe render --stats` (render/render_cost.h measures; this only
// lays the numbers out): Markdown for people, CSV for scripts.
#pragma once

#include "render/render_cost.h"
#include "render/scene_description.h"

#include <string>
#include <vector>

namespace lobe {

// One render of the comparison: the scene as written ("scene") or with a model swapped in.
struct CostRun {
    std::string label;
    SceneSpec spec;
    RenderCost cost;
};

// The first run's parts and objects; with more runs, a table of the models on object `target`.
std::string costMarkdown(const std::vector<CostRun>& runs, int target, int threads, int repeat);
// One row per run and part, object and total: run,row,name,model,shaded_points,
// brdf_evaluations,cpu_seconds,ns_per_evaluation.
std::string costCsv(const std::vector<CostRun>& runs);
// The parts and objects of one render as plain text lines (for `lobe render --stats`).
std::string costSummary(const SceneSpec& spec, const RenderCost& cost);

}  // namespace lobe
