// The affine index → world map of a voxel grid, x_world = A·u + T, with its inverse and the
// inverse transpose that carries gradients (and so normals) from index to world space.
//
// Why not openvdb::math::Transform directly: the iso-surface callbacks run millions of times per
// image, and a plain 3×3 matrix in double is both faster and explicit about the convention
// (column vectors, A's columns are the world images of the index unit vectors). fromTransform
// reads A and T by mapping the index origin and unit vectors, so it does not depend on OpenVDB's
// row-vector matrix layout. Any affine transform works (anisotropic spacing, flips, rotations,
// shears); a non-linear (frustum) transform is refused with lobe::Error.
#pragma once

#include "core/error.h"
#include "core/math.h"
#include "volume/grid_world.h"

#include <openvdb/math/Transform.h>

#include <cmath>
#include <string>

namespace lobe {

struct Mat3 {
    double m[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};  // m[row][column]

    Vec3 operator*(const Vec3& v) const {
        return Vec3(m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z,
                    m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
                    m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z);
    }
    Mat3 transposed() const {
        Mat3 t;
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) t.m[r][c] = m[c][r];
        return t;
    }
    double determinant() const {
        return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
               m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
               m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    }
    // Inverse by the adjugate (cofactor transpose / determinant); the caller checks det ≠ 0.
    Mat3 inverse() const {
        const double det = determinant();
        Mat3 r;
        r.m[0][0] = (m[1][1] * m[2][2] - m[1][2] * m[2][1]) / det;
        r.m[0][1] = (m[0][2] * m[2][1] - m[0][1] * m[2][2]) / det;
        r.m[0][2] = (m[0][1] * m[1][2] - m[0][2] * m[1][1]) / det;
        r.m[1][0] = (m[1][2] * m[2][0] - m[1][0] * m[2][2]) / det;
        r.m[1][1] = (m[0][0] * m[2][2] - m[0][2] * m[2][0]) / det;
        r.m[1][2] = (m[0][2] * m[1][0] - m[0][0] * m[1][2]) / det;
        r.m[2][0] = (m[1][0] * m[2][1] - m[1][1] * m[2][0]) / det;
        r.m[2][1] = (m[0][1] * m[2][0] - m[0][0] * m[2][1]) / det;
        r.m[2][2] = (m[0][0] * m[1][1] - m[0][1] * m[1][0]) / det;
        return r;
    }
};

struct AffineMap {
    Mat3 a;       // index → world linear part (columns: world images of the index axes)
    Mat3 aInv;    // world → index linear part
    Mat3 aInvT;   // (A⁻¹)ᵀ: index-space gradient → world-space gradient
    Vec3 t{0.0};  // world position of index (0,0,0)

    Vec3 toWorld(const Vec3& u) const { return a * u + t; }
    Vec3 toIndex(const Vec3& x) const { return aInv * (x - t); }
    Vec3 directionToIndex(const Vec3& d) const { return aInv * d; }
    // f_world(x) = f_index(A⁻¹(x − T)) ⇒ ∇f_world = A⁻ᵀ ∇f_index (chain rule).
    Vec3 gradientToWorld(const Vec3& g) const { return aInvT * g; }

    static AffineMap fromMatrix(const Mat3& linear, const Vec3& translation,
                                const std::string& what = "grid transform") {
        AffineMap map;
        map.a = linear;
        map.t = translation;
        const double det = linear.determinant();
        if (!std::isfinite(det) || std::abs(det) < 1e-300)
            throw Error(what + ": the index-to-world map is singular (determinant " +
                        std::to_string(det) + ")");
        map.aInv = linear.inverse();
        map.aInvT = map.aInv.transposed();
        return map;
    }

    // An OpenVDB transform's map, its linear part and offset times `scale` (a grid's world scale).
    static AffineMap fromTransform(const openvdb::math::Transform& xform,
                                   const std::string& what = "grid transform", double scale = 1.0) {
        if (!xform.isLinear())
            throw Error(what + ": only affine (linear) transforms are supported, not '" +
                        xform.mapType() + "'");
        const openvdb::Vec3d o = xform.indexToWorld(openvdb::Vec3d(0, 0, 0));
        Mat3 linear;
        for (int c = 0; c < 3; ++c) {
            openvdb::Vec3d e(0, 0, 0);
            e[c] = 1.0;
            const openvdb::Vec3d col = xform.indexToWorld(e) - o;
            for (int r = 0; r < 3; ++r) linear.m[r][c] = col[r] * scale;
        }
        return fromMatrix(linear, Vec3(o[0] * scale, o[1] * scale, o[2] * scale), what);
    }

    // A grid's full map: its transform times its world scale (volume/grid_world.h; a power of
    // two, so the product is exact).
    static AffineMap fromGrid(const openvdb::GridBase& grid,
                              const std::string& what = "grid transform") {
        return fromTransform(grid.transform(), what, gridWorldScale(grid));
    }
};

}  // namespace lobe
