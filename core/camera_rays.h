// Camera rays for many pixel samples at once, with SIMD across the samples (Google Highway, the
// best target the CPU supports chosen at run time): what the pixel loop (render/render_scene.cpp,
// renderRow) makes for each sample of a tile row before tracing any. Every operation is a
// correctly rounded IEEE add, multiply, divide or square root in the scalar code's order —
// jitteredSample (core/sampling.h), the pixel's image point and PinholeCamera::generateRay
// (core/camera.h) — with no fused multiply-add (CMake compiles camera_rays.cpp with
// -ffp-contract=off), so every ray is bit for bit the one generateRay makes. The six divisions
// and the square root of a sample were a chain of about 90 cycles each sample waited for when
// made one sample after another (docs/performance.md, round 4).
#pragma once

#include "core/camera.h"

namespace lobe {

// n samples in structure-of-arrays form. Sample i lies in pixel (x[i], y[i]) at stratum
// offsets sx[i] = col + jx and sy[i] = row + jy (the stratum's column and row plus the uniform
// jitters drawn for it, as jitteredSample adds them), so its image point is
//     u = (x + sx / cols) / width,   v = (y + sy / rows) / height.
struct CameraSamplePoints {
    int n = 0;
    const double* x = nullptr;
    const double* y = nullptr;
    const double* sx = nullptr;
    const double* sy = nullptr;
    double cols = 1.0, rows = 1.0;     // the strata grid (StrataGrid)
    double width = 1.0, height = 1.0;  // the image, in pixels
};

// The unit directions of camera.generateRay(u, v) at the n points into dx, dy, dz (n each):
// bit for bit, including the rare direction of length below 2·DBL_MIN or not finite, which is
// made by generateRay itself. Every ray starts at camera.position().
void cameraRayDirections(const PinholeCamera& camera, const CameraSamplePoints& points, double* dx,
                         double* dy, double* dz);

}  // namespace lobe
