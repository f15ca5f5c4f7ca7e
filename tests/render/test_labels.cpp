// Label objects (volume/labels.h, render/scene_labels.h): the selection equals the mask voxel
// for voxel, the surface has no false shell where labels 1 < 2 < 3 meet and stays within half a
// voxel of the boundary of the label's voxel cubes, scene keys expand and name objects, framing
// uses the label's own box, and every kind of bad input is one clear error.
#include "core/error.h"
#include "label_test_maps.h"
#include "render/framing.h"
#include "render/scene.h"
#include "render/scene_file.h"
#include "scene_text.h"
#include "surface/iso_exact.h"
#include "surface/surface_scene.h"
#include "volume/labels.h"
#include "volume/reconstruction.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>

namespace lobe {
namespace {

using test::kMapN;
using test::syntheticLabel;

const std::string& mapPath() {
    static const std::string path = test::writeSyntheticMap("labels.nii");
    return path;
}

bool inSet(int i, int j, int k, const std::set<int>& ids) {
    return ids.count(syntheticLabel(i, j, k)) > 0;
}

TEST(LabelMap, IndexCountsAndBoxes) {
    const auto map = loadLabelMap(mapPath());
    EXPECT_EQ(map, loadLabelMap(mapPath()));  // loaded once
    ASSERT_EQ(map->labels.size(), 4u);
    std::int64_t count[5] = {};
    for (int k = 0; k < kMapN; ++k)
        for (int j = 0; j < kMapN; ++j)
            for (int i = 0; i < kMapN; ++i) count[syntheticLabel(i, j, k)]++;
    for (int id = 1; id <= 4; ++id) EXPECT_EQ(map->find(id)->voxels, count[id]) << id;
    EXPECT_EQ(map->find(4)->box, openvdb::CoordBBox(openvdb::Coord(22), openvdb::Coord(27)));
    EXPECT_EQ(map->find(2)->box, openvdb::CoordBBox(openvdb::Coord(7), openvdb::Coord(17)));
    EXPECT_EQ(map->nearestPresent(9, 2), (std::vector<int>{4, 3}));
}

TEST(LabelMap, SelectionEqualsTheMaskVoxelForVoxel) {
    const auto map = loadLabelMap(mapPath());
    for (const std::set<int>& ids : {std::set<int>{2}, std::set<int>{1, 3}, std::set<int>{4}}) {
        const openvdb::FloatGrid::Ptr mask =
            labelMask(*map, std::vector<int>(ids.begin(), ids.end()));
        auto acc = mask->getConstAccessor();
        int wrong = 0;
        for (int k = -2; k < kMapN + 2; ++k)
            for (int j = -2; j < kMapN + 2; ++j)
                for (int i = -2; i < kMapN + 2; ++i) {
                    const bool want = i >= 0 && j >= 0 && k >= 0 && i < kMapN && j < kMapN &&
                                      k < kMapN && inSet(i, j, k, ids);
                    const openvdb::Coord c(i, j, k);
                    wrong += (acc.getValue(c) == 1.0f) != want || acc.isValueOn(c) != want;
                }
        EXPECT_EQ(wrong, 0);
    }
}

SurfaceScene sceneOf(std::shared_ptr<const SurfaceGeometry> g) {
    SurfaceScene scene("threads=1");
    scene.add(std::move(g));
    scene.commit();
    return scene;
}

TEST(LabelSurface, NoFalseShellWhereLowerAndHigherLabelsMeet) {
    const auto map = loadLabelMap(mapPath());
    const SurfaceScene label2 = sceneOf(
        std::make_shared<IsoExactSurface>(*labelSurfaceField(*map, {2}, kLabelSmoothDefault), 0.5));
    // The iso value 1.5 on the labels themselves: the shell of "≥ 2" includes the 1|3 plane.
    const SurfaceScene onValues =
        sceneOf(std::make_shared<IsoExactSurface>(*map->volume->grid, 1.5));
    int falseShell = 0;
    for (double y : {3.0, 4.5, 19.0, 20.5})
        for (double z : {3.0, 4.5, 19.0, 20.5}) {
            // Along x through the 1|3 plane x = 11.5, away from the ball of label 2.
            Ray ray;
            ray.o = Vec3(2.5, y, z);
            ray.d = Vec3(1, 0, 0);
            ray.tMax = 18.0;  // to x = 20.5, inside the box of labels 1 and 3
            EXPECT_FALSE(label2.intersect(ray)) << y << " " << z;
            const auto hit = onValues.intersect(ray);
            falseShell += hit && std::abs(hit->position.x - 11.5) < 0.51;
        }
    EXPECT_EQ(falseShell, 16);  // what selection by value would show
}

// Distance from p to the boundary of the union of the voxel cubes [c − ½, c + ½]³ of the label
// set: max(distance to the union, distance to its complement), one of which is 0.
double boundaryDistance(const Vec3& p, const std::set<int>& ids) {
    double dIn = 1e9, dOut = 1e9;
    const int ci = int(std::floor(p.x + 0.5)), cj = int(std::floor(p.y + 0.5)),
              ck = int(std::floor(p.z + 0.5));
    for (int k = ck - 3; k <= ck + 3; ++k)
        for (int j = cj - 3; j <= cj + 3; ++j)
            for (int i = ci - 3; i <= ci + 3; ++i) {
                const double dx = std::max(0.0, std::abs(p.x - i) - 0.5);
                const double dy = std::max(0.0, std::abs(p.y - j) - 0.5);
                const double dz = std::max(0.0, std::abs(p.z - k) - 0.5);
                const double d = std::sqrt(dx * dx + dy * dy + dz * dz);
                const bool in = i >= 0 && j >= 0 && k >= 0 && i < kMapN && j < kMapN && k < kMapN &&
                                inSet(i, j, k, ids);
                (in ? dIn : dOut) = std::min(in ? dIn : dOut, d);
            }
    return std::max(dIn, dOut);
}

TEST(LabelSurface, WithinHalfAVoxelOfTheLabelBoundary) {
    const auto map = loadLabelMap(mapPath());
    for (int id : {2, 4}) {  // a ball (curved) and a cube (edges, corners)
        const std::set<int> ids{id};
        const SurfaceScene scene = sceneOf(std::make_shared<IsoExactSurface>(
            *labelSurfaceField(*map, {id}, kLabelSmoothDefault), 0.5));
        const Vec3 centre = id == 2 ? Vec3(12, 12, 12) : Vec3(24.5, 24.5, 24.5);
        int hits = 0;
        double worst = 0.0;
        // Rays towards the centre from a sphere of directions, offset across the shape.
        for (int a = 0; a < 24; ++a)
            for (int b = 1; b < 12; ++b)
                for (double off : {-2.0, 0.0, 2.0, 2.9}) {
                    const double th = M_PI * b / 12.0, ph = 2.0 * M_PI * a / 24.0;
                    const Vec3 dir(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph),
                                   std::cos(th));
                    Vec3 side = normalized(
                        dir.cross(std::abs(dir.z) < 0.9 ? Vec3(0, 0, 1) : Vec3(1, 0, 0)));
                    Ray ray;
                    ray.o = centre + dir * 20.0 + side * off;
                    ray.d = -dir;
                    const auto hit = scene.intersect(ray);
                    if (!hit) continue;
                    ++hits;
                    worst = std::max(worst, boundaryDistance(hit->position, ids));
                }
        EXPECT_GT(hits, 800) << id;
        EXPECT_LE(worst, 0.5) << "label " << id << ": a hit " << worst
                              << " voxel from the boundary";
        std::printf("label %d: %d hits, farthest %.4f voxel from the boundary of its voxel cubes\n",
                    id, hits, worst);
    }
}

TEST(LabelSurface, RawIndicatorKeepsEveryVoxel) {
    // label_smooth 0: the raw indicator, 1 on the voxels of the set: every voxel centre is inside.
    const auto map = loadLabelMap(mapPath());
    const openvdb::FloatGrid::Ptr f = labelSurfaceField(*map, {2}, 0.0);
    auto acc = f->getConstAccessor();
    for (int k = 0; k < kMapN; ++k)
        for (int j = 0; j < kMapN; ++j)
            for (int i = 0; i < kMapN; ++i)
                ASSERT_EQ(acc.getValue(openvdb::Coord(i, j, k)) > 0.5f, inSet(i, j, k, {2}));
}

TEST(LabelVolume, NearestNeverPassesThroughALabelBetween) {
    // Across the 1|3 plane: trilinear reconstruction passes through label 2, nearest does not.
    const auto map = loadLabelMap(mapPath());
    GridReconstructor recon(*map->volume->grid);
    int trilinearTwos = 0;
    for (double x = 2.0; x <= 21.0; x += 0.01) {
        const Vec3 p(x, 4.0, 4.0);
        const double n = recon.value(Reconstruction::kNearest, p);
        ASSERT_TRUE(n == 1.0 || n == 3.0) << x << " " << n;
        ASSERT_EQ(n, x < 11.5 ? 1.0 : 3.0) << x;
        const double t = recon.value(Reconstruction::kTrilinear, p);
        trilinearTwos += std::abs(t - 2.0) < 0.1;
    }
    EXPECT_GT(trilinearTwos, 0);
}

// ---- scene keys --------------------------------------------------------------------------------

std::string object(const std::string& body) {
    return R"({"camera": {"position": [0, 0, 80], "target": [16, 16, 16]}, "objects": [)" + body +
           "]}";
}

std::string source(const std::string& extra) {
    return R"({"path": ")" + mapPath() + "\"" + extra + "}";
}

