// Transfer functions for direct volume rendering (DVR): a piecewise-linear map from a
// reconstructed data value to an opacity and a colour, one per volume object.
//
// Opacity per voxel length. The opacity α_voxel stored at a control point is the fraction of
// light absorbed by a path of length ℓ_ref through homogeneous material of that value, where
// ℓ_ref is the volume's reference voxel length (volume/volume_marcher.h: the cube root of the
// voxel volume |det J|, i.e. exactly the voxel size for isotropic grids). A step of world length
// Δs therefore has opacity
//     α_step = 1 − (1 − α_voxel)^(Δs / ℓ_ref)                                     (1)
// (opacity correction: Lacroute & Levoy 1994, "Fast volume rendering using a shear-warp
// factorization of the viewing transformation", SIGGRAPH '94, the correction of stored opacities
// for the sample spacing; Engel, Hadwiger, Kniss, Rezk-Salama & Weiskopf, "Real-Time Volume
// Graphics", 2006, ch. 1, discretisation of the volume rendering integral). Equation (1) is exact
// for homogeneous material: N steps of Δ voxels give transmittance (1 − α_voxel)^(NΔ), the
// Beer–Lambert law T = exp(−σ s) with extinction σ = −ln(1 − α_voxel) / ℓ_ref (Max 1995,
// "Optical models for direct volume rendering", eq. 3).
//
// Control points (value, opacity, colour) are sorted by value; two points may share a value to
// make a step (left and right limits; at exactly that value the right limit holds). Below the
// first and above the last point the end values hold. Opacity is in [0, 1), colour is a band
// Spectrum (700 / 546.1 / 435.8 nm, core/spectrum.h) that multiplies the sample's shaded
// radiance. An empty transfer function is transparent everywhere.
//
// Colour: our bands are the CIE RGB primaries, so an sRGB colour name such as "blue" must be
// converted with linearSrgbToBands() (core/spectrum.h), which clamps at 0
// (sRGB colours outside the CIE RGB gamut lose their negative band).
#pragma once

#include "core/spectrum.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

namespace lobe {

struct TfPoint {
    double value = 0.0;
    double opacity = 0.0;  // per voxel length, [0, 1)
    Spectrum colour{1.0};
};

// Equation (1): opacity of a step of `stepInVoxels` reference voxel lengths.
double correctOpacity(double alphaVoxel, double stepInVoxels);

// Equation (1) for one exponent r = `stepInVoxels`, from a table: the marcher's hot path, where
// every sample on a transfer function's ramp has its own α, and −expm1(r log1p(−α)) had ~4 % of
// rendering 1's profile (~10 ns a call, the table ~4 ns; alone the table saved nothing measurable,
// with the marcher's ray-cell bound the two saved ~11 % of the volume time: docs/performance.md,
// round 6, opac39). On an isotropic
// grid every ray of a render has the same r up to rounding (volume_marcher.h: r = Δt |d| / ℓ_ref
// = stepVoxels), so one table serves them all.
//
// The table holds q(α) = f(α) / α with f(α) = 1 − (1 − α)^r, not f itself: f ~ r α at small α,
// where an absolute interpolation error would be a large relative one, while q is analytic on
// (−1, 1) with q(0) = r and q⁽ⁿ⁾(α) = ∫₀¹ sⁿ f⁽ⁿ⁺¹⁾(sα) ds. [0, top] is cut into intervals of
// h = 1/256, and on each q is the degree-5 polynomial interpolating it at the 6 Chebyshev points
// (evaluated with correctOpacity); its error is at most max |q⁽⁶⁾| / 6! · 2⁻⁵ (h/2)⁶ (the
// interpolation remainder with the nodal polynomial's maximum at Chebyshev points; Trefethen,
// "Approximation Theory and Approximation Practice", 2013, ch. 11 and Theorem 15.1), and
// |q⁽⁶⁾| ≤ max |f⁽⁷⁾| / 7 = r |(r − 1)…(r − 6)| (1 − top)^(r − 7) / 7. For top ≤ 0.75 and r in
// [0.01, 16] that is below 1e-15 of f; with the rounding of the nodes' values and of the
// evaluation the table is within 2e-15 of correctOpacity (the test checks 4e-15 over α from 1e-6
// to 0.75 and r from 0.01 to 16). Above top, at α ≤ 0 and for any other exponent correct() is
// correctOpacity() itself. An exponent within 1e-14 of the table's (a ray's r differs from
// stepVoxels by a few ulps) takes the table, i.e. the table's r: that moves α' by at most 1e-14
// of itself (d ln f / d ln r = x / (eˣ − 1) ≤ 1 with x = −r ln(1 − α) ≥ 0). Altogether
// |correct() − correctOpacity()| ≤ 2e-14 · correctOpacity() (the stated tolerance).
class OpacityCorrection {
public:
    OpacityCorrection() = default;  // no table: correct() is correctOpacity()
    // The table for exponent `stepInVoxels` (> 0, finite) on α in [0, min(alphaMax, 0.75)].
    OpacityCorrection(double stepInVoxels, double alphaMax);

