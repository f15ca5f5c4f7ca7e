#include "core/camera.h"

#include "core/error.h"

#include <string>

namespace lobe {

PinholeCamera::PinholeCamera(const Vec3& position, const Vec3& target, const Vec3& up,
                             double vfovDegrees, double aspect, const CropWindow& crop)
    : position_(position), crop_(crop) {
    const Vec3 view = target - position;
    if (!(view.length() > 0.0)) throw Error("camera: position and target are the same point");
    if (!(vfovDegrees > 0.0 && vfovDegrees < 180.0))
        throw Error("camera: field of view must be in (0, 180) degrees, got " +
                    std::to_string(vfovDegrees));
    if (!(aspect > 0.0)) throw Error("camera: aspect ratio must be positive");
    if (!(crop.x0 >= 0 && crop.x1 <= 1 && crop.y0 >= 0 && crop.y1 <= 1 && crop.x0 < crop.x1 &&
          crop.y0 < crop.y1))
        throw Error("camera: crop window must satisfy 0 <= x0 < x1 <= 1 and 0 <= y0 < y1 <= 1");
    forward_ = normalized(view);
    const Vec3 right = forward_.cross(up);
    if (!(right.length() > 1e-9))
        throw Error("camera: up vector is parallel to the view direction");
    right_ = normalized(right);
    up_ = right_.cross(forward_);
    halfHeight_ = std::tan(radians(vfovDegrees) * 0.5);
    halfWidth_ = halfHeight_ * aspect;
}

}  // namespace lobe