const char* kTable =
    R"(, "label_table": {"1": "Left", "2": "Ball", "3": "Right", "4": {"name": "Cube", "color": "#ff0000"}})";

TEST(LabelScene, NamesNumbersAndSegmentations) {
    SceneSpec s =
        parseScene(object(R"({"kind": "isosurface", "brdf": {"model": "lambert"}, "source": )" +
                          source(std::string(kTable) + R"(, "labels": ["Ball", 4])") + "}"),
                   test::kSceneBase, "scene.json");
    ASSERT_EQ(s.objects.size(), 1u);
    EXPECT_EQ(s.objects[0].source.labels, (std::vector<int>{2, 4}));
    EXPECT_EQ(s.objects[0].iso, 0.5);

    s = parseScene(
        object(
            R"({"kind": "segmentation", "labels": "all", "opacity": 0.5, "brdf": {"model": "lambert"},
        "source": )" +
            source(kTable) +
            R"(, "overrides": {"Ball": {"opacity": 1, "brdf": {"model": "phong"}}}})"),
        test::kSceneBase, "scene.json");
    ASSERT_EQ(s.objects.size(), 4u);
    EXPECT_EQ(s.objects[0].name, "Left");
    EXPECT_EQ(s.objects[1].name, "Ball");
    EXPECT_EQ(s.objects[3].name, "Cube");
    EXPECT_EQ(s.objects[1].source.labels, std::vector<int>{2});
    EXPECT_EQ(s.objects[1].opacity, 1.0);
    EXPECT_EQ(s.objects[1].brdfModel, "phong");
    EXPECT_EQ(s.objects[0].opacity, 0.5);
    EXPECT_EQ(s.objects[0].brdfModel, "lambert");
    // The table's #ff0000: sRGB 1, 0, 0 → linear 1, 0, 0 → bands; without a colour, white.
    EXPECT_GT(s.objects[3].color[0], s.objects[3].color[2]);
    EXPECT_EQ(s.objects[0].color[0], 1.0);
    EXPECT_EQ(s.objects[0].isoNormals, "trilinear");

    // "normals" applies to every label (smooth shading normals: no voxel grid in the highlights).
    s = parseScene(object(R"({"kind": "segmentation", "labels": [2, 4], "normals": "bspline",
        "brdf": {"model": "lambert"}, "source": )" +
                          source(kTable) + "}"),
                   test::kSceneBase, "scene.json");
    ASSERT_EQ(s.objects.size(), 2u);
    EXPECT_EQ(s.objects[0].isoNormals, "bspline");
    EXPECT_EQ(s.objects[1].isoNormals, "bspline");
}

