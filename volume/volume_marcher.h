// Ray marching of one DVR volume object: samples front to back along a world ray at a fixed step
// in voxels, with a jittered start and empty-space skipping through a min/max brick grid that
// knows the transfer function's transparent ranges. It yields samples (position, value, opacity,
// colour; the gradient on request) and never shades them: the integrator (render/integrator.h)
// interleaves several volumes and surfaces by depth with VolumeRaySampler::next(tEnd, sample),
// lights the samples (render/shading.h) and composites them (render/compositor.h).
//
// Sample lattice. For a ray entering the volume's domain at t_in (after clipping to
// [ray.tMin, ray.tMax]), samples lie at
//     t_k = t_in + (k + ξ) Δt,   k = 0, 1, …,   ξ ∈ [0, 1) the per-ray jitter,
// with Δt chosen so that a step is `stepVoxels` voxels long *in index space* along this ray:
// Δt = stepVoxels / |J⁻¹ d| (J: index → world, d: ray direction). On anisotropic grids the sample
// density per voxel is thus the same in every direction (the paper's "0.05, i.e. for every voxel
// 20 samples"). Each sample stands for one step of length Δt (a Riemann sum of
// the volume rendering integral, Max 1995, eq. 9) and its opacity is corrected for the world length
// of that interval (transfer_function.h eq. 1): α = 1 − (1 − α_TF(v))^(Δt |d| / ℓ_ref). The lattice
// depends only on the ray and ξ, never on how the integrator splits the ray into segments, so
// surfaces between samples change nothing but the order of compositing.
//
// Domain. The volume is the grid's active voxel bounding box grown by 2 voxels (the support of
// the cubic B-spline); outside it nothing is sampled, whatever the background value.
//
// Empty-space skipping. The domain is divided into bricks of B³ voxels (B = 4). For each brick we
// store the min and max voxel value over the footprint of every sample that can fall inside it
// (the brick grown by 1 voxel below and 2 above, the B-spline's 4³ support; trilinear needs less).
// Both filters have non-negative weights summing to 1 (reconstruction.h), so every value
// reconstructed in the brick lies in [min, max]; if the transfer function's maximum opacity over
// that range is 0 (TransferFunction::maxOpacity, exact for piecewise-linear functions) every
// sample in the brick is transparent and the marcher jumps to the first lattice point beyond the
// brick's exit. B = 4 rendered the paper scene ~15 % faster than B = 8 (finer bricks skip more of
// the cortex shell's surroundings; the table is 1 byte per 64 voxels; B = 1 and 2 were no faster:
// more jumps). Inside a brick that is not transparent, a second level marks single cells
// [c, c+1)³ whose own support (c−1 … c+2 for the B-spline, c … c+1 for trilinear) is
// transparent: from a lattice point in such a cell the marcher jumps to the first point past the
// cell's exit, as it does past a transparent brick (a thin shell transfer function such as the
// cortex's leaves most cells of its bricks transparent: on rendering 1 the reconstructions per
// camera ray fell from 60.8 to 31.5, the render time by ~16 %; the jump, instead of one bit test
// per point, matters at fine steps: a cell holds ~20 points at step 0.05). Jumps are
// conservative: a point that rounding leaves on an exit plane is tested again, never passed.
// The cell test works on floor(p) in integers — no std::floor or division per lattice point —
// hence brick sizes that are powers of two. Skipping therefore changes no sample that
// contributes: on and off give the same
// composited colour up to floating-point rounding (a tiny margin of 1e-6 on the range guards
// rounding). This min/max hierarchy replaces OpenVDB's HDDA (tools::VolumeRayIntersector),
// which only knows the active topology — a dense MRI grid is active almost everywhere — and
// refuses grids with non-uniform voxels such as the paper's 2 × 2 × 2.4 mm density maps.
//
// Cell distances. The two levels above cost a brick test and a cell test per lattice point, and
// at coarse steps a transparent cell inside a visible brick was stepped point by point: a T2 ray
// through the CThead at step 1 visited 37 points for 10 reconstructions (11 brick jumps, 14
// transparent cells stepped). When the dense copy exists (and without pre-integration) one byte
// per cell and octant of directions replaces both: for the octant of signs s = (±1, ±1, ±1),
// the side m of the largest cube of transparent cells that starts at the cell and extends
// towards s, {c + (s_x o_x, s_y o_y, s_z o_z) : 0 ≤ o_a < m} (0 for a cell that is not
// transparent), capped at 254. A ray reads the table of its own octant (a zero direction
// component counts as +: the ray then stays in its cell's slab along that axis), and from a
// lattice point in a cell with m ≥ 1 it jumps to the first point past that cube — a ray moving
// into the octant leaves the cube only through its far faces, so the cube's whole length ahead
// is one jump, where a cube centred on the cell (the single table before, one byte per cell:
// the chessboard distance d, cube (2d − 1)³) spent half its reach behind the ray and was limited
// by whatever lay behind it. On T2 at step 1 the table reads per ray fell from 27 to 18 (jumps
// 11.2 → 6.0, cells stepped 5.4 → 2.2; docs/performance.md). At fine steps (below 0.3 voxel) the
// points after the first one in a visible cell, up to the ray's exit from that cell, skip the
// read too (at step 0.05 a cell holds ~20 points). Where the distance saturates the brick
// clearance gives the longer jump when it reaches further. Each table is exact: m = 0 on cells
// that are not transparent, else min(cap, 1 + min over the 7 neighbours c + s∘δ, δ ∈ {0,1}³,
// δ ≠ 0), one raster pass against the octant's signs; cells outside the table count as
// transparent as for the bricks. The cells' transparency is the two levels' (a cell of a
// transparent brick, or a cell whose bit is set), so the samples that contribute are the same
// as with the two levels, bit for bit. Memory: 8 bytes per cell (the CThead's 7.8 M cells: 63
// MB, twice its dense copy), built in parallel at load (~0.1 s for the CThead); only when that
// fits the dense copy's budget (DenseField::kMaxBytes and an eighth of the memory), else the
// marcher keeps the brick and cell tests. At coarse steps (≥ 0.3 voxel) with these tables and
// trilinear values, next() runs a shorter loop (nextCoarseTrilinear): the same operations for
// every point it evaluates, one floor(p) for the table read and the value, no transfer-function
// interpolation between two transparent control points (docs/performance.md, round 4). That loop
// keeps its lattice index in a register and is compiled twice: for the baseline x86-64 and, run
// where the CPU has it, for AVX2 (floor and the jump's ceil one instruction each; no fused
// multiply-add, so the same samples bit for bit; round 6).
//
// Ray cells. The tables above know a cell, not the ray's stretch through it: on rendering 1 half
// of the cortex's lattice packets (1.6 M of 3.1 M at 512² × 2 spp, 14.9 M of its 30.9 M points)
// were all transparent, in cells whose values reach the shell's tent where the ray's do not.
// On the B-spline's ray-polynomial path (steps below 0.075 voxel, no pre-integration, skipping
// on), at the first point next() evaluates in a cell it bounds the ray's degree-9 polynomial
// over the stretch from that point to the cell's exit by its Bernstein coefficients (convex
// hull; Farouki & Rajan, "On the numerical condition of polynomials in Bernstein form", CAGD 4,
// 1987); when they lie, with the tables' margin, below the transfer function's first visible
// value or above its last (TransferFunction::transparentRanges), every point of the stretch is
// transparent and the marcher jumps past the cell as past a transparent one. The packet and
// the scalar path bound the same cells at the same points, so they still agree sample for
// sample, counters and peekT() included.
//
// Pre-integration (DvrSettings::preIntegrated; volume/pre_integration.h). Each sample then
// stands for the segment from the previous lattice point to it: its opacity and colour are the
// segment's, for a value running linearly between the two points' values, and it is shaded with
// the normal at its own (back) point. Skipping needs one change: the segment that leaves a
// visible region ends at the first point of a transparent brick or cell, which is therefore
// evaluated; and a segment that enters one starts at a skipped point, whose value is then
// reconstructed (not counted as evaluated). A segment between two points of transparent cells
// counts as transparent (its values lie in the union of the two cells' ranges, transparent
// unless the ray clips a visible cell between them), so skipping changes a pre-integrated image
// by at most such clipped corners: the tests bound it.
//
// Normals. The gradient is computed only for samples with non-zero opacity (and, with
// next(…, false), only for those the caller shades), in world space. The
// sample has a usable normal when |∇f| · ℓ_ref ≥ minGradientPerVoxel (default 1e-3 value units
// per voxel: an 8-bit map quantised to 1/255 has steps of 4e-3 per voxel, so flat regions below a
// quarter of one quantisation step per voxel are called flat). normal = −∇f / |∇f| (pointing from
// dense to sparse material, outwards of a structure). Samples without a usable normal are not
// BRDF-shaded (render/shading.h lights them with the Lambertian term and cos θ = 1).
#pragma once

