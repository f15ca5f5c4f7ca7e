// Reconstruction of a continuous field from an openvdb::FloatGrid, and its gradient, for direct
// volume rendering. Positions are in the grid's *index* space, where integer coordinates are voxel
// centres (OpenVDB's convention); GridGeometry converts rays, positions and gradients between
// index and world space.
//
// Filters (Marschner & Lobb 1994, "An evaluation of reconstruction filters for volume
// rendering", the paper's ref. [13]):
// - Trilinear: the tensor product of linear interpolation over the 2³ voxels around p. It
//   interpolates (passes through the voxel values) and reproduces linear fields exactly.
// - Cubic B-spline: the tensor product of the uniform cubic B-spline over the 4³ voxels around
//   p, with weights for t = frac(p) (de Boor, "A Practical Guide to Splines", 1978; Unser,
//   Aldroubi & Eden 1991, eq. 2.3):
//       w0 = (1−t)³/6, w1 = (3t³ − 6t² + 4)/6, w2 = (−3t³ + 3t² + 3t + 1)/6, w3 = t³/6.
//   The B-spline *approximates*: it does not pass through the voxel values (it smooths; a
//   quadratic x² comes back as x² + 1/3 voxel², the kernel's variance), but it reproduces linear
//   fields exactly and is C², so its analytic derivative is a continuous normal field. This is
//   the paper's "cubic B-spline" normal estimation for the cortex. Both filters have
//   non-negative weights that sum to 1, so a reconstructed value lies within the min/max of its
//   footprint — the property empty-space skipping relies on (volume/volume_marcher.h).
//
// Gradients:
// - Central differences of the trilinear field: g_i = (f(p + e_i) − f(p − e_i)) / 2 with a one
//   voxel offset. Because trilinear interpolation commutes with shifts by whole voxels, this is
//   exactly the trilinear interpolation of the classic voxel central differences
//   (f[i+1] − f[i−1]) / 2 (Höhne & Bernstein 1986; the paper's "central differences" for the
//   density maps). Exact for linear fields.
// - B-spline derivative: the analytic derivative of the cubic B-spline field, weights
//       w0' = −(1−t)²/2, w1' = (3t² − 4t)/2, w2' = (−3t² + 2t + 1)/2, w3' = t²/2.
// Gradients here are in index space (value per voxel); GridGeometry::gradientToWorld applies the
// inverse transpose of the index → world linear map.
//
// A GridReconstructor holds an OpenVDB ValueAccessor, which caches tree nodes, and the last 4³
// block of voxel values the B-spline read; it is not thread-safe: make one per thread (they are
// cheap). The grid's values must not change while a reconstructor reads it. Given a dense copy
// of the grid (volume/dense_field.h), it reads the voxels inside the copy's box from the copy —
// the same values, hence the same results — and the others from the tree.
#pragma once

#include "core/math.h"
#include "volume/dense_field.h"

#include <openvdb/openvdb.h>

#include <cstddef>

namespace lobe {

// kNearest: the value of the voxel whose centre is nearest (floor(p + ½) per axis): for volumes
// of labels, where an interpolated value between labels a and b is a third label's value.
// Its gradient is the trilinear field's central differences (a shading normal).
enum class Reconstruction { kTrilinear, kCubicBSpline, kNearest };
enum class GradientMethod { kCentralDifferences, kBSplineDerivative };

const char* reconstructionName(Reconstruction r);
const char* gradientMethodName(GradientMethod g);

// The index ↔ world map of a grid, which must be linear (affine): the case of every volume we
// load (NIfTI sform, raw spacing). World = J · index + origin.
class GridGeometry {
public:
    GridGeometry() = default;
    // Throws lobe::Error naming `name` when the grid's transform is not linear or is singular.
    explicit GridGeometry(const openvdb::math::Transform& transform,
                          const std::string& name = "volume");
    // The grid's full map: its transform times its world scale (volume/grid_world.h: grids of
    // tiny voxels keep a power-of-two scale OpenVDB's maps do not hold).
    explicit GridGeometry(const openvdb::GridBase& grid, const std::string& name = "volume");

    Vec3 indexToWorld(const Vec3& p) const {
        return origin_ + Vec3(j_[0][0] * p.x + j_[0][1] * p.y + j_[0][2] * p.z,
                              j_[1][0] * p.x + j_[1][1] * p.y + j_[1][2] * p.z,
                              j_[2][0] * p.x + j_[2][1] * p.y + j_[2][2] * p.z);
    }
    Vec3 worldToIndex(const Vec3& p) const;
    // Image of a world direction (or displacement) in index space: J⁻¹ d. Not normalised: the
    // ray parameter t is the same in both spaces.
    Vec3 worldToIndexDirection(const Vec3& d) const;
    // World gradient from an index-space gradient: J⁻ᵀ g (chain rule, ∇_w f = J⁻ᵀ ∇_i f).
    Vec3 gradientToWorld(const Vec3& gIndex) const;
    // Reference voxel length ℓ_ref = |det J|^(1/3): the voxel size for isotropic grids, the edge
    // of the cube of equal volume otherwise. Opacities are per ℓ_ref (transfer_function.h).
    double referenceVoxelLength() const { return refLength_; }

private:
    double j_[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};     // index → world
    double jInv_[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};  // world → index
    Vec3 origin_{0.0};
    double refLength_ = 1.0;
};

class GridReconstructor {
public:
    explicit GridReconstructor(const openvdb::FloatGrid& grid, const DenseField* dense = nullptr)
        : acc_(grid.getConstAccessor()), dense_(dense) {}

