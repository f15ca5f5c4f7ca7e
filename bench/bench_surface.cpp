// The three iso-surface methods (surface/iso_exact.h, iso_mesh.h, iso_levelset.h) on the CThead
// skull, measured side by side in one run: build time, memory, rays per second, hit-distance
// error against the exact method, and image error against a 64-spp exact reference at 1/4/16 spp;
// then the same on the CThead upsampled 2× per axis (trilinear), to show how memory grows.
//
// Scene: assets/cthead (256×256×113 int16, spacing 1,1,2) through the volume loader,
// value/3272, iso 0.5 (the paper's skull, docs/paper-scene.md); the camera of "A placement
// that works": 560 units from the skull's centre (110, 131, 116) at 45° azimuth from
// straight-front (front = −y), up = −z, 30° vertical field of view; SIZE² pixels (default 256),
// 2 threads.
//
// Image: a headlight shading |n·d| of the first hit (0 for a miss), so the image carries the hit
// position's silhouette and the normal — the two things the methods differ in. Pixel value =
// mean over n×n stratified jittered samples (pixelSampleRng).
//
// Hit-distance error: one ray through each pixel centre; |t − t_exact| in source voxels (world
// units over the voxel size along the ray) where both hit, and the share of rays that one method
// hits and the other does not. The exact method is the reference: its roots are within 1e-5
// voxel of an independent root finder (tests/surface/test_iso_surface.cpp).
//
// Build peak: the rise of the process's peak resident memory while the method builds (the
// source grid is already loaded). Memory kept: what the method keeps for rendering — the exact
// method its bricks (9³ values per brick holding the surface), the mesh its vertices, quads and
// bounds plus the source grid (its shading normals are the grid's gradient), the level set its tree
// and block classes.
//
// --terraces runs the terrace study instead (below, "The skull without terraces").
//
// Usage: lobe_bench_surface [--size N] [--no-upsampled] [--terraces]
#include "bench/bench_common.h"
#include "core/camera.h"
#include "core/error.h"
#include "core/pixel_loop.h"
#include "core/rng.h"
#include "surface/iso_exact.h"
#include "surface/iso_levelset.h"
#include "surface/iso_mesh.h"
#include "surface/surface_scene.h"
#include "volume/gaussian_blur.h"
#include "volume/volume.h"

