#include "render/scene.h"

#include "core/error.h"
#include "core/progress.h"
#include "render/framing.h"
#include "surface/iso_exact.h"
#include "surface/iso_levelset.h"
#include "surface/iso_mesh.h"
#include "surface/surface_scene.h"
#include "volume/gaussian_blur.h"
#include "volume/volume.h"
#include "volume/volume_marcher.h"

#include <openvdb/tools/Interpolation.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstdio>
#include <limits>
#include <map>
#include <optional>

namespace lobe {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// The object's axis and a second axis for where the first degenerates, both in world space.
TangentAxes worldAxes(const ObjectSpec& spec) {
    const auto& L = spec.transform.linear;
    auto apply = [&](const Vec3& v) {
        return normalized(Vec3(L[0][0] * v.x + L[0][1] * v.y + L[0][2] * v.z,
                               L[1][0] * v.x + L[1][1] * v.y + L[1][2] * v.z,
                               L[2][0] * v.x + L[2][1] * v.y + L[2][2] * v.z));
    };
    const Vec3 a = spec.tangentAxis;
    const Vec3 f = std::abs(a.x) < 0.9 ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
    return {apply(a), apply(f)};
}

// Everything a loaded volume depends on.
std::string sourceKey(const VolumeSourceSpec& s) {
    char numbers[256];
    std::snprintf(numbers, sizeof numbers, "|%d|%.17g|%.17g|%.17g|%.17g|%.17g|%.17g|%.17g", int(s.divideByMax),
                  s.divideByPercentile, s.divideBy,
                  s.background, s.blurFwhmMm, s.spacing[0], s.spacing[1], s.spacing[2]);
    std::string key = s.path + numbers + "|" + s.type + "|" + s.endian + "|" + s.series;
    for (const std::string& p : s.morePaths) key += "|" + p;
    if (s.dims)
        for (int d : *s.dims) key += "|" + std::to_string(d);
    return key;
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
    options.normalizeByMax = s.divideByMax;
    options.normalizePercentile = s.divideByPercentile;
    options.background = s.background;
    options.series = s.series;
    std::vector<std::string> paths{s.path};
    paths.insert(paths.end(), s.morePaths.begin(), s.morePaths.end());
    Volume v = loadVolume(paths, options);
    if (s.blurFwhmMm > 0.0) gaussianBlurFwhm(v, s.blurFwhmMm);
    return v;
}

}  // namespace

// Every distinct source not yet held loaded once, the files in parallel (decompressing one file
// is serial, so loading the skull and the brain side by side saves ~0.2 s of a preview). A
// failure is reported for the first failing object in scene order, whatever order the loads
// finished in.
std::vector<std::string> VolumeCache::preload(const std::vector<const SceneSpec*>& specs) {
    std::vector<const VolumeSourceSpec*> missing;
    std::vector<std::string> missingKeys;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        for (const SceneSpec* spec : specs)
            for (const ObjectSpec& object : spec->objects) {
                const std::string key = sourceKey(object.source);
                if (volumes_.count(key) || errors_.count(key) ||
                    std::find(missingKeys.begin(), missingKeys.end(), key) != missingKeys.end())
                    continue;
                missing.push_back(&object.source);
                missingKeys.push_back(key);
            }
    }
    std::vector<std::shared_ptr<const Volume>> loaded(missing.size());
    std::vector<std::string> failed(missing.size());
    tbb::parallel_for(size_t(0), missing.size(), [&](size_t i) {
        try {
            loaded[i] = std::make_shared<const Volume>(loadSource(*missing[i]));
        } catch (const std::exception& e) {
            failed[i] = e.what();
        }
    });
    std::lock_guard<std::mutex> lock(mutex_);
    for (size_t i = 0; i < missing.size(); ++i) {
        if (loaded[i]) volumes_[missingKeys[i]] = loaded[i];
        else errors_[missingKeys[i]] = failed[i];
    }
    std::vector<std::string> errors(specs.size());
    for (size_t s = 0; s < specs.size(); ++s)
        for (size_t i = 0; i < specs[s]->objects.size(); ++i) {
            const auto it = errors_.find(sourceKey(specs[s]->objects[i].source));
            if (it == errors_.end()) continue;
            errors[s] = specs[s]->path + ": objects[" + std::to_string(i) + "] (" +
                        specs[s]->objects[i].name + "): " + it->second;
            break;
        }
    return errors;
}

std::shared_ptr<const Volume> VolumeCache::get(const VolumeSourceSpec& source) {
    const std::string key = sourceKey(source);
    {
        std::lock_guard<std::mutex> lock(mutex_);
        const auto it = volumes_.find(key);
        if (it != volumes_.end()) return it->second;
        const auto bad = errors_.find(key);
        if (bad != errors_.end()) throw Error(bad->second);
    }
    auto volume = std::make_shared<const Volume>(loadSource(source));
    std::lock_guard<std::mutex> lock(mutex_);
    return volumes_.emplace(key, volume).first->second;
}

