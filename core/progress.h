// Progress of a long computation, shown on standard error: a redrawn bar with ETA when stderr is
// a terminal, plain periodic lines otherwise (logs, CI: each tenth of the work, or every 10 s,
// once a second has passed). Thread-safe: workers call advance().
//
// The ETA is elapsed · (1 − f)/f, f the fraction of the work's cost that is done. Without a cost
// schedule f is the fraction of units (pixels) done: honest when the units done are a fair sample
// of the cost, which is why an image's tiles are rendered in a shuffled order
// (core/tile_scheduler.h, tileOrder). It is not when the work comes in parts done one after
// another whose cost per pixel differs — a poster's bands (the sky first, the skull below), the
// scenes of a batch: "ETA 14.5 s" at 10 % of a poster that took 6 min 48 s (issue 31). Then the
// caller gives a CostSchedule: each part's predicted cost, measured before the work starts (a
// pilot: RenderScene::costProfile), and f is the predicted cost of the parts done plus the done
// share of the current part's, over the total.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

namespace lobe {

// Parts of a run done in order — scenes, orbit frames, bands of rows — each `units` (pixels) long
// with a predicted cost (any unit: the ratios matter). Within the part under way the units done
// count for their share of its cost: its tiles go in a shuffled order, so the pixels done are a
// fair sample of it. A part whose cost is not measured yet (a batch's later scenes, measured when
// they are assembled) is priced by its `weight` (pixels × samples) at the cost per weight of the
// parts measured by setCost, until setCost gives its own.
class CostSchedule {
public:
    // Appends a part; a cost < 0 or not finite counts as 0, units <= 0 adds nothing. Returns
    // the part's index (-1 when nothing was added).
    int addPart(int64_t units, double predictedCost);
    int addUnknownPart(int64_t units, double weight);
    // The measured cost of part `index` (from then on it is known).
    void setCost(int index, double predictedCost);
    int partCount() const { return int(ends_.size()); }
    bool empty() const { return ends_.empty(); }
    int64_t totalUnits() const { return ends_.empty() ? 0 : ends_.back(); }
    double totalCost() const { return cumulative_.empty() ? 0.0 : cumulative_.back(); }
    // The cost of part `index` as the schedule prices it now.
    double partCost(int index) const { return priced_[size_t(index)]; }
    // The predicted cost of the first `unitsDone` units.
    double costDone(int64_t unitsDone) const;
    // costDone / totalCost in [0, 1]; the fraction of units when every cost is 0.
    double fractionDone(int64_t unitsDone) const;

private:
    void price();

    std::vector<int64_t> ends_;       // units at the end of each part
    std::vector<double> costs_;       // each part's measured cost (NaN: not yet)
    std::vector<double> weights_;     // addUnknownPart's weights (0 for addPart's parts)
    std::vector<double> priced_;      // each part's cost as priced
    std::vector<double> cumulative_;  // priced cost at the end of each part
};

// Seconds left of a run `fraction` done (of its cost) after `elapsed` seconds: elapsed ·
// (1 − f)/f; infinite before anything is done.
double remainingSeconds(double elapsed, double fraction);

// Seconds of loading still to come when `loadsDone` of `loadsExpected` loads (a batch assembling
// its scenes between renders) took `loadSeconds`: the loads left at the mean of those done; 0 when
// none is expected or none is done yet.
double remainingLoadSeconds(double loadSeconds, int loadsDone, int loadsExpected);

class ProgressReporter {
public:
    // enabled = false prints nothing at all (tests, benchmarks, --quiet).
    ProgressReporter(std::string label, int64_t totalUnits, bool enabled);
    ~ProgressReporter();

    void advance(int64_t units = 1);
    // Prints the final line (with the total time). Called by the destructor if not before.
    void finish();

    // Time counted towards the ETA: since construction, less the paused time.
    double elapsedSeconds() const;
    // Stop and restart that clock, for work between the units that is not theirs (a batch
    // assembling its next scene between renders): it does not slow the ETA's rate, and the final
    // line shows it apart ("done in 20.1 s (+ 1.3 s loading)").
    void pause();
    void resume();
    // How many pauses (loads) the whole run will take: the ETA then adds the loads still to come
    // at the mean time of those done (remainingLoadSeconds), so a batch whose scenes take longer
    // to assemble than to render is not promised too early an end. 0 (the default): none added.
    void expectLoads(int loads);
    // From now on the share done — the bar's percentage and the ETA — is the schedule's
    // fractionDone of the units done (its totalUnits should be this reporter's total). The
    // schedule must outlive the reporter's use; set it before the work starts.
    void setSchedule(const CostSchedule* schedule);
    // The share of the work done, by the schedule when there is one, else by units.
    double fractionDone() const;

private:
    void print(int64_t done, bool final);
    double fractionAt(int64_t done) const;

    std::string label_;
    int64_t total_;
    const CostSchedule* schedule_ = nullptr;
    bool enabled_;
    bool terminal_;
    bool finished_ = false;
    std::atomic<int64_t> done_{0};
    std::mutex printMutex_;
    std::chrono::steady_clock::time_point start_;
    std::chrono::steady_clock::time_point lastPrint_;
    int lastDecile_ = 0;  // a log gets its first line after a tenth of the work
    mutable std::mutex clockMutex_;
    double pausedSeconds_ = 0.0;
    int loadsDone_ = 0;      // pauses ended
    int loadsExpected_ = 0;  // expectLoads
    bool paused_ = false;
    std::chrono::steady_clock::time_point pausedAt_;
};

// "1.2 s", "3 min 04 s", "2 h 05 min": durations for people.
std::string formatDuration(double seconds);

}  // namespace lobe
