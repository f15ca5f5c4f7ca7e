// Pre-integrated classification (Engel, Kraus & Ertl 2001, "High-quality pre-integrated volume
// rendering using hardware-accelerated pixel shading", Graphics Hardware '01): the opacity and
// colour of a whole ray *segment* between two samples, assuming the data value varies linearly
// along it from s_f (front) to s_b (back), instead of the transfer function at one point.
//
// Why: point sampling evaluates the transfer function only at the samples, so a narrow peak of
// the transfer function (the density maps' ramps are 0.02 wide in value) is hit or missed
// depending on where the samples fall, and the error grows fast with the step (54 % at one voxel
// on the density maps). The segment integral sees every value between s_f and s_b, so its error
// depends on how linear the *data* is over a step, not on the transfer function's width.
//
// Quantities (per reference voxel length ℓ_ref, transfer_function.h): extinction
// τ(v) = −ln(1 − α_TF(v)), so that α_step = 1 − exp(−τ L) for a step of L reference lengths
// (equation (1) there). With the integral functions (Engel et al. §3; the "1-D table" form of
// Lum, Wilson & Ma 2004, "High-quality lighting and efficient pre-integration for volume
// rendering", eq. 4)
//     T(v) = ∫_{v0}^{v} τ(u) du,   K(v) = ∫_{v0}^{v} τ(u) c(u) du,
// a segment of length L whose value runs linearly from s_f to s_b has mean extinction
//     τ̄ = (T(s_b) − T(s_f)) / (s_b − s_f)       (exact)
// hence opacity α = 1 − exp(−τ̄ L), and colour c̄ = (K(s_b) − K(s_f)) / (T(s_b) − T(s_f)), the
// extinction-weighted mean colour. The colour neglects the attenuation *within* the segment (the
// usual approximation of the 1-D table; the exact 2-D table would weight c(u) by the
// transmittance from the segment's start): its error vanishes as α → 0 and with the step. When
// Where in the segment: the extinction-weighted mean value ū = (M(s_b) − M(s_f)) / (T(s_b) −
// T(s_f)) with M(v) = ∫ τ(u) u du, as a fraction (ū − s_f) / (s_b − s_f) of the way from front to
// back — the segment's centre of extinction, where the marcher places and shades its sample
// (shading at the back point instead shifted every surface-like structure up to a step deeper: on
// the CThead at step 1 that made the error worse than point sampling's). When |s_b − s_f| < 1e-6 of
// the span, the point values at the midpoint are used (the limit of both formulas; below it the
// quotients would lose more digits to cancellation than the limit does).
//
// Table: T and K at 4096 equal intervals spanning the transfer function's control points, each
// interval integrated by 4-point Gauss–Legendre quadrature (exact for τ·c polynomial of degree
// ≤ 7 on an interval; τ is smooth between control points); linear interpolation between nodes.
// Outside the span the end values hold (transfer_function.h), so T and K continue linearly.
#pragma once

#include "core/spectrum.h"
#include "volume/transfer_function.h"

#include <vector>

namespace lobe {

class PreIntegratedTf {
public:
    static constexpr int kIntervals = 4096;

    explicit PreIntegratedTf(const TransferFunction& tf);

    // Opacity and colour of a segment of `lengthRef` reference voxel lengths whose value runs
    // linearly from sFront to sBack.
    // `where` ∈ [0, 1]: the fraction of the way from front to back of its centre of extinction.
    void segment(double sFront, double sBack, double lengthRef, double& alpha, Spectrum& colour,
                 double& where) const;

    // T(v) and K(v) of the header (for tests).
    double extinctionIntegral(double v) const;
    double momentIntegral(double v) const;
    Spectrum colourIntegral(double v) const;

private:
    // Node index and fraction of v; outside the span, clamps and returns the distance beyond.
    void locate(double v, int& i, double& frac, double& beyond) const;
    // A node table at v, linearly interpolated; `beyond` as locate's, `end` the span's end it
    // lies beyond.
    double interpolate(const std::vector<double>& nodes, double v, double& beyond,
                       double& end) const;

    TransferFunction tf_;
    double v0_ = 0.0, v1_ = 1.0, h_ = 1.0 / kIntervals;
    double tauLo_ = 0.0, tauHi_ = 0.0;    // τ below v0 and above v1
    Spectrum tauCLo_{0.0}, tauCHi_{0.0};  // τ·c there
    std::vector<double> t_;               // T at the nodes
    std::vector<Spectrum> k_;             // K at the nodes
    std::vector<double> m_;               // M at the nodes
};

}  // namespace lobe
