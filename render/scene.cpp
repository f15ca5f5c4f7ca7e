#include "render/scene.h"

#include "core/error.h"
#include "core/memory.h"
#include "core/progress.h"
#include "materials/he_torrance_table.h"
#include "render/framing.h"
#include "surface/iso_exact.h"
#include "surface/iso_levelset.h"
#include "surface/iso_mesh.h"
#include "surface/surface_scene.h"
#include "volume/gaussian_blur.h"
#include "volume/grid_world.h"
#include "volume/labels.h"
#include "volume/volume.h"
#include "volume/volume_marcher.h"

#include <openvdb/tools/Interpolation.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <mutex>
#include <optional>
#include <sstream>

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

bool isLabelSource(const VolumeSourceSpec& s) { return !s.labels.empty(); }

// A label source's map: the one the parser loaded (an array's lives only there), else the file's
// from the per-process memo.
std::shared_ptr<const LabelMap> labelMapOf(const VolumeSourceSpec& s) {
    return s.labelMap ? s.labelMap : loadLabelMap(s.path);
}

// Everything a loaded volume depends on. A label map is the file alone (loaded once per process,
// volume/labels.h): every label object of it shares one entry.
std::string sourceKey(const VolumeSourceSpec& s) {
    if (isLabelSource(s)) return "labels|" + (s.array ? "array:" + s.array->name : s.path);
    char numbers[256];
    std::snprintf(numbers, sizeof numbers, "|%d|%.17g|%.17g|%.17g|%.17g|%.17g|%.17g|%.17g",
                  int(s.divideByMax), s.divideByPercentile, s.divideBy, s.background, s.blurFwhmMm,
                  s.spacing[0], s.spacing[1], s.spacing[2]);
    std::string key = (s.array ? "array:" + s.array->name : s.path) + numbers + "|" + s.type + "|" +
                      s.endian + "|" + s.series;
    for (const std::string& p : s.morePaths) key += "|" + p;
    if (s.dims)
        for (int d : *s.dims) key += "|" + std::to_string(d);
    return key;
}

std::shared_ptr<const Volume> loadShared(const VolumeSourceSpec& s);

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
    Volume v = s.array ? loadArray(*s.array, options) : loadVolume(paths, options);
    if (s.blurFwhmMm > 0.0) gaussianBlurFwhm(v, s.blurFwhmMm);
    return v;
}

std::shared_ptr<const Volume> loadShared(const VolumeSourceSpec& s) {
    if (isLabelSource(s)) return labelMapOf(s)->volume;
    return std::make_shared<const Volume>(loadSource(s));
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
            loaded[i] = loadShared(*missing[i]);
        } catch (const std::bad_alloc&) {
            failed[i] = missing[i]->path + ": " + outOfMemoryText();
        } catch (const std::exception& e) {
            failed[i] = e.what();
        }
    });
    std::lock_guard<std::mutex> lock(mutex_);
    for (size_t i = 0; i < missing.size(); ++i) {
        if (loaded[i])
            volumes_[missingKeys[i]] = loaded[i];
        else
            errors_[missingKeys[i]] = failed[i];
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
    auto volume = loadShared(source);
    std::lock_guard<std::mutex> lock(mutex_);
    return volumes_.emplace(key, volume).first->second;
}

std::string VolumeCache::contentHashes(const SceneSpec& spec) {
    std::string text;
    std::vector<std::string> seen;
    for (const ObjectSpec& object : spec.objects) {
        const std::string key = sourceKey(object.source);
        if (std::find(seen.begin(), seen.end(), key) != seen.end()) continue;
        seen.push_back(key);
        std::string hash;
        {
            std::lock_guard<std::mutex> lock(mutex_);
            const auto it = hashes_.find(key);
            if (it != hashes_.end()) hash = it->second;
        }
        if (hash.empty()) {
            hash = volumeContentHash(*get(object.source));
            std::lock_guard<std::mutex> lock(mutex_);
            hashes_[key] = hash;
        }
        std::string file = object.source.path;
        for (const std::string& p : object.source.morePaths) file += "," + p;
        text += file + " " + hash + "\n";
    }
    return text;
}

std::string contentHashDifference(const std::string& there, const std::string& here) {
    if (there == here) return "";
    // Line by line, in object order: the files may sit at other paths there (node-local copies).
    const auto lines = [](const std::string& t) {
        std::vector<std::pair<std::string, std::string>> out;  // file, hash
        std::istringstream in(t);
        for (std::string line; std::getline(in, line);) {
            const size_t space = line.rfind(' ');
            if (space != std::string::npos)
                out.emplace_back(line.substr(0, space), line.substr(space + 1));
        }
        return out;
    };
    const auto a = lines(there), b = lines(here);
    for (size_t k = 0; k < std::min(a.size(), b.size()); ++k)
        if (a[k].second != b[k].second)
            return b[k].first + " (content hash " + a[k].second + " there, " + b[k].second +
                   " here)";
    if (a.size() == b.size()) return "";  // the same data under other paths
    return "the volumes: " + std::to_string(a.size()) + " there, " + std::to_string(b.size()) +
           " here";
}

