#include "render/render_cost.h"

#include <pthread.h>

#include <algorithm>
#include <chrono>
#include <ctime>

namespace lobe {

ObjectCost& ObjectCost::operator+=(const ObjectCost& o) {
    shadedPoints += o.shadedPoints;
    brdfEvaluations += o.brdfEvaluations;
    shadingSeconds += o.shadingSeconds;
    return *this;
}

void CostCounters::enable(int objectCount) {
    *this = CostCounters();
    enabled = true;
    objects.resize(size_t(std::max(objectCount, 0)));
}

namespace {
double seconds(clockid_t clock, bool& valid) {
    timespec ts{};
    if (!valid || clock_gettime(clock, &ts) != 0) {
        valid = false;
        return 0.0;
    }
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}
}  // namespace

void CostCounters::start() {
    started_ = true;
    clockValid_ = pthread_getcpuclockid(pthread_self(), &clock_) == 0;
    cpuStart_ = seconds(clock_, clockValid_);
}

void CostCounters::stop() {
    const double now = seconds(clock_, clockValid_);
    // Without a CPU clock (it cannot fail on Linux): wall time stands for it.
    cpuSeconds = clockValid_ ? now - cpuStart_ : pixelSeconds;
}

void RenderCost::add(const CostCounters& t) {
    // The thread's CPU share of its wall time in the pixel loop, applied to the phases timed
    // inside it (preemption is taken to hit every phase alike). The thread's CPU time beyond its
    // pixels (tile hand-out, waiting for the last tiles) counts as other.
    const double toCpu = t.pixelSeconds > 0.0 ? std::min(1.0, t.cpuSeconds / t.pixelSeconds) : 1.0;
    const double surf = t.surfaceSeconds * toCpu;
    const double vol = std::max(0.0, t.volumeSeconds - t.volumeShadingSeconds) * toCpu;
    const double shade = (t.surfaceShadingSeconds + t.volumeShadingSeconds) * toCpu;
    surfaces += surf;
    volumes += vol;
    shading += shade;
    const double thread = std::max(t.cpuSeconds, surf + vol + shade);
    other += thread - (surf + vol + shade);
    cpuSeconds += thread;
    if (objects.size() < t.objects.size()) objects.resize(t.objects.size());
    for (size_t i = 0; i < t.objects.size(); ++i) {
        ObjectCost o = t.objects[i];
        o.shadingSeconds *= toCpu;
        objects[i] += o;
    }
}

RenderCost& RenderCost::operator+=(const RenderCost& o) {
    wallSeconds += o.wallSeconds;
    cpuSeconds += o.cpuSeconds;
    surfaces += o.surfaces;
    volumes += o.volumes;
    shading += o.shading;
    other += o.other;
    if (objects.size() < o.objects.size()) objects.resize(o.objects.size());
    for (size_t i = 0; i < o.objects.size(); ++i) objects[i] += o.objects[i];
    return *this;
}

long long RenderCost::brdfEvaluations() const {
    long long n = 0;
    for (const ObjectCost& o : objects) n += o.brdfEvaluations;
    return n;
}

double threadCpuSeconds() {
    timespec ts{};
    if (clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts) != 0) return steadySeconds();
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

double steadySeconds() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
}
}  // namespace lobe
