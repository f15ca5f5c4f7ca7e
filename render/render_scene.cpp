#include "render/render_scene.h"

#include "core/error.h"
#include "core/progress.h"
#include "core/rng.h"
#include "core/sampling.h"
#include "core/tile_scheduler.h"
#include "surface/iso_exact.h"
#include "surface/iso_mesh.h"
#include "surface/surface_scene.h"
#include "volume/gaussian_blur.h"
#include "volume/volume.h"
#include "volume/volume_marcher.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <chrono>
#include <limits>
#include <map>
#include <optional>

namespace lobe {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// At most this many surfaces are composited along one ray: a guard against pathological
// geometry, far above what a head (skin, two skull walls, …) produces.
constexpr int kMaxSurfaceHits = 64;

// The object's axis and a second axis for where the first degenerates, both in world space.
void worldAxes(const ObjectSpec& spec, Vec3& axis, Vec3& fallback) {
    const auto& L = spec.transform.linear;
    auto apply = [&](const Vec3& v) {
        return normalized(Vec3(L[0][0] * v.x + L[0][1] * v.y + L[0][2] * v.z,
                               L[1][0] * v.x + L[1][1] * v.y + L[1][2] * v.z,
                               L[2][0] * v.x + L[2][1] * v.y + L[2][2] * v.z));
    };
    const Vec3 a = spec.tangentAxis;
    const Vec3 f = std::abs(a.x) < 0.9 ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
    axis = apply(a);
    fallback = apply(f);
}

std::string sourceKey(const VolumeSourceSpec& s) {
    return s.path + "|" + std::to_string(s.divideBy) + "|" + std::to_string(s.background) + "|" +
           std::to_string(s.blurFwhmMm);
}

Volume loadSource(const VolumeSourceSpec& s) {
    LoadOptions options;
    if (s.dims) {
        options.hasLayout = true;
        options.layout.dims = *s.dims;
        options.layout.type = parseVoxelType(s.type.empty() ? "uint8" : s.type);
        options.layout.endian = parseEndian(s.endian);
        options.layout.spacing = s.spacing;
    }
    if (s.divideBy != 1.0) options.normalize = s.divideBy;
    options.background = s.background;
    Volume v = loadVolume(s.path, options);
    if (s.blurFwhmMm > 0.0) gaussianBlurFwhm(v, s.blurFwhmMm);
    return v;
}

// Every distinct source of the scene loaded once, the files in parallel (decompressing one
// file is serial, so loading the skull and the brain side by side saves ~0.2 s of a preview).
// Returns, per object, the index of its volume in `volumes`. A failure is reported for the
// first failing object in scene order, whatever order the loads finished in.
std::vector<size_t> loadSources(const SceneSpec& spec, std::vector<Volume>& volumes) {
    std::map<std::string, size_t> slotOfKey;
    std::vector<size_t> slotOfObject, firstObjectOfSlot;
    for (size_t i = 0; i < spec.objects.size(); ++i) {
        const auto [it, isNew] =
            slotOfKey.emplace(sourceKey(spec.objects[i].source), firstObjectOfSlot.size());
        if (isNew) firstObjectOfSlot.push_back(i);
        slotOfObject.push_back(it->second);
    }
    volumes.resize(firstObjectOfSlot.size());
    std::vector<std::optional<std::string>> errors(volumes.size());
    tbb::parallel_for(size_t(0), volumes.size(), [&](size_t slot) {
        try {
            volumes[slot] = loadSource(spec.objects[firstObjectOfSlot[slot]].source);
        } catch (const std::exception& e) {
            errors[slot] = e.what();
        }
    });
    for (size_t i = 0; i < spec.objects.size(); ++i)
        if (errors[slotOfObject[i]])
            throw Error(spec.path + ": objects[" + std::to_string(i) + "] (" +
                        spec.objects[i].name + "): " + *errors[slotOfObject[i]]);
    return slotOfObject;
}

// A shallow copy of the volume's grid (same voxels) whose transform is followed by the object's
// transform, so the grid maps index → scene world directly.
openvdb::FloatGrid::Ptr placeInWorld(const Volume& volume, const ObjectTransform& t,
                                     const std::string& context) {
    const openvdb::math::AffineMap::Ptr affine = volume.grid->transform().baseMap()->getAffineMap();
    if (!affine) throw Error(context + ": the volume's transform is not affine");
    // OpenVDB multiplies row vectors (world = index · M): the object map in that form.
    openvdb::math::Mat4d object = openvdb::math::Mat4d::identity();
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) object[r][c] = t.linear[c][r];
    for (int c = 0; c < 3; ++c) object[3][c] = t.translation[c];
    const openvdb::math::Mat4d total = affine->getMat4() * object;
    openvdb::FloatGrid::Ptr grid = volume.grid->copy();  // shares the tree
    grid->setTransform(openvdb::math::Transform::createLinearTransform(total));
    return grid;
}