namespace {

// A shallow copy of the volume's grid (same voxels) whose transform is followed by the object's
// transform, so the grid maps index → scene world directly.
openvdb::FloatGrid::Ptr placeInWorld(const openvdb::FloatGrid::Ptr& source,
                                     const ObjectTransform& t, const std::string& context) {
    if (!source->transform().isLinear())
        throw Error(context + ": the volume's transform is not affine");
    // OpenVDB multiplies row vectors (world = index · M): the object map in that form.
    openvdb::math::Mat4d object = openvdb::math::Mat4d::identity();
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) object[r][c] = t.linear[c][r];
    for (int c = 0; c < 3; ++c) object[3][c] = t.translation[c];
    // The volume's full map (its world scale included) followed by the object's. The scene's
    // check of the transform is relative (core/math.h, nearlySingular): a scale of 1e-5 on 1 mm
    // voxels is a map OpenVDB refuses (det < 3e-15), given to the grid rescaled
    // (volume/grid_world.h).
    const openvdb::math::Mat4d total = gridWorldMatrix(*source) * object;
    openvdb::FloatGrid::Ptr grid = source->copy();  // shares the tree
    try {
        setGridWorldMap(*grid, total);
    } catch (const openvdb::Exception& e) {
        throw Error(context + ": the transform's map is not usable (" + e.what() + ")");
    }
    return grid;
}

openvdb::FloatGrid::Ptr placeInWorld(const Volume& volume, const ObjectTransform& t,
                                     const std::string& context) {
    return placeInWorld(volume.grid, t, context);
}

// The grid an object is made of, in scene world: its volume's; for a label object (source.labels,
// volume/labels.h) the anti-aliased indicator of its labels (iso-surfaces, surfaced at 0.5) or
// their mask (volumes), built now from the one loaded map.
openvdb::FloatGrid::Ptr objectGrid(const ObjectSpec& object, const Volume& volume,
                                   const std::string& context) {
    if (object.source.labels.empty()) return placeInWorld(volume, object.transform, context);
    const std::shared_ptr<const LabelMap> map = labelMapOf(object.source);
    const openvdb::FloatGrid::Ptr grid =
        object.kind == ObjectSpec::Kind::IsoSurface
            ? labelSurfaceField(*map, object.source.labels, object.source.labelSmooth)
            : labelMask(*map, object.source.labels);
    return placeInWorld(grid, object.transform, context);
}

// World bounding box of an index box of voxels (their centres ± half a voxel).
void growByIndexBox(const openvdb::GridBase& grid, const openvdb::CoordBBox& box, Vec3& lo,
                    Vec3& hi) {
    if (box.empty()) return;
    for (int corner = 0; corner < 8; ++corner) {
        const openvdb::Vec3d idx((corner & 1) ? box.max().x() + 0.5 : box.min().x() - 0.5,
                                 (corner & 2) ? box.max().y() + 0.5 : box.min().y() - 0.5,
                                 (corner & 4) ? box.max().z() + 0.5 : box.min().z() - 0.5);
        const openvdb::Vec3d w = gridIndexToWorld(grid, idx);
        lo = Vec3(std::min(lo.x, w.x()), std::min(lo.y, w.y()), std::min(lo.z, w.z()));
        hi = Vec3(std::max(hi.x, w.x()), std::max(hi.y, w.y()), std::max(hi.z, w.z()));
    }
}

// World bounding box of a grid's active voxels.
void growByGridBox(const openvdb::FloatGrid& grid, Vec3& lo, Vec3& hi) {
    growByIndexBox(grid, grid.evalActiveVoxelBoundingBox(), lo, hi);
}

// An object's world box (framing.h): its active voxels', or for a label object its labels' voxels'.
void growByObjectBox(const ObjectSpec& object, const openvdb::FloatGrid& placed, Vec3& lo,
                     Vec3& hi) {
    if (object.source.labels.empty()) return growByGridBox(placed, lo, hi);
    growByIndexBox(placed, labelMapOf(object.source)->boxOf(object.source.labels), lo, hi);
}

}  // namespace

