#include "volume/reconstruction.h"

#include <Imath/ImathMatrix.h>

#include <cmath>

#include "core/error.h"

namespace lobe {

const char* reconstructionName(Reconstruction r) {
    return r == Reconstruction::kTrilinear ? "trilinear" : "cubic-bspline";
}

const char* gradientMethodName(GradientMethod g) {
    return g == GradientMethod::kCentralDifferences ? "central-differences" : "bspline-derivative";
}

GridGeometry::GridGeometry(const openvdb::math::Transform& transform, const std::string& name) {
    if (!transform.isLinear())
        throw Error(name + ": the grid's index-to-world transform is not linear (" +
                    transform.mapType() + "); DVR needs an affine map");
    // Columns of J are the images of the index unit vectors; read them through the transform
    // itself so any linear map type (scale, translate, affine) is handled alike.
    const openvdb::Vec3d o = transform.indexToWorld(openvdb::Vec3d(0, 0, 0));
    origin_ = Vec3(o.x(), o.y(), o.z());
    Imath::M33d j;
    for (int c = 0; c < 3; ++c) {
        openvdb::Vec3d e(0, 0, 0);
        e[c] = 1.0;
        const openvdb::Vec3d w = transform.indexToWorld(e) - o;
        for (int r = 0; r < 3; ++r) j[r][c] = w[r];
    }
    const double det = j.determinant();
    if (!(std::abs(det) > 1e-300) || !std::isfinite(det))
        throw Error(name + ": the grid's index-to-world transform is singular");
    const Imath::M33d inv = j.inverse();
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) {
            j_[r][c] = j[r][c];
            jInv_[r][c] = inv[r][c];
        }
    refLength_ = std::cbrt(std::abs(det));
}

Vec3 GridGeometry::indexToWorld(const Vec3& p) const {
    return origin_ + Vec3(j_[0][0] * p.x + j_[0][1] * p.y + j_[0][2] * p.z,
                          j_[1][0] * p.x + j_[1][1] * p.y + j_[1][2] * p.z,
                          j_[2][0] * p.x + j_[2][1] * p.y + j_[2][2] * p.z);
}

Vec3 GridGeometry::worldToIndexDirection(const Vec3& d) const {
    return Vec3(jInv_[0][0] * d.x + jInv_[0][1] * d.y + jInv_[0][2] * d.z,
                jInv_[1][0] * d.x + jInv_[1][1] * d.y + jInv_[1][2] * d.z,
                jInv_[2][0] * d.x + jInv_[2][1] * d.y + jInv_[2][2] * d.z);
}

Vec3 GridGeometry::worldToIndex(const Vec3& p) const { return worldToIndexDirection(p - origin_); }

Vec3 GridGeometry::gradientToWorld(const Vec3& g) const {
    // J⁻ᵀ g: column r of J⁻¹ dotted with g.
    return Vec3(jInv_[0][0] * g.x + jInv_[1][0] * g.y + jInv_[2][0] * g.z,
                jInv_[0][1] * g.x + jInv_[1][1] * g.y + jInv_[2][1] * g.z,
                jInv_[0][2] * g.x + jInv_[1][2] * g.y + jInv_[2][2] * g.z);
}

namespace {

// Uniform cubic B-spline weights and derivatives at fraction t (header, de Boor 1978).
inline void bsplineWeights(double t, double w[4], double dw[4]) {
    const double s = 1.0 - t;
    const double t2 = t * t, t3 = t2 * t;
    w[0] = s * s * s / 6.0;
    w[1] = (3.0 * t3 - 6.0 * t2 + 4.0) / 6.0;
    w[2] = (-3.0 * t3 + 3.0 * t2 + 3.0 * t + 1.0) / 6.0;
    w[3] = t3 / 6.0;
    dw[0] = -0.5 * s * s;
    dw[1] = 0.5 * (3.0 * t2 - 4.0 * t);
    dw[2] = 0.5 * (-3.0 * t2 + 2.0 * t + 1.0);
    dw[3] = 0.5 * t2;
}

}  // namespace

