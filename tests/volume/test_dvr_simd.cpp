// Lattice packets (volume/dvr_simd.h) against the scalar path and closed forms. The stated
// tolerance is zero: the packet kernels perform the scalar path's IEEE operations in the same
// order, so every sample must come back with the same bits (t, value, opacity, colour, normal),
// with the packet path really taken (packetsFilled > 0) on the SIMD target the CPU offers.
#include "core/rng.h"
#include "dvr_test_grids.h"
#include "volume/dvr_simd.h"
#include "volume/volume_marcher.h"

#include <gtest/gtest.h>
#include <hwy/targets.h>

#include <cmath>
#include <cstdio>
#include <set>
#include <string>

namespace lobe {
namespace {

using openvdb::Coord;

// A bumpy blob, so that values vary within a cell and between cells.
openvdb::FloatGrid::Ptr bumpyBlob() {
    return test::makeGrid(
        [](int i, int j, int k) {
            const double r2 =
                (i - 16.0) * (i - 16.0) + (j - 16.0) * (j - 16.0) + (k - 16.0) * (k - 16.0);
            return std::exp(-r2 / 60.0) * (1.0 + 0.2 * std::sin(0.9 * i + 0.4 * j - 0.7 * k));
        },
        Coord(0), Coord(32));
}

// Several pieces, a step (two points at one value) and a plateau: every branch of the lookup.
TransferFunction pieces() {
    return TransferFunction({{0.15, 0.0, Spectrum(0.1, 0.2, 0.9)},
                             {0.3, 0.05, Spectrum(0.2, 0.8, 0.1)},
                             {0.5, 0.05, Spectrum(0.9, 0.5, 0.2)},
                             {0.5, 0.4, Spectrum(1.0, 0.1, 0.1)},
                             {0.8, 0.6, Spectrum(0.7, 0.7, 0.7)}});
}

// Marches 200 random rays through the blob with the packet path on and off and requires equal
// samples; returns the number of packets the SIMD path computed. cut > 0: the segments end
// every `cut` (from a random start) instead of once, so many ends fall inside packets.
long long expectPacketsChangeNoSample(Reconstruction rec, double step, bool skipping,
                                      double cut = 0.0) {
    const auto grid = bumpyBlob();
    DvrSettings on, off;
    on.reconstruction = off.reconstruction = rec;
    on.gradient = off.gradient = rec == Reconstruction::kCubicBSpline
                                     ? GradientMethod::kBSplineDerivative
                                     : GradientMethod::kCentralDifferences;
    on.stepVoxels = off.stepVoxels = step;
    on.emptySpaceSkipping = off.emptySpaceSkipping = skipping;
    off.simd = false;
    const DvrVolume vOn(grid, pieces(), on), vOff(grid, pieces(), off);
    VolumeRaySampler a(vOn), b(vOff);  // reused across rays, as the renderer does
    long long samples = 0;
    for (int n = 0; n < 200; ++n) {
        Rng rng(5, n);
        const Vec3 dir =
            normalized(Vec3(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5));
        Ray ray;
        ray.o = Vec3(16) +
                6.0 * Vec3(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5) -
                40.0 * dir;
        ray.d = dir;
        const double jitter = rng.uniform();
        EXPECT_EQ(a.begin(ray, jitter), b.begin(ray, jitter));
        VolumeSample sa, sb;
        // Segments end at arbitrary depths (as surfaces cut a ray): the packet must survive them.
        double tEnd = 30.0 + 10.0 * rng.uniform();
        for (;;) {
            const bool ha = a.next(tEnd, sa), hb = b.next(tEnd, sb);
            EXPECT_EQ(ha, hb);
            if (ha != hb) return -1;
            if (!ha) {
                // Where each sampler stands: the renderer orders volume and surfaces by it.
                EXPECT_EQ(a.peekT(), b.peekT());
                if (tEnd > 1e3) break;
                tEnd = cut > 0.0 && tEnd < 80.0 ? tEnd + cut : 1e30;
                continue;
            }
            ++samples;
            EXPECT_EQ(sa.t, sb.t);
            EXPECT_EQ(sa.value, sb.value);
            EXPECT_EQ(sa.alpha, sb.alpha);
            for (int c = 0; c < 3; ++c) EXPECT_EQ(sa.colour[c], sb.colour[c]);
            EXPECT_EQ(sa.hasNormal, sb.hasNormal);
            for (int c = 0; c < 3; ++c) EXPECT_EQ(sa.normal[c], sb.normal[c]);
        }
    }
    EXPECT_GT(samples, 2000);
    EXPECT_EQ(a.samplesEvaluated(), b.samplesEvaluated());
    EXPECT_EQ(a.samplesSkipped(), b.samplesSkipped());
    EXPECT_EQ(b.packetsFilled(), 0);
    return a.packetsFilled();
}

TEST(DvrSimd, TrilinearPacketsGiveTheScalarSamplesBitForBit) {
    std::printf("lattice packets on %s\n", latticePacketTarget());
    for (bool skipping : {true, false})
        for (double step : {0.05, 0.1, 0.2})
            EXPECT_GT(expectPacketsChangeNoSample(Reconstruction::kTrilinear, step, skipping), 100)
                << step;
}

TEST(DvrSimd, BSplineRayPolynomialPacketsGiveTheScalarSamplesBitForBit) {
    // The ray polynomial is used below 0.075 voxels (volume_marcher.cpp, kRayPolynomialStep).
    for (bool skipping : {true, false})
        for (double step : {0.02, 0.05, 0.07})
            EXPECT_GT(expectPacketsChangeNoSample(Reconstruction::kCubicBSpline, step, skipping),
                      100)
                << step;
}

TEST(DvrSimd, PacketsStopAtEverySegmentEnd) {
    // Segment ends every 0.013–0.5 voxel: they fall inside the packets' runs of transparent
    // points (the TF is 0 below 0.15, the blob's rim), which next() passes in one step
    // (skipTransparentPacketRun) only when the run ends before tEnd.
    for (const Reconstruction rec : {Reconstruction::kTrilinear, Reconstruction::kCubicBSpline})
        for (double cut : {0.013, 0.11, 0.5})
            EXPECT_GT(expectPacketsChangeNoSample(rec, 0.05, true, cut), 100) << cut;
}

TEST(DvrSimd, EveryTargetGivesTheScalarSamples) {
    // Each SIMD target this CPU runs (AVX-512, AVX2, SSE4, plain C++), chosen in turn.
    std::set<std::string> names;
    for (const int64_t target : hwy::SupportedAndGeneratedTargets()) {
        hwy::SetSupportedTargetsForTest(target);
        names.insert(latticePacketTarget());
        EXPECT_STREQ(latticePacketTarget(), hwy::TargetName(target));
        EXPECT_GT(expectPacketsChangeNoSample(Reconstruction::kTrilinear, 0.05, true), 100);
        EXPECT_GT(expectPacketsChangeNoSample(Reconstruction::kCubicBSpline, 0.05, true), 100);
    }
    hwy::SetSupportedTargetsForTest(0);
    EXPECT_EQ(names.size(), hwy::SupportedAndGeneratedTargets().size());
    EXPECT_GE(names.size(), 2u);  // at least a SIMD target and the plain C++ one on x86-64
}

TEST(DvrSimd, CoarseStepsAndOtherFiltersStayScalar) {
    // One point per voxel or more: packets would run past what stops the ray (dvr_simd.h).
    EXPECT_EQ(expectPacketsChangeNoSample(Reconstruction::kTrilinear, 0.5, true), 0);
    EXPECT_EQ(expectPacketsChangeNoSample(Reconstruction::kCubicBSpline, 0.1, true), 0);
    EXPECT_EQ(expectPacketsChangeNoSample(Reconstruction::kNearest, 0.05, true), 0);
}

TEST(DvrSimd, TrilinearPacketReproducesALinearFieldAndTheTfLookup) {
    // Trilinear reconstruction is exact for f = 0.01 i + 0.02 j + 0.03 k (Marschner & Lobb
    // 1994); the TF at each value is TransferFunction::evaluate's.
    const auto grid = test::makeGrid(
        [](int i, int j, int k) { return 0.01 * i + 0.02 * j + 0.03 * k; }, Coord(0), Coord(15));
    const DenseField field(*grid, openvdb::CoordBBox(Coord(0), Coord(15)));
    const TransferFunction tf = pieces();
    const TfArrays arrays(tf);
    RayLattice ray{{1.3, 2.1, 0.7}, {0.9, 0.3, 0.6}, 0.0, 0.25, 0.1};
    LatticePacket out;
    ASSERT_EQ(latticePacketTrilinear(ray, 3, 16, field, arrays, out), 16);
    for (int i = 0; i < 16; ++i) {
        const double t = ray.tEnter + (double(3 + i) + ray.jitter) * ray.dt;
        const double x = ray.o[0] + ray.d[0] * t, y = ray.o[1] + ray.d[1] * t,
                     z = ray.o[2] + ray.d[2] * t;
        EXPECT_NEAR(out.value[i], 0.01 * x + 0.02 * y + 0.03 * z, 1e-7);  // float voxels
        double a;
        Spectrum c;
        tf.evaluate(out.value[i], a, c);
        EXPECT_EQ(out.alpha[i], a);
        for (int b = 0; b < 3; ++b) EXPECT_EQ(out.colour[b][i], c[b]);
    }
    // Values below the first point, between, at the step (the right limit wins) and above.
    const auto flat = [](double v) {
        return test::makeGrid([v](int, int, int) { return v; }, Coord(0), Coord(3));
    };
    for (double v : {0.0, 0.2, 0.5, 0.65, 0.9}) {
        const auto g = flat(v);
        const DenseField f(*g, openvdb::CoordBBox(Coord(0), Coord(3)));
        RayLattice r{{0.5, 0.5, 0.5}, {1.0, 0.0, 0.0}, 0.0, 0.0, 0.1};
        ASSERT_EQ(latticePacketTrilinear(r, 0, 4, f, arrays, out), 4);
        double a;
        Spectrum c;
        tf.evaluate(double(float(v)), a, c);
        EXPECT_EQ(out.alpha[0], a) << v;
        EXPECT_EQ(out.colour[0][3], c[0]) << v;
    }
    // A footprint leaving the dense box: no packet (the caller reads the tree).
    RayLattice outside{{13.5, 1.5, 1.5}, {1.0, 0.0, 0.0}, 0.0, 0.0, 0.5};
    EXPECT_EQ(latticePacketTrilinear(outside, 0, 4, field, arrays, out), 0);
}

// GridReconstructor::ensureRayCell's loops as they were before rayCellPolynomial (scalar, the
// reference the kernel must match bit for bit).
void rayCellPolynomialScalar(const float f[4][16], const double wx[4][4], const double wy[4][4],
                             const double wz[4][4], double poly[10]) {
    double px[4][16] = {};
    for (int a = 0; a < 4; ++a) {
        double fa[16];
        for (int row = 0; row < 16; ++row) fa[row] = f[a][row];
        for (int k = 0; k < 4; ++k)
            for (int row = 0; row < 16; ++row) px[k][row] += fa[row] * wx[a][k];
    }
    double py[7][4] = {};
    for (int b = 0; b < 4; ++b)
        for (int k = 0; k < 4; ++k)
            for (int l = 0; l < 4; ++l)
                for (int c = 0; c < 4; ++c) py[k + l][c] += px[k][4 * b + c] * wy[b][l];
    for (int j = 0; j < 10; ++j) poly[j] = 0.0;
    for (int k = 0; k < 7; ++k)
        for (int c = 0; c < 4; ++c)
            for (int l = 0; l < 4; ++l) poly[k + l] += py[k][c] * wz[c][l];
}

TEST(DvrSimd, RayCellPolynomialIsTheScalarLoopsBitForBitOnEveryTarget) {
    // Random blocks (signed, so sums cancel) and weights, on each SIMD target this CPU runs; and a
    // closed form: a single voxel of 1 at (a, b, c) gives poly[j] = Σ_{k+l+m=j} wx[a][k] wy[b][l]
    // wz[c][m] (up to rounding).
    int targets = 0;
    for (const int64_t target : hwy::SupportedAndGeneratedTargets()) {
        hwy::SetSupportedTargetsForTest(target);
        ++targets;
        for (int n = 0; n < 500; ++n) {
            Rng rng(11, n);
            float f[4][16];
            double w[3][4][4];
            for (auto& row : f)
                for (float& x : row) x = float(2.0 * rng.uniform() - 1.0);
            for (auto& axis : w)
                for (auto& a : axis)
                    for (double& x : a) x = 4.0 * rng.uniform() - 2.0;
            double got[10], want[10];
            rayCellPolynomial(f, w[0], w[1], w[2], got);
            rayCellPolynomialScalar(f, w[0], w[1], w[2], want);
            for (int j = 0; j < 10; ++j)
                ASSERT_EQ(got[j], want[j])
                    << hwy::TargetName(target) << " case " << n << " j " << j;
            if (n % 50 == 0) {
                const int a = n % 4, b = (n / 4) % 4, c = (n / 16) % 4;
                float one[4][16] = {};
                one[a][4 * b + c] = 1.0f;
                rayCellPolynomial(one, w[0], w[1], w[2], got);
                for (int j = 0; j < 10; ++j) {
                    double sum = 0.0;
                    for (int k = 0; k < 4; ++k)
                        for (int l = 0; l < 4; ++l) {
                            const int m = j - k - l;
                            if (m >= 0 && m < 4) sum += w[0][a][k] * w[1][b][l] * w[2][c][m];
                        }
                    EXPECT_NEAR(got[j], sum, 1e-13) << j;
                }
            }
        }
    }
    hwy::SetSupportedTargetsForTest(0);
    EXPECT_GE(targets, 2);
}

// GridReconstructor::bsplineWithGradient's loops as they were before bsplineBlock (scalar, the
// reference the kernel must match bit for bit).
void bsplineBlockScalar(const float f[4][16], const double w[3][4], const double dw[3][4],
                        double out[4]) {
    double vx[16] = {}, dvx[16] = {};
    for (int a = 0; a < 4; ++a)
        for (int r = 0; r < 16; ++r) {
            vx[r] += w[0][a] * double(f[a][r]);
            dvx[r] += dw[0][a] * double(f[a][r]);
        }
    double vz[4] = {0, 0, 0, 0}, gxz[4] = {0, 0, 0, 0}, gyz[4] = {0, 0, 0, 0};
    for (int b = 0; b < 4; ++b)
        for (int c = 0; c < 4; ++c) {
            vz[c] += w[1][b] * vx[4 * b + c];
            gxz[c] += w[1][b] * dvx[4 * b + c];
            gyz[c] += dw[1][b] * vx[4 * b + c];
        }
    double v = 0.0, gx = 0.0, gy = 0.0, gz = 0.0;
    for (int c = 0; c < 4; ++c) {
        v += w[2][c] * vz[c];
        gx += w[2][c] * gxz[c];
        gy += w[2][c] * gyz[c];
        gz += dw[2][c] * vz[c];
    }
    out[0] = v;
    out[1] = gx;
    out[2] = gy;
    out[3] = gz;
}

TEST(DvrSimd, BSplineBlockIsTheScalarLoopsBitForBitOnEveryTarget) {
    // Random signed blocks and weights on each SIMD target this CPU runs, value alone and with
    // the gradient; and a closed form: a single voxel of 1 at (a, b, c) gives w[0][a] w[1][b]
    // w[2][c] and its derivatives (up to rounding).
    int targets = 0;
    for (const int64_t target : hwy::SupportedAndGeneratedTargets()) {
        hwy::SetSupportedTargetsForTest(target);
        ++targets;
        for (int n = 0; n < 500; ++n) {
            Rng rng(13, n);
            float f[4][16];
            double w[3][4], dw[3][4];
            for (auto& row : f)
                for (float& x : row) x = float(2.0 * rng.uniform() - 1.0);
            for (int a = 0; a < 3; ++a)
                for (int i = 0; i < 4; ++i) {
                    w[a][i] = rng.uniform();
                    dw[a][i] = 2.0 * rng.uniform() - 1.0;
                }
            double got[4], value[4], want[4];
            bsplineBlock(f, w, dw, got);
            bsplineBlock(f, w, nullptr, value);
            bsplineBlockScalar(f, w, dw, want);
            for (int j = 0; j < 4; ++j)
                ASSERT_EQ(got[j], want[j])
                    << hwy::TargetName(target) << " case " << n << " j " << j;
            ASSERT_EQ(value[0], want[0]) << hwy::TargetName(target) << " case " << n;
            if (n % 50 == 0) {
                const int a = n % 4, b = (n / 4) % 4, c = (n / 16) % 4;
                float one[4][16] = {};
                one[a][4 * b + c] = 1.0f;
                bsplineBlock(one, w, dw, got);
                EXPECT_NEAR(got[0], w[0][a] * w[1][b] * w[2][c], 1e-15);
                EXPECT_NEAR(got[1], dw[0][a] * w[1][b] * w[2][c], 1e-15);
                EXPECT_NEAR(got[2], w[0][a] * dw[1][b] * w[2][c], 1e-15);
                EXPECT_NEAR(got[3], w[0][a] * w[1][b] * dw[2][c], 1e-15);
            }
        }
    }
    hwy::SetSupportedTargetsForTest(0);
    EXPECT_GE(targets, 2);
}

TEST(DvrSimd, PolynomialPacketStopsAtTheCellExit) {
    // f(t) = 1 + t (coefficients of (t − t0)^j with t0 = 0): values are exact; the ray leaves
    // cell (0, 0, 0) at x = 1, i.e. t = 0.75 for o.x = 0.25, d.x = 1: points t = 0.05 … 0.7
    // (k = 0 … 13 at Δt = 0.05, ξ = 0) lie in it, k = 14 (t = 0.75) does not.
    const double poly[10] = {1.0, 1.0, 0, 0, 0, 0, 0, 0, 0, 0};
    const int cell[3] = {0, 0, 0};
    const TfArrays arrays(pieces());
    RayLattice ray{{0.25, 0.5, 0.5}, {1.0, 0.0, 0.0}, 0.05, 0.0, 0.05};
    LatticePacket out;
    EXPECT_EQ(latticePacketPolynomial(ray, 0, 16, poly, 0.0, cell, arrays, out), 14);
    for (int i = 0; i < 14; ++i) EXPECT_NEAR(out.value[i], 1.05 + 0.05 * i, 1e-14);
    EXPECT_EQ(latticePacketPolynomial(ray, 0, 5, poly, 0.0, cell, arrays, out), 5);
}

}  // namespace
}  // namespace lobe
