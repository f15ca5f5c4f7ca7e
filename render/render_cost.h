// Where a render's CPU time goes, and what each object's BRDF costs (`lobe cost`, `lobe render
// --stats`, docs/cost.md).
//
// Counting and timing happen only when RenderOptions::cost is set; otherwise the integrator takes
// one predictable branch per surface hit and volume segment and shades exactly as before (the
// image is the same bit for bit either way: the counting light loop does the same arithmetic in
// the same order).
//
// What is measured, per thread (no shared counters, so nothing is contended and the counts do not
// depend on the thread count or tile order):
//  - surfaces: each Embree traversal along a ray segment (surfaces->intersect, hit included);
//  - volumes: the marching of every volume up to the next surface (reconstruction, transfer
//    function, gradients), minus the shading of its samples;
//  - shading: each call of the one light loop (render/shading.h) for a surface hit or a volume
//    sample — the BRDF evaluations and the light loop around them (frame, directions, 1/d²);
//  - other: the rest of the pixel loop (camera rays, compositing, the backdrop, the timers).
// Phases are timed with the steady clock (one pair of reads per surface query, per volume segment
// and per shaded point, never per BRDF call), and so is each pixel. The thread's CPU clock is read
// only at its first pixel and after the render (a read costs 2-5 µs on a virtual machine's
// kvm-clock, against ~50 ns for the steady clock): each thread's phase times are scaled by its
// CPU/(pixel wall) ratio, so on a loaded machine a thread's preempted time is not counted as work.
// An object's cost is the shading time of its points; "ns per evaluation" divides it by its BRDF
// evaluations, so it is the cost of one (point, light) pair of the light loop with that object's
// model.
#pragma once

#include <ctime>
#include <vector>

namespace lobe {

struct ObjectCost {
    long long shadedPoints = 0;  // surface hits and volume samples lit with the object's material
    // Evaluations of f = kd/π + f_s(wi, wo): one per shaded point and light above its surface
    // (render/shading.h); a volume sample without a usable normal is lit without its BRDF (none).
    long long brdfEvaluations = 0;
    double shadingSeconds = 0.0;  // CPU s (RenderCost) or thread wall s (CostCounters)

    ObjectCost& operator+=(const ObjectCost& o);
};

// One thread's counters during a render (TraceState::cost). Seconds are the thread's steady-clock
// time, converted to CPU time when merged into a RenderCost.
struct CostCounters {
    bool enabled = false;
    double surfaceSeconds = 0.0;
    double volumeSeconds = 0.0;         // volume segments, the shading of their samples included
    double volumeShadingSeconds = 0.0;  // of which shading
    double surfaceShadingSeconds = 0.0;
    double pixelSeconds = 0.0;        // the pixel loop, steady clock
    double cpuSeconds = 0.0;          // this thread's CPU time from its first pixel to stop()
    std::vector<ObjectCost> objects;  // by SceneSpec::objects index

    void enable(int objectCount);
    // start() on the thread, at its first pixel; stop() from any thread once the render is done.
    bool started() const { return started_; }
    void start();
    void stop();

private:
    bool started_ = false, clockValid_ = false;
    clockid_t clock_{};
    double cpuStart_ = 0.0;
};

// A whole render's cost: CPU seconds by part (they sum to cpuSeconds) and per object.
struct RenderCost {
    double wallSeconds = 0.0;  // the render, start to end
    double cpuSeconds = 0.0;   // CPU time of the threads in the pixel loop
    double surfaces = 0.0, volumes = 0.0, shading = 0.0, other = 0.0;
    std::vector<ObjectCost> objects;

    // Adds one thread's counters, converted to CPU seconds.
    void add(const CostCounters& thread);
    // Adds another render's cost (the bands of a poster are renders of their own).
    RenderCost& operator+=(const RenderCost& other);
    long long brdfEvaluations() const;
};

// Seconds of a monotonic clock (steady_clock).
double steadySeconds();
// CPU seconds of the calling thread (CLOCK_THREAD_CPUTIME_ID): not advanced while the thread
// waits or is pre-empted. The cost pilot's clock (RenderScene::costProfile).
double threadCpuSeconds();

}  // namespace lobe
