// Point ("omni") light of intensity I (W/sr per band): irradiance at distance d is I/d² · cos θ.
#pragma once

#include "core/math.h"
#include "core/spectrum.h"

namespace lobe {

struct PointLight {
    Vec3 position{0.0};
    Spectrum intensity{1.0};
};

}  // namespace lobe
