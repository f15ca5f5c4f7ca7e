// Camera and lights without arithmetic: what a scene's "camera": {"fit": …, "zoom": …} and
// "lights": {"rig": …} ask for (docs/scene-format.md, "Framing"), turned into the plain position,
// target, up, crop and point lights the renderer uses. It runs at scene assembly
// (render/scene.cpp), where the objects' world boxes are known, and `lobe render` prints its result
// so a user can freeze it into the scene.
//
// Conventions (world axes, which for NIfTI data are RAS: +x right, +y anterior, +z superior):
// - A named view names the side the camera looks *from*: "anterior" puts the camera on +y looking
//   towards −y, so it sees the face; "left" puts it on −x. Up is +z for the four side views and
//   +y (anterior at the top of the image) for "superior" and "inferior".
// - azimuth/elevation give the direction from the target to the camera: azimuth 0° anterior,
//   90° right, 180° posterior, −90° left; elevation +90° superior. Up is +z, or +y rotated by
//   the azimuth, (sin az, cos az, 0), at elevation ±90°.
// - margin m: the objects' projection spans at most 1/m of the image's width and height, in the
//   image plane (so the fitted tangent of the half angle is tan(fov/2)/m).
// - A light's irradiance at the target is I/d² on a plane facing the light (no cosine): the
//   convention of core/light.h's point lights (I · cos θ / d², θ = 0).
#pragma once

#include "core/camera.h"
#include "core/light.h"
#include "render/scene_description.h"

#include <limits>
#include <string>
#include <vector>

namespace lobe {

struct WorldBox {
    Vec3 lo{std::numeric_limits<double>::infinity()};
    Vec3 hi{-std::numeric_limits<double>::infinity()};
    bool empty() const { return !(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z); }
    void grow(const Vec3& p);
    void grow(const WorldBox& b);
    Vec3 center() const { return (lo + hi) * 0.5; }
};

// The direction from the target to the camera and the up vector of a named view ("" for
// azimuth/elevation). Throws lobe::Error for an unknown name.
struct ViewDirection {
    Vec3 toCamera;
    Vec3 up;
};
ViewDirection viewDirection(const std::string& view, double azimuthDeg, double elevationDeg);

// The camera looking along −toCamera at the box's centre from the distance where the box fits:
// "box" keeps its 8 projected corners within 1/margin of the frame (vertical fov `vfovDeg`,
// aspect width/height), "sphere" the sphere through the box's corners.
struct FittedCamera {
    Vec3 position, target, up;
    double distance = 0.0;
};
FittedCamera fitCamera(const WorldBox& box, const ViewDirection& dir, double vfovDeg, double aspect,
                       double margin, const std::string& method);

// The crop window (of the camera's full view) around a world point or box, with equal normalised
// extents in x and y, which is what keeps the image's aspect (cropAspectMismatch). Throws
// lobe::Error when the point or box is behind the camera or does not fit in the view.
CropWindow zoomCrop(const ZoomSpec& zoom, const Vec3& position, const Vec3& target, const Vec3& up,
                    double vfovDeg, double aspect);

// How far a crop's normalised width and height differ, (x1−x0)/(y1−y0): the factor the image
// would be stretched horizontally. A crop of the full view keeps the image's aspect iff it is 1.
double cropStretch(const CropWindow& crop);

// The lights of a rig for a camera at `position` looking at `target`:
// - headlight: one light at the camera;
// - paper: four lights `behind`·D behind the camera (D = camera–target distance), towards the
//   four corners of the view at the target's depth (Koldenhof 2003: "four omni lights … all behind
//   the camera in each corner"; scripts/make_paper_scenes.py places them so), or at `angleDeg`
//   off the view axis as seen from the target, along the view's diagonals.
// Each light's intensity gives the rig's irradiance at the target: I = irradiance · d².
std::vector<PointLight> lightRig(const LightRigSpec& rig, const Vec3& position, const Vec3& target,
                                 const Vec3& up, double vfovDeg, double aspect);

// Turns a point about the axis through `centre` along `axis` (unit) by `degrees`, right-handed.
Vec3 rotateAbout(const Vec3& p, const Vec3& centre, const Vec3& axis, double degrees);

// Everything above applied to a parsed scene, in order: fit the camera to the named objects'
// boxes (objectBoxes[i] is objects[i]'s world box), turn camera and lights by orbitDeg about the
// up axis through the objects' centre, zoom, place the rig's lights. A scene with none of these
// is left as it is. Errors name the scene file and key.
void resolveView(SceneSpec& spec, const std::vector<WorldBox>& objectBoxes);

// A turntable of n frames (`lobe render --orbit N`): copies of the scene with orbitDeg = 360°·k/n,
// output names NAME-orbit-000 … and titles with the angle, grouped into one contact sheet
// (group NAME-orbit). n ≤ 0: the scene itself.
std::vector<SceneSpec> orbitFrames(const SceneSpec& spec, int n);

class VolumeCache;  // render/scene.h

// The world box of each object's active voxels (centres ± half a voxel, after its transform), as
// scene assembly computes it, the volumes taken from (or loaded into) `cache`. In render/scene.cpp.
std::vector<WorldBox> objectWorldBoxes(const SceneSpec& spec, VolumeCache& cache);

// What scene assembly would find wrong with the scene's computed view (a fit to objects with no
// active voxel, a zoom outside the view, …), as its error message; "" when nothing. For checking
// a batch before anything renders. In render/scene.cpp.
std::string computedViewError(const SceneSpec& spec, VolumeCache& cache);

// True when resolveView computed anything a user may want to freeze into the scene.
bool hasComputedView(const SceneSpec& spec);

// The camera and lights of a resolved scene as scene-file JSON ("camera": {…}, "lights": […]).
std::string frozenViewJson(const SceneSpec& spec);

}  // namespace lobe