    bool tabulated() const { return !coef_.empty(); }
    double exponent() const { return r_; }
    double top() const { return top_; }
    // correctOpacity(alphaVoxel, stepInVoxels) within 2e-14 of it (above).
    double correct(double alphaVoxel, double stepInVoxels) const {
        if (alphaVoxel > 0.0 && alphaVoxel <= top_ &&
            std::abs(stepInVoxels - r_) <= kExponentMatch * r_) {
            // Interval i of [0, top]; u in [−½, ½] across it (α = top exactly: the last one).
            const double x = alphaVoxel * invH_;
            const int i = std::min(int(x), last_);
            const double u = x - (double(i) + 0.5);
            const double* c = coef_.data() + size_t(i) * kCoefs;
            // Estrin's scheme: three short chains instead of Horner's one of five.
            const double u2 = u * u;
            const double q = (c[0] + u * c[1]) + u2 * ((c[2] + u * c[3]) + u2 * (c[4] + u * c[5]));
            return alphaVoxel * q;
        }
        return correctOpacity(alphaVoxel, stepInVoxels);
    }

    static constexpr int kCoefs = 6;                  // degree 5
    static constexpr double kIntervalsPerUnit = 256;  // h = 1 / 256
    static constexpr double kTopLimit = 0.75;
    static constexpr double kExponentMatch = 1e-14;

private:
    double r_ = 0.0, top_ = -1.0, invH_ = 0.0;
    int last_ = 0;
    std::vector<double> coef_;  // kCoefs per interval, powers of u ascending
};

class TransferFunction {
public:
    TransferFunction() = default;
    // Throws lobe::Error (naming `name` and the point index) when values are not finite or not
    // sorted, or an opacity is outside [0, 1) or a colour band negative/not finite. Opacity 1 is
    // refused because equation (1) then makes every step opaque whatever its length.
    explicit TransferFunction(std::vector<TfPoint> points,
                              const std::string& name = "transfer function");

    double opacity(double value) const;
    Spectrum colour(double value) const;
    // Both at once (one search).
    void evaluate(double value, double& opacity, Spectrum& colour) const;
    // The marcher's hot path, which drops transparent samples: evaluate()'s opacity, bit for bit,
    // and its colour only where that opacity is > 0 (else `colour` is left as it was). Between
    // two control points of opacity 0 the opacity is 0 + s · 0 = 0 for every s in [0, 1], so
    // neither the division nor the colour's interpolation is done there.
    double opacityIfVisible(double value, Spectrum& colour) const {
        const size_t n = points_.size();
        if (n == 0) return 0.0;
        const TfPoint* p = points_.data();
        // The first point strictly above `value`, as in evaluate().
        const size_t i =
            size_t(std::upper_bound(p, p + n, value,
                                    [](double v, const TfPoint& q) { return v < q.value; }) -
                   p);
        if (i == 0 || i == n) {
            const TfPoint& e = p[i == 0 ? 0 : n - 1];
            colour = e.colour;
            return e.opacity;
        }
        const TfPoint& a = p[i - 1];
        const TfPoint& b = p[i];
        if (a.opacity == 0.0 && b.opacity == 0.0) return 0.0;
        const double s = (value - a.value) / (b.value - a.value);
        colour = a.colour * (1.0 - s) + b.colour * s;
        return a.opacity + s * (b.opacity - a.opacity);
    }