TEST(LabelScene, FitUsesTheLabelsOwnBox) {
    const SceneSpec s =
        parseScene(object(R"({"kind": "isosurface", "brdf": {"model": "lambert"}, "source": )" +
                          source(R"(, "labels": [4])") + "}"),
                   test::kSceneBase, "scene.json");
    VolumeCache cache;
    const std::vector<WorldBox> boxes = objectWorldBoxes(s, cache);
    ASSERT_EQ(boxes.size(), 1u);
    EXPECT_EQ(boxes[0].lo, Vec3(21.5, 21.5, 21.5));
    EXPECT_EQ(boxes[0].hi, Vec3(27.5, 27.5, 27.5));
}

TEST(LabelScene, ZoomOnALabelObjectUsesItsOwnBox) {
    const auto sceneWith = [](const std::string& zoom) {
        return R"({"camera": {"fit": {"view": "left"}, "zoom": )" + zoom + R"(}, "objects": [
            {"name": "cube", "kind": "isosurface", "brdf": {"model": "lambert"}, "source": )" +
               source(R"(, "labels": [4])") + R"(},
            {"name": "rest", "kind": "isosurface", "brdf": {"model": "lambert"}, "source": )" +
               source(R"(, "labels": [1, 2, 3])") + "}]}";
    };
    SceneSpec byName =
        parseScene(sceneWith(R"({"objects": "cube", "margin": 1.2})"), test::kSceneBase, "a.json");
    SceneSpec byBox =
        parseScene(sceneWith(R"({"box": [[21.5, 21.5, 21.5], [27.5, 27.5, 27.5]], "margin": 1.2})"),
                   test::kSceneBase, "b.json");
    VolumeCache cache;
    resolveView(byName, objectWorldBoxes(byName, cache));
    resolveView(byBox, objectWorldBoxes(byBox, cache));
    EXPECT_EQ(byName.crop.x0, byBox.crop.x0);
    EXPECT_EQ(byName.crop.y1, byBox.crop.y1);
    EXPECT_LT(byName.crop.x1 - byName.crop.x0, 0.5);  // a close-up, not the whole view
    EXPECT_NE(test::errorOf(sceneWith(R"({"objects": "cubes"})"))
                  .find("camera.zoom.objects: no object is named 'cubes'"),
              std::string::npos);
}

