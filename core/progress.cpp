#include "core/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace lobe {

namespace {
constexpr double kQuietSeconds = 1.0;
}  // namespace

std::string formatDuration(double seconds) {
    char buf[64];
    if (seconds < 60.0) {
        std::snprintf(buf, sizeof buf, "%.1f s", seconds);
    } else if (seconds < 3600.0) {
        const int s = static_cast<int>(seconds + 0.5);
        std::snprintf(buf, sizeof buf, "%d min %02d s", s / 60, s % 60);
    } else {
        const int m = static_cast<int>(seconds / 60.0 + 0.5);
        std::snprintf(buf, sizeof buf, "%d h %02d min", m / 60, m % 60);
    }
    return buf;
}

namespace {
double validCost(double cost) { return std::isfinite(cost) && cost > 0.0 ? cost : 0.0; }
}  // namespace

int CostSchedule::addPart(int64_t units, double predictedCost) {
    if (units <= 0) return -1;
    ends_.push_back(totalUnits() + units);
    costs_.push_back(validCost(predictedCost));
    weights_.push_back(0.0);
    price();
    return int(ends_.size()) - 1;
}

int CostSchedule::addUnknownPart(int64_t units, double weight) {
    if (units <= 0) return -1;
    ends_.push_back(totalUnits() + units);
    costs_.push_back(std::numeric_limits<double>::quiet_NaN());
    weights_.push_back(validCost(weight));
    price();
    return int(ends_.size()) - 1;
}

void CostSchedule::setCost(int index, double predictedCost) {
    if (index < 0 || size_t(index) >= costs_.size()) return;
    costs_[size_t(index)] = validCost(predictedCost);
    price();
}

void CostSchedule::price() {
    // The measured parts that have a weight give the cost per weight; an unknown part costs its
    // weight at that rate (before any is measured, its weight: only the ratios matter then).
    double knownCost = 0.0, knownWeight = 0.0;
    for (size_t k = 0; k < ends_.size(); ++k)
        if (!std::isnan(costs_[k]) && weights_[k] > 0.0) {
            knownCost += costs_[k];
            knownWeight += weights_[k];
        }
    const double rate = knownWeight > 0.0 ? knownCost / knownWeight : 1.0;
    priced_.assign(ends_.size(), 0.0);
    cumulative_.assign(ends_.size(), 0.0);
    double sum = 0.0;
    for (size_t k = 0; k < ends_.size(); ++k) {
        priced_[k] = std::isnan(costs_[k]) ? rate * weights_[k] : costs_[k];
        sum += priced_[k];
        cumulative_[k] = sum;
    }
}

double CostSchedule::costDone(int64_t unitsDone) const {
    if (ends_.empty() || unitsDone <= 0) return 0.0;
    if (unitsDone >= ends_.back()) return cumulative_.back();
    // The part under way: the first whose end lies beyond the units done.
    const size_t k =
        size_t(std::upper_bound(ends_.begin(), ends_.end(), unitsDone) - ends_.begin());
    const int64_t begin = k == 0 ? 0 : ends_[k - 1];
    const double before = k == 0 ? 0.0 : cumulative_[k - 1];
    return before + priced_[k] * double(unitsDone - begin) / double(ends_[k] - begin);
}

double CostSchedule::fractionDone(int64_t unitsDone) const {
    if (ends_.empty()) return 0.0;
    if (!(totalCost() > 0.0)) return std::clamp(double(unitsDone) / double(totalUnits()), 0.0, 1.0);
    return std::clamp(costDone(unitsDone) / totalCost(), 0.0, 1.0);
}

double remainingSeconds(double elapsed, double fraction) {
    if (!(fraction > 0.0)) return std::numeric_limits<double>::infinity();
    return elapsed * (1.0 - std::min(fraction, 1.0)) / fraction;
}

double remainingLoadSeconds(double loadSeconds, int loadsDone, int loadsExpected) {
    if (loadsDone <= 0 || loadsExpected <= loadsDone) return 0.0;
    return loadSeconds / loadsDone * (loadsExpected - loadsDone);
}

ProgressReporter::ProgressReporter(std::string label, int64_t totalUnits, bool enabled)
    : label_(std::move(label)),
      total_(totalUnits > 0 ? totalUnits : 1),
      enabled_(enabled),
      terminal_(isatty(STDERR_FILENO) != 0),
      start_(std::chrono::steady_clock::now()),
      lastPrint_(start_) {}

