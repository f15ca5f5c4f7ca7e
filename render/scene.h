// Scene assembly: a Scene is built once from a SceneSpec — volumes loaded (each file once,
// however many objects use it), object transforms applied, iso-surfaces handed to Embree (exact
// or meshed), density volumes prepared for ray marching with empty-space skipping, the backdrop
// placed behind the objects — and is then read, never changed, by the integrator
// (render/integrator.h) on every thread.
#pragma once

#include "core/camera.h"
#include "materials/material.h"
#include "render/backdrop.h"
#include "render/framing.h"
#include "render/scene_description.h"
#include "volume/reconstruction.h"
#include "volume/volume.h"
#include "volume/volume_mask.h"

#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace lobe {

class SurfaceScene;
class DvrVolume;

// An object's tangent field (the anisotropic models' direction): its axis and a second axis for
// where the first degenerates, both in world space (docs/scene-format.md, "Tangent field").
struct TangentAxes {
    Vec3 axis{0, 0, 1};
    Vec3 fallback{1, 0, 0};
};

struct SceneSurface {
    const ObjectSpec* spec = nullptr;
    int objectIndex = 0;  // in SceneSpec::objects
    TangentAxes tangent;
    // With "normals": "bspline": the grid (placed in the world) whose B-spline gradient gives the
    // shading normal (smoothIsoNormal); null: the hit's own normal.
    openvdb::FloatGrid::ConstPtr smoothGrid;
    GridGeometry smoothGeometry;
    // Clipping (core/clip.h): the scene's and the object's shapes; with caps, the field whose
    // inside (value > iso; a level-set source's value < 0) the cut faces close.
    std::vector<ClipShape> clip;
    bool caps = false;
    openvdb::FloatGrid::ConstPtr field;
    double iso = 0.0;
    bool insideBelow = false;
    std::shared_ptr<const VolumeMask> mask;  // caps only where the mask keeps the object
    // Whether the solid bounded by the surface holds world point x (the field reconstructed
    // trilinearly, as the exact iso-surface interpolates it).
    bool inside(const Vec3& x) const;
};

// The unit gradient of `grid`'s cubic B-spline at world `position`, turned to the side of
// `fallback` (the hit's own normal, which fixes the outward convention); `fallback` where the
// gradient vanishes.
Vec3 smoothIsoNormal(const openvdb::FloatGrid& grid, const GridGeometry& geometry,
                     const Vec3& position, const Vec3& fallback);

struct SceneVolume {
    const ObjectSpec* spec = nullptr;
    int objectIndex = 0;  // in SceneSpec::objects
    std::unique_ptr<DvrVolume> volume;
    TangentAxes tangent;
};

// The volumes of a batch, each distinct source (file and load settings) loaded once and shared
// by every scene that names it. Thread-safe.
class VolumeCache {
public:
    // Loads every distinct source of `specs` not yet held, the files in parallel. Returns, per
    // scene, its first error (the first failing object in scene order; "" when all loaded).
    std::vector<std::string> preload(const std::vector<const SceneSpec*>& specs);
    // The loaded volume of a source (loading it now if it is not held).
    std::shared_ptr<const Volume> get(const VolumeSourceSpec& source);
    // "FILE HASH" lines, one per distinct source of the scene in object order, HASH the
    // volume's content (volumeContentHash, computed once per source): what each shard part's
    // header carries and MPI ranks compare, so parts or ranks that read different data are
    // never joined into one image.
    std::string contentHashes(const SceneSpec& spec);

private:
    std::mutex mutex_;
    std::map<std::string, std::shared_ptr<const Volume>> volumes_;
    std::map<std::string, std::string> errors_;  // key → message, for sources that failed
    std::map<std::string, std::string> hashes_;  // key → volumeContentHash
};

// The first source whose hash differs between two contentHashes texts, compared in object order
// (the same file may sit at another path on another node), as "FILE (content hash A there, B
// here)", FILE as named here; "" when they are the same.
std::string contentHashDifference(const std::string& there, const std::string& here);

// The object's transfer function, its percentile values ("pNN", ObjectSpec::transferPercentiles)
// taken from `volume`, the object's source as loaded (divided and blurred): percentileHistogram,
// the numbers `lobe info` prints. Throws lobe::Error naming the scene file and keys when the
// placed points are out of order.
TransferFunction resolvedTransfer(const ObjectSpec& object, const Volume& volume);
// resolvedTransfer's error for any object of the scene, "" when none: for checking a batch
// before anything renders.
std::string transferError(const SceneSpec& spec, VolumeCache& cache);

class Scene {
public:
    // Loads every source (from `cache` when given) and builds the acceleration structures;
    // throws lobe::Error naming the scene file and the object for anything it cannot load.
    explicit Scene(const SceneSpec& spec, bool progress = true, VolumeCache* cache = nullptr);
    ~Scene();
    Scene(const Scene&) = delete;
    Scene& operator=(const Scene&) = delete;

    const SceneSpec& spec() const { return spec_; }
    // Turns the assembled scene to another frame of itself: `frame` must be the scene it was
    // built from with another view only (an orbit frame: render/framing.h, orbitFrames). Its
    // camera, lights, orbit angle, title and output names are resolved against the objects'
    // boxes as the constructor does, and the camera and backdrop placed anew; the surfaces and
    // volume structures are kept (a turntable assembles them once). Throws lobe::Error when the
    // frame's camera is invalid.
    void setView(const SceneSpec& frame);
    const PinholeCamera& camera() const { return camera_; }
    const Backdrop& backdrop() const { return backdrop_; }
    const SurfaceScene* surfaces() const { return surfaces_.get(); }  // null: no surface
    const std::vector<SceneSurface>& surfaceObjects() const { return surfaceObjects_; }  // by ID
    const std::vector<SceneVolume>& volumeObjects() const { return volumeObjects_; }
    // Each object's world box as its clips cut it (render/framing.h), by SceneSpec::objects.
    const std::vector<WorldBox>& objectBoxes() const { return objectBoxes_; }

private:
    // camera_ and backdrop_ from spec_'s resolved view and the objects' world box.
    void placeView();

    SceneSpec spec_;
    std::vector<WorldBox> objectBoxes_;  // each object's world box (framing.h)
    WorldBox worldBox_;                  // all objects'
    PinholeCamera camera_;
    Backdrop backdrop_;
    std::unique_ptr<SurfaceScene> surfaces_;
    std::vector<SceneSurface> surfaceObjects_;
    std::vector<SceneVolume> volumeObjects_;
};

}  // namespace lobe