#include "core/clip.h"
#include "core/ray.h"
#include "core/spectrum.h"
#include "volume/dvr_simd.h"
#include "volume/pre_integration.h"
#include "volume/reconstruction.h"
#include "volume/transfer_function.h"
#include "volume/volume_mask.h"

#include <array>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace lobe {

struct DvrSettings {
    Reconstruction reconstruction = Reconstruction::kTrilinear;
    GradientMethod gradient = GradientMethod::kCentralDifferences;
    double stepVoxels = 0.05;  // the paper's sampling: 20 samples per voxel
    bool emptySpaceSkipping = true;
    int brickSize = 4;                  // voxels per brick side, a power of two
    double minGradientPerVoxel = 1e-3;  // below: no usable normal (header)
    // Segments between samples classified by pre-integration (volume/pre_integration.h, header
    // "Pre-integration") instead of the transfer function at the sample.
    bool preIntegrated = false;
    // Clip shapes (core/clip.h): only the ray's kept intervals are sampled. The lattice starts
    // at the first kept point (t_in above is then the later of the domain entry and the first
    // interval's start) and jumps over the gaps between intervals, so empty-space skipping
    // works inside them as before.
    std::vector<ClipShape> clip;
    // A mask (volume/volume_mask.h): samples where it does not keep the object are transparent.
    // Tested only for samples the transfer function makes visible, so skipping is unchanged.
    std::shared_ptr<const VolumeMask> mask;
    // Lattice packets (volume/dvr_simd.h): at steps below 1/4 voxel, trilinear values from the
    // dense copy and the B-spline's ray polynomial are computed for up to 16 consecutive lattice
    // points at once with SIMD — the same bits as one by one. false (or LOBE_SIMD=off in the
    // environment) keeps the scalar path, the reference; it also keeps the coarse-step path's
    // baseline copy instead of its AVX2 one (VolumeRaySampler::coarsePathAvx2; the same bits).
    bool simd = true;
};

