#include "analysis/study_report.h"

#include "figure/image_text.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace lobe {

namespace {

std::string fmt(const char* format, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, format, v == 0.0 ? 0.0 : v);  // no "-0.00"
    if (std::string(buf).find_first_not_of("-0.") == std::string::npos && buf[0] == '-')
        return std::string(buf + 1);
    return buf;
}

bool hasJod(const StudyAnalysis& a) { return !a.jod.q.empty(); }
bool hasMarkers(const StudyAnalysis& a) {
    return std::any_of(a.markerAccuracy.begin(), a.markerAccuracy.end(),
                       [](const Proportion& p) { return p.trials > 0; });
}

void fillRect(RgbImage& img, int x0, int y0, int x1, int y1, const std::array<double, 3>& c) {
    for (int y = std::max(0, y0); y < std::min(img.height, y1); ++y)
        for (int x = std::max(0, x0); x < std::min(img.width, x1); ++x) img.set(x, y, c);
}

// A panel: values mapped from [lo, hi] to [x0, x1); ticks every `step` with labels.
struct Axis {
    int x0, x1;
    double lo, hi;
    int at(double v) const { return x0 + int(std::lround((v - lo) / (hi - lo) * (x1 - x0 - 1))); }
};

void drawPanel(RgbImage& img, const Axis& axis, int top, int rows, int rowHeight, double step,
               const char* tickFormat, const std::string& title, double reference) {
    const std::array<float, 3> black{0.0f, 0.0f, 0.0f};
    const int bottom = top + rows * rowHeight;
    drawText(img, (axis.x0 + axis.x1) / 2, top - 30, title, 15, black, true);
    for (double v = std::ceil(axis.lo / step) * step; v <= axis.hi + 1e-9; v += step) {
        const int x = axis.at(v);
        const double grey = std::fabs(v - reference) < 1e-9 ? 0.45 : 0.85;
        fillRect(img, x, top - 6, x + 1, bottom, {grey, grey, grey});
        drawText(img, x, bottom + 18, fmt(tickFormat, std::fabs(v) < 1e-12 ? 0.0 : v), 12, black,
                 true);
    }
    fillRect(img, axis.x0, bottom, axis.x1, bottom + 1, {0.0, 0.0, 0.0});
}

void drawEstimate(RgbImage& img, const Axis& axis, int y, double v, double lo, double hi,
                  const std::array<double, 3>& colour) {
    const int a = axis.at(lo), b = axis.at(hi), x = axis.at(v);
    fillRect(img, a, y - 1, b + 1, y + 2, colour);
    fillRect(img, a, y - 6, a + 2, y + 7, colour);
    fillRect(img, b - 1, y - 6, b + 1, y + 7, colour);
    fillRect(img, x - 4, y - 4, x + 5, y + 5, colour);
}

}  // namespace

std::string studyMarkdown(const StudyAnalysis& a, const std::vector<std::string>& inputs) {
    const int percent = int(std::lround(a.jod.level * 100));
    std::string md = "# Study results\n\n";
    md += std::to_string(inputs.size()) + " answers files; " + std::to_string(a.included.size()) +
          " participants analysed, " + std::to_string(a.excluded.size()) +
          " excluded for failed attention checks.\n\n";
    md += "| condition |";
    if (hasJod(a)) md += " JOD | " + std::to_string(percent) + " % interval |";
    if (hasMarkers(a))
        md += " marker task correct | accuracy | " + std::to_string(percent) + " % interval |";
    md += "\n|---|";
    if (hasJod(a)) md += "---:|---|";
    if (hasMarkers(a)) md += "---:|---:|---|";
    md += "\n";
    for (size_t i = 0; i < a.conditions.size(); ++i) {
        md += "| " + a.conditions[i] + " |";
        if (hasJod(a))
            md += " " + fmt("%.2f", a.jod.q[i]) + " | [" + fmt("%.2f", a.jod.low[i]) + ", " +
                  fmt("%.2f", a.jod.high[i]) + "] |";
        if (hasMarkers(a)) {
            const Proportion& p = a.markerAccuracy[i];
            if (p.trials == 0)
                md += " 0 of 0 | – | – |";
            else
                md += " " + std::to_string(p.successes) + " of " + std::to_string(p.trials) +
                      " | " + fmt("%.2f", p.p) + " | [" + fmt("%.2f", p.low) + ", " +
                      fmt("%.2f", p.high) + "] |";
        }
        md += "\n";
    }
    md += "\n";
    if (hasJod(a))
        md += "JOD: Thurstone case V maximum-likelihood scaling of " +
              std::to_string(a.pairTrials) +
              " paired comparisons (1 JOD: 75 % choose the better condition), relative to " +
              a.conditions.front() +
              " (0); higher means chosen more often. Intervals: percentile "
              "bootstrap over participants, " +
              std::to_string(a.jod.samples) + " resamples.\n";
    if (hasMarkers(a))
        md +=
            "Marker task: share of trials naming the object whose highlight the marker is on; "
            "Wilson score intervals.\n";
    md += "\nAnswers files:\n";
    for (const std::string& f : inputs) md += "- " + f + "\n";
    if (!a.excluded.empty()) {
        md += "\nExcluded:\n";
        for (const std::string& e : a.excluded) md += "- " + e + "\n";
    }
    return md;
}

