// A ray o + t·d for t in [tMin, tMax]; d is unit length wherever the renderer creates one.
#pragma once

#include "core/math.h"

#include <limits>

namespace lobe {

struct Ray {
    Vec3 o{0.0};
    Vec3 d{0, 0, 1};
    double tMin = 0.0;
    double tMax = std::numeric_limits<double>::infinity();

    Vec3 at(double t) const { return o + d * t; }
};

}  // namespace lobe
