// Camera and lights without arithmetic (render/framing.h) against hand-computed cases: fitted
// distances of boxes and their bounding spheres, named views in RAS, the paper rig's irradiance 1
// at the target (I/d² on a plane facing the light), close-up crops of world points and boxes, the
// crop-aspect error, turntable frames as rotations of frame 0, and one scene fitted end to end
// from a loaded volume's world box.
#include "core/error.h"
#include "render/framing.h"
#include "render/render_scene.h"
#include "render/scene_file.h"
#include "scene_text.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>

namespace lobe {
namespace {

namespace fs = std::filesystem;

void expectNear(const Vec3& a, const Vec3& b, double tol = 1e-9) {
    EXPECT_NEAR(a.x, b.x, tol) << "x";
    EXPECT_NEAR(a.y, b.y, tol) << "y";
    EXPECT_NEAR(a.z, b.z, tol) << "z";
}

WorldBox cube(const Vec3& c, double r) { return WorldBox{c - Vec3(r), c + Vec3(r)}; }

const std::string& kBase = test::kSceneBase;
using test::errorOf;

// A scene whose source exists (the parser checks existence only) with the given camera and lights.
std::string sceneWith(const std::string& camera, const std::string& lights = "[]") {
    return R"({"image": {"width": 64, "height": 64}, "camera": )" + camera + R"(, "lights": )" +
           lights + R"(, "objects": [{"name": "a", "kind": "isosurface", "iso": 0.5,
             "source": {"path": "test_framing.cpp"}, "brdf": {"model": "lambert"}}]})";
}

}  // namespace

// RAS: "anterior" is the side the camera looks from (+y), so it sees the face; up is superior.
TEST(Framing, NamedViewsAreSidesOfTheHeadInRas) {
    expectNear(viewDirection("anterior", 0, 0).toCamera, Vec3(0, 1, 0));
    expectNear(viewDirection("posterior", 0, 0).toCamera, Vec3(0, -1, 0));
    expectNear(viewDirection("right", 0, 0).toCamera, Vec3(1, 0, 0));
    expectNear(viewDirection("left", 0, 0).toCamera, Vec3(-1, 0, 0));
    expectNear(viewDirection("superior", 0, 0).toCamera, Vec3(0, 0, 1));
    expectNear(viewDirection("inferior", 0, 0).toCamera, Vec3(0, 0, -1));
    expectNear(viewDirection("anterior", 0, 0).up, Vec3(0, 0, 1));
    expectNear(viewDirection("superior", 0, 0).up, Vec3(0, 1, 0));
    // Azimuth from anterior towards right, elevation towards superior.
    expectNear(viewDirection("", 90, 0).toCamera, Vec3(1, 0, 0));
    expectNear(viewDirection("", -90, 0).toCamera, Vec3(-1, 0, 0));
    expectNear(viewDirection("", 180, 0).toCamera, Vec3(0, -1, 0), 1e-12);
    expectNear(viewDirection("", 45, 30).toCamera,
               Vec3(std::cos(kPi / 6) * std::sqrt(0.5), std::cos(kPi / 6) * std::sqrt(0.5), 0.5));
    expectNear(viewDirection("", 90, 90).up, Vec3(1, 0, 0));
    EXPECT_THROW(viewDirection("frontal", 0, 0), Error);
}

