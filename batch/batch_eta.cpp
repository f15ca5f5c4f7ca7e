#include "batch/batch_eta.h"

#include "core/error.h"
#include "figure/figure_output.h"

#include <algorithm>
#include <cmath>

namespace lobe {

bool needsCostSchedule(const std::vector<SceneSpec>& specs, int bandRowsRequested) {
    if (specs.size() > 1) return true;
    for (const SceneSpec& spec : specs)
        if (bandRowsFor(spec, bandRowsRequested) < spec.height) return true;
    return false;
}

int pilotStride(const SceneSpec& spec) {
    const double pixels = double(spec.width) * double(spec.height);
    const double target =
        std::clamp(pixels * double(std::max(1, spec.samplesPerPixel)) / 200.0, 1024.0, 16384.0);
    return std::max(1, int(std::sqrt(pixels / target)));
}

BatchPilot::BatchPilot(const std::vector<SceneSpec>& specs, int bandRowsRequested, int threads,
                       const std::function<bool(const SceneSpec&)>& skipped)
    : specs_(specs), threads_(threads), measured_(specs.size(), false) {
    for (size_t k = 0; k < specs.size(); ++k) {
        const SceneSpec& spec = specs[k];
        const int bandRows = std::max(1, bandRowsFor(spec, bandRowsRequested));
        bandRows_.push_back(bandRows);
        firstPart_.push_back(schedule_.partCount());
        if (skipped(spec)) {  // written already: done at once
            schedule_.addPart(int64_t(spec.width) * spec.height, 0.0);
            firstPart_.back() = -1;
            measured_[k] = true;
            continue;
        }
        for (int y0 = 0; y0 < spec.height; y0 += bandRows) {
            const int64_t pixels =
                int64_t(spec.width) * (std::min(spec.height, y0 + bandRows) - y0);
            schedule_.addUnknownPart(pixels, double(pixels) * std::max(1, spec.samplesPerPixel));
        }
    }
}

void BatchPilot::setParts(size_t index, const std::vector<double>& rowSeconds) {
    const SceneSpec& spec = specs_[index];
    const int bandRows = bandRows_[index];
    int part = firstPart_[index];
    for (int y0 = 0; y0 < spec.height; y0 += bandRows, ++part) {
        const int y1 = std::min(spec.height, y0 + bandRows);
        double seconds = 0.0;
        for (int y = y0; y < y1 && size_t(y) < rowSeconds.size(); ++y) seconds += rowSeconds[y];
        schedule_.setCost(part, seconds);
    }
    measured_[index] = true;
}

void BatchPilot::profileFirst(VolumeCache& volumes, std::unique_ptr<RenderScene>& assembled) {
    if (specs_.empty()) return;
    const SceneSpec& first = specs_.front();
    // The first scene's frames (an orbit), last to first, so that `assembled` ends at frame 0.
    size_t frames = 0;
    while (frames < specs_.size() && specs_[frames].path == first.path &&
           specs_[frames].group == first.group)
        ++frames;
    try {
        for (size_t k = frames; k-- > 0;) {
            if (measured_[k]) continue;
            if (assembled && assembled->spec().path == first.path &&
                assembled->spec().group == first.group) {
                assembled->setView(specs_[k]);
            } else {
                assembled.reset();
                assembled = std::make_unique<RenderScene>(specs_[k], false, &volumes);
            }
            setParts(k, assembled->costProfile(pilotStride(specs_[k]), threads_));
        }
    } catch (const Error&) {
        assembled.reset();  // the batch assembles it again and reports the error
    }
}

void BatchPilot::profile(size_t index, const RenderScene& scene) {
    if (index >= specs_.size() || measured_[index]) return;
    const std::vector<double> rows = scene.costProfile(pilotStride(specs_[index]), threads_);
    // The scene's later frames (an orbit) take the same profile: they share its cost closely.
    for (size_t k = index; k < specs_.size(); ++k) {
        if (specs_[k].path != specs_[index].path || specs_[k].group != specs_[index].group) break;
        if (!measured_[k] && specs_[k].width == specs_[index].width &&
            specs_[k].height == specs_[index].height)
            setParts(k, rows);
    }
}

}  // namespace lobe
