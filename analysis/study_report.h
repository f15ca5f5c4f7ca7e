// The tables and plot of `lobe study analyse` (docs/study.md) for a StudyAnalysis
// (analysis/study.h): Markdown, CSV and a PNG drawn with the project's own image and text code.
#pragma once

#include "analysis/study.h"
#include "core/rgb_image.h"

#include <string>
#include <vector>

namespace lobe {

// One row per condition: JOD with its bootstrap interval, marker accuracy with its Wilson
// interval; the participants analysed and excluded. `inputs`: the answers files, listed.
std::string studyMarkdown(const StudyAnalysis& analysis, const std::vector<std::string>& inputs);
// Header: condition,jod,jod_low,jod_high,marker_correct,marker_trials,marker_accuracy,
// marker_low,marker_high (empty cells where a task had no trials).
std::string studyCsv(const StudyAnalysis& analysis);
// JOD per condition (dot and interval bar) and, when there were marker trials, accuracy per
// condition beside it; white background, one row per condition.
RgbImage studyPlot(const StudyAnalysis& analysis);

}  // namespace lobe
