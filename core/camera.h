// Pinhole camera (position, target, up, vertical field of view) with a crop window: the image
// shows only the sub-rectangle [x0,x1]×[y0,y1] of the full view (normalised, origin top-left), at
// full resolution, which is how close-ups of a region are rendered without moving the camera.
#pragma once

#include "core/math.h"
#include "core/ray.h"

namespace lobe {

struct CropWindow {
    double x0 = 0.0, y0 = 0.0, x1 = 1.0, y1 = 1.0;
};

class PinholeCamera {
public:
    PinholeCamera() = default;
    // Throws lobe::Error when position == target, up is parallel to the view direction, or the
    // field of view is outside (0°, 180°).
    PinholeCamera(const Vec3& position, const Vec3& target, const Vec3& up, double vfovDegrees,
                  double aspect, const CropWindow& crop = {});

    // Ray through the point (u, v) of the image, both in [0,1], u to the right, v downwards.
    // Inline: the pixel loop calls it once per sample.
    Ray generateRay(double u, double v) const {
        const double fu = crop_.x0 + u * (crop_.x1 - crop_.x0);
        const double fv = crop_.y0 + v * (crop_.y1 - crop_.y0);
        const double sx = (2.0 * fu - 1.0) * halfWidth_;
        const double sy = (1.0 - 2.0 * fv) * halfHeight_;
        Ray ray;
        ray.o = position_;
        ray.d = normalized(forward_ + right_ * sx + up_ * sy);
        return ray;
    }

    const Vec3& position() const { return position_; }
    const Vec3& forward() const { return forward_; }
    const Vec3& right() const { return right_; }
    const Vec3& up() const { return up_; }
    // tan(vfov/2) and tan(vfov/2)·aspect: the image plane's half extents at distance 1.
    double halfHeight() const { return halfHeight_; }
    double halfWidth() const { return halfWidth_; }
    const CropWindow& crop() const { return crop_; }

private:
    Vec3 position_{0.0};
    Vec3 forward_{0, 0, -1};
    Vec3 right_{1, 0, 0};
    Vec3 up_{0, 1, 0};
    double halfHeight_ = 1.0;  // tan(vfov/2)
    double halfWidth_ = 1.0;
    CropWindow crop_;
};

}  // namespace lobe