ProgressReporter::~ProgressReporter() { finish(); }

double ProgressReporter::elapsedSeconds() const {
    std::lock_guard<std::mutex> lock(clockMutex_);
    const auto end = paused_ ? pausedAt_ : std::chrono::steady_clock::now();
    return std::chrono::duration<double>(end - start_).count() - pausedSeconds_;
}

void ProgressReporter::pause() {
    std::lock_guard<std::mutex> lock(clockMutex_);
    if (paused_) return;
    paused_ = true;
    pausedAt_ = std::chrono::steady_clock::now();
}

void ProgressReporter::resume() {
    std::lock_guard<std::mutex> lock(clockMutex_);
    if (!paused_) return;
    paused_ = false;
    pausedSeconds_ +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - pausedAt_).count();
    ++loadsDone_;
}

void ProgressReporter::expectLoads(int loads) {
    std::lock_guard<std::mutex> lock(clockMutex_);
    loadsExpected_ = loads;
}

void ProgressReporter::setSchedule(const CostSchedule* schedule) {
    schedule_ = schedule && !schedule->empty() ? schedule : nullptr;
}

double ProgressReporter::fractionAt(int64_t done) const {
    return schedule_ ? schedule_->fractionDone(done) : std::min(1.0, double(done) / double(total_));
}

double ProgressReporter::fractionDone() const { return fractionAt(done_.load()); }

void ProgressReporter::advance(int64_t units) {
    const int64_t done = done_.fetch_add(units) + units;
    if (!enabled_) return;
    const auto now = std::chrono::steady_clock::now();
    // On a terminal redraw at most 10 times a second; in a log print each tenth of the work, or
    // every 10 s when tenths are slow, so a CI log stays short but never silent for long.
    std::unique_lock<std::mutex> lock(printMutex_, std::try_to_lock);
    if (!lock.owns_lock() || finished_) return;
    const double sinceLast = std::chrono::duration<double>(now - lastPrint_).count();
    const int decile = static_cast<int>(10.0 * fractionAt(done));
    const bool due = terminal_ ? sinceLast >= 0.1 : (decile > lastDecile_ || sinceLast >= 10.0);
    if (!due) return;
    // A log line is worth its space after a second: a phase that ends sooner (loading a scene of
    // a few objects) prints only its final line.
    if (!terminal_ && elapsedSeconds() < kQuietSeconds) return;
    lastDecile_ = decile;
    lastPrint_ = now;
    print(done, false);
}

void ProgressReporter::finish() {
    std::lock_guard<std::mutex> lock(printMutex_);
    if (finished_) return;
    finished_ = true;
    if (enabled_) print(done_.load(), true);
}

void ProgressReporter::print(int64_t done, bool final) {
    const double fraction = fractionAt(done);
    const double elapsed = elapsedSeconds();
    std::string tail;
    if (final) {
        tail = "done in " + formatDuration(elapsed);
        double paused;
        {
            std::lock_guard<std::mutex> lock(clockMutex_);
            paused = pausedSeconds_;
        }
        if (paused > 0.0) tail += " (+ " + formatDuration(paused) + " loading)";
    } else if (fraction > 0.0) {
        double loadsLeft;
        {
            std::lock_guard<std::mutex> lock(clockMutex_);
            loadsLeft = remainingLoadSeconds(pausedSeconds_, loadsDone_, loadsExpected_);
        }
        tail = formatDuration(elapsed) + " elapsed, ETA " +
               formatDuration(remainingSeconds(elapsed, fraction) + loadsLeft);
    }
    if (terminal_) {
        constexpr int kWidth = 30;
        const int filled = static_cast<int>(fraction * kWidth);
        std::string bar(filled, '#');
        bar.append(kWidth - filled, '.');
        std::fprintf(stderr, "\r%s [%s] %3d%%  %s\033[K%s", label_.c_str(), bar.c_str(),
                     static_cast<int>(fraction * 100.0), tail.c_str(), final ? "\n" : "");
    } else {
        std::fprintf(stderr, "%s: %3d%%  %s\n", label_.c_str(), static_cast<int>(fraction * 100.0),
                     tail.c_str());
    }
    std::fflush(stderr);
}

}  // namespace lobe
