#include "core/frame.h"

namespace lobe {

Frame Frame::fromNormal(const Vec3& n) {
    const double sign = std::copysign(1.0, n.z);
    const double a = -1.0 / (sign + n.z);
    const double b = n.x * n.y * a;
    Frame f;
    f.n = n;
    f.t = Vec3(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
    f.b = Vec3(b, sign + n.y * n.y * a, -n.y);
    return f;
}

}  // namespace lobe