// World bounding box of a grid's active voxels (their centres ± half a voxel).
void growByGridBox(const openvdb::FloatGrid& grid, Vec3& lo, Vec3& hi) {
    const openvdb::CoordBBox box = grid.evalActiveVoxelBoundingBox();
    if (box.empty()) return;
    for (int corner = 0; corner < 8; ++corner) {
        const openvdb::Vec3d idx((corner & 1) ? box.max().x() + 0.5 : box.min().x() - 0.5,
                                 (corner & 2) ? box.max().y() + 0.5 : box.min().y() - 0.5,
                                 (corner & 4) ? box.max().z() + 0.5 : box.min().z() - 0.5);
        const openvdb::Vec3d w = grid.transform().indexToWorld(idx);
        lo = Vec3(std::min(lo.x, w.x()), std::min(lo.y, w.y()), std::min(lo.z, w.z()));
        hi = Vec3(std::max(hi.x, w.x()), std::max(hi.y, w.y()), std::max(hi.z, w.z()));
    }
}

}  // namespace

struct RenderScene::SurfaceObject {
    const ObjectSpec* spec = nullptr;
    Vec3 axis{0, 0, 1}, fallback{1, 0, 0};
};

struct RenderScene::VolumeObject {
    const ObjectSpec* spec = nullptr;
    std::unique_ptr<DvrVolume> volume;
    Vec3 axis{0, 0, 1}, fallback{1, 0, 0};
};

struct RenderScene::ThreadState {
    std::vector<VolumeRaySampler> samplers;
    std::vector<VolumeSample> pending;
    std::vector<char> hasPending;
};

RenderScene::ThreadState RenderScene::newThreadState() const {
    ThreadState st;
    for (const VolumeObject& vo : volumeObjects_) st.samplers.emplace_back(*vo.volume);
    st.pending.resize(volumeObjects_.size());
    st.hasPending.resize(volumeObjects_.size());
    return st;
}

RenderScene::RenderScene(const SceneSpec& spec, bool progress) : spec_(spec) {
    openvdb::initialize();
    camera_ = PinholeCamera(spec_.cameraPosition, spec_.cameraTarget, spec_.cameraUp,
                            spec_.fovDegrees, double(spec_.width) / spec_.height, spec_.crop);
    ProgressReporter loading("load " + spec_.title, int64_t(spec_.objects.size()), progress);
    std::vector<Volume> volumes;
    const std::vector<size_t> volumeOfObject = loadSources(spec_, volumes);
    Vec3 lo(kInf), hi(-kInf);
    for (size_t i = 0; i < spec_.objects.size(); ++i) {
        const ObjectSpec& object = spec_.objects[i];
        const std::string context =
            spec_.path + ": objects[" + std::to_string(i) + "] (" + object.name + ")";
        const Volume& volume = volumes[volumeOfObject[i]];
        openvdb::FloatGrid::Ptr grid = placeInWorld(volume, object.transform, context);
        growByGridBox(*grid, lo, hi);
        Vec3 axis, fallback;
        worldAxes(object, axis, fallback);
        if (object.kind == ObjectSpec::Kind::IsoSurface) {
            if (!surfaces_) surfaces_ = std::make_unique<SurfaceScene>();
            std::shared_ptr<const SurfaceGeometry> geometry;
            try {
                if (object.method == "mesh")
                    geometry = std::make_shared<IsoMeshSurface>(*grid, object.iso, object.name);
                else
                    geometry = std::make_shared<IsoExactSurface>(*grid, object.iso, object.name);
            } catch (const Error& e) {
                throw Error(context + ": " + e.what());
            }
            const int id = surfaces_->add(geometry);
            if (id != int(surfaceObjects_.size())) throw Error("internal: surface IDs out of order");
            surfaceObjects_.push_back({&object, axis, fallback});
        } else {
            DvrSettings settings;
            settings.reconstruction = object.reconstruction == "bspline"
                                          ? Reconstruction::kCubicBSpline
                                          : Reconstruction::kTrilinear;
            settings.gradient = object.gradient == "bspline" ? GradientMethod::kBSplineDerivative
                                                             : GradientMethod::kCentralDifferences;
            settings.stepVoxels = spec_.volumeStepVoxels;
            settings.emptySpaceSkipping = spec_.emptySpaceSkipping;
            VolumeObject vo;
            vo.spec = &object;
            vo.volume = std::make_unique<DvrVolume>(grid, object.transfer, settings, context);
            vo.axis = axis;
            vo.fallback = fallback;
            volumeObjects_.push_back(std::move(vo));
        }
        loading.advance();
    }
    if (surfaces_) surfaces_->commit();
    loading.finish();

    if (spec_.backdrop.enabled) {
        // Behind everything: the farthest corner of the objects' box along the view, plus 10 %.
        const Vec3 forward = camera_.forward();
        double depth = (spec_.cameraTarget - spec_.cameraPosition).dot(forward) * 1.5;
        if (lo.x <= hi.x) {
            depth = 0.0;
            for (int c = 0; c < 8; ++c) {
                const Vec3 p((c & 1) ? hi.x : lo.x, (c & 2) ? hi.y : lo.y, (c & 4) ? hi.z : lo.z);
                depth = std::max(depth, (p - spec_.cameraPosition).dot(forward));
            }
            depth *= 1.1;
        }
        const double halfFov = std::tan(radians(spec_.fovDegrees) * 0.5);
        const double half = depth * halfFov * std::max(1.0, double(spec_.width) / spec_.height);
        BackdropSettings b;
        b.seed = spec_.backdrop.seed;
        b.ambient = spec_.backdrop.ambient;
        b.diffuse = spec_.backdrop.diffuse;
        b.cells = spec_.backdrop.cells;
        b.blur = spec_.backdrop.blur;
        backdrop_ = Backdrop(b, spec_.cameraPosition + forward * depth, forward, camera_.right(),
                             camera_.up(), half * 1.05);
    }
}

