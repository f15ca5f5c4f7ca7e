// Front-to-back compositing (Porter & Duff 1984 "over", evaluated front to back as in Levoy 1990,
// "Efficient ray tracing of volume data", and Engel et al. 2006, ch. 1):
//     C ← C + T α L,   T ← T (1 − α),
// with early ray termination once T falls below a threshold (the scene's
// termination_transmittance, default 1e-3: the light still to come can then change the pixel by
// at most that fraction of the remaining radiance). The integrator (render/integrator.h)
// composites surface hits and volume samples with it; it is the only compositor in Lobe.
#pragma once

#include "core/spectrum.h"

#include <cmath>

namespace lobe {

constexpr double kDefaultTerminationTransmittance = 1e-3;

struct FrontToBackCompositor {
    Spectrum radiance{0.0};
    double transmittance = 1.0;
    double terminationTransmittance = kDefaultTerminationTransmittance;

    FrontToBackCompositor() = default;
    explicit FrontToBackCompositor(double termination) : terminationTransmittance(termination) {}

    void add(double alpha, const Spectrum& sampleRadiance) {
        radiance += sampleRadiance * (transmittance * alpha);
        transmittance *= 1.0 - alpha;
    }
    // add(alpha, 0): a sample that adds no radiance (one the shading roulette did not shade) only
    // attenuates. The same state bit for bit: adding +0 changes no value but −0, and the radiance
    // is never −0 (it starts at +0, and a sum is −0 only when both terms are).
    void pass(double alpha) { transmittance *= 1.0 - alpha; }
    bool terminated() const { return transmittance < terminationTransmittance; }
};

// The shading roulette's systematic draws along one ray (render/integrator.cpp, volumesUpTo):
// Russian roulette (Arvo & Kirk 1990) shades a volume sample of weight w = T·α below the
// threshold w0 with probability w/w0, the draws systematic (Kitagawa 1996): a running sum of
// w/w0 from one uniform offset u ∈ [0, 1), and a sample is shaded when the sum crosses an
// integer, floor(sum after) > floor(sum before).
//
// The sum's next integer, floor(sum) + 1, is kept, so a draw is one division, one addition and
// one comparison; floor only runs when the sum crosses. The same decisions, bit for bit: the
// sum never decreases (w ≥ 0), so between crossings floor(sum) stays that integer, and
// floor(sum) + 1 is exact while sum < 2⁵³. The sum is at most u + Σ T·α / w0 ≤ 1 + 1/w0 (the
// weights along a ray add up to at most 1 − T), so that holds for w0 > kExactW0; for smaller w0
// (and w0 = 0, where no sample is below it) the floors are compared as such.
class ShadingRoulette {
public:
    static constexpr double kExactW0 = 1e-12;

    ShadingRoulette(double offset, double w0)
        : sum_(offset), next_(std::floor(offset) + 1.0), w0_(w0), byThreshold_(w0 > kExactW0) {}

    // Whether a sample of weight w < w0 is shaded (it then counts w0/w times).
    bool draw(double weight) {
        const double before = sum_;
        sum_ += weight / w0_;
        if (!byThreshold_) return std::floor(sum_) > std::floor(before);
        if (!(sum_ >= next_)) return false;
        next_ = std::floor(sum_) + 1.0;
        return true;
    }
    double sum() const { return sum_; }

private:
    double sum_;
    double next_;  // floor(sum_) + 1 (byThreshold_ only)
    double w0_;
    bool byThreshold_;
};

}  // namespace lobe
