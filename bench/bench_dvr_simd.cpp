// Lattice packets (volume/dvr_simd.h) against the scalar path: DVR samples per second per core.
//
// One thread (CPU time, so the rate is per core). Data: the CThead (assets/cthead, 256×256×113,
// the T2 task of bench/peers) with T2's transfer function shape (0 below 0.45 of the CT range,
// rising to its maximum at 0.6), seen from 45° as in T2; 96² parallel rays through the head, one
// jitter per ray. Three levels:
// - BM_Kernel/<simd>: reconstruction + TF lookup only, for every lattice point of every ray
//   inside the volume's box (no skipping): trilinear from the dense copy, 16-point packets
//   (simd = 1) against GridReconstructor::trilinear + TransferFunction::evaluate (simd = 0).
//   Comparable with the "~380 M trilinear samples/s per core" packet figure of issue 31.
// - BM_March/<simd>/<bspline>: VolumeRaySampler::next over whole rays (empty-space skipping,
//   TF, opacity correction, no normals, no early termination): evaluated lattice points per
//   second, trilinear or cubic B-spline (ray polynomial), step 0.05.
// Checks first: both paths give the same values (the run aborts otherwise).
#include "core/rng.h"
#include "volume/dvr_simd.h"
#include "volume/volume.h"
#include "volume/volume_marcher.h"

#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

namespace lobe {
namespace {

constexpr int kRays = 96;
constexpr double kStep = 0.05;

struct Setup {
    openvdb::FloatGrid::Ptr grid;
    TransferFunction tf;
    std::vector<Ray> rays;
    std::vector<double> jitter;
};

Setup& setup() {
    static Setup s = [] {
        openvdb::initialize();
        Setup st;
        st.grid = loadVolume(LOBE_SOURCE_DIR "/assets/cthead/cthead.nhdr").grid;
        // CT values 0 … ~3272 (bench/peers/common.py divides by 3272); T2's ramp 0.45 → 0.6.
        const double s = 3272.0;
        st.tf = TransferFunction(
            {{0.45 * s, 0.0, Spectrum(0.8, 0.6, 0.4)}, {0.6 * s, 0.2, Spectrum(1.0, 0.95, 0.9)}});
        const openvdb::CoordBBox b = st.grid->evalActiveVoxelBoundingBox();
        const openvdb::Vec3d c = st.grid->indexToWorld(b.getCenter());
        const Vec3 centre(c.x(), c.y(), c.z()), dir = normalized(Vec3(-1, 1, 0));
        const Vec3 right = normalized(dir.cross(Vec3(0, 0, 1))), up = right.cross(dir);
        for (int y = 0; y < kRays; ++y)
            for (int x = 0; x < kRays; ++x) {
                Ray r;
                r.d = dir;
                r.o = centre - 400.0 * dir + (2.4 * (x - kRays / 2)) * right +
                      (2.4 * (y - kRays / 2)) * up;
                st.rays.push_back(r);
                st.jitter.push_back(Rng(7, y * kRays + x).uniform());
            }
        return st;
    }();
    return s;
}

// Every lattice point of every ray inside the box, through the kernel or the scalar path.
long long kernelPass(const DvrVolume& vol, bool simd, double& checksum) {
    Setup& s = setup();
    const TfArrays arrays(vol.transferFunction());
    GridReconstructor recon(vol.grid(), vol.dense());
    VolumeRaySampler sampler(vol);
    LatticePacket packet;
    long long points = 0;
    for (size_t i = 0; i < s.rays.size(); ++i) {
        if (!sampler.begin(s.rays[i], s.jitter[i])) continue;
        const GridGeometry& g = vol.geometry();
        const Vec3 o = g.worldToIndex(s.rays[i].o), d = g.worldToIndexDirection(s.rays[i].d);
        const RayLattice lat{
            {o.x, o.y, o.z}, {d.x, d.y, d.z}, sampler.tEnter(), s.jitter[i], sampler.stepT()};
        const long long last = (long long)std::floor(
            (sampler.tExit() - sampler.tEnter()) / sampler.stepT() - s.jitter[i]);
        for (long long k = 0; k <= last; k += LatticePacket::kMaxPoints) {
            const int n = int(std::min<long long>(LatticePacket::kMaxPoints, last + 1 - k));
            // A packet whose footprint leaves the dense copy (at the box's rim) goes scalar.
            if (simd && latticePacketTrilinear(lat, k, n, *vol.dense(), arrays, packet) == n) {
                for (int j = 0; j < n; ++j) checksum += packet.value[j] + packet.alpha[j];
            } else {
                for (int j = 0; j < n; ++j) {
                    const double t = lat.tEnter + (double(k + j) + lat.jitter) * lat.dt;
                    const double v = recon.trilinear(o + d * t);
                    double a;
                    Spectrum c;
                    vol.transferFunction().evaluate(v, a, c);
                    checksum += v + a;
                }
            }
            points += n;
        }
    }
    return points;
}

const DvrVolume& volume(bool bspline, bool simd) {
    auto make = [](bool bs, bool si) {
        DvrSettings set;
        set.stepVoxels = kStep;
        set.reconstruction = bs ? Reconstruction::kCubicBSpline : Reconstruction::kTrilinear;
        set.simd = si;
        return new DvrVolume(setup().grid, setup().tf, set, "CThead");
    };
    static const DvrVolume* v[2][2] = {{make(false, false), make(false, true)},
                                       {make(true, false), make(true, true)}};
    return *v[bspline][simd];
}

void BM_Kernel(benchmark::State& state) {
    const bool simd = state.range(0) != 0;
    const DvrVolume& vol = volume(false, false);
    double ref = 0.0, got = 0.0;
    kernelPass(vol, false, ref);
    kernelPass(vol, true, got);
    if (ref != got) state.SkipWithError("the packet kernel's values differ from the scalar path");
    long long points = 0;
    double checksum = 0.0;
    for (auto _ : state) points += kernelPass(vol, simd, checksum);
    benchmark::DoNotOptimize(checksum);
    state.counters["Msamples/s"] =
        benchmark::Counter(double(points) * 1e-6, benchmark::Counter::kIsRate);
    state.SetLabel(simd ? latticePacketTarget() : "scalar");
}

void BM_March(benchmark::State& state) {
    const bool simd = state.range(0) != 0, bspline = state.range(1) != 0;
    const DvrVolume& vol = volume(bspline, simd);
    Setup& s = setup();
    VolumeRaySampler sampler(vol);
    long long evaluated = 0;
    double checksum = 0.0;
    for (auto _ : state) {
        const long long before = sampler.samplesEvaluated();
        for (size_t i = 0; i < s.rays.size(); ++i) {
            if (!sampler.begin(s.rays[i], s.jitter[i])) continue;
            VolumeSample smp;
            while (sampler.next(1e30, smp, false)) checksum += smp.alpha;
        }
        evaluated += sampler.samplesEvaluated() - before;
    }
    benchmark::DoNotOptimize(checksum);
    state.counters["Msamples/s"] =
        benchmark::Counter(double(evaluated) * 1e-6, benchmark::Counter::kIsRate);
    state.counters["packets"] = double(sampler.packetsFilled());
    state.SetLabel(simd ? latticePacketTarget() : "scalar");
}

BENCHMARK(BM_Kernel)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_March)->Args({0, 0})->Args({1, 0})->Args({0, 1})->Args({1, 1})->Unit(
    benchmark::kMillisecond);

}  // namespace
}  // namespace lobe

BENCHMARK_MAIN();
