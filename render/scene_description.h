// What a scene file says, validated and with paths resolved, before anything is loaded: camera,
// lights, backdrop, objects (iso-surfaces and volumes, each with its own BRDF), image and sampling
// settings. render/scene_file.h reads it from JSON; render/render_scene.h builds it.
#pragma once

#include "core/camera.h"
#include "core/clip.h"
#include "core/light.h"
#include "materials/material.h"
#include "render/background.h"
#include "volume/transfer_function.h"
#include "volume/volume_array.h"

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace lobe {

struct LabelMap;  // volume/labels.h

// Where an object's voxels come from and how their values are mapped before use.
struct VolumeSourceSpec {
    std::string path;                              // resolved (relative to the scene file's folder)
    std::vector<std::string> morePaths;            // "path": [a, b, …]: the DICOM slices after a
    std::string series;                            // DICOM: the SeriesInstanceUID to read
    std::optional<std::array<int, 3>> dims;        // raw files only
    std::string type;                              // raw files only: uint8, int16, float32, ...
    std::string endian = "little";                 // raw files only
    std::array<double, 3> spacing{1.0, 1.0, 1.0};  // raw files only
    double divideBy = 1.0;                         // value ↦ value / divideBy (CThead: 3272)
    bool divideByMax = false;                      // "divide_by": "max": by the data's maximum
    double divideByPercentile = 0.0;  // "divide_by": "p99": by that percentile (0: none)
    double background = 0.0;          // file units: voxels ≤ this are inactive
    double blurFwhmMm = 0.0;          // Gaussian blur in world millimetres; 0: none
    // "labels": the source is a label map and the object the region whose label is in this set
    // (volume/labels.h); empty: the voxel values themselves. Checked against the map at parse
    // time (every label present, names from the table).
    std::vector<int> labels;
    double labelSmooth = 0.6;  // "label_smooth": σ of the indicator's anti-aliasing, in voxels
    std::string labelTable;    // where the names came from ("" none), for messages
    // In place of a file: an array in memory ("array": NAME, resolved by parseScene from the
    // arrays it is given — the Python module's; render/scene_file.h). path is empty then.
    std::shared_ptr<const VolumeArray> array;
    // A label source's map, loaded and indexed when the scene is read (its labels and names
    // are checked then): a file's from the per-process memo by path, an array's its own (it
    // lives as long as the scene that holds it).
    std::shared_ptr<const LabelMap> labelMap;
};

// Object-to-world map: world = linear · p + translation, p in the volume's own world space
// (index × spacing for raw files, the NIfTI affine's millimetres for NIfTI).
struct ObjectTransform {
    std::array<std::array<double, 3>, 3> linear{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
    std::array<double, 3> translation{0, 0, 0};
};

// "mask": an object exists only where another volume is inside (value > iso) or, inverted, outside
// (volume/volume_mask.h; docs/scene-format.md, "Mask").
struct MaskSpec {
    bool enabled = false;
    VolumeSourceSpec source;  // placed with the object's transform
    double iso = 0.5;
    bool invert = false;
    // A label set of a label map ("labels": [...]; source.labels holds the same ids, so the map
    // loads as one): non-empty keeps the points inside the set's surface, the 0.5 level of its
    // anti-aliased indicator (volume/labels.h; σ = source.labelSmooth), in place of `iso`.
    std::vector<int> labels;
};

struct ObjectSpec {
    enum class Kind { IsoSurface, Volume };
    std::string name;
    Kind kind = Kind::IsoSurface;
    VolumeSourceSpec source;
    ObjectTransform transform;
    Material material;
    std::string brdfModel;
    Vec3 tangentAxis{0, 0, 1};  // anisotropy direction: this object axis projected on the surface
    // What colours the specular highlight: the light's colour (true: the dichromatic reflection
    // model — the interface of a dielectric reflects all wavelengths alike, the colour of the
    // object or transfer function is its body colour and tints the Lambert term only; Shafer
    // 1985) or, as before, the object's colour (false).
    bool highlightTakesLight = true;
    // Iso-surfaces
    double iso = 0.5;
    std::string method = "exact";  // exact | mesh | levelset
    // Shading normals: "trilinear", the gradient of the method's own (trilinear) field, which
    // turns at every cell face (facets on coarse data); "bspline", the gradient of the cubic
    // B-spline of the data at the hit (continuous across cells: volume/reconstruction.h).
    std::string isoNormals = "trilinear";
    double levelSetVoxel = 0.0;      // levelset: world voxel size of the rebuild; 0: the source's
    double levelSetHalfWidth = 3.0;  // levelset: band half width in voxels
    int levelSetSmooth = 0;          // levelset: iterations of mean-curvature flow
    double opacity = 1.0;
    Spectrum color{1.0};  // surface colour multiplying the reflected light
    // Volumes
    TransferFunction transfer;  // from explicit points or one of the paper's presets
    // Transfer-function values given as percentiles of the volume's values ("value": "p95", a
    // preset's "boundary": "p99"). The file alone cannot place them: `transferPoints` holds the
    // control points with each such value as its offset from the percentile, and scene assembly
    // (render/scene.cpp) adds the percentile of the loaded volume and builds `transfer`.
    struct TfPercentile {
        double percent = 0.0;             // 0 < percent <= 100
        std::vector<std::size_t> points;  // the control points it places
        std::string key;                  // "scene.json: objects[0].transfer_function.boundary"
    };
    std::vector<TfPercentile> transferPercentiles;
    std::vector<TfPoint> transferPoints;       // only with transferPercentiles
    std::string transferName;                  // "scene.json: objects[0].transfer_function"
    std::string reconstruction = "trilinear";  // trilinear | bspline | nearest
    std::string gradient = "central";          // central | bspline
    // An object expanded from a "kind": "segmentation" entry: that entry's key path ("" else).
    std::string segmentation;
    // Clip shapes of this object (core/clip.h), on top of the scene's.
    std::vector<ClipShape> clip;
    // Whether the object shadows the lights when SceneSpec::shadows is on.
    bool castsShadows = true;
    MaskSpec mask;
};

struct BackdropSpec {
    bool enabled = true;
    uint64_t seed = 7;
    double ambient = 0.2;
    double diffuse = 0.3;
    int cells = 24;     // random colour cells across the backdrop before blurring
    double blur = 1.5;  // Gaussian blur, in cells
    bool grey = false;  // cells of random lightness but no hue (no tint through glass)
};

// A camera fitted to the objects at scene assembly (render/framing.h): from a named view or an
// azimuth/elevation in world axes (RAS for NIfTI data), at the distance where the objects' box
// fills 1/margin of the frame.
struct CameraFitSpec {
    bool enabled = false;
    std::string view;           // anterior, posterior, left, right, superior, inferior; "": angles
    double azimuthDeg = 0.0;    // from +y (anterior) towards +x (right)
    double elevationDeg = 0.0;  // towards +z (superior)
    bool upGiven = false;       // camera.up given: it wins over the view's own up
    std::vector<std::string> objects;  // names of the objects to fit; empty: all
    double margin = 1.1;
    std::string method = "box";  // box (its 8 corners projected) | sphere (around the box)
};

// A close-up of a world point or box: the crop window of the (fitted or given) view around it.
struct ZoomSpec {
    enum class Kind { None, Point, Box };
    Kind kind = Kind::None;
    Vec3 center{0.0};
    double size = 0.0;  // Point: world units across the crop's shorter side at the point's depth
    Vec3 lo{0.0}, hi{0.0};  // Box
    double margin = 1.1;    // Box: the box's projection fills 1/margin of the crop
    // Box from objects: the world box of these objects (a label object's is its labels' own),
    // set at scene assembly (render/framing.cpp, resolveView).
    std::vector<std::string> objects;
};

// Lights placed relative to the camera at scene assembly (render/framing.h).
struct LightRigSpec {
    std::string rig;               // "": the scene's own lights; headlight | paper
    Spectrum irradiance{1.0};      // each light's irradiance at the target, on a plane facing it
    double angleDeg = 0.0;         // paper: off-axis angle of the lights seen from the target; 0:
                                   // towards the corners of the view at the target's depth
    double behind = 50.0 / 560.0;  // paper: distance behind the camera / camera-target distance
};

struct SceneSpec {
    std::string path;   // the scene file
    std::string title;  // caption for contact sheets (default: the file's name)
    std::string group;  // contact sheets collect the scenes of one group
    int width = 1024;
    int height = 1024;
    int samplesPerPixel = 8;
    uint64_t seed = 1;
    double exposure = 1.0;
    // The display transform of PNG/JPEG output (the EXR stays linear): "clip" at 1, or
    // "shoulder", linear up to a knee and then rolling off towards white (core/rgb_image.h).
    std::string tone = "clip";
    Vec3 cameraPosition{0, 0, 4};
    Vec3 cameraTarget{0, 0, 0};
    Vec3 cameraUp{0, 1, 0};
    double fovDegrees = 30.0;
    CropWindow crop;
    CameraFitSpec fit;
    ZoomSpec zoom;
    // Turntable: the camera (and every light with it) turned by this angle about the axis along
    // cameraUp through the objects' centre, after fitting (`lobe render --orbit N`).
    double orbitDeg = 0.0;
    std::string outputSuffix;  // appended to the output file name (orbit frames: "-orbit-003")
    std::vector<PointLight> lights;
    LightRigSpec lightRig;
    BackdropSpec backdrop;
    Background background;  // backdrop (default), none or a colour: render/background.h
    double volumeStepVoxels = 0.05;
    double terminationTransmittance = 1e-3;
    // Volume samples whose weight in the pixel (transmittance × opacity) is below this are
    // shaded by Russian roulette (render_scene.cpp): unbiased, less work, a little noise. 0: off.
    double shadingRoulette = 0.03;
    bool emptySpaceSkipping = true;  // volume_marcher.h; off only to time it (same image)
    // Volume segments classified by pre-integration (volume/pre_integration.h): the same
    // accuracy at several times the step on narrow transfer functions.
    bool volumePreIntegrated = false;
    // Clip shapes of every object (core/clip.h; docs/scene-format.md, "Clip").
    std::vector<ClipShape> clip;
    // Shadows (render/integrator.h, "Shadows"): "off", "exact" (a shadow ray per light from
    // every shaded point) or "cached" (shaded points read a per-light transmittance cache of
    // nodes shadowCacheVoxels voxels apart).
    std::string shadows = "off";
    double shadowCacheVoxels = 4.0;
    double shadowCacheStepVoxels = 0.5;  // the node rays' step (the scene's if that is coarser)
    // "cached": surface hits read the surfaces' shadows from the cache too (true, "surfaces":
    // "cached") or cast exact shadow rays through the surfaces (false, "exact": sharp).
    bool shadowCacheSurfaces = true;
    std::vector<ObjectSpec> objects;
    // He–Torrance materials read a table of their parameters instead of summing the series
    // (materials/he_torrance_table.h, render/scene.cpp): the fine table (within 0.5 %) in full
    // renders, the preview table (within 2 %) with `--preview` (previewBrdfTables), the series
    // itself with `--exact-brdf` (exactBrdf; the reference). Not scene keys.
    bool previewBrdfTables = false;
    bool exactBrdf = false;
};

}  // namespace lobe
