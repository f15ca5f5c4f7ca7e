// Camera rays with Google Highway: this file is compiled once per SIMD target
// (hwy/foreach_target.h) and the best target the CPU supports is chosen at run time
// (HWY_DYNAMIC_DISPATCH). See camera_rays.h for the exactness argument; CMake compiles this file
// with -ffp-contract=off.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "core/camera_rays.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
// clang-format off: foreach_target.h must come before highway.h
#include <hwy/highway.h>
// clang-format on

#include "core/camera_rays.h"

#include <limits>
#include <vector>

HWY_BEFORE_NAMESPACE();
namespace lobe {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// Four lanes: 512-bit divisions cost twice 256-bit ones (core/light_directions.cpp).
using D = hn::CappedTag<double, 4>;
using V = hn::Vec<D>;

// Points [0, vectorEnd) in vectors of `lanes`; a vector with a lane whose |d|² is below
// 2·DBL_MIN or NaN (Imath's length() takes its slow path there, normalized() may give 0) is
// listed in redo[] by its first point, for generateRay to make again.
void CameraRayDirectionsImpl(const PinholeCamera& camera, const CameraSamplePoints& pts,
                             double* outX, double* outY, double* outZ, int& vectorEnd,
                             int& lanesOut, int* redo, int& redoCount) {
    const D d;
    const int lanes = int(hn::Lanes(d));
    const CropWindow& crop = camera.crop();
    const V cols = hn::Set(d, pts.cols), rows = hn::Set(d, pts.rows);
    const V width = hn::Set(d, pts.width), height = hn::Set(d, pts.height);
    const V cx0 = hn::Set(d, crop.x0), cy0 = hn::Set(d, crop.y0);
    const V cw = hn::Set(d, crop.x1 - crop.x0), ch = hn::Set(d, crop.y1 - crop.y0);
    const V one = hn::Set(d, 1.0), two = hn::Set(d, 2.0);
    const V hw = hn::Set(d, camera.halfWidth()), hh = hn::Set(d, camera.halfHeight());
    const Vec3 &f = camera.forward(), &r = camera.right(), &up = camera.up();
    const V fx = hn::Set(d, f.x), fy = hn::Set(d, f.y), fz = hn::Set(d, f.z);
    const V rx = hn::Set(d, r.x), ry = hn::Set(d, r.y), rz = hn::Set(d, r.z);
    const V ux = hn::Set(d, up.x), uy = hn::Set(d, up.y), uz = hn::Set(d, up.z);
    const V tiny = hn::Set(d, 2.0 * std::numeric_limits<double>::min());
    lanesOut = lanes;
    redoCount = 0;
    int i = 0;
    for (; i + lanes <= pts.n; i += lanes) {
        // jitteredSample: (col + jx) / cols; the pixel's image point: (x + j.x) / width.
        const V u = hn::Div(
            hn::Add(hn::LoadU(d, pts.x + i), hn::Div(hn::LoadU(d, pts.sx + i), cols)), width);
        const V v = hn::Div(
            hn::Add(hn::LoadU(d, pts.y + i), hn::Div(hn::LoadU(d, pts.sy + i), rows)), height);
        // generateRay: the crop window, the image plane, forward + right·sx + up·sy.
        const V fu = hn::Add(cx0, hn::Mul(u, cw));
        const V fv = hn::Add(cy0, hn::Mul(v, ch));
        const V sx = hn::Mul(hn::Sub(hn::Mul(two, fu), one), hw);
        const V sy = hn::Mul(hn::Sub(one, hn::Mul(two, fv)), hh);
        const V dx = hn::Add(hn::Add(fx, hn::Mul(rx, sx)), hn::Mul(ux, sy));
        const V dy = hn::Add(hn::Add(fy, hn::Mul(ry, sx)), hn::Mul(uy, sy));
        const V dz = hn::Add(hn::Add(fz, hn::Mul(rz, sx)), hn::Mul(uz, sy));
        // normalized(): Imath's dot (x·x + y·y) + z·z, its square root, three divisions.
        const V len2 = hn::Add(hn::Add(hn::Mul(dx, dx), hn::Mul(dy, dy)), hn::Mul(dz, dz));
        if (!hn::AllTrue(d, hn::Ge(len2, tiny))) redo[redoCount++] = i;
        const V len = hn::Sqrt(len2);
        hn::StoreU(hn::Div(dx, len), d, outX + i);
        hn::StoreU(hn::Div(dy, len), d, outY + i);
        hn::StoreU(hn::Div(dz, len), d, outZ + i);
    }
    vectorEnd = i;
}

}  // namespace HWY_NAMESPACE
}  // namespace lobe
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace lobe {

HWY_EXPORT(CameraRayDirectionsImpl);

void cameraRayDirections(const PinholeCamera& camera, const CameraSamplePoints& pts, double* dx,
                         double* dy, double* dz) {
    thread_local std::vector<int> redo;
    redo.resize(size_t(pts.n));
    int vectorEnd = 0, lanes = 1, redoCount = 0;
    HWY_DYNAMIC_DISPATCH(CameraRayDirectionsImpl)
    (camera, pts, dx, dy, dz, vectorEnd, lanes, redo.data(), redoCount);
    // generateRay itself for the points after the last full vector, and for the vectors listed
    // in redo (rays of |d|² below 2·DBL_MIN or NaN: none for a valid camera).
    const auto scalar = [&](int i) {
        const Ray ray = camera.generateRay((pts.x[i] + pts.sx[i] / pts.cols) / pts.width,
                                           (pts.y[i] + pts.sy[i] / pts.rows) / pts.height);
        dx[i] = ray.d.x;
        dy[i] = ray.d.y;
        dz[i] = ray.d.z;
    };
    for (int k = 0; k < redoCount; ++k)
        for (int i = redo[size_t(k)]; i < redo[size_t(k)] + lanes; ++i) scalar(i);
    for (int i = vectorEnd; i < pts.n; ++i) scalar(i);
}

}  // namespace lobe
#endif  // HWY_ONCE