// The sphere through a cube's corners (radius ρ = r√3) seen with fov 60°, margin 1: the cone of
// half angle 30° touches it at ρ / sin 30° = 2ρ. With margin m the half angle is atan(tan 30°/m).
TEST(Framing, SphereFitSitsAtRadiusOverSineOfHalfFov) {
    const Vec3 c(10, 20, 30);
    const double r = 5.0, rho = r * std::sqrt(3.0);
    const FittedCamera a =
        fitCamera(cube(c, r), viewDirection("anterior", 0, 0), 60.0, 1.0, 1.0, "sphere");
    EXPECT_NEAR(a.distance, 2.0 * rho, 1e-9);
    expectNear(a.position, c + Vec3(0, 2.0 * rho, 0));
    expectNear(a.target, c);
    const double alpha = std::atan(std::tan(radians(30.0)) / 1.25);
    const FittedCamera m =
        fitCamera(cube(c, r), viewDirection("left", 0, 0), 60.0, 1.0, 1.25, "sphere");
    EXPECT_NEAR(m.distance, rho / std::sin(alpha), 1e-9);
    expectNear(m.position, c - Vec3(rho / std::sin(alpha), 0, 0));
    // A wide image: the vertical field is the narrower one and decides.
    EXPECT_NEAR(
        fitCamera(cube(c, r), viewDirection("anterior", 0, 0), 60.0, 2.0, 1.0, "sphere").distance,
        2.0 * rho, 1e-9);
}

// The box's 8 corners: with fov 90° (tan 45° = 1) the nearest face's corners (depth d − r,
// offset r) touch the frame's edge at d = r + r.
TEST(Framing, BoxFitPutsTheNearestCornersOnTheFrameEdge) {
    const Vec3 c(1, 2, 3);
    const double r = 2.0;
    EXPECT_NEAR(
        fitCamera(cube(c, r), viewDirection("anterior", 0, 0), 90.0, 1.0, 1.0, "box").distance,
        2.0 * r, 1e-12);
    // Margin 2: the box spans half the frame, tan = 1/2, d = r/0.5 + r.
    EXPECT_NEAR(
        fitCamera(cube(c, r), viewDirection("anterior", 0, 0), 90.0, 1.0, 2.0, "box").distance,
        3.0 * r, 1e-12);
    // Half extents (1, 2, 3) from the left: image right is −y (extent 2), image up +z (extent 3),
    // the nearest corners 1 in front of the centre: d = max(2/1 + 1, 3/1 + 1) = 4.
    const WorldBox b{c - Vec3(1, 2, 3), c + Vec3(1, 2, 3)};
    const FittedCamera left = fitCamera(b, viewDirection("left", 0, 0), 90.0, 1.0, 1.0, "box");
    EXPECT_NEAR(left.distance, 4.0, 1e-12);
    expectNear(left.position, c + Vec3(-4, 0, 0));
    // Twice as wide as high: the horizontal field (tan = 2) no longer binds, still 4.
    EXPECT_NEAR(fitCamera(b, viewDirection("left", 0, 0), 90.0, 2.0, 1.0, "box").distance, 4.0,
                1e-12);
    // From above (superior, up anterior): image right +x (1), up +y (2), nearest 3 above: 2 + 3.
    EXPECT_NEAR(fitCamera(b, viewDirection("superior", 0, 0), 90.0, 1.0, 1.0, "box").distance, 5.0,
                1e-12);
    EXPECT_THROW(fitCamera(WorldBox{}, viewDirection("left", 0, 0), 30, 1, 1, "box"), Error);
    EXPECT_THROW(fitCamera(WorldBox{c, c}, viewDirection("left", 0, 0), 30, 1, 1, "box"), Error);
}

