// The ray marcher against analytic answers: a homogeneous slab's transmittance (exact with opacity
// correction at every step, and the exponential law), on an anisotropic grid too; opacity
// correction on a smooth Gaussian blob (small and large steps agree, uncorrected ones do not);
// empty-space skipping leaves every contributing sample unchanged; segments do not move the
// lattice; the gradient threshold. Samples are composited with the renderer's compositor
// (render/compositor.h); the integrator's depth merge of several volumes is tested through the
// integrator itself (tests/render/test_hybrid.cpp).
#include "core/memory.h"
#include "core/rng.h"
#include "dvr_test_grids.h"
#include "render/compositor.h"
#include "volume/volume_marcher.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

namespace lobe {
namespace {

using openvdb::Coord;

// Opacity α (per voxel) wherever the value is ≥ 0.5, 0 below: on a field that is 1 on a box of
// voxels and 0 outside, trilinear reconstruction crosses 0.5 half a voxel outside the box, so
// the slab of voxels 0..63 is exactly 64 voxels thick.
TransferFunction stepTf(double alpha, const Spectrum& colour = Spectrum(1.0)) {
    return TransferFunction({{0.5, 0.0, colour}, {0.5, alpha, colour}});
}

openvdb::FloatGrid::Ptr slabGrid(int x0, int x1, const openvdb::Vec3d& voxel = openvdb::Vec3d(1)) {
    return test::makeGrid([](int, int, int) { return 1.0; }, Coord(x0, 0, 0), Coord(x1, 15, 15),
                          voxel);
}

// Composites every sample with its colour as radiance (no lighting): C = Σ T α c.
FrontToBackCompositor compositeRay(const DvrVolume& vol, const Ray& ray, double jitter,
                                   bool stopEarly = false) {
    VolumeRaySampler s(vol);
    FrontToBackCompositor c;
    if (!s.begin(ray, jitter)) return c;
    s.marchSegment(ray.tMax, [&](const VolumeSample& v) {
        c.add(v.alpha, v.colour);
        return !(stopEarly && c.terminated());
    });
    return c;
}

TEST(VolumeMarcher, SlabTransmittanceIsExactForEveryStep) {
    // T after L = 64 voxels of per-voxel opacity α: (1 − α)^64 = exp(−σ L) with σ = −ln(1 − α)
    // per voxel (Beer–Lambert). Each of the L/Δ samples has 1 − (1 − α)^Δ (eq. 1), so the product
    // is exact for any Δ that divides L (jitter 0.37 keeps lattice points off the slab faces).
    const double alpha = 0.05;
    auto grid = slabGrid(0, 63);
    for (double step : {0.05, 0.1, 0.25, 0.5, 1.0}) {
        DvrSettings set;
        set.stepVoxels = step;
        const DvrVolume vol(grid, stepTf(alpha), set);
        Ray ray;
        ray.o = Vec3(-10, 7.3, 8.1);
        ray.d = Vec3(1, 0, 0);
        const FrontToBackCompositor c = compositeRay(vol, ray, 0.37);
        const double sigma = -std::log(1.0 - alpha);
        EXPECT_NEAR(c.transmittance, std::exp(-sigma * 64.0), 1e-12) << "step " << step;
        EXPECT_NEAR(c.transmittance, std::pow(1.0 - alpha, 64.0), 1e-12) << "step " << step;
        // White emission-only compositing: C = 1 − T.
        EXPECT_NEAR(c.radiance[1], 1.0 - c.transmittance, 1e-12);
    }
}

TEST(VolumeMarcher, SlabOnAnisotropicGridIsIsotropicInWorld) {
    // Voxels 1 × 1 × 2: ℓ_ref = cbrt(2). Along x the slab (index x 0..63, 64 voxels) is 64 world
    // units thick: T = (1 − α)^(64/ℓ_ref). A slab of 64 voxels along z is 128 world units: T =
    // (1 − α)^(128/ℓ_ref). Same world length → same T, whatever the direction.
    const double alpha = 0.05, ref = std::cbrt(2.0);
    auto gx = slabGrid(0, 63, openvdb::Vec3d(1, 1, 2));
    auto gz = test::makeGrid([](int, int, int) { return 1.0; }, Coord(0, 0, 0), Coord(15, 15, 63),
                             openvdb::Vec3d(1, 1, 2));
    for (double step : {0.05, 0.5}) {
        DvrSettings set;
        set.stepVoxels = step;
        const DvrVolume vx(gx, stepTf(alpha), set), vz(gz, stepTf(alpha), set);
        Ray rx;
        rx.o = Vec3(-10, 7.3, 16.2);
        rx.d = Vec3(1, 0, 0);
        Ray rz;
        rz.o = Vec3(7.3, 8.1, -20);
        rz.d = Vec3(0, 0, 1);
        EXPECT_NEAR(compositeRay(vx, rx, 0.37).transmittance, std::pow(1 - alpha, 64 / ref), 1e-12);
        EXPECT_NEAR(compositeRay(vz, rz, 0.37).transmittance, std::pow(1 - alpha, 128 / ref),
                    1e-12);
        // Samples per voxel along z: Δt = step × 2 world units, so 64/step samples in the slab.
        VolumeRaySampler s(vz);
        ASSERT_TRUE(s.begin(rz, 0.37));
        EXPECT_NEAR(s.stepT(), 2 * step, 1e-15);
    }
}

TEST(VolumeMarcher, EarlyTerminationAtDocumentedTransmittance) {
    // α = 0.5 per voxel: T = 2^−n after n voxels; 2^−10 < 1e-3 ≤ 2^−9, so the march stops within
    // the 10th voxel and the stopped colour differs from the full one by less than 1e-3.
    auto grid = slabGrid(0, 63);
    DvrSettings set;
    set.stepVoxels = 0.25;
    const DvrVolume vol(grid, stepTf(0.5), set);
    Ray ray;
    ray.o = Vec3(-10, 7.3, 8.1);
    ray.d = Vec3(1, 0, 0);
    const FrontToBackCompositor stopped = compositeRay(vol, ray, 0.37, true);
    const FrontToBackCompositor full = compositeRay(vol, ray, 0.37, false);
    EXPECT_TRUE(stopped.terminated());
    EXPECT_GT(stopped.transmittance, std::pow(0.5, 10.25));
    EXPECT_LT(stopped.transmittance, kDefaultTerminationTransmittance);
    EXPECT_LT(std::abs(stopped.radiance[0] - full.radiance[0]), kDefaultTerminationTransmittance);
}

// A Gaussian blob (σ_b = 5 voxels) with a colour ramp blue → red and opacity 0 → 0.3 over
// value 0 → 1: smooth data.
struct Blob {
    openvdb::FloatGrid::Ptr grid = test::makeGrid(
        [](int i, int j, int k) {
            const double r2 =
                (i - 20.0) * (i - 20.0) + (j - 20.0) * (j - 20.0) + (k - 20.0) * (k - 20.0);
            return std::exp(-r2 / (2 * 25.0));
        },
        Coord(0), Coord(40));
    TransferFunction tf{{{0.0, 0.0, Spectrum(0, 0, 1)}, {1.0, 0.3, Spectrum(1, 0, 0)}}};
};

// Averages over a 5×5 bundle of parallel rays through the blob, one jitter per ray.
void renderBundle(const DvrVolume& vol, bool correct, double& alphaOut, Spectrum& colourOut) {
    alphaOut = 0;
    colourOut = Spectrum(0.0);
    for (int y = 0; y < 5; ++y)
        for (int x = 0; x < 5; ++x) {
            Ray ray;
            ray.o = Vec3(-5, 12 + 4 * x, 12.5 + 4 * y);
            ray.d = Vec3(1, 0, 0);
            Rng rng = pixelSampleRng(7, x, y, 0);
            VolumeRaySampler s(vol);
            FrontToBackCompositor c;
            if (s.begin(ray, rng.uniform()))
                s.marchSegment(ray.tMax, [&](const VolumeSample& v) {
                    // Uncorrected: the per-voxel opacity used as the step's opacity.
                    c.add(correct ? v.alpha : vol.transferFunction().opacity(v.value), v.colour);
                    return true;
                });
            alphaOut += (1 - c.transmittance) / 25;
            colourOut += c.radiance * (1.0 / 25);
        }
}

TEST(VolumeMarcher, OpacityCorrectionMakesStepsAgreeOnSmoothData) {
    // Tolerance: with correction the remaining difference is the Riemann-sum error of a smooth
    // integrand, O(Δ · |d(α c)/ds|) per voxel and averaged by the jitter; on this blob (values
    // change by < 0.13 per voxel) 1-voxel steps stay within 2e-3 of 0.05-voxel steps in alpha
    // and in every colour band (measured: 3e-4). Without correction, 0.05-voxel steps each take the
    // full per-voxel opacity (20 absorptions per voxel), and alpha differs by far more than the
    // tolerance.
    Blob blob;
    double aRef, a1, a05, aBad;
    Spectrum cRef, c1, c05, cBad;
    DvrSettings set;
    set.stepVoxels = 0.05;
    renderBundle(DvrVolume(blob.grid, blob.tf, set), true, aRef, cRef);
    set.stepVoxels = 1.0;
    renderBundle(DvrVolume(blob.grid, blob.tf, set), true, a1, c1);
    set.stepVoxels = 0.5;
    renderBundle(DvrVolume(blob.grid, blob.tf, set), true, a05, c05);
    set.stepVoxels = 0.05;
    renderBundle(DvrVolume(blob.grid, blob.tf, set), false, aBad, cBad);
    EXPECT_GT(aRef, 0.3);  // the blob is far from transparent: the comparison means something
    EXPECT_NEAR(a1, aRef, 2e-3);
    EXPECT_NEAR(a05, aRef, 2e-3);
    for (int b = 0; b < 3; ++b) {
        EXPECT_NEAR(c1[b], cRef[b], 2e-3);
        EXPECT_NEAR(c05[b], cRef[b], 2e-3);
    }
    EXPECT_GT(std::abs(aBad - aRef), 0.1);
}

// Every sample that contributes must be identical with and without skipping (same lattice, same
// value), and the skipped + reconstructed points must be the points marched without skipping.
// Marches one ray through the volume with skipping (a) and without (b): both must yield the same
// samples (same lattice point, value and opacity). Returns how many.
// A ray of random direction (three draws of rng) aimed at ball n of `centres`, starting 90 voxels
// before it.
Ray rayAtBall(const std::vector<Vec3>& centres, int n, Rng& rng) {
    const Vec3 dir =
        normalized(Vec3(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5));
    Ray ray;
    ray.o = centres[size_t(n) % centres.size()] - 90.0 * dir;
    ray.d = dir;
    return ray;
}

int expectSameSamples(VolumeRaySampler& a, VolumeRaySampler& b, const Ray& ray, double jitter) {
    EXPECT_EQ(a.begin(ray, jitter), b.begin(ray, jitter));
    VolumeSample sa, sb;
    int contributing = 0;
    while (true) {
        const bool ha = a.next(1e30, sa), hb = b.next(1e30, sb);
        EXPECT_EQ(ha, hb);
        if (!ha || !hb) break;
        ++contributing;
        EXPECT_EQ(sa.t, sb.t);
        EXPECT_EQ(sa.value, sb.value);
        EXPECT_EQ(sa.alpha, sb.alpha);
        EXPECT_EQ(sa.colour, sb.colour);
    }
    return contributing;
}

// Rays start on a sphere of `reach` voxels around `centre` and aim within `spread` of it.
void expectSkippingChangesNoSample(const openvdb::FloatGrid::Ptr& grid, const TransferFunction& tf,
                                   Reconstruction reconstruction, double step,
                                   const Vec3& centre = Vec3(20), double reach = 30.0,
                                   double spread = 4.0) {
    DvrSettings on, off;
    on.reconstruction = off.reconstruction = reconstruction;
    on.stepVoxels = off.stepVoxels = step;
    off.emptySpaceSkipping = false;
    const DvrVolume vOn(grid, tf, on), vOff(grid, tf, off);
    EXPECT_GT(vOn.transparentBrickFraction(), 0.3);
    long long skipped = 0, evalOn = 0, evalOff = 0, contributing = 0;
    for (int n = 0; n < 100; ++n) {
        Rng rng(11, n);
        const Vec3 dir =
            normalized(Vec3(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5));
        const Vec3 target =
            centre + spread * Vec3(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5);
        Ray ray;
        ray.o = target - reach * dir;
        ray.d = dir;
        const double jitter = rng.uniform();
        VolumeRaySampler a(vOn), b(vOff);
        contributing += expectSameSamples(a, b, ray, jitter);
        skipped += a.samplesSkipped();
        evalOn += a.samplesEvaluated();
        evalOff += b.samplesEvaluated();
        EXPECT_EQ(b.samplesSkipped(), 0);
    }
    EXPECT_GT(contributing, 1000);
    EXPECT_GT(skipped, evalOn);  // skipping really happened, and saved most of the work
    EXPECT_EQ(evalOn + skipped, evalOff);
}

TEST(VolumeMarcher, EmptySpaceSkippingChangesNoSample) {
    // The density-map transfer function is transparent below 0.69, so most bricks of the blob
    // are skipped (brick level).
    Blob blob;
    expectSkippingChangesNoSample(blob.grid, TransferFunction::densityMaps(),
                                  Reconstruction::kTrilinear, 0.05);
    expectSkippingChangesNoSample(blob.grid, TransferFunction::densityMaps(),
                                  Reconstruction::kCubicBSpline, 0.05);
    // A thin shell (the cortex preset around value 0.5, width 0.1): the bricks it crosses are
    // not transparent, but most of their cells are (cell level), for both supports (2³ and 4³).
    const TransferFunction shell = TransferFunction::cortex(0.5, 0.1);
    expectSkippingChangesNoSample(blob.grid, shell, Reconstruction::kTrilinear, 0.1);
    expectSkippingChangesNoSample(blob.grid, shell, Reconstruction::kCubicBSpline, 0.1);
    // A hard ball (1 inside radius 8, 0 outside) under a shell at 0.05 … 0.15: B-spline values
    // there come only from voxels up to two cells away (a 2³ support would call those cells
    // transparent and lose them; trilinear values there come from the cell's own corners).
    const openvdb::FloatGrid::Ptr ball = test::makeGrid(
        [](int i, int j, int k) {
            return (i - 20.0) * (i - 20.0) + (j - 20.0) * (j - 20.0) + (k - 20.0) * (k - 20.0) <
                           64.0
                       ? 1.0
                       : 0.0;
        },
        Coord(0), Coord(40));
    const TransferFunction low = TransferFunction::cortex(0.1, 0.1);
    expectSkippingChangesNoSample(ball, low, Reconstruction::kTrilinear, 0.1);
    expectSkippingChangesNoSample(ball, low, Reconstruction::kCubicBSpline, 0.1);
}

// Two small balls in the corners of a 100³ grid of zeros: most bricks are far from any visible
// one, so the marcher jumps past cubes of many bricks at once.
openvdb::FloatGrid::Ptr twoBalls() {
    return test::makeGrid(
        [](int i, int j, int k) {
            auto inside = [&](double cx, double cy, double cz, double r) {
                return (i - cx) * (i - cx) + (j - cy) * (j - cy) + (k - cz) * (k - cz) < r * r;
            };
            return inside(15, 15, 15, 6) || inside(80, 70, 60, 5) ? 1.0 : 0.0;
        },
        Coord(0), Coord(99));
}

TEST(VolumeMarcher, BrickClearanceIsTheChessboardDistance) {
    // Against a brute-force search: for every transparent brick, the largest L∞ distance in
    // bricks to the nearest brick that is not (capped at 64); 0 for those that are not.
    DvrSettings set;
    const DvrVolume vol(twoBalls(), stepTf(0.3), set);
    const std::array<int, 3> n = vol.brickCounts();
    std::vector<std::array<int, 3>> visible;
    for (int z = 0; z < n[2]; ++z)
        for (int y = 0; y < n[1]; ++y)
            for (int x = 0; x < n[0]; ++x)
                if (vol.brickClearance(x, y, z) == 0) visible.push_back({x, y, z});
    ASSERT_GT(visible.size(), 10u);
    int largest = 0;
    for (int z = 0; z < n[2]; ++z)
        for (int y = 0; y < n[1]; ++y)
            for (int x = 0; x < n[0]; ++x) {
                int expected = 64;
                for (const auto& v : visible)
                    expected = std::min(expected, std::max({std::abs(x - v[0]), std::abs(y - v[1]),
                                                            std::abs(z - v[2])}));
                ASSERT_EQ(vol.brickClearance(x, y, z), expected) << x << " " << y << " " << z;
                largest = std::max(largest, expected);
            }
    EXPECT_GE(largest, 8);  // long jumps exist to be tested below
}

TEST(VolumeMarcher, LongJumpsChangeNoSample) {
    // Rays from outside the grid through both balls and the empty space between them.
    const openvdb::FloatGrid::Ptr grid = twoBalls();
    for (Reconstruction r : {Reconstruction::kTrilinear, Reconstruction::kCubicBSpline}) {
        expectSkippingChangesNoSample(grid, stepTf(0.3), r, 0.25, Vec3(15), 120.0, 10.0);
        expectSkippingChangesNoSample(grid, stepTf(0.3), r, 0.05, Vec3(80, 70, 60), 120.0, 8.0);
    }
}

// A 48³ grid of zeros with a few random small balls (fixed seed): most cells are transparent
// under a step transfer function, the visible ones few enough for brute-force references.
openvdb::FloatGrid::Ptr randomBalls(uint64_t seed, int balls,
                                    std::vector<Vec3>* centres = nullptr) {
    Rng rng(seed, 0);
    std::vector<std::array<double, 4>> b;
    for (int n = 0; n < balls; ++n)
        b.push_back({4.0 + 40.0 * rng.uniform(), 4.0 + 40.0 * rng.uniform(),
                     4.0 + 40.0 * rng.uniform(), 1.0 + 2.5 * rng.uniform()});
    if (centres)
        for (const auto& c : b) centres->push_back(Vec3(c[0], c[1], c[2]));
    return test::makeGrid(
        [b](int i, int j, int k) {
            double v = 0.0;
            for (const auto& c : b) {
                const double r2 =
                    (i - c[0]) * (i - c[0]) + (j - c[1]) * (j - c[1]) + (k - c[2]) * (k - c[2]);
                v = std::max(v, std::exp(-r2 / (c[3] * c[3])));
            }
            return v;
        },
        Coord(0), Coord(47));
}

// Random balls (seed) under a step transfer function, with the given brick size and filter: the
// volumes of the distance-table tests.
DvrVolume ballsVolume(int brickSize, Reconstruction r, int seed) {
    DvrSettings set;
    set.brickSize = brickSize;
    set.reconstruction = r;
    return DvrVolume(randomBalls(seed, 3), stepTf(0.3), set);
}

// The cells of vol's distance tables in [−12, 64)³ (the random-ball grids lie inside), those of
// them the brick and cell tables call visible into `visible`, and those `keep` picks into `cells`.
template <class Keep>
void tableCells(const DvrVolume& vol, std::vector<std::array<int, 3>>& visible,
                std::vector<std::array<int, 3>>& cells, Keep keep) {
    for (int k = -12; k < 64; ++k)
        for (int j = -12; j < 64; ++j)
            for (int i = -12; i < 64; ++i) {
                if (vol.cellDistance(i, j, k) < 0) continue;  // outside the tables
                if (!vol.cellTransparent(i, j, k)) visible.push_back({i, j, k});
                if (keep(i, j, k)) cells.push_back({i, j, k});
            }
}

TEST(VolumeMarcher, CellDistanceIsTheCappedChessboardDistance) {
    // Against a brute-force search over the cells the brick and cell tables call visible: every
    // cell of the table holds min(cap, L∞ distance in cells to the nearest visible one), for
    // several brick sizes and both supports (trilinear 2³, B-spline 4³).
    const int cap = DvrVolume::kCellDistanceCap;
    int largest = 0, checked = 0;
    for (int bs : {2, 4, 8})
        for (Reconstruction r : {Reconstruction::kTrilinear, Reconstruction::kCubicBSpline}) {
            const DvrVolume vol = ballsVolume(bs, r, 7 + bs);
            ASSERT_TRUE(vol.hasCellDistances());
            std::vector<std::array<int, 3>> visible, cells;
            tableCells(vol, visible, cells, [](int, int, int) { return true; });
            ASSERT_GT(visible.size(), 20u);
            ASSERT_GT(cells.size(), 50u * 50u * 50u);
            for (const auto& c : cells) {
                int expected = cap;
                for (const auto& v : visible)
                    expected =
                        std::min(expected, std::max({std::abs(c[0] - v[0]), std::abs(c[1] - v[1]),
                                                     std::abs(c[2] - v[2])}));
                ASSERT_EQ(vol.cellDistance(c[0], c[1], c[2]), expected)
                    << c[0] << " " << c[1] << " " << c[2] << " brick " << bs;
                largest = std::max(largest, expected);
                ++checked;
            }
        }
    EXPECT_EQ(largest, cap);  // saturated cells exist: the brick clearance takes over there
    EXPECT_GT(checked, 6 * 125000);
}

TEST(VolumeMarcher, OctantDistanceIsTheLargestTransparentForwardCube) {
    // Against a brute-force search over the visible cells, for all 8 octants (bit a set: the
    // cube extends towards −a): the side of the largest cube of transparent cells that starts at
    // a cell and extends into the octant is the smallest chessboard offset of a visible cell in
    // that octant's closed orthant, capped; outside the table counts as transparent. Every
    // seventh cell of the table, two brick sizes and both supports.
    const int cap = DvrVolume::kOctantDistanceCap;
    long long checked = 0;
    int largest = 0, capped = 0;
    for (int bs : {2, 4})
        for (Reconstruction r : {Reconstruction::kTrilinear, Reconstruction::kCubicBSpline}) {
            const DvrVolume vol = ballsVolume(bs, r, 40 + bs);
            ASSERT_TRUE(vol.hasCellDistances());
            std::vector<std::array<int, 3>> visible, cells;
            tableCells(vol, visible, cells,
                       [](int i, int j, int k) { return (i + 2 * j + 3 * k) % 7 == 0; });
            ASSERT_GT(visible.size(), 20u);
            for (int octant = 0; octant < 8; ++octant) {
                const int s[3] = {octant & 1 ? -1 : 1, octant & 2 ? -1 : 1, octant & 4 ? -1 : 1};
                for (const auto& c : cells) {
                    int expected = cap;
                    for (const auto& v : visible) {
                        int m = 0;
                        for (int a = 0; a < 3; ++a) m = std::max(m, s[a] * (v[a] - c[a]));
                        bool inOrthant = true;
                        for (int a = 0; a < 3; ++a)
                            inOrthant = inOrthant && s[a] * (v[a] - c[a]) >= 0;
                        if (inOrthant) expected = std::min(expected, m);
                    }
                    ASSERT_EQ(vol.octantDistance(octant, c[0], c[1], c[2]), expected)
                        << c[0] << " " << c[1] << " " << c[2] << " octant " << octant << " brick "
                        << bs;
                    if (expected < cap) largest = std::max(largest, expected);
                    capped += expected == cap ? 1 : 0;
                    ++checked;
                }
            }
        }
    EXPECT_GT(largest, DvrVolume::kCellDistanceCap);  // longer than the centred table's cap
    EXPECT_GT(capped, 1000);                          // no visible cell in the orthant at all
    EXPECT_GT(checked, 4 * 8 * 20000);
}

TEST(VolumeMarcher, OctantDistanceReachesAlongLongRows) {
    // A 300-voxel row with one visible ball at its +x end: the table's rows are scanned by
    // doubling, and the distances towards +x must run up to ~290 cells (capped at 254), the ones
    // towards −x stay capped past the ball. Brute force as above, on every cell of the table.
    const openvdb::FloatGrid::Ptr grid = test::makeGrid(
        [](int i, int j, int k) {
            const double r2 =
                (i - 292.0) * (i - 292.0) + (j - 4.0) * (j - 4.0) + (k - 4.0) * (k - 4.0);
            return std::exp(-r2 / 4.0);
        },
        Coord(0, 0, 0), Coord(299, 8, 8));
    const DvrVolume vol(grid, stepTf(0.3), DvrSettings());
    ASSERT_TRUE(vol.hasCellDistances());
    const int cap = DvrVolume::kOctantDistanceCap;
    std::vector<std::array<int, 3>> visible, cells;
    for (int k = -8; k < 20; ++k)
        for (int j = -8; j < 20; ++j)
            for (int i = -8; i < 320; ++i) {
                if (vol.octantDistance(0, i, j, k) < 0) continue;
                cells.push_back({i, j, k});
                if (!vol.cellTransparent(i, j, k)) visible.push_back({i, j, k});
            }
    ASSERT_GT(visible.size(), 8u);
    int largest = 0;
    for (int octant : {0, 1, 6, 7})
        for (const auto& c : cells) {
            const int s[3] = {octant & 1 ? -1 : 1, octant & 2 ? -1 : 1, octant & 4 ? -1 : 1};
            int expected = cap;
            for (const auto& v : visible) {
                int m = 0;
                bool inOrthant = true;
                for (int a = 0; a < 3; ++a) {
                    m = std::max(m, s[a] * (v[a] - c[a]));
                    inOrthant = inOrthant && s[a] * (v[a] - c[a]) >= 0;
                }
                if (inOrthant) expected = std::min(expected, m);
            }
            ASSERT_EQ(vol.octantDistance(octant, c[0], c[1], c[2]), expected)
                << c[0] << " " << c[1] << " " << c[2] << " octant " << octant;
            if (expected < cap) largest = std::max(largest, expected);
        }
    EXPECT_GT(largest, 200);
}

TEST(VolumeMarcher, OctantJumpsChangeNoSampleOnAxisAndDiagonalRays) {
    // Rays along the 26 directions of {−1, 0, 1}³ (zero components: the ray stays in its cell's
    // slab, and −0 and +0 pick different octants) through random volumes, started on lattice
    // planes and between them: with skipping every contributing sample equals the one without.
    for (Reconstruction r : {Reconstruction::kTrilinear, Reconstruction::kCubicBSpline})
        for (double step : {1.0, 0.5, 0.05}) {
            DvrSettings on, off;
            on.reconstruction = off.reconstruction = r;
            on.stepVoxels = off.stepVoxels = step;
            off.emptySpaceSkipping = false;
            std::vector<Vec3> centres;
            const openvdb::FloatGrid::Ptr grid = randomBalls(77, 6, &centres);
            const TransferFunction tf = TransferFunction::cortex(0.4, 0.3);
            const DvrVolume vOn(grid, tf, on), vOff(grid, tf, off);
            long long skipped = 0, contributing = 0;
            Rng rng(9, int(step * 100));
            for (int dz = -1; dz <= 1; ++dz)
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) {
                        if (dx == 0 && dy == 0 && dz == 0) continue;
                        for (int n = 0; n < 8; ++n) {
                            const double z = n % 2 ? 0.0 : -0.0;  // signed zeros
                            const Vec3 dir =
                                normalized(Vec3(dx ? dx : z, dy ? dy : z, dz ? dz : z));
                            Vec3 target = centres[size_t(n) % centres.size()];
                            if (n % 4 < 2)  // on lattice planes
                                target = Vec3(std::floor(target.x), std::floor(target.y),
                                              std::floor(target.z));
                            else
                                target += Vec3(rng.uniform() - 0.5, rng.uniform() - 0.5,
                                               rng.uniform() - 0.5);
                            Ray ray;
                            ray.o = target - 90.0 * dir;
                            ray.d = dir;
                            VolumeRaySampler a(vOn), b(vOff);
                            contributing += expectSameSamples(a, b, ray, rng.uniform());
                            skipped += a.samplesSkipped();
                        }
                    }
            EXPECT_GT(contributing, 100) << step;
            EXPECT_GT(skipped, 1000) << step;
        }
}

TEST(VolumeMarcher, CellsCalledTransparentReconstructOnlyTransparentValues) {
    // Independent of the tables' construction: at random points of every cell within 2 cells of
    // a visible one (where a wrong table would show first), the reconstructed value's opacity
    // is 0 — so a jump past a cube of cells with distance ≥ 1 passes no visible sample.
    for (Reconstruction r : {Reconstruction::kTrilinear, Reconstruction::kCubicBSpline}) {
        const openvdb::FloatGrid::Ptr grid = randomBalls(21, 4);
        const TransferFunction tf = stepTf(0.3);
        DvrSettings set;
        set.reconstruction = r;
        const DvrVolume vol(grid, tf, set);
        GridReconstructor recon(*grid);
        Rng rng(5, 1);
        long long tested = 0;
        for (int k = -4; k < 52; ++k)
            for (int j = -4; j < 52; ++j)
                for (int i = -4; i < 52; ++i) {
                    const int d = vol.cellDistance(i, j, k);
                    if (d < 1 || d > 2) continue;
                    for (int n = 0; n < 4; ++n) {
                        const Vec3 p(i + rng.uniform(), j + rng.uniform(), k + rng.uniform());
                        ASSERT_EQ(tf.opacity(recon.value(r, p)), 0.0) << i << " " << j << " " << k;
                        ++tested;
                    }
                }
        EXPECT_GT(tested, 4000);
    }
}

TEST(VolumeMarcher, CellDistanceJumpsChangeNoSampleOnRandomVolumes) {
    // Random volumes and rays (fixed seeds) at coarse and fine steps: with skipping (the cell
    // distance table) every contributing sample equals the one without skipping, and the points
    // skipped plus those evaluated are the points marched without skipping.
    for (int volume = 0; volume < 3; ++volume)
        for (Reconstruction r : {Reconstruction::kTrilinear, Reconstruction::kCubicBSpline})
            for (double step : {1.0, 0.5, 0.3, 0.05}) {
                DvrSettings on, off;
                on.reconstruction = off.reconstruction = r;
                on.stepVoxels = off.stepVoxels = step;
                off.emptySpaceSkipping = false;
                std::vector<Vec3> centres;
                const openvdb::FloatGrid::Ptr grid = randomBalls(100 + volume, 6, &centres);
                const TransferFunction tf = TransferFunction::cortex(0.4, 0.3);
                const DvrVolume vOn(grid, tf, on), vOff(grid, tf, off);
                ASSERT_TRUE(vOn.hasCellDistances());
                long long skipped = 0, evalOn = 0, evalOff = 0, contributing = 0;
                for (int n = 0; n < 60; ++n) {
                    Rng rng(31 + volume, n);
                    const Vec3 dir = normalized(
                        Vec3(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5));
                    // Half the rays aim near a ball, half anywhere.
                    const Vec3 target =
                        n % 2 ? centres[size_t(n / 2) % centres.size()] +
                                    3.0 * Vec3(rng.uniform() - 0.5, rng.uniform() - 0.5,
                                               rng.uniform() - 0.5)
                              : Vec3(4.0 + 40.0 * rng.uniform(), 4.0 + 40.0 * rng.uniform(),
                                     4.0 + 40.0 * rng.uniform());
                    Ray ray;
                    ray.o = target - 90.0 * dir;
                    ray.d = dir;
                    VolumeRaySampler a(vOn), b(vOff);
                    contributing += expectSameSamples(a, b, ray, rng.uniform());
                    skipped += a.samplesSkipped();
                    evalOn += a.samplesEvaluated();
                    evalOff += b.samplesEvaluated();
                }
                EXPECT_GT(contributing, 20) << volume << " " << step;
                EXPECT_GT(skipped, evalOn) << volume << " " << step;
                EXPECT_EQ(evalOn + skipped, evalOff) << volume << " " << step;
            }
}

// Narrow tents (T3's shape: transparent pieces between visible ones) for the coarse-path tests.
TransferFunction narrowTents() {
    const Spectrum a(0.2, 0.4, 0.9), b(0.9, 0.5, 0.1);
    return TransferFunction({{0.39, 0.0, a},
                             {0.4, 0.3, b},
                             {0.41, 0.0, a},
                             {0.5, 0.0, b},
                             {0.52, 0.45, a},
                             {0.54, 0.0, b}});
}

TEST(VolumeMarcher, CoarsePathGivesTheSamplesOfThePlainMarch) {
    // next()'s coarse-step path (octant tables, trilinear; VolumeRaySampler::coarsePath) against
    // the plain march without skipping, which takes the general path: the same contributing
    // samples (t, value, opacity, colour), with a transfer function of narrow tents (T3's
    // shape: transparent pieces between visible ones, where the path skips the interpolation)
    // and with the cortex preset, at the coarse steps the path serves.
    const TransferFunction tents = narrowTents();
    for (const TransferFunction& tf : {tents, TransferFunction::cortex(0.4, 0.3)})
        for (double step : {1.0, 0.575, 0.5, 0.3}) {
            DvrSettings on, off;
            on.stepVoxels = off.stepVoxels = step;
            off.emptySpaceSkipping = false;
            std::vector<Vec3> centres;
            const openvdb::FloatGrid::Ptr grid = randomBalls(61, 6, &centres);
            const DvrVolume vOn(grid, tf, on), vOff(grid, tf, off);
            long long contributing = 0, coarse = 0;
            for (int n = 0; n < 80; ++n) {
                Rng rng(17, n);
                const Ray ray = rayAtBall(centres, n, rng);
                VolumeRaySampler sa(vOn), sb(vOff);
                contributing += expectSameSamples(sa, sb, ray, rng.uniform());
                coarse += sa.coarsePath() ? 1 : 0;
                EXPECT_FALSE(sb.coarsePath());
            }
            EXPECT_EQ(coarse, 80) << step;
            EXPECT_GT(contributing, 25) << step;  // the narrow tents: 31 at step 1
        }
    // Finer steps, the B-spline and pre-integration keep the general path.
    DvrSettings fine, bspline, pre;
    fine.stepVoxels = 0.25;
    bspline.reconstruction = Reconstruction::kCubicBSpline;
    bspline.stepVoxels = pre.stepVoxels = 1.0;
    pre.preIntegrated = true;
    const openvdb::FloatGrid::Ptr grid = randomBalls(62, 3);
    Ray ray;
    ray.o = Vec3(-40.0, 20.0, 20.0);
    ray.d = Vec3(1.0, 0.0, 0.0);
    for (const DvrSettings* set : {&fine, &bspline, &pre}) {
        const DvrVolume vol(grid, tents, *set);
        VolumeRaySampler s(vol);
        ASSERT_TRUE(s.begin(ray, 0.5));
        EXPECT_FALSE(s.coarsePath());
    }
}

TEST(VolumeMarcher, CoarsePathAvx2CopyGivesTheBaselineSamplesBitForBit) {
    // The coarse path's AVX2 copy (VolumeRaySampler::coarsePathAvx2, where the CPU has AVX2)
    // against its baseline copy (DvrSettings::simd = false): every sample's t, value, opacity,
    // colour, world position, gradient and normal equal, marched in segments of random length
    // (the loop writes its lattice index back at each return), and the counters equal. Narrow
    // tents and the cortex preset, trilinear at the coarse steps, with random jitter.
    const TransferFunction tents = narrowTents();
    const bool avx2 = __builtin_cpu_supports("avx2");
    long long compared = 0;
    for (const TransferFunction& tf : {tents, TransferFunction::cortex(0.4, 0.3)})
        for (double step : {1.0, 0.575, 0.5, 0.3}) {
            DvrSettings vector, baseline;
            vector.stepVoxels = baseline.stepVoxels = step;
            baseline.simd = false;
            std::vector<Vec3> centres;
            const openvdb::FloatGrid::Ptr grid = randomBalls(63, 6, &centres);
            const DvrVolume vv(grid, tf, vector), vb(grid, tf, baseline);
            for (int n = 0; n < 120; ++n) {
                Rng rng(23, n);
                const Ray ray = rayAtBall(centres, n, rng);
                const double jitter = rng.uniform();
                VolumeRaySampler sv(vv), sb(vb);
                ASSERT_EQ(sv.begin(ray, jitter), sb.begin(ray, jitter));
                EXPECT_TRUE(sv.coarsePath() && sb.coarsePath());
                EXPECT_EQ(sv.coarsePathAvx2(), avx2);
                EXPECT_FALSE(sb.coarsePathAvx2());
                double tEnd = sv.tEnter();
                while (true) {
                    tEnd += 40.0 * rng.uniform() * sv.stepT();
                    VolumeSample x, y;
                    const bool withNormal = rng.uniform() < 0.5;
                    const bool hv = sv.next(tEnd, x, withNormal), hb = sb.next(tEnd, y, withNormal);
                    ASSERT_EQ(hv, hb);
                    EXPECT_EQ(sv.peekT(), sb.peekT());
                    if (!hv) {
                        if (sv.peekT() == std::numeric_limits<double>::infinity()) break;
                        continue;
                    }
                    if (!withNormal) {
                        sv.addNormal(x);
                        sb.addNormal(y);
                    }
                    ++compared;
                    EXPECT_EQ(x.t, y.t);
                    EXPECT_EQ(x.value, y.value);
                    EXPECT_EQ(x.alpha, y.alpha);
                    EXPECT_EQ(x.colour, y.colour);
                    EXPECT_EQ(x.position, y.position);
                    EXPECT_EQ(x.indexPosition, y.indexPosition);
                    EXPECT_EQ(x.gradient, y.gradient);
                    EXPECT_EQ(x.normal, y.normal);
                    EXPECT_EQ(x.hasNormal, y.hasNormal);
                }
                EXPECT_EQ(sv.samplesEvaluated(), sb.samplesEvaluated());
                EXPECT_EQ(sv.samplesSkipped(), sb.samplesSkipped());
            }
        }
    EXPECT_GT(compared, 2000);
}

TEST(VolumeMarcher, CellDistancesOnlyWhereTheyApply) {
    // Pre-integration keeps the brick and cell tests (its segments need them); so does a volume
    // rendered without skipping.
    DvrSettings pre, noSkip;
    pre.preIntegrated = true;
    noSkip.emptySpaceSkipping = false;
    EXPECT_FALSE(DvrVolume(randomBalls(3, 2), stepTf(0.3), pre).hasCellDistances());
    EXPECT_FALSE(DvrVolume(randomBalls(3, 2), stepTf(0.3), noSkip).hasCellDistances());
    EXPECT_TRUE(DvrVolume(randomBalls(3, 2), stepTf(0.3), DvrSettings()).hasCellDistances());
}

TEST(VolumeMarcher, OctantTablesOnlyWithinTheMemoryBudget) {
    // The 8 octant tables (8 bytes a cell) are built only within the dense copy's budget (an
    // eighth of the memory): with a budget that holds the dense copy (4 bytes a voxel) but not
    // the tables, the marcher falls back to the brick and cell tests — the same samples.
    std::vector<Vec3> centres;
    const openvdb::FloatGrid::Ptr grid = randomBalls(5, 4, &centres);
    const TransferFunction tf = TransferFunction::cortex(0.4, 0.3);
    DvrSettings on, off;
    off.emptySpaceSkipping = false;
    on.stepVoxels = off.stepVoxels = 0.5;
    const DvrVolume full(grid, tf, on);
    ASSERT_TRUE(full.hasCellDistances());
    const MemoryBudget measured = memoryBudget();
    setMemoryBudget({8.0 * 0.9e6, "the test's budget"});  // an eighth: 0.9 MB
    const DvrVolume small(grid, tf, on), reference(grid, tf, off);
    setMemoryBudget({0.0, ""});
    ASSERT_GT(measured.bytes, 0.0);
    ASSERT_NE(small.dense(), nullptr);       // ~0.8 MB: the dense copy fits
    EXPECT_FALSE(small.hasCellDistances());  // 8 × 56³ bytes do not
    long long skipped = 0, contributing = 0;
    for (int n = 0; n < 40; ++n) {
        Rng rng(3, n);
        const Ray ray = rayAtBall(centres, n, rng);
        VolumeRaySampler a(small), b(reference);
        contributing += expectSameSamples(a, b, ray, rng.uniform());
        skipped += a.samplesSkipped();
    }
    EXPECT_GT(contributing, 20);
    EXPECT_GT(skipped, 1000);
}

// The ramp f = x on [0, 15]³ and a transfer function opaque (0.2) only on [5.2, 5.8]: the
// B-spline skipping tests' scene.
openvdb::FloatGrid::Ptr rampGrid() {
    return test::makeGrid([](int i, int, int) { return double(i); }, Coord(0), Coord(15));
}
TransferFunction shellOn52To58() {
    return TransferFunction({{5.2, 0.0, Spectrum(1.0)},
                             {5.2, 0.2, Spectrum(1.0)},
                             {5.8, 0.2, Spectrum(1.0)},
                             {5.8, 0.0, Spectrum(1.0)}});
}

TEST(VolumeMarcher, BSplineCellsAreSkippedByTheirBezierRange) {
    // On the ramp f = x the cubic B-spline reproduces x exactly, so cell [c, c+1) holds values
    // [c, c+1]: its Bézier coefficients (c, c + 1/3, c + 2/3, c + 1 along x) say so, where the
    // range of its 4³ control values says [c − 1, c + 2]. With opacity only on [5.2, 5.8], a ray
    // along x at step 0.1 reconstructs the ~10 lattice points of cell 5 alone — not the ~30 of
    // cells 4, 5 and 6 — and still composites exactly the samples of the march without skipping.
    const openvdb::FloatGrid::Ptr grid = rampGrid();
    const TransferFunction shell = shellOn52To58();
    DvrSettings on, off;
    on.reconstruction = off.reconstruction = Reconstruction::kCubicBSpline;
    on.stepVoxels = off.stepVoxels = 0.1;
    off.emptySpaceSkipping = false;
    const DvrVolume vOn(grid, shell, on), vOff(grid, shell, off);
    Ray ray;
    ray.o = Vec3(-3.0, 7.3, 7.6);
    ray.d = Vec3(1.0, 0.0, 0.0);
    ray.tMax = 15.0;  // to x = 12, short of the grid's end where the field falls back to 0
    VolumeRaySampler a(vOn), b(vOff);
    EXPECT_EQ(expectSameSamples(a, b, ray, 0.37), 6);  // x = 5.24, 5.34, …, 5.74
    EXPECT_LE(a.samplesEvaluated(), 12);
}

TEST(VolumeMarcher, BSplineRayCellsAreSkippedByTheRaysBernsteinBound) {
    // The ramp f = x again, opacity only on [5.2, 5.8]: cell x in [5, 6) holds values [5, 6] and
    // is visible to the tables, but a ray along y at x = 5.1 sees 5.1 throughout. At step 0.05
    // (the ray polynomial) the Bernstein bound of its polynomial over each cell's stretch,
    // [5.1, 5.1], lies below 5.2: no point is reconstructed (before: every point, ~220), in the
    // packet and the scalar path alike. A ray at x = 5.5 is visible everywhere and must give
    // the samples of the march without skipping; a diagonal one through x = 4.5 … 5.6 has
    // visible and transparent stretches in one cell row.
    const openvdb::FloatGrid::Ptr grid = rampGrid();
    const TransferFunction shell = shellOn52To58();
    for (bool simd : {true, false}) {
        SCOPED_TRACE(simd ? "packets" : "scalar");
        DvrSettings on, off;
        on.reconstruction = off.reconstruction = Reconstruction::kCubicBSpline;
        on.stepVoxels = off.stepVoxels = 0.05;
        on.simd = off.simd = simd;
        off.emptySpaceSkipping = false;
        const DvrVolume vOn(grid, shell, on), vOff(grid, shell, off);
        Ray ray;
        ray.o = Vec3(5.1, 2.0, 7.6);
        ray.d = Vec3(0.0, 1.0, 0.0);
        ray.tMax = 11.0;  // y from 2 to 13, inside the ramp's reproduction
        VolumeRaySampler a(vOn), b(vOff);
        EXPECT_EQ(expectSameSamples(a, b, ray, 0.37), 0);
        EXPECT_EQ(a.samplesEvaluated(), 0);
        EXPECT_GE(a.samplesSkipped(), 200);
        ray.o = Vec3(5.5, 2.0, 7.6);
        EXPECT_GE(expectSameSamples(a, b, ray, 0.37), 200);
        ray.o = Vec3(4.5, 2.0, 7.6);
        ray.d = Vec3(0.1, 1.0, 0.0).normalized();
        const int visible = expectSameSamples(a, b, ray, 0.61);
        EXPECT_GT(visible, 50);  // x from 5.2 to 5.6: ~4 of the 11 voxels of y
        EXPECT_LT(a.samplesEvaluated(), b.samplesEvaluated());
    }
}

TEST(VolumeMarcher, SegmentsKeepTheLattice) {
    // Marching in random pieces (as an integrator does between surface hits) yields the same
    // samples as one march.
    Blob blob;
    DvrSettings set;
    set.stepVoxels = 0.1;
    const DvrVolume vol(blob.grid, blob.tf, set);
    Ray ray;
    ray.o = Vec3(-5, 19.2, 21.7);
    ray.d = normalized(Vec3(1, 0.1, -0.05));
    VolumeRaySampler whole(vol), pieces(vol);
    ASSERT_TRUE(whole.begin(ray, 0.61));
    ASSERT_TRUE(pieces.begin(ray, 0.61));
    std::vector<double> tw, tp;
    whole.marchSegment(1e30, [&](const VolumeSample& s) { return tw.push_back(s.t), true; });
    Rng rng(3, 4);
    double tEnd = pieces.tEnter();
    while (pieces.peekT() < 1e30) {
        tEnd += 3.0 * rng.uniform();
        pieces.marchSegment(tEnd, [&](const VolumeSample& s) {
            EXPECT_LT(s.t, tEnd);
            return tp.push_back(s.t), true;
        });
    }
    ASSERT_GT(tw.size(), 100u);
    EXPECT_EQ(tw, tp);
}

TEST(VolumeMarcher, GradientThresholdDecidesShading) {
    // Inside the slab the field is flat (gradient 0 < threshold): no normal, Lambert with
    // cos θ = 1. Near the front face x = −0.5 the field rises by 1 per voxel: normal −x (outwards).
    auto grid = slabGrid(0, 63);
    DvrSettings set;
    set.stepVoxels = 0.25;
    const DvrVolume vol(grid, stepTf(0.01, Spectrum(0.5, 1.0, 0.25)), set);
    Ray ray;
    ray.o = Vec3(-10, 7.3, 8.1);
    ray.d = Vec3(1, 0, 0);
    VolumeRaySampler s(vol);
    ASSERT_TRUE(s.begin(ray, 0.37));
    VolumeSample front, inside;
    ASSERT_TRUE(s.next(1e30, front));
    EXPECT_LT(front.position.x, 0.0);
    ASSERT_TRUE(front.hasNormal);
    EXPECT_NEAR(front.normal.x, -1.0, 1e-6);
    s.marchSegment(30.0, [&](const VolumeSample& v) { return inside = v, true; });
    EXPECT_GT(inside.position.x, 19.0);  // the last sample before t = 30, i.e. x = 20
    EXPECT_LT(inside.position.x, 20.0);
    EXPECT_FALSE(inside.hasNormal);
    EXPECT_EQ(inside.gradient.length(), 0.0);
}

}  // namespace
}  // namespace lobe