struct VolumeSample {
    double t = 0.0;           // ray parameter
    Vec3 position{0.0};       // world
    Vec3 indexPosition{0.0};  // the same point in the grid's index space (for addNormal)
    double value = 0.0;       // reconstructed data value
    Vec3 gradient{0.0};       // world-space gradient of the value
    Vec3 normal{0, 0, 1};     // −gradient / |gradient|, valid when hasNormal
    bool hasNormal = false;
    double alpha = 0.0;    // opacity of this step, already corrected (header)
    Spectrum colour{0.0};  // transfer-function colour
};

// One DVR object: a grid, its transfer function and the sampling settings, plus the brick
// min/max table. Immutable after construction and shared by all threads.
class DvrVolume {
public:
    // Throws lobe::Error naming `name` for a non-linear/singular transform or bad settings
    // (step not in (0, 16], brick size not a power of two in [1, 64], negative gradient
    // threshold).
    DvrVolume(openvdb::FloatGrid::ConstPtr grid, TransferFunction tf, const DvrSettings& settings,
              const std::string& name = "volume");

    const openvdb::FloatGrid& grid() const { return *grid_; }
    const TransferFunction& transferFunction() const { return tf_; }
    const DvrSettings& settings() const { return settings_; }
    const GridGeometry& geometry() const { return geometry_; }
    bool empty() const { return empty_; }
    // Fraction of bricks that are transparent under the transfer function (for reports).
    double transparentBrickFraction() const;
    // The dense copy of the domain's voxels the samplers read (volume/dense_field.h), or null
    // when the domain is larger than DenseField::kMaxBytes (then they read the tree).
    const DenseField* dense() const { return dense_.get(); }
    // The brick table (header, "Empty-space skipping"): bricks per axis, and a brick's
    // clearance — 0 when a sample in it may be visible, else c ≥ 1 such that the cube of
    // (2c − 1)³ bricks centred on it is transparent (at most 64).
    std::array<int, 3> brickCounts() const {
        return {brickCount_[0], brickCount_[1], brickCount_[2]};
    }
    int brickClearance(int bx, int by, int bz) const {
        return brickTransparent_[(size_t(bz) * brickCount_[1] + by) * brickCount_[0] + bx];
    }
    // The cell distance tables (header, "Cell distances"): whether they were built, and for the
    // cell [i, i+1) × [j, j+1) × [k, k+1) (index space) its chessboard distance in cells to the
    // nearest cell that may hold a visible sample, capped at kCellDistanceCap; 0 for such a
    // cell. Cells outside the table: −1. The minimum over the 8 octant tables (the nearest
    // visible cell lies in some octant's orthant); for reports and tests — the marcher reads
    // the octant tables.
    bool hasCellDistances() const { return octantDistance_[0] != nullptr; }
    int cellDistance(int i, int j, int k) const;
    static constexpr int kCellDistanceCap = 16;
    // The octant tables the marcher reads (header, "Cell distances"): for the octant of
    // directions with signs s = (±1, ±1, ±1) (octant bit a set when s_a = −1), the side m of the
    // largest cube of transparent cells {c + (s_x o_x, s_y o_y, s_z o_z) : 0 ≤ o_a < m}, capped at
    // kOctantDistanceCap; 0 for a visible cell, −1 outside the table.
    int octantDistance(int octant, int i, int j, int k) const {
        const int q[3] = {i - brickLo_[0], j - brickLo_[1], k - brickLo_[2]};
        for (int a = 0; a < 3; ++a)
            if (q[a] < 0 || q[a] >= cellCount_[a]) return -1;
        return octantDistance_[size_t(octant)][cellSlot(q[0], q[1], q[2])];
    }
    static constexpr int kOctantDistanceCap = 254;
    // Whether the brick and cell tables call the cell [i, i+1)³ … transparent (a cell of a
    // transparent brick, or one whose bit is set); false outside the tables.
    bool cellTransparent(int i, int j, int k) const;

private:
    friend class VolumeRaySampler;
    openvdb::FloatGrid::ConstPtr grid_;
    TransferFunction tf_;
    DvrSettings settings_;
    GridGeometry geometry_;
    bool empty_ = true;
    std::shared_ptr<const DenseField> dense_;
    std::shared_ptr<const PreIntegratedTf> pre_;  // when settings_.preIntegrated
    std::shared_ptr<const TfArrays> tfArrays_;    // the TF for lattice packets
    // Equation (1) of transfer_function.h for the exponent stepVoxels (an isotropic grid's rays
    // at stepScale 1) on the TF's opacities.
    OpacityCorrection correction_;
    // Values below visibleLo_ or above visibleHi_ are transparent (−inf / +inf: no such end).
    double visibleLo_ = -std::numeric_limits<double>::infinity();
    double visibleHi_ = std::numeric_limits<double>::infinity();
    Vec3 domainLo_{0.0}, domainHi_{0.0};  // index space, continuous
    int brickLo_[3] = {0, 0, 0};          // index of brick (0,0,0)'s first voxel
    int brickCount_[3] = {0, 0, 0};
    int brickShift_ = 0;  // log2 of the brick size
    // Per brick: 0 when some sample in it may be visible, else its clearance c ≥ 1 — the cube of
    // (2c − 1)³ bricks centred on it is transparent (brickClearance), so a ray jumps past it.
    std::vector<unsigned char> brickTransparent_;
    static constexpr int kMaxClearance = 64;
    void computeClearance();
    // Inside bricks that are not transparent: one bit per cell [c, c+1)³ (cells x-fastest within
    // the brick, cellWords_ words per brick), set when every sample in the cell is transparent
    // (header, "Empty-space skipping").
    int cellWords_ = 0;
    std::vector<uint64_t> cellTransparent_;
    // Per octant and cell of the brick table's box (cellCount_ = brickCount_ · B per axis): the
    // side of the largest transparent cube from the cell towards the octant, capped at
    // kOctantDistanceCap (header, "Cell distances"). Null without the dense copy (very large
    // grids), with pre-integration or without skipping: the marcher then tests bricks and cells.
    int cellCount_[3] = {0, 0, 0};
    // Not value-initialised: every cell is written by computeCellDistances.
    std::array<std::unique_ptr<unsigned char[]>, 8> octantDistance_;
    void computeCellDistances();
    // Where cell (x, y, z) of the table (from brickLo_) is stored: brick by brick, B³ cells each.
    size_t cellSlot(int x, int y, int z) const {
        const int s = brickShift_, m = (1 << s) - 1;
        const size_t brick =
            (size_t(z >> s) * brickCount_[1] + size_t(y >> s)) * brickCount_[0] + size_t(x >> s);
        return (brick << (3 * s)) + size_t((((z & m) << s) + (y & m)) << s) + size_t(x & m);
    }
};