// Camera at (0, 0, 10) looking down −z with up +y, fov 90°: the point (x, y, 0) is at
// u = (1 + x/10)/2, v = (1 − y/10)/2, and a close-up `size` wide spans size/20 of the view.
TEST(Framing, ZoomOnAWorldPointOrBoxIsASquareCrop) {
    const Vec3 eye(0, 0, 10), at(0, 0, 0), up(0, 1, 0);
    ZoomSpec z;
    z.kind = ZoomSpec::Kind::Point;
    z.center = Vec3(5, 5, 0);
    z.size = 4.0;
    CropWindow c = zoomCrop(z, eye, at, up, 90.0, 1.0);
    EXPECT_NEAR(c.x0, 0.75 - 0.1, 1e-12);
    EXPECT_NEAR(c.x1, 0.75 + 0.1, 1e-12);
    EXPECT_NEAR(c.y0, 0.25 - 0.1, 1e-12);
    EXPECT_NEAR(c.y1, 0.25 + 0.1, 1e-12);
    // A 2:1 image: the shorter (vertical) side spans `size`, so 4/20 of the view's height.
    c = zoomCrop(z, eye, at, up, 90.0, 2.0);
    EXPECT_NEAR(c.y1 - c.y0, 0.2, 1e-12);
    EXPECT_NEAR(cropStretch(c), 1.0, 1e-12);
    // Near the edge the window slides inside the view.
    z.center = Vec3(9.5, 0, 0);
    c = zoomCrop(z, eye, at, up, 90.0, 1.0);
    EXPECT_NEAR(c.x1, 1.0, 1e-12);
    EXPECT_NEAR(c.x0, 0.8, 1e-12);
    // The cube [−1, 1]³: its near face (depth 9) spans u ∈ 1/2 ± 1/18; margin 1.5.
    ZoomSpec b;
    b.kind = ZoomSpec::Kind::Box;
    b.lo = Vec3(-1);
    b.hi = Vec3(1);
    b.margin = 1.5;
    c = zoomCrop(b, eye, at, up, 90.0, 1.0);
    EXPECT_NEAR(c.x0, 0.5 - 1.5 / 18, 1e-12);
    EXPECT_NEAR(c.y1, 0.5 + 1.5 / 18, 1e-12);
    // Behind the camera, outside the view, or larger than it: errors.
    z.center = Vec3(0, 0, 20);
    EXPECT_THROW(zoomCrop(z, eye, at, up, 90.0, 1.0), Error);
    z.center = Vec3(30, 0, 0);
    EXPECT_THROW(zoomCrop(z, eye, at, up, 90.0, 1.0), Error);
    z.center = Vec3(0, 0, 0);
    z.size = 30.0;
    EXPECT_THROW(zoomCrop(z, eye, at, up, 90.0, 1.0), Error);
}

// Camera at (0, 0, 10) looking at the origin, up +y, fov 90°, D = 10, behind 0.1·D = 1: the view's
// half extent at the target is 10, so the lights sit at (±10, ±10, 11), d² = 321, I = 321·E.
TEST(Framing, PaperRigGivesIrradianceOneAtTheTarget) {
    LightRigSpec rig;
    rig.rig = "paper";
    rig.behind = 0.1;
    const std::vector<PointLight> lights =
        lightRig(rig, Vec3(0, 0, 10), Vec3(0), Vec3(0, 1, 0), 90.0, 1.0);
    ASSERT_EQ(lights.size(), 4u);
    // Order: right −/+ outer, up −/+ inner; camera right is +x here.
    expectNear(lights[0].position, Vec3(-10, -10, 11));
    expectNear(lights[1].position, Vec3(-10, 10, 11));
    expectNear(lights[2].position, Vec3(10, -10, 11));
    expectNear(lights[3].position, Vec3(10, 10, 11));
    for (const PointLight& l : lights) {
        EXPECT_NEAR(l.intensity[0], 321.0, 1e-9);
        EXPECT_NEAR(l.intensity[0] / (l.position - Vec3(0)).length2(), 1.0, 1e-12);
    }
    // At angle_deg off the view axis seen from the target, along the diagonals.
    rig.angleDeg = 20.0;
    rig.irradiance = Spectrum(0.5);
    for (const PointLight& l : lightRig(rig, Vec3(0, 0, 10), Vec3(0), Vec3(0, 1, 0), 90.0, 1.0)) {
        const Vec3 toLight = normalized(l.position);
        EXPECT_NEAR(std::acos(toLight.dot(Vec3(0, 0, 1))), radians(20.0), 1e-12);
        EXPECT_NEAR(std::abs(l.position.x), std::abs(l.position.y), 1e-12);
        EXPECT_NEAR(l.intensity[1] / l.position.length2(), 0.5, 1e-12);
    }
    LightRigSpec head;
    head.rig = "headlight";
    const std::vector<PointLight> h = lightRig(head, Vec3(3, 4, 0), Vec3(0), Vec3(0, 0, 1), 30, 1);
    ASSERT_EQ(h.size(), 1u);
    expectNear(h[0].position, Vec3(3, 4, 0));
    EXPECT_NEAR(h[0].intensity[2], 25.0, 1e-12);
}