    double trilinear(const Vec3& p);
    // trilinear(p) for a caller that has floor(p) already, (i, j, k): the same bits, and from
    // the dense copy without a call (the DVR marcher's coarse steps).
    double trilinear(const Vec3& p, int i, int j, int k) {
        if (!(dense_ && dense_->holds(i, j, k, 2))) return trilinear(p);
        return trilinearDense(dense_->at(i, j, k), std::ptrdiff_t(dense_->xStride()),
                              std::ptrdiff_t(dense_->yStride()), p.x - double(i), p.y - double(j),
                              p.z - double(k));
    }
    double nearest(const Vec3& p) {
        return acc_.getValue(openvdb::Coord(int(std::floor(p.x + 0.5)), int(std::floor(p.y + 0.5)),
                                            int(std::floor(p.z + 0.5))));
    }
    double bspline(const Vec3& p);
    // B-spline value and its analytic index-space gradient from one 4³ fetch.
    double bsplineWithGradient(const Vec3& p, Vec3& gradient);
    // Central differences of the trilinear field (six trilinear lookups).
    Vec3 centralDifferences(const Vec3& p);

    double value(Reconstruction r, const Vec3& p) {
        return r == Reconstruction::kTrilinear ? trilinear(p)
               : r == Reconstruction::kNearest ? nearest(p)
                                               : bspline(p);
    }
    // The B-spline at o + d·t, for many t along one ray. Inside one voxel cell the field along
    // the ray is a polynomial of degree 9 in t (each weight is a cubic in t); it is built once
    // per cell from the 4³ block (~600 products) and then costs 9 products a sample, where
    // bspline() costs ~90. Worth it from ~7 samples a cell (steps below ~0.1 voxel). Equal to
    // bspline(o + d·t) up to rounding (~1e-13 of the block's values; tested).
    double bsplineOnRay(const Vec3& o, const Vec3& d, double t);
    // bsplineOnRay's polynomial for the cell of o + d·t, built as bsplineOnRay builds it (or
    // kept): its 10 coefficients in powers of (t − t0), and the cell's integer corner.
    const double* rayPolynomial(const Vec3& o, const Vec3& d, double t, double& t0, int cell[3]);
    // Drops bsplineOnRay's polynomial (the next call builds one).
    void forgetRay() { ray_.valid = false; }
    // Value and index-space gradient with the chosen filter and gradient method; the value of the
    // B-spline + B-spline-derivative pair comes from the same fetch.
    double valueAndGradient(Reconstruction r, GradientMethod g, const Vec3& p, Vec3& gradient);

private:
    // The trilinear interpolation of the 2³ voxels at q (x, y, z strides sx, sy, 1) at fractions
    // (tx, ty, tz): lerps a + t (b − a) along x, then y, then z.
    static double trilinearDense(const float* q, std::ptrdiff_t sx, std::ptrdiff_t sy, double tx,
                                 double ty, double tz) {
        auto lerp = [](double a, double b, double t) { return a + t * (b - a); };
        const double c00 = lerp(q[0], q[sx], tx), c01 = lerp(q[sy], q[sx + sy], tx);
        const double c10 = lerp(q[1], q[sx + 1], tx), c11 = lerp(q[sy + 1], q[sx + sy + 1], tx);
        return lerp(lerp(c00, c01, ty), lerp(c10, c11, ty), tz);
    }
    // A 4³ block of voxels: f[a][4b + c] = voxel (i + a, j + b, k + c) for a, b, c in 0..3.
    using Block = float[4][16];
    // The block at (i, j, k), from the cache when it is the last one asked for.
    const Block& block(int i, int j, int k);
    // Builds bsplineOnRay's polynomial for the cell of o + d·t unless it holds it already.
    void ensureRayCell(const Vec3& o, const Vec3& d, double t);
    // Reads the block leaf by leaf.
    void gather4(int i, int j, int k, Block& f);

    openvdb::FloatGrid::ConstAccessor acc_;
    const DenseField* dense_;  // may be null
    Block block_;
    openvdb::Coord blockOrigin_;
    bool hasBlock_ = false;
    // bsplineOnRay's polynomial: f(o + d·t) = Σ_k poly[k] (t − t0)^k in the cell `cell`.
    struct RayCell {
        Vec3 o{0.0}, d{0.0};
        openvdb::Coord cell;
        double t0 = 0.0;
        double poly[10] = {};
        bool valid = false;
    } ray_;
};

}  // namespace lobe