RenderScene::~RenderScene() = default;

Spectrum RenderScene::trace(const Ray& ray, double jitter, Rng& rng, ThreadState& st,
                            RenderStats& stats) const {
    ++stats.rays;
    const double threshold = spec_.terminationTransmittance;
    double rouletteSum = rng.uniform();  // the shading roulette's offset (below)
    Spectrum radiance;
    double transmittance = 1.0;
    auto composite = [&](double alpha, const Spectrum& L) {
        radiance += L * (transmittance * alpha);
        transmittance *= 1.0 - alpha;
    };

    const size_t nv = volumeObjects_.size();
    for (size_t i = 0; i < nv; ++i) {
        // Each volume gets its own jitter (a fixed irrational offset), so coincident lattices of
        // volumes sharing a grid do not sample the same depths.
        const double xi = jitter + 0.6180339887498949 * double(i);
        st.samplers[i].begin(ray, xi - std::floor(xi));
        st.hasPending[i] = 0;
    }
    // The ray ends at ray.tMax (the volume samplers clip to it too): a backdrop beyond it is not seen.
    double tBackdrop = backdrop_.enabled() ? backdrop_.intersect(ray) : kInf;
    if (tBackdrop > ray.tMax) tBackdrop = kInf;
    const Vec3 toViewer = -ray.d;

    // Composites every volume sample with t < tEnd in depth order; false once opaque.
    auto volumesUpTo = [&](double tEnd) {
        if (nv == 0) return true;
        for (;;) {
            int best = -1;
            for (size_t i = 0; i < nv; ++i) {
                if (!st.hasPending[i]) st.hasPending[i] = st.samplers[i].next(tEnd, st.pending[i], false);
                if (st.hasPending[i] && (best < 0 || st.pending[i].t < st.pending[best].t))
                    best = int(i);
            }
            if (best < 0) return true;
            const VolumeObject& vo = volumeObjects_[best];
            VolumeSample& s = st.pending[best];
            // Russian roulette on shading (Arvo & Kirk 1990): a sample whose weight in the pixel,
            // w = T·α, is below the scene's threshold w0 is shaded with probability w/w0 and then
            // counted w0/w times; the expected radiance is unchanged (no bias), only the
            // gradient and BRDF work of faint samples is saved. The transmittance is always
            // updated exactly, so the weights along a ray do not depend on the draws. The draws
            // are systematic (one uniform offset per ray, as in systematic resampling — Kitagawa
            // 1996): a running sum of w/w0 from that offset, and a sample is shaded when the sum
            // crosses an integer. Each sample's probability is still exactly w/w0, but the shaded
            // samples are spread evenly over the ray's faint weight instead of clumping, which
            // lowers the noise at the same cost.
            const double weight = transmittance * s.alpha;
            const double w0 = spec_.shadingRoulette;
            bool shade = weight >= w0;
            if (!shade) {
                const double before = rouletteSum;
                rouletteSum += weight / w0;
                shade = std::floor(rouletteSum) > std::floor(before);
            }
            Spectrum L(0.0);
            if (shade) {
                st.samplers[best].addNormal(s);
                L = shadeVolumeSample(vo.spec->material, s, toViewer, spec_.lights, vo.axis,
                                      vo.fallback);
                if (weight < w0) L *= w0 / weight;
                ++stats.volumeShaded;
            }
            composite(s.alpha, L);
            st.hasPending[best] = 0;
            ++stats.volumeSamples;
            if (transmittance < threshold) return false;
        }
    };

    Ray segment = ray;
    segment.tMax = std::min(ray.tMax, tBackdrop);
    for (int hits = 0;; ++hits) {
        std::optional<SurfaceHit> hit;
        if (surfaces_ && hits < kMaxSurfaceHits) hit = surfaces_->intersect(segment);
        const double tEnd = hit ? hit->t : std::min(tBackdrop, kInf);
        if (!volumesUpTo(tEnd)) return radiance;
        if (!hit) break;
        ++stats.surfaceHits;
        const SurfaceObject& so = surfaceObjects_[hit->objectId];
        const Frame frame = Frame::fromNormalAndAxis(hit->normal, so.axis, so.fallback);
        const Spectrum L = so.spec->color * directLighting(so.spec->material, frame,
                                                           hit->position, toViewer, spec_.lights,
                                                           /*twoSided=*/true);
        composite(so.spec->opacity, L);
        if (transmittance < threshold) return radiance;
        segment.tMin = hit->t + 1e-6 * (1.0 + hit->t);
    }
    if (tBackdrop < kInf) composite(1.0, backdrop_.radiance(ray.at(tBackdrop), spec_.lights));
    return radiance;
}