// The rig with its defaults reproduces the lights scripts/make_paper_scenes.py wrote for the
// paper's view (camera 560 from the head, 50 behind, towards the corners at the head's depth),
// rounded there to 3 decimals and 0.1 in intensity.
TEST(Framing, PaperRigReproducesTheShippedPaperScenesLights) {
    const SceneSpec paper =
        loadSceneFile(std::string(LOBE_SOURCE_DIR) + "/assets/scenes/paper/rendering-01.json");
    LightRigSpec rig;
    rig.rig = "paper";
    const std::vector<PointLight> lights =
        lightRig(rig, paper.cameraPosition, paper.cameraTarget, paper.cameraUp, paper.fovDegrees,
                 double(paper.width) / paper.height);
    ASSERT_EQ(lights.size(), paper.lights.size());
    for (size_t i = 0; i < lights.size(); ++i) {
        expectNear(lights[i].position, paper.lights[i].position, 0.02);
        EXPECT_NEAR(lights[i].intensity[0] / paper.lights[i].intensity[0], 1.0, 1e-4);
    }
}

// A crop of another aspect than the image would stretch it: an error naming camera.crop.
TEST(Framing, CropWithAnotherAspectIsAnError) {
    const std::string e = errorOf(sceneWith(
        R"({"position": [0, 0, 5], "target": [0, 0, 0], "crop": [0.1, 0.2, 0.6, 0.45]})"));
    EXPECT_NE(e.find("scene.json: camera.crop:"), std::string::npos) << e;
    EXPECT_NE(e.find("stretched 2 times"), std::string::npos) << e;
    EXPECT_NE(e.find("[0.225, 0.2, 0.475, 0.45]"), std::string::npos) << e;
    EXPECT_EQ(
        errorOf(sceneWith(
            R"({"position": [0, 0, 5], "target": [0, 0, 0], "crop": [0.1, 0.2, 0.35, 0.45]})")),
        "");
    // The shipped close-ups' crop (scripts/make_paper_scenes.py ZOOM_CROP) is square.
    EXPECT_NEAR(cropStretch(CropWindow{0.3, 0.22, 0.7, 0.62}), 1.0, 1e-12);
    EXPECT_NEAR(cropStretch(CropWindow{0.1, 0.2, 0.6, 0.45}), 2.0, 1e-12);
}