// Per-thread, per-ray marching state for one DvrVolume (holds an OpenVDB accessor: never share
// between threads; reuse across rays with begin()).
class VolumeRaySampler {
public:
    explicit VolumeRaySampler(const DvrVolume& volume);

    // Starts a ray with jitter ξ ∈ [0, 1). Returns false when the ray misses the domain (then
    // next() returns false at once).
    // stepScale ≥ 1 multiplies the volume's step for this ray (shadow rays of the shadow cache,
    // render/shadow_cache.h; the opacity correction follows the step, as it does for any step).
    bool begin(const Ray& ray, double jitter, double stepScale = 1.0);

    // The next sample with non-zero opacity and t < tEnd, in lattice order. Returns false when
    // there is none before tEnd; the state then stays at the first lattice point ≥ tEnd (or
    // beyond a skipped brick — only transparent points are ever passed), so calling again with a
    // larger tEnd continues the same lattice. With withNormal = false the gradient, normal and
    // hasNormal are left unset — an integrator that may not shade the sample (Russian roulette)
    // calls addNormal() only when it does, and saves the gradient (a third of a B-spline
    // sample's cost) otherwise.
    bool next(double tEnd, VolumeSample& sample, bool withNormal = true);

    // Fills gradient, normal and hasNormal of a sample this sampler returned; the same values
    // next(…, true) would have given.
    void addNormal(VolumeSample& sample);