#include <openvdb/tools/GridTransformer.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace lobe {
namespace {

constexpr int kThreads = 2;
constexpr int kReferenceStrata = 8;  // 64 spp
constexpr double kIso = 0.5;
const char* kDataPath = LOBE_SOURCE_DIR "/assets/cthead/cthead.nhdr";
int gSize = 256;

double seconds(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

PinholeCamera paperCamera() {
    // paper-scene.md, "A placement that works".
    const Vec3 centre(110, 131, 116);
    const double az = radians(45.0);
    const Vec3 position = centre + Vec3(std::sin(az), -std::cos(az), 0.0) * 560.0;
    return PinholeCamera(position, centre, Vec3(0, 0, -1), 30.0, 1.0);
}

struct Image {
    std::vector<double> pixels;
    double seconds = 0.0;
    long long rays = 0;
};

Image render(const SurfaceScene& scene, int strata) {
    const PinholeCamera cam = paperCamera();
    Image img;
    img.pixels.assign(std::size_t(gSize) * gSize, 0.0);
    const auto t0 = std::chrono::steady_clock::now();
    // The one pixel loop (core/pixel_loop.h): strata² stratified samples per pixel, seed 7.
    SchedulerOptions scheduler;
    scheduler.progress = false;
    forEachPixel(
        gSize, gSize, PixelSampling{strata * strata, 7}, scheduler, [&](const PixelSamples& px) {
            double sum = 0.0;
            px.forEach([&](const Vec2& j, Rng&) {
                const Ray ray = cam.generateRay((px.x() + j.x) / gSize, (px.y() + j.y) / gSize);
                if (const auto hit = scene.intersect(ray)) sum += std::abs(hit->normal.dot(ray.d));
            });
            img.pixels[std::size_t(px.y()) * gSize + std::size_t(px.x())] = sum / px.count();
        });
    img.seconds = seconds(t0);
    img.rays = (long long)gSize * gSize * strata * strata;
    for (double p : img.pixels)
        if (!std::isfinite(p)) throw Error("an image is not finite");
    return img;
}

// First-hit distances through the pixel centres (NaN for a miss).
std::vector<double> hitDistances(const SurfaceScene& scene) {
    const PinholeCamera cam = paperCamera();
    std::vector<double> t(std::size_t(gSize) * gSize);
    tbb::parallel_for(0, gSize, [&](int y) {
        for (int x = 0; x < gSize; ++x) {
            const auto hit = scene.intersect(cam.generateRay((x + 0.5) / gSize, (y + 0.5) / gSize));
            t[std::size_t(y) * gSize + x] = hit ? hit->t : std::nan("");
        }
    });
    return t;
}

// Resident memory now and its peak since the last reset, in MB (/proc/self/status); the peak is
// reset through /proc/self/clear_refs (Linux ≥ 4.0) so that each build's own peak is seen.
double statusMb(const char* key) {
    FILE* f = std::fopen("/proc/self/status", "r");
    if (!f) return std::nan("");
    char line[256];
    double kb = std::nan("");
    while (std::fgets(line, sizeof line, f))
        if (!std::strncmp(line, key, std::strlen(key))) kb = std::atof(line + std::strlen(key));
    std::fclose(f);
    return kb / 1024.0;
}
void resetPeak() {
    if (FILE* f = std::fopen("/proc/self/clear_refs", "w")) {
        std::fputs("5", f);
        std::fclose(f);
    }
}

struct Method {
    const char* name;
    std::function<std::shared_ptr<const SurfaceGeometry>(const openvdb::FloatGrid&)> build;
    std::function<double(const SurfaceGeometry&)> memoryMb;
};

void measure(const char* label, const openvdb::FloatGrid& grid, double voxel) {
    const double sourceMb = grid.tree().memUsage() / 1048576.0;
    const openvdb::Coord dims = grid.evalActiveVoxelDim();
    std::printf(
        "\n### %s: %d × %d × %d voxels, voxel %.2f (along z ×2), source grid %.1f MB, %d², "
        "%d threads\n\n",
        label, dims.x(), dims.y(), dims.z(), voxel, sourceMb, gSize, kThreads);
    const std::vector<Method> methods = {
        {"exact",
         [](const openvdb::FloatGrid& g) {
             return std::make_shared<IsoExactSurface>(g, kIso, "CThead");
         },
         [](const SurfaceGeometry& s) {
             return static_cast<const IsoExactSurface&>(s).memoryBytes() / 1048576.0;
         }},
        {"mesh",
         [](const openvdb::FloatGrid& g) {
             return std::make_shared<IsoMeshSurface>(g, kIso, "CThead");
         },
         [sourceMb](const SurfaceGeometry& s) {
             return static_cast<const IsoMeshSurface&>(s).memoryBytes() / 1048576.0 + sourceMb;
         }},
        {"levelset",
         [](const openvdb::FloatGrid& g) {
             return LevelSetSurface::fromDensity(g, kIso, LevelSetOptions{}, "CThead");
         },
         [](const SurfaceGeometry& s) {
             return static_cast<const LevelSetSurface&>(s).memoryBytes() / 1048576.0;
         }},
        {"levelset, voxel ½",
         [voxel](const openvdb::FloatGrid& g) {
             LevelSetOptions o;
             o.voxelSize = voxel / 2;
             return LevelSetSurface::fromDensity(g, kIso, o, "CThead");
         },
         [](const SurfaceGeometry& s) {
             return static_cast<const LevelSetSurface&>(s).memoryBytes() / 1048576.0;
         }},
    };
    std::vector<std::unique_ptr<SurfaceScene>> scenes;
    std::vector<double> buildSeconds, memory, buildPeak;
    for (const Method& m : methods) {
        resetPeak();
        const double before = statusMb("VmRSS:");
        const auto t0 = std::chrono::steady_clock::now();
        auto surface = m.build(grid);
        auto scene = std::make_unique<SurfaceScene>();
        scene->add(surface);
        scene->commit();
        buildSeconds.push_back(seconds(t0));
        buildPeak.push_back(statusMb("VmHWM:") - before);
        memory.push_back(m.memoryMb(*surface));
        scenes.push_back(std::move(scene));
    }
    const Image reference = render(*scenes[0], kReferenceStrata);
    const std::vector<double> tExact = hitDistances(*scenes[0]);
    std::printf(
        "| method | build s | build peak MB | kept MB | Mrays/s (4 spp) | Δt mean / p99 / "
        "max voxel | hit ≠ exact | RMSE 1 / 4 / 16 spp | ms 1 / 4 / 16 spp |\n");
    std::printf("|---|---:|---:|---:|---:|---|---:|---|---|\n");
    for (std::size_t i = 0; i < methods.size(); ++i) {
        const std::vector<double> t = hitDistances(*scenes[i]);
        std::vector<double> err;
        long long disagree = 0;
        for (std::size_t p = 0; p < t.size(); ++p) {
            if (std::isnan(t[p]) != std::isnan(tExact[p])) ++disagree;
            if (!std::isnan(t[p]) && !std::isnan(tExact[p]))
                err.push_back(std::abs(t[p] - tExact[p]) / voxel);
        }
        std::sort(err.begin(), err.end());
        double mean = 0.0;
        for (double e : err) mean += e;
        mean /= std::max<std::size_t>(1, err.size());
        const double p99 = err.empty() ? 0.0 : err[std::size_t(0.99 * (err.size() - 1))];
        const double mx = err.empty() ? 0.0 : err.back();
        double rm[3], ms[3], mrays = 0.0;
        for (int k = 0; k < 3; ++k) {
            const int strata = 1 << k;
            const Image img = render(*scenes[i], strata);
            rm[k] = bench::rmse(img.pixels, reference.pixels);
            ms[k] = img.seconds * 1e3;
            if (strata == 2) mrays = img.rays * 1e-6 / img.seconds;
        }
        std::printf(
            "| %s | %.2f | %.0f | %.1f | %.2f | %.3f / %.2f / %.1f | %.3f %% | %.4f / %.4f / %.4f "
            "| "
            "%.0f / %.0f / %.0f |\n",
            methods[i].name, buildSeconds[i], buildPeak[i], memory[i], mrays, mean, p99, mx,
            100.0 * disagree / double(t.size()), rm[0], rm[1], rm[2], ms[0], ms[1], ms[2]);
        std::fflush(stdout);
    }
}

// ---------------------------------------------------------------------------------------------
// The skull without terraces (--terraces): remedies compared by a measured terrace amplitude and
// by the thin bone they lose.
//
// Terrace amplitude. The CThead's slices are 2 mm apart along z; a surface oblique to them
// carries one step per slice, so along any path over the crown the surface's radius, as a
// function of height z, holds a component of period exactly 2 mm. Profiles: for 36 azimuths,
// rays aimed at the skull's centre from elevations 30° … 80° above the horizontal (crown side,
// −z is up) in steps of 0.02°; the hit's distance from the centre R against its height z. The
// trend is removed by a local quadratic in z over ±3 mm, and the residual's 2-mm Fourier
// component gives the amplitude (mm, median over the profiles); the residual's RMS is printed too.
// The same for the shading normal's tilt within the profile's plane (degrees): a 0.07 mm step
// every 2 mm turns the normal by several degrees, which is what makes the terraces visible.
//
// Thin bone. One ray per pixel centre of the paper view at 512²: a pixel whose first hit lies
// more than 3 mm deeper than the untreated exact surface's, or that misses where it hit, lost
// bone (the maxilla, orbits and mandible are 1–2 voxels thick); the share of skull pixels.
struct Remedy {
    std::string name;
    std::function<std::shared_ptr<const SurfaceGeometry>()> build;
};

// Local quadratic fit of y against x over |x − x0| ≤ h, evaluated at x0 (x sorted).
double localQuadratic(const std::vector<double>& x, const std::vector<double>& y, std::size_t i,
                      double h) {
    double s[5] = {0, 0, 0, 0, 0}, t[3] = {0, 0, 0};
    for (std::size_t j = 0; j < x.size(); ++j) {
        const double dx = x[j] - x[i];
        if (std::abs(dx) > h) continue;
        double p = 1.0;
        for (int k = 0; k < 5; ++k) {
            s[k] += p;
            if (k < 3) t[k] += p * y[j];
            p *= dx;
        }
    }
    // Normal equations [s0 s1 s2; s1 s2 s3; s2 s3 s4] c = t; the value at x0 is c0 (Cramer).
    const double a[3][3] = {{s[0], s[1], s[2]}, {s[1], s[2], s[3]}, {s[2], s[3], s[4]}};
    const auto det3 = [](const double m[3][3]) {
        return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
               m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
               m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    };
    const double d = det3(a);
    if (!(std::abs(d) > 0.0)) return y[i];
    const double b[3][3] = {{t[0], s[1], s[2]}, {t[1], s[2], s[3]}, {t[2], s[3], s[4]}};
    return det3(b) / d;
}

// The grid with F times as many slices along index z, the new ones interpolated by Catmull–Rom
// cubics through the 4 nearest slices (an interpolating, C¹ kernel: the original slices keep
// their values; between them the field no longer has a kink at every slice plane).
openvdb::FloatGrid::Ptr cubicSlices(const openvdb::FloatGrid& grid, int f) {
    openvdb::FloatGrid::Ptr out = openvdb::FloatGrid::create(grid.background());
    openvdb::math::Transform::Ptr xform = grid.transform().copy();
    xform->preScale(openvdb::Vec3d(1.0, 1.0, 1.0 / f));
    out->setTransform(xform);
    const openvdb::CoordBBox box = grid.evalActiveVoxelBoundingBox();
    auto in = grid.getConstAccessor();
    auto acc = out->getAccessor();
    for (int k = box.min().z(); k <= box.max().z(); ++k)
        for (int r = 0; r < f; ++r) {
            const double t = double(r) / f;
            const double w[4] = {(-t * t * t + 2 * t * t - t) / 2,
                                 (3 * t * t * t - 5 * t * t + 2) / 2,
                                 (-3 * t * t * t + 4 * t * t + t) / 2, (t * t * t - t * t) / 2};
            for (int j = box.min().y(); j <= box.max().y(); ++j)
                for (int i = box.min().x(); i <= box.max().x(); ++i) {
                    double v = 0.0;
                    for (int m = 0; m < 4; ++m)
                        v += w[m] * in.getValue(openvdb::Coord(i, j, k - 1 + m));
                    if (v != grid.background())
                        acc.setValue(openvdb::Coord(i, j, f * k + r), float(v));
                }
        }
    return out;
}

void terraceStudy(const Volume& ct) {
    const Vec3 centre(110, 131, 116);
    constexpr double kSlice = 2.0;  // mm between the CThead's slices
    const std::vector<Remedy> remedies = {
        {"exact (untreated)",
         [&] { return std::make_shared<IsoExactSurface>(*ct.grid, kIso, "CThead"); }},
        {"exact, source blurred 1 mm FWHM",
         [&] {
             Volume v = ct;
             v.grid = ct.grid->deepCopy();
             gaussianBlurFwhm(v, 1.0);
             return std::make_shared<IsoExactSurface>(*v.grid, kIso, "CThead");
         }},
        {"exact, source blurred 2 mm FWHM",
         [&] {
             Volume v = ct;
             v.grid = ct.grid->deepCopy();
             gaussianBlurFwhm(v, 2.0);
             return std::make_shared<IsoExactSurface>(*v.grid, kIso, "CThead");
         }},
        {"exact, slices ×2 by Catmull–Rom",
         [&] {
             return std::make_shared<IsoExactSurface>(*cubicSlices(*ct.grid, 2), kIso, "CThead");
         }},
        {"exact, slices ×4 by Catmull–Rom",
         [&] {
             return std::make_shared<IsoExactSurface>(*cubicSlices(*ct.grid, 4), kIso, "CThead");
         }},
        {"levelset",
         [&] { return LevelSetSurface::fromDensity(*ct.grid, kIso, LevelSetOptions{}, "CThead"); }},
        {"levelset, voxel 1 (isotropic)",
         [&] {
             LevelSetOptions o;
             o.voxelSize = 1.0;
             return LevelSetSurface::fromDensity(*ct.grid, kIso, o, "CThead");
         }},
    };
    std::vector<Remedy> all = remedies;
    for (int it : {1, 2, 5, 10}) {
        all.push_back(
            {"levelset, voxel 1, mean curvature × " + std::to_string(it), [&ct, it] {
                 LevelSetOptions o;
                 o.smoothIterations =
                     it;  // built at the source's smallest side, 1 (the filter needs cubes)
                 return LevelSetSurface::fromDensity(*ct.grid, kIso, o, "CThead");
             }});
    }

    const int size = 512;
    const PinholeCamera cam = paperCamera();
    std::vector<double> tRaw;
    std::printf("\n### The skull without terraces (CThead, iso 0.5)\n\n");
    std::printf(
        "| remedy | build s | terrace amplitude mm | normal's terrace amplitude ° | residual RMS "
        "mm | thin bone lost, %% of skull pixels |\n");
    std::printf("|---|---:|---:|---:|---:|---:|\n");
    for (const Remedy& r : all) {
        const auto t0 = std::chrono::steady_clock::now();
        SurfaceScene scene;
        scene.add(r.build());
        scene.commit();
        const double buildS = seconds(t0);
        // Profiles.
        std::vector<double> amplitude(36), rms(36), normalAmplitude(36);
        tbb::parallel_for(0, 36, [&](int p) {
            const double az = radians(10.0 * p);
            std::vector<double> z, radius, tilt;
            for (double e = 30.0; e <= 80.0; e += 0.02) {
                const double el = radians(e);
                const Vec3 d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az),
                             -std::sin(el));
                Ray ray;
                ray.o = centre + d * 400.0;
                ray.d = -d;
                const auto hit = scene.intersect(ray);
                if (!hit) continue;
                z.push_back(hit->position.z);
                radius.push_back((hit->position - centre).length());
                // The normal's angle from the ray's radial direction within the profile's
                // plane (degrees): what the shading sees.
                const Vec3 radial = normalized(hit->position - centre);
                const Vec3 across =
                    normalized(Vec3(-std::sin(az), std::cos(az), 0.0).cross(radial));
                tilt.push_back(std::atan2(hit->normal.dot(across), hit->normal.dot(radial)) *
                               180.0 / kPi);
            }
            // Sort by z (monotonic along the arc but for folds), detrend, project on 2-mm period.
            std::vector<std::size_t> order(z.size());
            for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
            std::sort(order.begin(), order.end(),
                      [&](std::size_t a, std::size_t b) { return z[a] < z[b]; });
            std::vector<double> zs, rs, ts;
            for (std::size_t i : order) {
                zs.push_back(z[i]);
                rs.push_back(radius[i]);
                ts.push_back(tilt[i]);
            }
            // The 2-mm Fourier component of a detrended signal, and the residual's RMS.
            const auto slicePeriod = [&](const std::vector<double>& v, double& rmsOut) {
                double c = 0, s = 0, sq = 0;
                for (std::size_t i = 0; i < zs.size(); ++i) {
                    const double res = v[i] - localQuadratic(zs, v, i, 1.5 * kSlice);
                    c += res * std::cos(2 * kPi * zs[i] / kSlice);
                    s += res * std::sin(2 * kPi * zs[i] / kSlice);
                    sq += res * res;
                }
                const double n = std::max<std::size_t>(1, zs.size());
                rmsOut = std::sqrt(sq / n);
                return 2.0 * std::sqrt(c * c + s * s) / n;
            };
            double tiltRms = 0.0;
            amplitude[p] = slicePeriod(rs, rms[p]);
            normalAmplitude[p] = slicePeriod(ts, tiltRms);
        });
        std::sort(amplitude.begin(), amplitude.end());
        std::sort(rms.begin(), rms.end());
        std::sort(normalAmplitude.begin(), normalAmplitude.end());
        // Thin bone against the untreated exact surface.
        std::vector<double> t(std::size_t(size) * size);
        tbb::parallel_for(0, size, [&](int y) {
            for (int x = 0; x < size; ++x) {
                const auto hit =
                    scene.intersect(cam.generateRay((x + 0.5) / size, (y + 0.5) / size));
                t[std::size_t(y) * size + x] = hit ? hit->t : std::nan("");
            }
        });
        if (tRaw.empty()) tRaw = t;
        long long skull = 0, lost = 0;
        for (std::size_t i = 0; i < t.size(); ++i) {
            if (std::isnan(tRaw[i])) continue;
            ++skull;
            if (std::isnan(t[i]) || t[i] > tRaw[i] + 3.0) ++lost;
        }
        std::printf("| %s | %.2f | %.3f | %.2f | %.3f | %.2f |\n", r.name.c_str(), buildS,
                    amplitude[18], normalAmplitude[18], rms[18], 100.0 * lost / double(skull));
        std::fflush(stdout);
    }
}

}  // namespace
}  // namespace lobe

