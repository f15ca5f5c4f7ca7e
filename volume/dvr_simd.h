// Lattice packets for the DVR marcher (volume/volume_marcher.h): the values, transfer-function
// opacities and colours of up to kMaxPoints consecutive lattice points of one ray, computed with
// Google Highway (portable SIMD, runtime dispatch to the best target the CPU has: AVX-512, AVX2,
// SSE4, or plain C++).
//
// Why packets along a ray and not across rays: the integrator (render/integrator.h) interleaves
// several volumes and surfaces by depth for each ray, with Russian roulette and shadow rays per
// sample; a lattice packet fits behind VolumeRaySampler::next() unchanged, and at fine steps the
// points of a packet lie in one or two voxel cells (20 points a cell at the paper's step 0.05), so
// their gathers hit the same cache lines. At coarse steps (≥ 1/kMinPoints voxel) the marcher
// stays scalar: a packet would run past the bone that stops the ray.
//
// Exactness. Every lane performs the scalar path's IEEE operations in the same order (the
// lattice t_k = t_in + (k + ξ) Δt, p = o + d t, trilinear lerps a + t (b − a) of
// GridReconstructor::trilinear, Estrin's scheme of GridReconstructor::bsplineOnRay,
// TransferFunction::evaluate's upper-bound search and linear interpolation), and the file is
// compiled with floating-point contraction off (no fused multiply-add the scalar code lacks), so
// the packet path returns the same bits as the scalar path (tests/volume/test_dvr_simd.cpp checks
// samples and images for equality). LOBE_SIMD=off in the environment, or DvrSettings::simd =
// false, forces the scalar path.
#pragma once

#include "volume/dense_field.h"
#include "volume/transfer_function.h"

#include <vector>

namespace lobe {

// A transfer function as arrays (one per field), for the packet kernels.
struct TfArrays {
    std::vector<double> value, opacity, red, green, blue;  // bands 0, 1, 2
    explicit TfArrays(const TransferFunction& tf);
    int size() const { return int(value.size()); }
};

struct LatticePacket {
    static constexpr int kMaxPoints = 16;
    // Packets shorter than this are not worth it (the marcher stays scalar).
    static constexpr int kMinPoints = 4;
    alignas(64) double value[kMaxPoints];
    alignas(64) double alpha[kMaxPoints];  // per reference voxel, before the step correction
    alignas(64) double colour[3][kMaxPoints];
    // How many leading points lie in the voxel cell of the first (floor(p) equal per axis).
    int sameCell = 0;
};

// The lattice of one ray: t_k = tEnter + (k + jitter) dt, index-space point o + d t_k.
struct RayLattice {
    double o[3], d[3];
    double tEnter, jitter, dt;
};

// Trilinear values and TF of lattice points k0 … k0 + n − 1 (n ≤ kMaxPoints) read from `field`.
// Returns n, or 0 when some point's 2³ footprint leaves the field's box (the caller then
// evaluates them one by one from the tree).
int latticePacketTrilinear(const RayLattice& ray, long long k0, int n, const DenseField& field,
                           const TfArrays& tf, LatticePacket& out);

// Values of the ray's cell polynomial f(t) = Σ_j poly[j] (t − t0)^j (bsplineOnRay) and TF at
// lattice points k0 … k0 + m − 1, where m ≤ n is the number of leading points that lie in the
// cell `cell` (integer corner, floor of the point). Returns m (≥ 1 when point k0 lies in the cell).
int latticePacketPolynomial(const RayLattice& ray, long long k0, int n, const double poly[10],
                            double t0, const int cell[3], const TfArrays& tf, LatticePacket& out);

// The coefficients of GridReconstructor::bsplineOnRay's polynomial from a 4³ block f[a][4b + c]
// and the Taylor coefficients W[a][k] of the weights along x, y, z (reconstruction.cpp,
// ensureRayCell): poly[j] = Σ f[a][4b + c] wx[a][k] wy[b][l] wz[c][m] over k + l + m = j, summed
// along x, then y, then z, in the scalar loops' order (so the same bits, with vectors).
void rayCellPolynomial(const float f[4][16], const double wx[4][4], const double wy[4][4],
                       const double wz[4][4], double poly[10]);

// The cubic B-spline over a 4³ block f[a][4b + c] with weights w[axis][·] (GridReconstructor::
// bspline): out[0] = Σ w[0][a] w[1][b] w[2][c] f[a][4b + c], summed along x, then y, then z in
// its loops' order (the same bits). With derivative weights dw (not null), out[1..3] = the
// index-space gradient as bsplineWithGradient sums it.
void bsplineBlock(const float f[4][16], const double w[3][4], const double dw[3][4], double out[4]);

// The Highway target the packet kernels run on ("AVX3", "AVX2", "SSE4", "EMU128", …).
const char* latticePacketTarget();
// Whether the environment forces the scalar path (LOBE_SIMD=off or 0).
bool simdDisabledByEnvironment();

}  // namespace lobe