TEST(Framing, SceneKeysAreReadAndMisuseNamed) {
    const SceneSpec s = parseScene(
        sceneWith(R"({"fit": {"view": "left", "objects": "a", "margin": 1.3, "method": "sphere"},
                      "fov_deg": 20, "zoom": {"point": [1, 2, 3], "size": 10}})",
                  R"({"rig": "paper", "irradiance": 2, "angle_deg": 15})"),
        kBase, "scene.json");
    EXPECT_TRUE(s.fit.enabled);
    EXPECT_EQ(s.fit.view, "left");
    EXPECT_FALSE(s.fit.upGiven);
    EXPECT_EQ(s.fit.objects, std::vector<std::string>{"a"});
    EXPECT_DOUBLE_EQ(s.fit.margin, 1.3);
    EXPECT_EQ(s.fit.method, "sphere");
    EXPECT_EQ(s.zoom.kind, ZoomSpec::Kind::Point);
    EXPECT_DOUBLE_EQ(s.zoom.size, 10.0);
    EXPECT_EQ(s.lightRig.rig, "paper");
    EXPECT_DOUBLE_EQ(s.lightRig.irradiance[0], 2.0);
    EXPECT_DOUBLE_EQ(s.lightRig.angleDeg, 15.0);
    EXPECT_TRUE(s.lights.empty());

    const auto has = [](const std::string& e, const std::string& what) {
        return e.find(what) != std::string::npos;
    };
    std::string e = errorOf(sceneWith(R"({"fit": {"view": "left"}, "position": [0, 0, 5]})"));
    EXPECT_TRUE(has(e, "camera.position: a fitted camera")) << e;
    e = errorOf(sceneWith(R"({"fit": {"view": "front"}})"));
    EXPECT_TRUE(has(e, "camera.fit.view: 'front' is not one of")) << e;
    e = errorOf(sceneWith(R"({"fit": {"view": "left", "azimuth_deg": 10}})"));
    EXPECT_TRUE(has(e, "camera.fit: give either view or azimuth_deg")) << e;
    e = errorOf(sceneWith(R"({"fit": {"objects": ["b"]}})"));
    EXPECT_TRUE(has(e, "camera.fit.objects: no object is named 'b' (objects: a)")) << e;
    e = errorOf(
        sceneWith(R"({"fit": {}, "crop": [0, 0, 0.5, 0.5], "zoom": {"point": [0, 0, 0]}})"));
    EXPECT_TRUE(has(e, "camera.zoom: give either zoom or crop")) << e;
    e = errorOf(sceneWith(R"({"fit": {}, "zoom": {"point": [0, 0, 0]}})"));
    EXPECT_TRUE(has(e, "camera.zoom.size: missing")) << e;
    e = errorOf(sceneWith(R"({"fit": {}})", R"({"rig": "headlight", "angle_deg": 10})"));
    EXPECT_TRUE(has(e, "lights.angle_deg: applies to the paper rig only")) << e;
    e = errorOf(sceneWith(R"({"fit": {}})", R"({"rig": "studio"})"));
    EXPECT_TRUE(has(e, "lights.rig: 'studio' is not one of")) << e;
}

// Orbit frame k is frame 0's camera and lights turned by 360°·k/N about the up axis through the
// objects' centre. Frame 0 at (0, −10, 0), centre (1, 0, 0), up +z: a quarter turn takes the
// offset (−1, −10, 0) to (10, −1, 0), so the camera to (11, −1, 0).
TEST(Framing, OrbitFramesAreRotationsOfFrameZero) {
    SceneSpec spec =
        parseScene(sceneWith(R"({"position": [0, -10, 0], "target": [1, 0, 0], "up": [0, 0, 1]})",
                             R"([{"position": [0, -12, 3], "intensity": 5}])"),
                   kBase, "dir/turn.json");
    const std::vector<WorldBox> boxes{cube(Vec3(1, 0, 0), 2.0)};
    std::vector<SceneSpec> frames = orbitFrames(spec, 4);
    ASSERT_EQ(frames.size(), 4u);
    EXPECT_EQ(frames[1].outputSuffix, "-orbit-001");
    EXPECT_EQ(frames[3].group, "turn-orbit");
    for (SceneSpec& f : frames) resolveView(f, boxes);
    expectNear(frames[0].cameraPosition, Vec3(0, -10, 0));
    expectNear(frames[1].cameraPosition, Vec3(11, -1, 0));
    expectNear(frames[2].cameraPosition, Vec3(2, 10, 0));
    expectNear(frames[1].cameraTarget, Vec3(1, 0, 0));
    // The light turns with the camera: offset (−1, −12, 3) → (12, −1, 3).
    expectNear(frames[1].lights[0].position, Vec3(13, -1, 3));
    for (int k = 0; k < 4; ++k) {
        const Vec3 p =
            rotateAbout(frames[0].cameraPosition, Vec3(1, 0, 0), Vec3(0, 0, 1), 90.0 * k);
        expectNear(frames[size_t(k)].cameraPosition, p, 1e-9);
    }
    // A rig follows the turned camera: the headlight sits on it.
    spec.lights.clear();
    spec.lightRig.rig = "headlight";
    frames = orbitFrames(spec, 3);
    for (SceneSpec& f : frames) resolveView(f, boxes);
    expectNear(frames[2].lights[0].position, frames[2].cameraPosition);
    expectNear(frames[2].cameraPosition,
               rotateAbout(Vec3(0, -10, 0), Vec3(1, 0, 0), Vec3(0, 0, 1), 240.0), 1e-9);
}