    // Calls fn(const VolumeSample&) → bool (false: stop) for every sample with t < tEnd. Returns
    // false if fn stopped the march.
    template <class Fn>
    bool marchSegment(double tEnd, Fn&& fn) {
        VolumeSample s;
        while (next(tEnd, s))
            if (!fn(s)) return false;
        return true;
    }

    // Ray parameter of the next lattice point still to be visited (may be transparent);
    // +inf when the ray has left the domain.
    double peekT() const;
    double tEnter() const { return tEnter_; }
    double tExit() const { return tExit_; }
    double stepT() const { return dt_; }

    // Counters over the sampler's life: lattice points whose value was reconstructed, and lattice
    // points jumped over by empty-space skipping.
    long long samplesEvaluated() const { return evaluated_; }
    long long samplesSkipped() const { return skipped_; }
    // Lattice packets computed (DvrSettings::simd; 0 on the scalar path).
    long long packetsFilled() const { return packets_; }
    // Whether this ray runs next()'s coarse-step path (octant tables, trilinear, steps ≥ 0.3
    // voxel, no clip gaps or pre-integration): the same samples with fewer branches.
    bool coarsePath() const { return coarseTrilinear_; }
    // Whether it runs that path's AVX2 copy (CPUs with AVX2, unless DvrSettings::simd is false
    // or LOBE_SIMD=off): the same samples bit for bit.
    bool coarsePathAvx2() const { return coarseAvx2_; }

private:
    // Moves k_ to the first lattice point past the box [lo, lo + size)³ (index space), which
    // must be transparent, counting the points passed as skipped.
    void jumpPastBox(const int lo[3], int size);
    // The lattice index jumpPastBox moves to from index k.
    long long pastBox(const int lo[3], int size, long long k) const;
    // The lattice index past the transparent cells ahead of the point at index k in cell
    // (table coordinates q = cell − brickLo_), whose octant distance is d ≥ 1: past the octant's
    // cube of side d, or past the cube of transparent bricks around it when d is capped and that
    // reaches further (skipByCellDistance and the coarse path).
    long long pastTransparentCells(const int q[3], const int cell[3], int d, long long k) const;
    // The empty-space test of next() through the cell distance table for the lattice point p:
    // true when it moved k_ past transparent points (the caller goes on to the next point),
    // false when p must be evaluated.
    // Sets cell to floor(p) in any case.
    bool skipByCellDistance(const Vec3& p, int cell[3]);
    // next() at coarse steps with the octant tables and trilinear values, without clipping
    // intervals or pre-integration (begin() decides): the same samples, fewer branches.
    bool nextCoarseTrilinear(double tEnd, VolumeSample& s, bool withNormal);
    // The same compiled for AVX2 (coarseAvx2_; volume_marcher.cpp), and the loop both run: the
    // lattice index and the counters in locals, written back when it returns.
    bool nextCoarseTrilinearAvx2(double tEnd, VolumeSample& s, bool withNormal);
    template <bool kFloorInstruction>
    [[gnu::always_inline]] inline bool coarseTrilinearLoop(double tEnd, VolumeSample& s,
                                                           bool withNormal);
    // The B-spline path's third level of skipping (header, "Ray cells"): at the first point
    // next() evaluates in a cell, whether the Bernstein bound of the ray's polynomial over its
    // stretch through the cell lies outside the TF's visible values; sets cell to the cell.
    bool rayCellTransparent(double t, int cell[3]);
    bool boundRayCells_ = false;
    int boundCell_[3] = {0, 0, 0};  // the cell last bounded on this ray
    // The opacity of one step for a voxel opacity (correctOpacity; from the volume's table when
    // the ray's exponent is the table's, within 2e-14 of it), computed once per run of equal
    // opacities — a transfer function's plateau is common.
    double correctedOpacity(double alphaVoxel) {
        if (alphaVoxel != lastAlphaVoxel_) {
            lastAlphaVoxel_ = alphaVoxel;
            lastAlpha_ = vol_->correction_.correct(alphaVoxel, stepRefLengths_);
        }
        return lastAlpha_;
    }
    // The end of every path of next(): fills s for the point at t (index position p) and
    // returns true.
    bool emit(VolumeSample& s, double t, const Vec3& p, double value, double alpha,
              const Spectrum& colour, bool withNormal) {
        s.t = t;
        s.indexPosition = p;
        s.position = vol_->geometry_.indexToWorld(p);
        s.value = value;
        s.alpha = alpha;
        s.colour = colour;
        if (withNormal) addNormal(s);
        return true;
    }
    bool coarseTrilinear_ = false;
    bool coarseAvx2_ = false;  // coarsePathAvx2()
    // Ray parameter where the ray leaves the last visible cell skipByCellDistance found (fine
    // steps only): points before it are evaluated without a table read.
    double visibleCellEnd_ = -std::numeric_limits<double>::infinity();
    // The octant table of this ray's direction (null without the tables), and its signs.
    const unsigned char* octantTable_ = nullptr;