namespace {

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

// The "levelset" method: a level-set source (grid class GRID_LEVEL_SET, e.g. a .vdb from
// vdb_tool or Houdini) as it is, its zero crossing the surface; any other grid rebuilt as one.
std::shared_ptr<const SurfaceGeometry> levelSetOf(const openvdb::FloatGrid::Ptr& grid,
                                                  const ObjectSpec& object) {
    if (grid->getGridClass() == openvdb::GRID_LEVEL_SET) {
        if (object.iso != 0.0)
            throw Error("the source is a level set, whose surface is its zero crossing: set \"iso\": 0");
        return std::make_shared<LevelSetSurface>(grid, object.name);
    }
    LevelSetOptions options;
    options.voxelSize = object.levelSetVoxel;
    options.halfWidth = object.levelSetHalfWidth;
    options.smoothIterations = object.levelSetSmooth;
    return LevelSetSurface::fromDensity(*grid, object.iso, options, object.name);
}

}  // namespace

TransferFunction resolvedTransfer(const ObjectSpec& object, const Volume& volume) {
    if (object.transferPercentiles.empty()) return object.transfer;
    // The volume as loaded: divided (divide_by) and blurred (blur_fwhm_mm), as `lobe info
    // --blur-fwhm` measures it.
    const ValueHistogram histogram = percentileHistogram(volume);
    std::vector<TfPoint> points = object.transferPoints;
    std::string resolved;
    for (const ObjectSpec::TfPercentile& p : object.transferPercentiles) {
        const double value = histogram.percentile(p.percent);
        for (std::size_t i : p.points) points[i].value += value;
        char text[96];
        std::snprintf(text, sizeof text, " \"p%g\" = %.9g", p.percent, value);
        resolved += (resolved.empty() ? "" : ", ") + p.key + text;
    }
    try {
        return TransferFunction(std::move(points), object.transferName);
    } catch (const Error& e) {
        throw Error(std::string(e.what()) + " (percentiles of the volume's values: " + resolved + ")");
    }
}