// The printed numbers, pasted into a scene, give the same camera and lights.
TEST(Framing, PrintedViewReadsBackAsTheSameCamera) {
    SceneSpec spec =
        parseScene(sceneWith(R"({"fit": {"azimuth_deg": 30, "elevation_deg": 20}, "fov_deg": 25,
                      "zoom": {"box": [[0, 0, 0], [1, 1, 1]]}})",
                             R"({"rig": "paper"})"),
                   kBase, "scene.json");
    resolveView(spec, {WorldBox{Vec3(-3, -4, -5), Vec3(6, 7, 8)}});
    const std::string frozen = frozenViewJson(spec);
    const std::string text = R"({"image": {"width": 64, "height": 64}, )" + frozen +
                             R"(, "objects": [{"kind": "isosurface", "iso": 0.5,
                               "source": {"path": "test_framing.cpp"},
                               "brdf": {"model": "lambert"}}]})";
    const SceneSpec back = parseScene(text, kBase, "frozen.json");
    expectNear(back.cameraPosition, spec.cameraPosition, 1e-7);
    expectNear(back.cameraTarget, spec.cameraTarget, 1e-7);
    EXPECT_DOUBLE_EQ(back.fovDegrees, 25.0);
    EXPECT_NEAR(back.crop.x0, spec.crop.x0, 1e-9);
    EXPECT_NEAR(back.crop.y1, spec.crop.y1, 1e-9);
    ASSERT_EQ(back.lights.size(), 4u);
    expectNear(back.lights[3].position, spec.lights[3].position, 1e-7);
    EXPECT_NEAR(back.lights[3].intensity[0] / spec.lights[3].intensity[0], 1.0, 1e-9);
}

// End to end: a 4×4×40 slab of float 1s (spacing 1) has the active box [−0.5, 3.5]² × [−0.5, 39.5]
// (centres ± half a voxel), centre (1.5, 1.5, 19.5), half extents (2, 2, 20). From anterior with
// fov 30° and margin 1.1 its height binds: d = 20/t + 2, t = tan 15°/1.1.
TEST(Framing, SceneFitsTheCameraToTheLoadedVolumesBox) {
    const fs::path dir =
        fs::temp_directory_path() / ("lobe_framing_test-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    std::vector<float> slab(4 * 4 * 40, 1.0f);
    std::ofstream(dir / "slab.raw", std::ios::binary)
        .write(reinterpret_cast<const char*>(slab.data()), std::streamsize(slab.size() * 4));
    const std::string text = R"({"image": {"width": 32, "height": 32},
        "camera": {"fit": {"view": "anterior"}}, "lights": {"rig": "headlight"},
        "backdrop": {"enabled": false},
        "objects": [{"name": "slab", "kind": "isosurface", "iso": 0.5,
          "source": {"path": "slab.raw", "dims": [4, 4, 40], "type": "float32"},
          "brdf": {"model": "lambert"}}]})";
    const RenderScene scene(parseScene(text, dir.string(), "slab.json"), false);
    const double d = 20.0 / (std::tan(radians(15.0)) / 1.1) + 2.0;
    expectNear(scene.spec().cameraPosition, Vec3(1.5, 1.5 + d, 19.5), 1e-9);
    expectNear(scene.spec().cameraTarget, Vec3(1.5, 1.5, 19.5), 1e-9);
    ASSERT_EQ(scene.spec().lights.size(), 1u);
    EXPECT_NEAR(scene.spec().lights[0].intensity[0], d * d, 1e-6);
    expectNear(scene.scene().camera().forward(), Vec3(0, -1, 0), 1e-12);
    // The ray through the top edge's middle grazes the top of the slab's near face (z = 39.5 at
    // depth d − 2) inside the margin: at that depth the frame's top is 1.1 × 20 above the centre.
    const Ray top = scene.scene().camera().generateRay(0.5, 0.0);
    const double tNear = (d - 2.0) / top.d.dot(Vec3(0, -1, 0));
    EXPECT_NEAR(top.at(tNear).z, 19.5 + 1.1 * 20.0, 1e-9);
}