std::string studyCsv(const StudyAnalysis& a) {
    std::string csv =
        "condition,jod,jod_low,jod_high,marker_correct,marker_trials,marker_accuracy,"
        "marker_low,marker_high\n";
    for (size_t i = 0; i < a.conditions.size(); ++i) {
        std::string name = a.conditions[i];
        if (name.find_first_of(",\"") != std::string::npos) {
            std::string quoted = "\"";
            for (char c : name) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
            name = quoted + "\"";
        }
        csv += name + ",";
        csv += hasJod(a) ? fmt("%.6f", a.jod.q[i]) + "," + fmt("%.6f", a.jod.low[i]) + "," +
                               fmt("%.6f", a.jod.high[i]) + ","
                         : ",,,";
        const Proportion& p = a.markerAccuracy[i];
        csv += std::to_string(p.successes) + "," + std::to_string(p.trials) + ",";
        csv += p.trials > 0
                   ? fmt("%.6f", p.p) + "," + fmt("%.6f", p.low) + "," + fmt("%.6f", p.high)
                   : ",,";
        csv += "\n";
    }
    return csv;
}

RgbImage studyPlot(const StudyAnalysis& a) {
    const int rows = int(a.conditions.size());
    const int rowHeight = 34, top = 70, labelWidth = 220, panel = 320, gap = 50;
    const bool jod = hasJod(a), markers = hasMarkers(a);
    const int panels = int(jod) + int(markers);
    RgbImage img(labelWidth + std::max(1, panels) * (panel + gap), top + rows * rowHeight + 50);
    fillRect(img, 0, 0, img.width, img.height, {1.0, 1.0, 1.0});
    const std::array<float, 3> black{0.0f, 0.0f, 0.0f};
    for (int i = 0; i < rows; ++i)
        drawText(img, 10, top + i * rowHeight + rowHeight / 2 + 5, a.conditions[size_t(i)], 14,
                 black);
    int x = labelWidth;
    const int percent = int(std::lround(a.jod.level * 100));
    if (jod) {
        double lo = 0.0, hi = 0.0;
        for (size_t i = 0; i < a.jod.q.size(); ++i) {
            lo = std::min(lo, a.jod.low[i]);
            hi = std::max(hi, a.jod.high[i]);
        }
        lo = std::floor(lo * 2.0 - 0.5) / 2.0;
        hi = std::ceil(hi * 2.0 + 0.5) / 2.0;
        const double step = hi - lo > 6.0 ? 1.0 : 0.5;
        const Axis axis{x, x + panel, lo, hi};
        drawPanel(img, axis, top, rows, rowHeight, step, "%.1f",
                  "JOD (" + std::to_string(percent) + " % bootstrap interval)", 0.0);
        for (int i = 0; i < rows; ++i)
            drawEstimate(img, axis, top + i * rowHeight + rowHeight / 2, a.jod.q[size_t(i)],
                         a.jod.low[size_t(i)], a.jod.high[size_t(i)], {0.05, 0.2, 0.6});
        x += panel + gap;
    }
    if (markers) {
        const Axis axis{x, x + panel, 0.0, 1.0};
        drawPanel(img, axis, top, rows, rowHeight, 0.25, "%.2f",
                  "marker task accuracy (" + std::to_string(percent) + " % Wilson)", -1.0);
        for (int i = 0; i < rows; ++i) {
            const Proportion& p = a.markerAccuracy[size_t(i)];
            if (p.trials > 0)
                drawEstimate(img, axis, top + i * rowHeight + rowHeight / 2, p.p, p.low, p.high,
                             {0.6, 0.15, 0.05});
        }
    }
    return img;
}

}  // namespace lobe