int main(int argc, char** argv) {
    using namespace lobe;
    bool upsampled = true, terraces = false;
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--size") && i + 1 < argc) {
            gSize = std::atoi(argv[++i]);
        } else if (!std::strcmp(argv[i], "--no-upsampled")) {
            upsampled = false;
        } else if (!std::strcmp(argv[i], "--terraces")) {
            terraces = true;
        } else {
            std::fprintf(stderr,
                         "usage: lobe_bench_surface [--size N] [--no-upsampled] [--terraces]\n");
            return 2;
        }
    }
    if (gSize < 16 || gSize > 4096) {
        std::fprintf(stderr, "lobe_bench_surface: --size must be 16 … 4096\n");
        return 2;
    }
    tbb::global_control threads(tbb::global_control::max_allowed_parallelism, kThreads);
    openvdb::initialize();
    try {
        LoadOptions opts;
        opts.normalize = 3272.0;
        const Volume vol = loadNrrd(kDataPath, opts);
        if (terraces) {
            terraceStudy(vol);
            return 0;
        }
        measure("CThead", *vol.grid, 1.0);
        if (upsampled) {
            // 2× per axis: a grid at half the voxel size, values resampled trilinearly.
            openvdb::FloatGrid::Ptr fine = openvdb::FloatGrid::create(vol.grid->background());
            openvdb::math::Transform::Ptr xform = vol.grid->transform().copy();
            xform->preScale(0.5);
            fine->setTransform(xform);
            openvdb::tools::resampleToMatch<openvdb::tools::BoxSampler>(*vol.grid, *fine);
            measure("CThead upsampled 2× per axis", *fine, 0.5);
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "lobe_bench_surface: %s\n", e.what());
        return 1;
    }
    return 0;
}