Spectrum RenderScene::pixel(int x, int y, ThreadState& st, RenderStats& counters) const {
    const int spp = spec_.samplesPerPixel;
    const StrataGrid strata = strataFor(spp);
    Spectrum sum;
    for (int s = 0; s < spp; ++s) {
        Rng rng = pixelSampleRng(spec_.seed, x, y, s);
        const Vec2 j = jitteredSample(strata, s, rng);
        const Ray ray = camera_.generateRay((x + j.x) / spec_.width, (y + j.y) / spec_.height);
        const double jitter = rng.uniform();
        sum += trace(ray, jitter, rng, st, counters);
    }
    Spectrum value = sum * (1.0 / spp);
    if (!value.isFinite()) value = Spectrum(0.0);  // never NaN into an image
    return value;
}

Spectrum RenderScene::traceRay(const Ray& ray, double jitter, uint64_t seed) const {
    ThreadState st = newThreadState();
    RenderStats stats;
    Rng rng(seed);
    return trace(ray, jitter, rng, st, stats);
}

Spectrum RenderScene::renderPixel(int x, int y) const {
    ThreadState st = newThreadState();
    RenderStats stats;
    return pixel(x, y, st, stats);
}

Film RenderScene::render(const RenderOptions& options, RenderStats* statsOut) const {
    const auto start = std::chrono::steady_clock::now();
    Film film(spec_.width, spec_.height);
    tbb::enumerable_thread_specific<ThreadState> states([&] { return newThreadState(); });
    tbb::enumerable_thread_specific<RenderStats> stats;

    SchedulerOptions scheduler;
    scheduler.threads = options.threads;
    scheduler.progress = options.progress;
    scheduler.label = options.label;
    scheduler.tileSize = 16;
    scheduler.sharedProgress = options.sharedProgress;
    forEachTile(film.width(), film.height(), scheduler, [&](const Tile& tile) {
        ThreadState& st = states.local();
        RenderStats& counters = stats.local();
        for (int y = tile.y0; y < tile.y1; ++y)
            for (int x = tile.x0; x < tile.x1; ++x) film.at(x, y) = pixel(x, y, st, counters);
    });
    if (statsOut) {
        *statsOut = RenderStats();
        for (const RenderStats& s : stats) {
            statsOut->rays += s.rays;
            statsOut->surfaceHits += s.surfaceHits;
            statsOut->volumeSamples += s.volumeSamples;
            statsOut->volumeShaded += s.volumeShaded;
        }
        for (const ThreadState& st : states)
            for (const VolumeRaySampler& sampler : st.samplers) {
                statsOut->volumeEvaluated += sampler.samplesEvaluated();
                statsOut->volumeSkipped += sampler.samplesSkipped();
            }
        statsOut->seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    return film;
}

}  // namespace lobe