    const DvrVolume* vol_;
    GridReconstructor recon_;
    Vec3 oIdx_{0.0}, dIdx_{0.0};
    double tEnter_ = 0.0, tExit_ = -1.0, dt_ = 1.0, jitter_ = 0.0;
    double stepVoxels_ = 0.05;     // this ray's step in voxels (the volume's × stepScale)
    bool rayPolynomial_ = false;   // B-spline values from the ray's polynomial per cell
    double stepRefLengths_ = 1.0;  // world length of one step / ℓ_ref: the opacity exponent
    double invDIdx_[3] = {0, 0, 0}, invDt_ = 1.0;  // 1 / dIdx_ (0 where dIdx_ is 0), 1 / dt_
    double kLast_ = -1.0;  // the last lattice index inside the domain (t ≤ tExit)
    double lastAlphaVoxel_ = -1.0, lastAlpha_ = 0.0;
    // Pre-integration: the last evaluated lattice point, its value, and whether it lay in a
    // transparent brick or cell.
    long long prevK_ = -2;
    double prevValue_ = 0.0;
    bool prevSkippable_ = false;  // the last opacity corrected, and its result
    long long k_ = 0;
    bool active_ = false;
    ClipIntervals clip_;  // kept intervals of the ray (DvrSettings::clip), when clipped
    int clipIndex_ = 0;
    long long evaluated_ = 0, skipped_ = 0;
    // Lattice packets (DvrSettings::simd): values and TF of points packetK0_ … + packetN_ − 1,
    // filled when an evaluated point is not in it; packetSize_ points at a time, 0: scalar.
    // The skipping decisions stay point by point, except for the points in the cell of the
    // packet's first point, which was found visible: their tables give the same answer.
    bool fillPacket();
    // After a transparent point of the packet (k_ already past it): past the transparent points
    // that follow it in the packet's first cell, counted as evaluated — what next()'s loop
    // does with them (they need no table test, their opacity is 0), without the loop. Only
    // when the last of them lies before tEnd and tExit (t grows with k, so all do) and the ray
    // has no clip gaps; otherwise the loop takes them one by one.
    void skipTransparentPacketRun(double tEnd);
    RayLattice lattice_{};
    LatticePacket packet_;
    long long packetK0_ = 0;
    int packetN_ = 0, packetSize_ = 0;
    int packetSameCell_ = 0;  // leading points of the packet in packetK0_'s cell
    long long packets_ = 0;
};

}  // namespace lobe
