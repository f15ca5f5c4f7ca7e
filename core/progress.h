// Progress of a long computation, shown on standard error: a redrawn bar with ETA when stderr is
// a terminal, plain periodic lines otherwise (logs, CI: each tenth of the work, or every 10 s,
// once a second has passed). Thread-safe: workers call advance().
//
// The ETA is elapsed · (1 − f)/f, f the fraction of units done: honest when the units done are a
// fair sample of the cost, which is why images are rendered in a shuffled tile order
// (core/tile_scheduler.h, tileOrder).
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>

namespace lobe {

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

private:
    void print(int64_t done, bool final);

    std::string label_;
    int64_t total_;
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
    bool paused_ = false;
    std::chrono::steady_clock::time_point pausedAt_;
};

// "1.2 s", "3 min 04 s", "2 h 05 min": durations for people.
std::string formatDuration(double seconds);

}  // namespace lobe