double GridReconstructor::trilinear(const Vec3& p) {
    const double fx = std::floor(p.x), fy = std::floor(p.y), fz = std::floor(p.z);
    const int i = int(fx), j = int(fy), k = int(fz);
    const double tx = p.x - fx, ty = p.y - fy, tz = p.z - fz;
    double c[2][2][2];
    for (int dz = 0; dz < 2; ++dz)
        for (int dy = 0; dy < 2; ++dy)
            for (int dx = 0; dx < 2; ++dx)
                c[dz][dy][dx] = acc_.getValue(openvdb::Coord(i + dx, j + dy, k + dz));
    auto lerp = [](double a, double b, double t) { return a + t * (b - a); };
    const double c00 = lerp(c[0][0][0], c[0][0][1], tx), c01 = lerp(c[0][1][0], c[0][1][1], tx);
    const double c10 = lerp(c[1][0][0], c[1][0][1], tx), c11 = lerp(c[1][1][0], c[1][1][1], tx);
    return lerp(lerp(c00, c01, ty), lerp(c10, c11, ty), tz);
}

double GridReconstructor::bsplineWithGradient(const Vec3& p, Vec3& gradient) {
    const double fx = std::floor(p.x), fy = std::floor(p.y), fz = std::floor(p.z);
    const int i = int(fx) - 1, j = int(fy) - 1, k = int(fz) - 1;
    double wx[4], wy[4], wz[4], dx[4], dy[4], dz[4];
    bsplineWeights(p.x - fx, wx, dx);
    bsplineWeights(p.y - fy, wy, dy);
    bsplineWeights(p.z - fz, wz, dz);
    double v = 0.0, gx = 0.0, gy = 0.0, gz = 0.0;
    for (int c = 0; c < 4; ++c) {
        // Separable sums: reduce along x, then y, then z.
        double vz = 0.0, gxz = 0.0, gyz = 0.0;
        for (int b = 0; b < 4; ++b) {
            double vx = 0.0, dvx = 0.0;
            for (int a = 0; a < 4; ++a) {
                const double f = acc_.getValue(openvdb::Coord(i + a, j + b, k + c));
                vx += wx[a] * f;
                dvx += dx[a] * f;
            }
            vz += wy[b] * vx;
            gxz += wy[b] * dvx;
            gyz += dy[b] * vx;
        }
        v += wz[c] * vz;
        gx += wz[c] * gxz;
        gy += wz[c] * gyz;
        gz += dz[c] * vz;
    }
    gradient = Vec3(gx, gy, gz);
    return v;
}

double GridReconstructor::bspline(const Vec3& p) {
    Vec3 g;
    return bsplineWithGradient(p, g);
}

Vec3 GridReconstructor::centralDifferences(const Vec3& p) {
    return Vec3(0.5 * (trilinear(p + Vec3(1, 0, 0)) - trilinear(p - Vec3(1, 0, 0))),
                0.5 * (trilinear(p + Vec3(0, 1, 0)) - trilinear(p - Vec3(0, 1, 0))),
                0.5 * (trilinear(p + Vec3(0, 0, 1)) - trilinear(p - Vec3(0, 0, 1))));
}

double GridReconstructor::valueAndGradient(Reconstruction r, GradientMethod g, const Vec3& p,
                                           Vec3& gradient) {
    if (r == Reconstruction::kCubicBSpline) {
        const double v = bsplineWithGradient(p, gradient);
        if (g == GradientMethod::kCentralDifferences) gradient = centralDifferences(p);
        return v;
    }
    const double v = trilinear(p);
    if (g == GradientMethod::kBSplineDerivative)
        bsplineWithGradient(p, gradient);
    else
        gradient = centralDifferences(p);
    return v;
}

}  // namespace lobe