// An orbit's frames share one assembled scene (`lobe render --orbit`): a scene built for frame 0
// and turned to frame k by setView renders frame k bit for bit as a scene built for it, backdrop
// included (it is placed from the view).
TEST(Framing, SceneTurnedToAnOrbitFrameRendersAsOneBuiltForIt) {
    const fs::path dir =
        fs::temp_directory_path() / ("lobe_framing_orbit_test-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    std::vector<float> slab(4 * 4 * 40);
    for (size_t i = 0; i < slab.size(); ++i) slab[i] = float((i * 7919) % 13) / 12.0f;
    std::ofstream(dir / "slab.raw", std::ios::binary)
        .write(reinterpret_cast<const char*>(slab.data()), std::streamsize(slab.size() * 4));
    const std::string text = R"({"image": {"width": 24, "height": 20, "samples_per_pixel": 2},
        "camera": {"fit": {"azimuth_deg": 30, "elevation_deg": 10}}, "lights": {"rig": "paper"},
        "volume": {"step_voxels": 0.5},
        "objects": [{"name": "iso", "kind": "isosurface", "iso": 0.5, "opacity": 0.5,
          "source": {"path": "slab.raw", "dims": [4, 4, 40], "type": "float32"},
          "brdf": {"model": "ward"}},
          {"name": "dvr", "kind": "volume",
          "source": {"path": "slab.raw", "dims": [4, 4, 40], "type": "float32"},
          "transfer_function": {"points": [{"value": 0.2, "opacity": 0},
                                           {"value": 0.9, "opacity": 0.3}]},
          "brdf": {"model": "phong"}}]})";
    const std::vector<SceneSpec> frames =
        orbitFrames(parseScene(text, dir.string(), "slab.json"), 3);
    RenderScene turned(frames[0], false);
    RenderOptions options;
    options.progress = false;
    for (size_t k = 1; k < frames.size(); ++k) {
        turned.setView(frames[k]);
        const RenderScene built(frames[k], false);
        EXPECT_EQ(turned.spec().title, built.spec().title);
        EXPECT_EQ(turned.spec().outputSuffix, built.spec().outputSuffix);
        expectNear(turned.spec().cameraPosition, built.spec().cameraPosition, 0.0);
        const Film a = turned.render(options), b = built.render(options);
        ASSERT_EQ(a.pixels().size(), b.pixels().size());
        size_t lit = 0;
        for (size_t i = 0; i < a.pixels().size(); ++i) {
            for (int c = 0; c < kBandCount; ++c) ASSERT_EQ(a.pixels()[i][c], b.pixels()[i][c]) << i;
            lit += a.pixels()[i].maxValue() > 0.0;
        }
        EXPECT_EQ(lit, a.pixels().size());  // the backdrop fills the rest
    }
    // Frame 1 is not frame 0: the turn did change the view.
    const RenderScene first(frames[0], false);
    EXPECT_GT((first.spec().cameraPosition - turned.spec().cameraPosition).length(), 1.0);
}

}  // namespace lobe