    // Exact maximum of the opacity over [lo, hi]: a piecewise-linear function takes its maximum
    // at an interval end or at a control point inside. Used by empty-space skipping.
    double maxOpacity(double lo, double hi) const;
    bool isTransparent(double lo, double hi) const { return !(maxOpacity(lo, hi) > 0.0); }

    // The maximal value ranges where the opacity is 0 (may start at −inf or end at +inf); for
    // reports and for integrators that want to clip rays themselves.
    std::vector<std::pair<double, double>> transparentRanges() const;

    const std::vector<TfPoint>& points() const { return points_; }

    // --- The paper's presets (Koldenhof 2003, "Rendering settings" and Figure 10) ---
    // Density map `index` (0..3): iso 0.70 / 0.75 / 0.80 / 0.85, opacity 0.3 / 0.4 / 0.5 / 0.6,
    // colour blue / green / yellow / red (pure linear-sRGB primaries converted to bands). Each map
    // is the band of values between its iso value and the next one (the last map has no upper
    // end), so the four maps are disjoint objects that may carry their own BRDF. The opacity
    // ramps linearly from 0 at iso − w/2 to full at iso + w/2 (w = rampWidth, < 0.05), so the half
    // opacity sits at the paper's iso value; it falls the same way at the next iso value.
    static TransferFunction densityMap(int index, double rampWidth = 0.02);
    // All four maps in one object: the same ramps, colour cross-fading between neighbours.
    static TransferFunction densityMaps(double rampWidth = 0.02);
    // Cortex: transparent below boundary − width/2, then opacity 0.001 rising linearly to 0.2 at
    // boundary + width/2 and staying there (the paper's "opacity of the cortex ranged from 0.001
    // to 0.2"; the boundary ≈ 0.47 of the T1 maximum, docs/paper-scene.md). The paper
    // gives no cortex colour; the default is a light warm grey, linear sRGB (0.8, 0.7, 0.65).
    static TransferFunction cortex(double boundary = 0.47, double width = 0.1,
                                   const Spectrum& colour = linearSrgbToBands(0.8, 0.7, 0.65));
    // Cortex shell: the translucent shell of the paper scenes (scripts/make_paper_scenes.py,
    // CORTEX_TF), where `cortex` above is opaque from the boundary up and hides what is inside.
    // A tent around the T1 boundary between CSF (≈ 0.30 of the maximum) and grey matter (≈ 0.65),
    // 0.47 (docs/paper-scene.md): transparent below boundary − width/2, a step to 0.001 there,
    // rising linearly to `opacity` at the boundary, falling back to 0.001 at boundary + width/2 and
    // a step to 0 above, so both the CSF and the tissue inside stay clear and what lies inside the
    // brain (the density maps) shows through. The paper's range "0.001 to 0.2" gives the edge and
    // default peak opacity (per voxel length, see above); opacity is in [0.001, 1). Width 0.14 and
    // the colour, bands (0.85, 0.72, 0.62) (a warm grey; the paper gives none), are the paper
    // scenes' own, so the preset reproduces them exactly.
    static TransferFunction cortexShell(double boundary = 0.47, double width = 0.14,
                                        double opacity = 0.2,
                                        const Spectrum& colour = Spectrum(0.85, 0.72, 0.62));

private:
    std::vector<TfPoint> points_;
};

}  // namespace lobe