void expectError(const std::string& text, std::initializer_list<std::string> parts) {
    const std::string e = test::errorOf(text);
    ASSERT_FALSE(e.empty()) << text;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
    for (const std::string& p : parts)
        EXPECT_NE(e.find(p), std::string::npos) << e << "\nmissing: " << p;
}

TEST(LabelScene, BadInputIsOneClearError) {
    const std::string iso = R"({"kind": "isosurface", "brdf": {"model": "lambert"}, "source": )";
    // A label not present: the nearest present labels named.
    expectError(
        object(iso + source(R"(, "labels": [9])") + "}"),
        {"objects[0].source.labels", "label 9 is not in", "nearest labels present: 4, 3, 2"});
    // A name in no table, with the nearest names.
    expectError(object(iso + source(std::string(kTable) + R"(, "labels": ["Bal"])") + "}"),
                {"'Bal' is in no label table", "Ball"});
    // A name without any table.
    expectError(object(iso + source(R"(, "labels": ["Ball"])") + "}"), {"has no label table"});
    // A table that does not match the map.
    expectError(
        object(iso + source(R"(, "label_table": {"1": "a", "2": "b"}, "labels": [1])") + "}"),
        {"label_table", "does not match the map", "2 of the map's 4 labels are not in it (3, 4)"});
    // A map that is not a label map.
    const std::string fractional = test::writeSyntheticMap("fractional.nii", true);
    expectError(object(iso + R"({"path": ")" + fractional + R"(", "labels": [1]}})"),
                {"not a label map", "0.5", "not a whole number"});
    // Two objects claiming one label.
    expectError(object(iso + source(R"(, "labels": [2])") + "}, " + iso +
                       source(R"(, "labels": [2, 3])") + "}"),
                {"both claim label 2"});
    // "all" is for segmentations, an iso value is not for labels, load options are not either.
    expectError(object(iso + source(R"(, "labels": "all")") + "}"), {"\"all\" is for"});
    expectError(
        object(R"({"kind": "isosurface", "iso": 2, "brdf": {"model": "lambert"}, "source": )" +
               source(R"(, "labels": [2])") + "}"),
        {"objects[0].iso", "0.5 level"});
    expectError(object(iso + source(R"(, "labels": [2], "divide_by": 2)") + "}"),
                {"divide_by", "not with labels"});
    // An override naming no label of the segmentation.
    expectError(
        object(
            R"({"kind": "segmentation", "labels": [1, 2], "brdf": {"model": "lambert"}, "source": )" +
            source(kTable) + R"(, "overrides": {"Cube": {"opacity": 0.5}}})"),
        {"overrides.Cube", "not one of this segmentation's labels"});
}

