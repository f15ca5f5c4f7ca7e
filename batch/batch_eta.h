// An honest ETA for a run of scenes (issue 31): "ETA 14.5 s" at 10 % of a 4096² poster that took
// 6 min 48 s, because the poster's first bands are sky and its later ones skull, and a batch's
// scenes differ in cost per pixel (the paper's 24 renderings by their BRDFs). The progress
// display counts pixels; what it shows as done is the measured cost of the parts done instead
// (core/progress.h, CostSchedule): a pilot traces one sample through a sparse grid of pixels of a
// scene, each row of it timed by its thread's CPU clock (RenderScene::costProfile), and each part
// — a band of rows of a frame of a scene — is predicted to cost what its pilot samples cost,
// scaled to its pixels and samples. The ETA is then elapsed · (predicted cost left / predicted
// cost done): the ratios come from the pilot, the seconds from the clock.
#pragma once

#include "core/progress.h"
#include "render/render_scene.h"
#include "render/scene_description.h"

#include <functional>
#include <memory>
#include <vector>

namespace lobe {

class VolumeCache;

// Whether the run comes in parts whose cost per pixel can differ: several scenes or frames, or
// an image in more than one band (figure/figure_output.h, bandRowsFor).
bool needsCostSchedule(const std::vector<SceneSpec>& specs, int bandRowsRequested);

// The pilot's spacing for a scene: about one traced pixel in 200 samples of the render, at
// least 1024 and at most 16384 pixels (a few tenths of a percent of a poster's work).
int pilotStride(const SceneSpec& spec);

// The schedule of a batch in render order, and the pilot of its scenes. The first scene is
// profiled before anything renders (its orbit's frames too, turned by setView; `assembled` ends
// holding it, so the batch does not build it again); every other scene when the batch assembles
// it to render (profile), priced until then at the measured scenes' cost per pixel and sample —
// profiling them all up front would build each twice (1.3 s a paper scene, more than its render
// at small sizes). `skipped` scenes (--skip-existing) cost nothing.
class BatchPilot {
public:
    BatchPilot(const std::vector<SceneSpec>& specs, int bandRowsRequested, int threads,
               const std::function<bool(const SceneSpec&)>& skipped);
    // Profiles the first scene (and its frames) into `assembled`; a scene that fails to
    // assemble stays priced by its pixels (the batch reports the error).
    void profileFirst(VolumeCache& volumes, std::unique_ptr<RenderScene>& assembled);
    // Scene `index` just assembled as `scene`: its parts, and those of its later frames not yet
    // measured, get its profile. Does nothing when they are measured already.
    void profile(size_t index, const RenderScene& scene);
    const CostSchedule& schedule() const { return schedule_; }

private:
    void setParts(size_t index, const std::vector<double>& rowSeconds);

    const std::vector<SceneSpec>& specs_;
    std::vector<int> bandRows_;
    int threads_;
    std::vector<int> firstPart_;  // each scene's first part in the schedule (-1: none)
    std::vector<bool> measured_;
    CostSchedule schedule_;
};

}  // namespace lobe