Vec3 smoothIsoNormal(const openvdb::FloatGrid& grid, const GridGeometry& geometry,
                     const Vec3& position, const Vec3& fallback) {
    GridReconstructor reconstructor(grid);
    Vec3 g;
    reconstructor.bsplineWithGradient(geometry.worldToIndex(position), g);
    Vec3 n = geometry.gradientToWorld(g);
    const double length = n.length();
    if (!(length > 0.0) || !std::isfinite(length)) return fallback;
    n = n * (1.0 / length);
    return n.dot(fallback) < 0.0 ? -n : n;
}

namespace {

// The "levelset" method: a level-set source (grid class GRID_LEVEL_SET, e.g. a .vdb from
// vdb_tool or Houdini) as it is, its zero crossing the surface; any other grid rebuilt as one.
std::shared_ptr<const SurfaceGeometry> levelSetOf(const openvdb::FloatGrid::Ptr& grid,
                                                  const ObjectSpec& object) {
    if (grid->getGridClass() == openvdb::GRID_LEVEL_SET) {
        if (object.iso != 0.0)
            throw Error(
                "the source is a level set, whose surface is its zero crossing: set \"iso\": 0");
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
        throw Error(std::string(e.what()) + " (percentiles of the volume's values: " + resolved +
                    ")");
    }
}

std::string transferError(const SceneSpec& spec, VolumeCache& cache) {
    try {
        for (const ObjectSpec& object : spec.objects)
            if (!object.transferPercentiles.empty())
                resolvedTransfer(object, *cache.get(object.source));
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
        growByObjectBox(object, *grid, boxes[i].lo, boxes[i].hi);
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

// He–Torrance tables (SceneSpec::exactBrdf, previewBrdfTables): each He–Torrance material reads a
// table of its parameters (materials/he_torrance_table.h; within its stated error bound, or the
// series where the table refuses) — the preview table under `--preview`, the fine one otherwise,
// none with exactBrdf. Tables are shared by equal parameter sets within the process (a batch's
// scenes build each once).
static void attachHeTorranceTables(SceneSpec& spec) {
    if (spec.exactBrdf) return;
    const HeTorranceTable::Resolution& res =
        spec.previewBrdfTables ? HeTorranceTable::kPreview : HeTorranceTable::kFine;
    struct Built {
        HeTorrance model;
        bool preview;
        std::shared_ptr<const HeTorranceTable> table;
    };
    static std::mutex mutex;
    static std::vector<Built> built;
    std::lock_guard<std::mutex> lock(mutex);
    for (ObjectSpec& object : spec.objects) {
        auto* model = std::get_if<HeTorrance>(&object.material.specular);
        if (!model) continue;
        const auto same = [&](const Built& b) {
            const HeTorrance& m = b.model;
            return b.preview == spec.previewBrdfTables && m.ks == model->ks &&
                   m.sigma0 == model->sigma0 && m.tau == model->tau && m.eta == model->eta &&
                   m.kappa == model->kappa;
        };
        auto it = std::find_if(built.begin(), built.end(), same);
        if (it == built.end()) {
            // At most kKeep tables stay (~4 MB each): a sweep over parameters does not pile
            // them up.
            constexpr size_t kKeep = 16;
            if (built.size() >= kKeep) built.erase(built.begin());
            HeTorrance series = *model;
            series.table = nullptr;
            built.push_back({series, spec.previewBrdfTables, HeTorranceTable::build(series, res)});
            it = built.end() - 1;
        }
        model->table = it->table;
    }
}

Scene::Scene(const SceneSpec& spec, bool progress, VolumeCache* cache) : spec_(spec) {
    openvdb::initialize();
    attachHeTorranceTables(spec_);
    ProgressReporter loading("load " + spec_.title, int64_t(spec_.objects.size()), progress);
    VolumeCache own;
    VolumeCache& volumes = cache ? *cache : own;
    const std::string error = volumes.preload({&spec_}).front();
    if (!error.empty()) throw Error(error);
    Vec3 lo(kInf), hi(-kInf);
    std::vector<WorldBox>& objectBoxes = objectBoxes_;  // for camera.fit (framing.h)
    objectBoxes.assign(spec_.objects.size(), WorldBox());
    const auto contextOf = [&](size_t i) {
        return spec_.path + ": objects[" + std::to_string(i) + "] (" + spec_.objects[i].name + ")";
    };
    // The surfaces first, built in parallel (a segmentation's labels are many small, independent
    // surfaces); each is deterministic, and they are added below in object order.
    std::vector<std::shared_ptr<const SurfaceGeometry>> geometries(spec_.objects.size());
    std::vector<openvdb::FloatGrid::Ptr> grids(spec_.objects.size());  // for smooth normals
    std::vector<std::string> failures(spec_.objects.size());
    tbb::parallel_for(size_t(0), spec_.objects.size(), [&](size_t i) {
        const ObjectSpec& object = spec_.objects[i];
        if (object.kind != ObjectSpec::Kind::IsoSurface) return;
        try {
            const openvdb::FloatGrid::Ptr grid =
                objectGrid(object, *volumes.get(object.source), contextOf(i));
            grids[i] = grid;
            if (object.method == "mesh") {
                geometries[i] = std::make_shared<IsoMeshSurface>(*grid, object.iso, object.name);
            } else if (object.method == "levelset") {
                geometries[i] = levelSetOf(grid, object);
            } else
                geometries[i] = std::make_shared<IsoExactSurface>(*grid, object.iso, object.name);
        } catch (const std::exception& e) {
            failures[i] = contextOf(i) + ": " + e.what();
        }
    });
    for (const std::string& failure : failures)
        if (!failure.empty()) throw Error(failure);
    for (size_t i = 0; i < spec_.objects.size(); ++i) {
        const ObjectSpec& object = spec_.objects[i];
        const std::string context = contextOf(i);
        const std::shared_ptr<const Volume> volume = volumes.get(object.source);
        // camera.fit frames what the clips keep.
        std::vector<ClipShape> clip = spec_.clip;
        clip.insert(clip.end(), object.clip.begin(), object.clip.end());
        const TangentAxes tangent = worldAxes(object);
        std::shared_ptr<const VolumeMask> mask;
        if (object.mask.enabled) {
            try {
                // A label set's mask is its anti-aliased indicator's 0.5 level, the surface a
                // segmentation draws for the same labels (volume/labels.h).
                const MaskSpec& m = object.mask;
                mask = std::make_shared<const VolumeMask>(
                    m.labels.empty()
                        ? placeInWorld(*volumes.get(m.source), object.transform, context)
                        : placeInWorld(labelSurfaceField(*loadLabelMap(m.source.path), m.labels,
                                                         m.source.labelSmooth),
                                       object.transform, context),
                    m.labels.empty() ? m.iso : 0.5, m.invert);
            } catch (const Error& e) {
                throw Error(context + ": mask: " + e.what());
            }
        }
        if (object.kind == ObjectSpec::Kind::IsoSurface) {
            const openvdb::FloatGrid::Ptr placed = placeInWorld(*volume, object.transform, context);
            growByObjectBox(object, *placed, objectBoxes[i].lo, objectBoxes[i].hi);
            growByObjectBox(object, *placed, lo, hi);
            clipBox(clip, objectBoxes[i].lo, objectBoxes[i].hi);
            if (!surfaces_) surfaces_ = std::make_unique<SurfaceScene>();
            const int id = surfaces_->add(geometries[i]);
            if (id != int(surfaceObjects_.size()))
                throw Error("internal: surface IDs out of order");
            SceneSurface so;
            so.spec = &object;
            so.objectIndex = int(i);
            so.tangent = tangent;
            if (object.isoNormals == "bspline") {
                so.smoothGrid = grids[i];
                so.smoothGeometry = GridGeometry(*grids[i], context);
            }
            so.clip = clip;
            for (const ClipShape& c : clip) so.caps = so.caps || c.cap;
            so.field = grids[i];  // the surface's own field (a label's indicator for labels)
            so.iso = object.iso;
            so.insideBelow = grids[i]->getGridClass() == openvdb::GRID_LEVEL_SET;
            surfaces_->setClip(id, clip);
            if (mask) {
                so.mask = mask;
                surfaces_->setMask(id, [mask](const Vec3& x) { return mask->keeps(x); });
            }
            surfaceObjects_.push_back(std::move(so));
        } else {
            openvdb::FloatGrid::Ptr grid = objectGrid(object, *volume, context);
            growByObjectBox(object, *grid, objectBoxes[i].lo, objectBoxes[i].hi);
            growByObjectBox(object, *grid, lo, hi);
            clipBox(clip, objectBoxes[i].lo, objectBoxes[i].hi);
            DvrSettings settings;
            settings.reconstruction =
                object.reconstruction == "bspline"   ? Reconstruction::kCubicBSpline
                : object.reconstruction == "nearest" ? Reconstruction::kNearest
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
    const openvdb::Vec3d u = gridWorldToIndex(*field, openvdb::Vec3d(x.x, x.y, x.z));
    const double v = openvdb::tools::BoxSampler::sample(field->tree(), u);
    return (insideBelow ? v < iso : v > iso) && (!mask || mask->keeps(x));
}

Scene::~Scene() = default;

}  // namespace lobe
