#include "render/render_cost.h"

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

void RenderCost::add(const CostCounters& t) {
    // The thread's CPU share of its wall time in the pixel loop, applied to the phases timed
    // inside it (preemption is taken to hit every phase alike).
    const double toCpu = t.pixelSeconds > 0.0 ? t.pixelCpuSeconds / t.pixelSeconds : 1.0;
    const double shade = t.surfaceShadingSeconds + t.volumeShadingSeconds;
    surfaces += t.surfaceSeconds * toCpu;
    volumes += std::max(0.0, t.volumeSeconds - t.volumeShadingSeconds) * toCpu;
    shading += shade * toCpu;
    const double timed = t.surfaceSeconds + std::max(t.volumeSeconds, t.volumeShadingSeconds) +
                         t.surfaceShadingSeconds;
    other += std::max(0.0, t.pixelSeconds - timed) * toCpu;
    cpuSeconds += std::max(t.pixelSeconds, timed) * toCpu;
    if (objects.size() < t.objects.size()) objects.resize(t.objects.size());
    for (size_t i = 0; i < t.objects.size(); ++i) {
        ObjectCost o = t.objects[i];
        o.shadingSeconds *= toCpu;
        objects[i] += o;
    }
}

long long RenderCost::brdfEvaluations() const {
    long long n = 0;
    for (const ObjectCost& o : objects) n += o.brdfEvaluations;
    return n;
}

double steadySeconds() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
}

double threadCpuSeconds() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

}  // namespace lobe
