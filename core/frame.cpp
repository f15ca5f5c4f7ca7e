#include "core/frame.h"

namespace lobe {

Frame Frame::fromNormalAndAxis(const Vec3& n, const Vec3& axis, const Vec3& fallbackAxis,
                               double minSine) {
    const Vec3& a = axis.cross(n).length() >= minSine ? axis : fallbackAxis;
    Vec3 t = a - n * a.dot(n);
    const double len = t.length();
    if (!(len > 1e-12)) return fromNormal(n);  // both axes parallel to n: any tangent will do
    Frame f;
    f.n = n;
    f.t = t / len;
    f.b = n.cross(f.t);
    return f;
}

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
