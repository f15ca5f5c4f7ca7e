// Front-to-back compositing (Porter & Duff 1984 "over", evaluated front to back as in Levoy 1990,
// "Efficient ray tracing of volume data", and Engel et al. 2006, ch. 1):
//     C ← C + T α L,   T ← T (1 − α),
// with early ray termination once T falls below a threshold (the scene's
// termination_transmittance, default 1e-3: the light still to come can then change the pixel by
// at most that fraction of the remaining radiance). The integrator (render/integrator.h)
// composites surface hits and volume samples with it; it is the only compositor in Lobe.
#pragma once

#include "core/spectrum.h"

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
    bool terminated() const { return transmittance < terminationTransmittance; }
};

}  // namespace lobe