// The installed AAL atlas against nibabel's mask of it (np.isin(data, S)): the voxel count, the
// index box and the sum of the flat (x-fastest) indices of the selected voxels, for {37} and
// {37, 38}, equal ours voxel for voxel.
TEST(LabelMap, AalSelectionEqualsNibabelsMask) {
    const std::string aal = "/usr/share/mricron/templates/aal.nii.gz";
    if (!std::filesystem::exists(aal))
        GTEST_SKIP() << "mricron-data is not installed (scripts/setup.sh)";
    const std::string out = (std::filesystem::temp_directory_path() /
                             ("lobe-label-tests-" + std::to_string(::getpid())) / "aal-mask.txt")
                                .string();
    std::filesystem::create_directories(std::filesystem::path(out).parent_path());
    const std::string cmd = std::string(LOBE_SYSTEM_PYTHON) +
                            " -c \"import nibabel as nib, numpy as np\n"
                            "d = np.asanyarray(nib.load('" +
                            aal +
                            "').dataobj)\n"
                            "with open('" +
                            out +
                            "', 'w') as f:\n"
                            "    for s in ([37], [37, 38]):\n"
                            "        m = np.isin(d, s)\n"
                            "        i = np.argwhere(m)\n"
                            "        flat = np.flatnonzero(m.flatten(order='F'))\n"
                            "        f.write('%d %s %s %d\\n' % (m.sum(), ' '.join(map(str, "
                            "i.min(0))), ' '.join(map(str, i.max(0))), flat.sum()))\n\"";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
    std::ifstream in(out);
    const auto map = loadLabelMap(aal);
    for (const std::vector<int>& ids : {std::vector<int>{37}, std::vector<int>{37, 38}}) {
        long long count, lo[3], hi[3], flatSum;
        in >> count >> lo[0] >> lo[1] >> lo[2] >> hi[0] >> hi[1] >> hi[2] >> flatSum;
        ASSERT_TRUE(in) << "nibabel's output";
        const openvdb::FloatGrid::Ptr mask = labelMask(*map, ids);
        long long ours = 0, oursFlat = 0;
        for (auto it = mask->cbeginValueOn(); it; ++it) {
            const openvdb::Coord c = it.getCoord();
            ++ours;
            oursFlat += c.x() + 181LL * (c.y() + 217LL * c.z());
        }
        EXPECT_EQ(ours, count);
        EXPECT_EQ(oursFlat, flatSum);
        const openvdb::CoordBBox box = map->boxOf(ids);
        EXPECT_EQ(box, openvdb::CoordBBox(openvdb::Coord(int(lo[0]), int(lo[1]), int(lo[2])),
                                          openvdb::Coord(int(hi[0]), int(hi[1]), int(hi[2]))));
    }
}

// The installed AAL atlas (Debian mricron-data): label 37 (Hippocampus_L) as a label object covers
// the image as a binary mask of label 37 (written as a .vdb) does as an exact iso-surface at 0.5
// — the route users took before labels existed. Same fitted camera, coverage = any surface hit.
TEST(LabelScene, AalLabel37CoversWhatItsBinaryMaskDoes) {
    const std::string aal = "/usr/share/mricron/templates/aal.nii.gz";
    if (!std::filesystem::exists(aal))
        GTEST_SKIP() << "mricron-data is not installed (scripts/setup.sh)";
    const std::string mask = (std::filesystem::temp_directory_path() /
                              ("lobe-label-tests-" + std::to_string(::getpid())) / "aal37.vdb")
                                 .string();
    std::filesystem::create_directories(std::filesystem::path(mask).parent_path());
    Volume maskVolume = *loadLabelMap(aal)->volume;
    maskVolume.grid = labelMask(*loadLabelMap(aal), {37});
    writeVdb(maskVolume, mask);
    const auto sceneText = [](const std::string& object) {
        return R"({"image": {"width": 96, "height": 96}, "camera": {"fit": {"view": "left", "margin": 1.2}},
                   "objects": [)" +
               object + "]}";
    };
    const SceneSpec label = parseScene(sceneText(
                                           R"({"kind": "isosurface", "brdf": {"model": "lambert"},
        "source": {"path": ")" + aal + R"(", "labels": [37]}})"),
                                       test::kSceneBase, "label.json");
    const SceneSpec binary =
        parseScene(sceneText(R"({"kind": "isosurface", "iso": 0.5, "brdf": {"model": "lambert"},
        "source": {"path": ")" +
                             mask + R"("}})"),
                   test::kSceneBase, "mask.json");
    const Scene a(label, false), b(binary, false);
    int both = 0, either = 0;
    for (int y = 0; y < 96; ++y)
        for (int x = 0; x < 96; ++x) {
            const Ray ray = a.camera().generateRay((x + 0.5) / 96.0, (y + 0.5) / 96.0);
            const bool inA = bool(a.surfaces()->intersect(ray)),
                       inB = bool(b.surfaces()->intersect(ray));
            both += inA && inB;
            either += inA || inB;
        }
    ASSERT_GT(either, 500);
    const double iou = double(both) / either;
    std::printf("AAL label 37 against its binary mask: IoU %.3f over %d pixels covered\n", iou,
                either);
    EXPECT_GE(iou, 0.9);
}

}  // namespace
}  // namespace lobe
