// A table of one He–Torrance material (he_torrance.h): f per band at the nodes of a regular grid
// over Rusinkiewicz's half/difference angles (S. Rusinkiewicz, "A New Change of Variables for
// Efficient BRDF Representation", EGWR 1998), read back by trilinear interpolation — about
// 60–150 ns against the series' ~500–800 ns. `lobe render --preview` reads the preview table
// (kPreview, within 2 %), full renders the fine one (kFine, within 0.5 %), `--exact-brdf` the
// series (render/scene.cpp).
//
// Coordinates. h = (wi + wo)/|wi + wo|, θh = ∠(h, n), θd = ∠(wi, h), and φd the azimuth of wi
// about h measured from the plane of n and h. He–Torrance depends on wi and wo only through
// cos θi, cos θo, |H_xy| and wi·h (docs/models.md, model 7), which are invariant under rotations
// about n and under mirroring in the plane of n and h, and symmetric in wi ↔ wo: so f depends on
// φd only through |cos φd|, and the table spans φd ∈ [0, π/2]. The axes: u = √(θh/(π/2)) (nodes
// crowd at the highlight's centre, as in the MERL database's θh axis), θd and φd uniform on
// [0, π/2]; kHalf × kDiff × kPhi nodes, the grid's ends included.
//
// Nodes below the horizon. A node whose wi or wo lies below the surface stores f at the same
// (θh, θd, φd) with that direction moved onto the horizon (z = 1e-6, renormalised): a continuous
// extension, so that cells straddling the horizon interpolate towards the horizon's values
// rather than towards 0. Lookups below the horizon return 0, as the series does.
//
// Error bound. e(wi, wo) = |f_table − f|·cos θi / M per band, M the largest f·cos θi over the
// nodes and the validation points below (the radiance error under one light, as a fraction of
// the brightest the material reflects). kErrorBound is the bound the table is held to: build()
// measures e at a regular grid of 9216 direction pairs and kValidationPoints quasi-random points
// in the table's coordinates, and returns no table when the largest exceeds 0.75·kErrorBound (a
// lobe too narrow for the grid: the caller keeps the series); tests check e ≤ kErrorBound over
// another grid of directions and at the table's cell centres for the accepted tables. The error
// is largest at grazing near-mirror pairs (θi, θo ≈ 80°), where Fresnel and the geometry term
// make f rise and fall within a few degrees of θd: hence the θd axis' crowding towards 90°.
#pragma once

#include "materials/he_torrance.h"

#include <memory>
#include <vector>

namespace lobe {

class HeTorranceTable {
public:
    // The nodes per axis and the error bound the table is held to.
    struct Resolution {
        int half;           // nodes along u = √(θh/(π/2))
        int diff;           // along v, θd = (π/2)(1 − (1 − v)²)
        int phi;            // along φd ∈ [0, π/2]
        double errorBound;  // kErrorBound below
    };
    static constexpr int kHalf = 72;  // the preview table's resolution (`--preview`)
    static constexpr int kDiff = 96;
    static constexpr int kPhi = 10;
    static constexpr double kErrorBound = 0.02;
    static constexpr Resolution kPreview = {kHalf, kDiff, kPhi, kErrorBound};
    // Full renders' table (render/scene.cpp, SceneSpec::heTorranceTables): twice the nodes along
    // θh and θd and 12 along φd, held to a bound four times tighter (measured 0.16 % for the
    // paper's parameters against the preview table's 0.65 %).
    static constexpr Resolution kFine = {144, 192, 12, 0.005};
    static constexpr int kValidationPoints = 4096;

    // The table of `model` (its table member ignored) at `resolution`, or null when the measured
    // error exceeds 0.75 of its bound. Deterministic; built in parallel.
    static std::shared_ptr<const HeTorranceTable> build(const HeTorrance& model,
                                                        const Resolution& resolution = kPreview);
    const Resolution& resolution() const { return res_; }

    // f(wi, wo) per band (unit local directions), as HeTorrance::eval within the error bound.
    Spectrum eval(const Vec3& wi, const Vec3& wo) const;
    // f(wi_k, wo) for n ≤ kLanes directions wi_k = (wx[k], wy[k], wz[k]) at one wo (the lights of
    // one shaded point, render/shading.cpp), into f[0 … n): eval's values, the coordinates with
    // SIMD across the directions (he_torrance_table_simd.cpp). The same operations as eval except
    // acos, which is Highway's (a few ulp from libm's): tested within 1e-12 of eval's f, relative
    // to the table's peak M (HeTorranceTable.LanesGiveEvalsValues).
    static constexpr int kLanes = 4;
    void evalLanes(int n, const double* wx, const double* wy, const double* wz, const Vec3& wo,
                   Spectrum* f) const;

    // e(wi, wo) (above): the largest over the bands of |f_table − f_series|·cos θi / M, f_series
    // from `series` (the model the table was built from).
    double relativeError(const HeTorrance& series, const Vec3& wi, const Vec3& wo) const;
    double measuredError() const { return measuredError_; }  // largest e at the validation points
    const Spectrum& peak() const { return peak_; }           // M per band

    // The table's coordinates of (wi, wo) (above the horizon): u, θd, φd, as described above.
    static void coordinates(const Vec3& wi, const Vec3& wo, double& u, double& thetaD,
                            double& phiD);
    // wi, wo at table coordinates (u, θd, φd), h in the x–z plane.
    static void directions(double u, double thetaD, double phiD, Vec3& wi, Vec3& wo);

private:
    // The trilinear interpolation of the cell whose first node is cell[0 … 2] (u, θd, φd) at
    // fractions frac[0 … 2], clamped at 0 per band (eval and evalLanes).
    Spectrum interpolate(const int* cell, const double* frac) const;
    Resolution res_ = kPreview;
    std::vector<float> values_;  // kBandCount per node; φd fastest, then θd, then u
    Spectrum peak_{0.0};
    double measuredError_ = 0.0;
};

}  // namespace lobe
