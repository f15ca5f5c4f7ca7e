// Progress of a long computation, shown on standard error: a redrawn bar with ETA when stderr is
// a terminal, plain periodic lines otherwise (logs, CI). Thread-safe: workers call advance().
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

    double elapsedSeconds() const;

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
};

// "1.2 s", "3 min 04 s", "2 h 05 min": durations for people.
std::string formatDuration(double seconds);

}  // namespace lobe