std::string transferError(const SceneSpec& spec, VolumeCache& cache) {
    try {
        for (const ObjectSpec& object : spec.objects)
            if (!object.transferPercentiles.empty()) resolvedTransfer(object, *cache.get(object.source));
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

std::vector<WorldBox> objectWorldBoxes(const SceneSpec& spec, VolumeCache& cache) {
    std::vector<WorldBox> boxes(spec.objects.size());
    for (size_t i = 0; i < spec.objects.size(); ++i) {
        const ObjectSpec& object = spec.objects[i];
        const std::string context =
            spec.path + ": objects[" + std::to_string(i) + "] (" + object.name + ")";
        const openvdb::FloatGrid::Ptr grid =
            placeInWorld(*cache.get(object.source), object.transform, context);
        growByGridBox(*grid, boxes[i].lo, boxes[i].hi);
        clipBox(spec.clip, boxes[i].lo, boxes[i].hi);
        clipBox(object.clip, boxes[i].lo, boxes[i].hi);
    }
    return boxes;
}

std::string computedViewError(const SceneSpec& spec, VolumeCache& cache) {
    if (!hasComputedView(spec)) return "";
    try {
        SceneSpec resolved = spec;
        resolveView(resolved, objectWorldBoxes(resolved, cache));
        try {
            PinholeCamera(resolved.cameraPosition, resolved.cameraTarget, resolved.cameraUp,
                          resolved.fovDegrees, double(resolved.width) / resolved.height,
                          resolved.crop);
        } catch (const Error& e) {
            throw Error(spec.path + ": " + e.what());
        }
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

Scene::Scene(const SceneSpec& spec, bool progress, VolumeCache* cache) : spec_(spec) {
    openvdb::initialize();
    ProgressReporter loading("load " + spec_.title, int64_t(spec_.objects.size()), progress);
    VolumeCache own;
    VolumeCache& volumes = cache ? *cache : own;
    const std::string error = volumes.preload({&spec_}).front();
    if (!error.empty()) throw Error(error);
    Vec3 lo(kInf), hi(-kInf);
    std::vector<WorldBox>& objectBoxes = objectBoxes_;  // for camera.fit (framing.h)
    objectBoxes.assign(spec_.objects.size(), WorldBox());
    for (size_t i = 0; i < spec_.objects.size(); ++i) {
        const ObjectSpec& object = spec_.objects[i];
        const std::string context =
            spec_.path + ": objects[" + std::to_string(i) + "] (" + object.name + ")";
        const std::shared_ptr<const Volume> volume = volumes.get(object.source);
        openvdb::FloatGrid::Ptr grid = placeInWorld(*volume, object.transform, context);
        growByGridBox(*grid, objectBoxes[i].lo, objectBoxes[i].hi);
        growByGridBox(*grid, lo, hi);
        // camera.fit frames what the clips keep.
        std::vector<ClipShape> clip = spec_.clip;
        clip.insert(clip.end(), object.clip.begin(), object.clip.end());
        clipBox(clip, objectBoxes[i].lo, objectBoxes[i].hi);
        const TangentAxes tangent = worldAxes(object);
        std::shared_ptr<const VolumeMask> mask;
        if (object.mask.enabled) {
            try {
                mask = std::make_shared<const VolumeMask>(
                    placeInWorld(*volumes.get(object.mask.source), object.transform, context),
                    object.mask.iso, object.mask.invert, object.mask.labels);
            } catch (const Error& e) {
                throw Error(context + ": mask: " + e.what());
            }
        }
        if (object.kind == ObjectSpec::Kind::IsoSurface) {
            if (!surfaces_) surfaces_ = std::make_unique<SurfaceScene>();
            std::shared_ptr<const SurfaceGeometry> geometry;
            try {
                if (object.method == "mesh") {
                    geometry = std::make_shared<IsoMeshSurface>(*grid, object.iso, object.name);
                } else if (object.method == "levelset") {
                    geometry = levelSetOf(grid, object);
                } else
                    geometry = std::make_shared<IsoExactSurface>(*grid, object.iso, object.name);
            } catch (const Error& e) {
                throw Error(context + ": " + e.what());
            }
            const int id = surfaces_->add(geometry);
            if (id != int(surfaceObjects_.size())) throw Error("internal: surface IDs out of order");
            SceneSurface so;
            so.spec = &object;
            so.objectIndex = int(i);
            so.tangent = tangent;
            so.clip = clip;
            for (const ClipShape& c : clip) so.caps = so.caps || c.cap;
            so.field = grid;
            so.iso = object.iso;
            so.insideBelow = grid->getGridClass() == openvdb::GRID_LEVEL_SET;
            surfaces_->setClip(id, clip);
            if (mask) {
                so.mask = mask;
                surfaces_->setMask(id, [mask](const Vec3& x) { return mask->keeps(x); });
            }
            surfaceObjects_.push_back(std::move(so));
        } else {
            DvrSettings settings;
            settings.reconstruction = object.reconstruction == "bspline"
                                          ? Reconstruction::kCubicBSpline
                                          : Reconstruction::kTrilinear;
            settings.gradient = object.gradient == "bspline" ? GradientMethod::kBSplineDerivative
                                                             : GradientMethod::kCentralDifferences;
            settings.stepVoxels = spec_.volumeStepVoxels;
            settings.emptySpaceSkipping = spec_.emptySpaceSkipping;
            settings.preIntegrated = spec_.volumePreIntegrated;
            settings.clip = clip;
            settings.mask = mask;
            SceneVolume vo;
            vo.spec = &object;
            vo.objectIndex = int(i);
            vo.volume = std::make_unique<DvrVolume>(grid, resolvedTransfer(object, *volume),
                                                    settings, context);
            vo.tangent = tangent;
            volumeObjects_.push_back(std::move(vo));
        }
        loading.advance();
    }
    if (surfaces_) surfaces_->commit();
    loading.finish();

    // The camera and lights a scene asks to be computed from the objects' boxes (framing.h).
    resolveView(spec_, objectBoxes);
    worldBox_.lo = lo;
    worldBox_.hi = hi;
    placeView();
}

void Scene::setView(const SceneSpec& frame) {
    if (frame.objects.size() != spec_.objects.size() || frame.path != spec_.path)
        throw Error("internal: Scene::setView given another scene (" + frame.path + ")");
    SceneSpec resolved = frame;
    resolveView(resolved, objectBoxes_);
    spec_.cameraPosition = resolved.cameraPosition;
    spec_.cameraTarget = resolved.cameraTarget;
    spec_.cameraUp = resolved.cameraUp;
    spec_.fovDegrees = resolved.fovDegrees;
    spec_.crop = resolved.crop;
    spec_.lights = resolved.lights;
    spec_.fit = resolved.fit;
    spec_.zoom = resolved.zoom;
    spec_.lightRig = resolved.lightRig;
    spec_.orbitDeg = resolved.orbitDeg;
    spec_.title = resolved.title;
    spec_.outputSuffix = resolved.outputSuffix;
    spec_.group = resolved.group;
    placeView();
}

void Scene::placeView() {
    const Vec3 lo = worldBox_.lo, hi = worldBox_.hi;
    try {
        camera_ = PinholeCamera(spec_.cameraPosition, spec_.cameraTarget, spec_.cameraUp,
                                spec_.fovDegrees, double(spec_.width) / spec_.height, spec_.crop);
    } catch (const Error& e) {
        throw Error(spec_.path + ": " + e.what());
    }

    if (spec_.backdrop.enabled && spec_.background.mode == Background::Mode::Backdrop) {
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
        b.grey = spec_.backdrop.grey;
        backdrop_ = Backdrop(b, spec_.cameraPosition + forward * depth, forward, camera_.right(),
                             camera_.up(), half * 1.05);
    }
}

bool SceneSurface::inside(const Vec3& x) const {
    if (!field) return false;
    const openvdb::Vec3d u = field->transform().worldToIndex(openvdb::Vec3d(x.x, x.y, x.z));
    const double v = openvdb::tools::BoxSampler::sample(field->tree(), u);
    return (insideBelow ? v < iso : v > iso) && (!mask || mask->keeps(x));
}

Scene::~Scene() = default;

}  // namespace lobe
