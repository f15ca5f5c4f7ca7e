#include "core/error.h"
#include "render/scene.h"
#include "render/scene_file.h"
#include "scene_text.h"
#include "volume/volume_summary.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace lobe {
namespace {

namespace fs = std::filesystem;

// A tiny scene whose source file exists (this test file itself stands in for a volume: the
// parser checks existence, not contents).
std::string validScene(const std::string& objectExtra = "", const std::string& brdfExtra = "") {
    return R"({
      "image": {"width": 64, "height": 32, "samples_per_pixel": 4, "seed": 3},
      "camera": {"position": [0, 0, 5], "target": [0, 0, 0], "up": [0, 1, 0], "fov_deg": 40},
      "lights": [{"position": [1, 2, 3], "intensity": [1, 2, 3]}],
      "volume": {"step_voxels": 0.1},
      "objects": [{
        "name": "skull", "kind": "isosurface", "iso": 0.5, "opacity": 0.97,
        "source": {"path": "test_scene_file.cpp"},
        "transform": {"scale": [1, -1, 2], "translate": [10, 0, 0]},
        "brdf": {"model": "ward", "alpha_x": 0.1)" +
           brdfExtra + R"(}, "kd": 0.2)" + objectExtra + R"(
      }]
    })";
}

const std::string& kBase = test::kSceneBase;
using test::errorOf;

}  // namespace

TEST(SceneFile, ValidSceneIsRead) {
    const SceneSpec s = parseScene(validScene(), kBase, "scene.json");
    EXPECT_EQ(s.width, 64);
    EXPECT_EQ(s.height, 32);
    EXPECT_EQ(s.samplesPerPixel, 4);
    EXPECT_EQ(s.seed, 3u);
    EXPECT_DOUBLE_EQ(s.volumeStepVoxels, 0.1);
    ASSERT_EQ(s.lights.size(), 1u);
    EXPECT_DOUBLE_EQ(s.lights[0].intensity[2], 3.0);
    ASSERT_EQ(s.objects.size(), 1u);
    const ObjectSpec& o = s.objects[0];
    EXPECT_EQ(o.name, "skull");
    EXPECT_DOUBLE_EQ(o.opacity, 0.97);
    EXPECT_DOUBLE_EQ(o.transform.linear[1][1], -1.0);
    EXPECT_DOUBLE_EQ(o.transform.translation[0], 10.0);
    EXPECT_DOUBLE_EQ(std::get<Ward>(o.material.specular).alphaX[0], 0.1);
    EXPECT_DOUBLE_EQ(std::get<Ward>(o.material.specular).alphaY[0], 0.3);  // default
    EXPECT_TRUE(fs::path(o.source.path).is_absolute());
}

TEST(SceneFile, ErrorsNameTheKeyPath) {
    const std::string range = errorOf(validScene("", ", \"alpha_y\": -1"));
    EXPECT_NE(range.find("objects[0].brdf.alpha_y"), std::string::npos) << range;
    const std::string unknownParam = errorOf(validScene("", ", \"alpha\": 1"));
    EXPECT_NE(unknownParam.find("objects[0].brdf.alpha: unknown key"), std::string::npos)
        << unknownParam;
    const std::string unknownKey = errorOf(validScene(", \"opacityy\": 1"));
    EXPECT_NE(unknownKey.find("objects[0].opacityy: unknown key"), std::string::npos) << unknownKey;
    const std::string wrongType = errorOf(validScene(", \"method\": 3"));
    EXPECT_NE(wrongType.find("objects[0].method: expected a string"), std::string::npos)
        << wrongType;
    const std::string badMethod = errorOf(validScene(", \"method\": \"voxels\""));
    EXPECT_NE(badMethod.find("not one of: exact, mesh"), std::string::npos) << badMethod;
}

// "source": {"array": NAME}: resolved from the arrays given to parseScene (the Python module's);
// in a file, or with a name not given, or beside a file key, an error at the key path.
TEST(SceneFile, InMemoryArraySources) {
    std::string text = validScene();
    text.replace(text.find("\"path\": \"test_scene_file.cpp\""), 29,
                 "\"array\": \"a1\", \"divide_by\": 2");
    const std::string inFile = errorOf(text);
    EXPECT_NE(inFile.find("scene.json: objects[0].source.array: arrays in memory are given through "
                          "the Python module"),
              std::string::npos)
        << inFile;
    auto array = std::make_shared<VolumeArray>();
    array->name = "a1";
    const SceneArrays arrays{{"a1", array}};
    const SceneSpec s = parseScene(text, kBase, "scene.json", &arrays);
    EXPECT_EQ(s.objects[0].source.array, array);
    EXPECT_EQ(s.objects[0].source.path, "");
    EXPECT_EQ(s.objects[0].source.divideBy, 2.0);
    const SceneArrays others{{"a2", array}};
    try {
        parseScene(text, kBase, "scene.json", &others);
        ADD_FAILURE() << "an unknown array name was accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("objects[0].source.array: no array named 'a1'"),
                  std::string::npos)
            << e.what();
    }
    std::string withDims = text;
    withDims.replace(withDims.find("\"divide_by\""), 11, "\"dims\": [1, 2, 3], \"divide_by\"");
    try {
        parseScene(withDims, kBase, "scene.json", &arrays);
        ADD_FAILURE() << "dims beside array was accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("objects[0].source.dims: not with \"array\""),
                  std::string::npos)
            << e.what();
    }
}

TEST(SceneFile, MissingFileUnknownModelAndSyntaxErrors) {
    std::string text = validScene();
    text.replace(text.find("test_scene_file.cpp"), 19, "no_such_volume.nii");
    EXPECT_NE(errorOf(text).find("objects[0].source.path: file"), std::string::npos);
    std::string model = validScene();
    model.replace(model.find("\"ward\""), 6, "\"blinn\"");
    model.replace(model.find(", \"alpha_x\": 0.1"), 16, "");
    EXPECT_NE(errorOf(model).find("unknown BRDF model 'blinn'"), std::string::npos)
        << errorOf(model);
    const std::string syntax = errorOf("{\n  \"image\": {\"width\": 64,,}\n}");
    EXPECT_NE(syntax.find("invalid JSON at line 2"), std::string::npos) << syntax;
    EXPECT_NE(errorOf("{\"objects\": []}").find("camera: missing"), std::string::npos);
    const std::string cam =
        errorOf(R"({"camera": {"position": [0,0,1], "target": [0,0,1]}, "objects": []})");
    EXPECT_NE(cam.find("same point"), std::string::npos) << cam;
}

TEST(SceneFile, PerBandBrdfValuesAndSingularTransform) {
    const SceneSpec s = parseScene(validScene("", ", \"rho_s\": [0.1, 0.2, 0.3]"), kBase, "s");
    EXPECT_DOUBLE_EQ(std::get<Ward>(s.objects[0].material.specular).rhoS[1], 0.2);
    std::string text = validScene();
    text.replace(text.find("[1, -1, 2]"), 10, "[1, 0, 2]");
    EXPECT_NE(errorOf(text).find("singular"), std::string::npos);
}

}  // namespace lobe

namespace lobe {

TEST(SceneFile, VolumeObjectsWithPresetAndExplicitTransferFunctions) {
    const std::string base = std::string(LOBE_SOURCE_DIR) + "/tests/render";
    const std::string text = R"({
      "camera": {"position": [0, 0, 5]},
      "objects": [
        {"kind": "volume", "source": {"path": "test_scene_file.cpp", "divide_by": 255},
         "transfer_function": {"preset": "density_map", "index": 2},
         "reconstruction": "bspline", "brdf": {"model": "phong"}},
        {"kind": "volume", "source": {"path": "test_scene_file.cpp"},
         "transfer_function": {"points": [{"value": 0.1, "opacity": 0},
                                          {"value": 0.2, "opacity": 0.5, "color": [1, 0, 0]}]},
         "brdf": {"model": "lambert"}}
      ]})";
    const SceneSpec s = parseScene(text, base, "s.json");
    ASSERT_EQ(s.objects.size(), 2u);
    EXPECT_EQ(s.objects[0].reconstruction, "bspline");
    EXPECT_DOUBLE_EQ(s.objects[0].source.divideBy, 255.0);
    // Density map 2 is iso 0.80 with opacity 0.5: half opacity at the iso value.
    EXPECT_NEAR(s.objects[0].transfer.opacity(0.80), 0.25, 1e-9);
    EXPECT_NEAR(s.objects[1].transfer.opacity(0.15), 0.25, 1e-12);
    EXPECT_DOUBLE_EQ(s.objects[1].transfer.colour(0.2)[1], 0.0);

    std::string bad = text;
    bad.replace(bad.find("\"opacity\": 0.5"), 14, "\"opacity\": 1.5");
    try {
        parseScene(bad, base, "s.json");
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("objects[1].transfer_function.points[1].opacity"),
                  std::string::npos)
            << e.what();
    }
}

}  // namespace lobe

namespace lobe {

// A number JSON cannot hold (1e400 overflows a double) is bad input, not an internal error.
TEST(SceneFile, NumberOverflowIsAnInputError) {
    try {
        parseScene(R"({"camera": {"fov_deg": 1e400}, "objects": []})", ".", "big.json");
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("big.json: invalid JSON"), std::string::npos)
            << e.what();
    }
}

}  // namespace lobe

namespace lobe {
namespace {

TEST(SceneFile, HighlightToneAndGreyBackdropKeys) {
    const SceneSpec d = parseScene(validScene(), kBase, "scene.json");
    EXPECT_TRUE(d.objects[0].highlightTakesLight);  // the dichromatic default
    EXPECT_EQ(d.tone, "clip");
    EXPECT_FALSE(d.backdrop.grey);
    const SceneSpec c = parseScene(validScene(R"(, "highlight": "colour")"), kBase, "scene.json");
    EXPECT_FALSE(c.objects[0].highlightTakesLight);
    EXPECT_NE(errorOf(validScene(R"(, "highlight": "white")")).find("objects[0].highlight"),
              std::string::npos);
    std::string toned = validScene();
    toned.replace(toned.find(R"("seed": 3})"), 10,
                  R"("seed": 3, "tone": "shoulder"}, "backdrop": {"colours": "grey"})");
    const SceneSpec t = parseScene(toned, kBase, "scene.json");
    EXPECT_EQ(t.tone, "shoulder");
    EXPECT_TRUE(t.backdrop.grey);
}

// "divide_by": a number, "max" (by the data's maximum) or "pNN" (a percentile); any other word
// is an error.
TEST(SceneFile, DivideByNumberOrMax) {
    std::string text = validScene();
    text.replace(text.find(R"("source": {"path": "test_scene_file.cpp"})"), 41,
                 R"("source": {"path": "test_scene_file.cpp", "divide_by": "max"})");
    const SceneSpec m = parseScene(text, kBase, "scene.json");
    EXPECT_TRUE(m.objects[0].source.divideByMax);
    std::string word = text;
    word.replace(word.find(R"("max")"), 5, R"("most")");
    EXPECT_NE(errorOf(word).find("divide_by"), std::string::npos) << errorOf(word);
    EXPECT_FALSE(parseScene(validScene(), kBase, "scene.json").objects[0].source.divideByMax);
    // A percentile "pNN", 0 < NN <= 100.
    std::string percentile = text;
    percentile.replace(percentile.find(R"("max")"), 5, R"("p99.5")");
    EXPECT_EQ(parseScene(percentile, kBase, "scene.json").objects[0].source.divideByPercentile,
              99.5);
    EXPECT_FALSE(parseScene(percentile, kBase, "scene.json").objects[0].source.divideByMax);
    for (const char* bad : {R"("p0")", R"("p100.5")", R"("p")"}) {
        std::string b = text;
        b.replace(b.find(R"("max")"), 5, bad);
        EXPECT_NE(errorOf(b).find("objects[0].source.divide_by"), std::string::npos) << errorOf(b);
        EXPECT_NE(errorOf(b).find("percentile"), std::string::npos) << errorOf(b);
    }
}

// The level-set method's keys: read with "method": "levelset", unknown with another method.
// "path": a list of files (the slices of one DICOM series) and "series" (a SeriesInstanceUID);
// a list item that is not a string, or that does not exist, is named.
TEST(SceneFile, DicomListAndSeries) {
    std::string text = validScene();
    const std::string source = R"("source": {"path": "test_scene_file.cpp"})";
    text.replace(
        text.find(source), source.size(),
        R"("source": {"path": ["test_scene_file.cpp", "CMakeLists.txt"], "series": "1.2.3"})");
    const SceneSpec s = parseScene(text, kBase, "scene.json");
    EXPECT_EQ(s.objects[0].source.path, kBase + "/test_scene_file.cpp");
    ASSERT_EQ(s.objects[0].source.morePaths.size(), 1u);
    EXPECT_EQ(s.objects[0].source.morePaths[0], kBase + "/CMakeLists.txt");
    EXPECT_EQ(s.objects[0].source.series, "1.2.3");
    std::string bad = text;
    bad.replace(bad.find(R"("CMakeLists.txt")"), 16, "7");
    EXPECT_NE(errorOf(bad).find("objects[0].source.path: expected a list of file names"),
              std::string::npos)
        << errorOf(bad);
    std::string missing = text;
    missing.replace(missing.find(R"("CMakeLists.txt")"), 16, R"("nowhere.dcm")");
    EXPECT_NE(errorOf(missing).find("nowhere.dcm' does not exist"), std::string::npos)
        << errorOf(missing);
}

// A DICOM file (by its magic, 'DICM' at byte 128, whatever its name) given as a scene.
TEST(SceneFile, ADicomFileIsNotAScene) {
    const std::string path = (std::filesystem::temp_directory_path() /
                              ("lobe-scene-dicom-" + std::to_string(::getpid()) + ".json"))
                                 .string();
    {
        std::ofstream out(path, std::ios::binary);
        out << std::string(128, '\0') << "DICM" << std::string(64, '\0');
    }
    try {
        loadSceneFile(path);
        ADD_FAILURE() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("is a DICOM file, not a scene file"),
                  std::string::npos)
            << e.what();
    }
    std::filesystem::remove(path);
}

TEST(SceneFile, LevelSetKeys) {
    const SceneSpec d = parseScene(validScene(R"(, "method": "levelset")"), kBase, "scene.json");
    EXPECT_EQ(d.objects[0].method, "levelset");
    EXPECT_EQ(d.objects[0].levelSetVoxel, 0.0);
    EXPECT_EQ(d.objects[0].levelSetHalfWidth, 3.0);
    EXPECT_EQ(d.objects[0].levelSetSmooth, 0);
    const SceneSpec o = parseScene(
        validScene(
            R"(, "method": "levelset", "levelset_voxel": 0.5, "levelset_half_width": 4, "levelset_smooth": 2)"),
        kBase, "scene.json");
    EXPECT_EQ(o.objects[0].levelSetVoxel, 0.5);
    EXPECT_EQ(o.objects[0].levelSetHalfWidth, 4.0);
    EXPECT_EQ(o.objects[0].levelSetSmooth, 2);
    EXPECT_NE(errorOf(validScene(R"(, "levelset_voxel": 0.5)")).find("levelset_voxel"),
              std::string::npos);
    EXPECT_NE(errorOf(validScene(R"(, "method": "levelset", "levelset_half_width": 0.5)"))
                  .find("levelset_half_width"),
              std::string::npos);
    EXPECT_NE(errorOf(validScene(R"(, "method": "levelset", "levelset_smooth": 1.5)"))
                  .find("levelset_smooth"),
              std::string::npos);
}

}  // namespace
}  // namespace lobe

namespace lobe {

// Limits of the format: 1024 lights and 1024 objects (every light is evaluated at every shaded
// point; 600 000 lights made a render that never ends).
TEST(SceneFile, TooManyLightsAreRefusedByNumber) {
    std::string lights = "\"lights\": [";
    for (int i = 0; i < 1025; ++i)
        lights += std::string(i ? ", " : "") + "{\"position\": [1, 2, 3], \"intensity\": 1}";
    lights += "]";
    std::string text = validScene();
    const std::string one = "\"lights\": [{\"position\": [1, 2, 3], \"intensity\": [1, 2, 3]}]";
    text.replace(text.find(one), one.size(), lights);
    EXPECT_EQ(errorOf(text),
              "scene.json: lights: more than 1024 lights; a scene holds at most 1024");
    // Refused while the text is read, at the 1025th light: a syntax error after the array is
    // never reached (the count was looked at only after the whole file had been parsed, in
    // time quadratic in the array's length: 600 000 lights, 27 MB, took 101 s).
    std::string broken = text;
    broken.insert(broken.rfind('}'), ", \"late\": [1, 2,, 3]");
    EXPECT_EQ(errorOf(broken),
              "scene.json: lights: more than 1024 lights; a scene holds at most 1024");
    // The same for objects.
    std::string objects = validScene();
    const size_t at = objects.find("\"objects\": [") + std::string("\"objects\": [").size();
    std::string many;
    for (int i = 0; i < 1025; ++i) many += "{},";
    objects.insert(at, many);
    objects.insert(objects.rfind('}'), ", \"late\": [1, 2,, 3]");
    EXPECT_EQ(errorOf(objects),
              "scene.json: objects: more than 1024 objects; a scene holds at most 1024");
}

}  // namespace lobe

namespace lobe {

// A group names a file: a slash in it is refused when the scene is read (it failed after the
// batch had rendered). Transforms are judged singular relative to their size: a 1e-5 scale is
// fine, a shear of 1e12 is not.
TEST(SceneFile, GroupNamesAFileAndSingularityIsRelative) {
    std::string text = validScene();
    text.replace(text.find("\"image\""), 0, "\"group\": \"a/b\", ");
    EXPECT_NE(errorOf(text).find("scene.json: group: 'a/b' names a file"), std::string::npos)
        << errorOf(text);
    std::string tiny = validScene();
    const std::string scale = "\"scale\": [1, -1, 2]";
    tiny.replace(tiny.find(scale), scale.size(), "\"scale\": [1e-5, -1e-5, 2e-5]");
    EXPECT_EQ(errorOf(tiny), "");
    std::string shear = validScene();
    const std::string scaled = "\"scale\": [1, -1, 2], \"translate\": [10, 0, 0]";
    shear.replace(shear.find(scaled), scaled.size(),
                  "\"matrix\": [[1, 1e12, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0]]");
    EXPECT_NE(errorOf(shear).find("singular, or so nearly"), std::string::npos) << errorOf(shear);
}

}  // namespace lobe

namespace lobe {
namespace {

// The cortex shell preset with its keys, and its defaults against the shell the generated paper
// scenes spell out point by point (scripts/make_paper_scenes.py, CORTEX_TF): the same points.
TEST(SceneFile, CortexShellPreset) {
    const auto scene = [](const std::string& tf) {
        return R"({"camera": {"position": [0, 0, 5]}, "objects": [
            {"kind": "volume", "source": {"path": "test_scene_file.cpp"},
             "transfer_function": )" +
               tf + R"(, "brdf": {"model": "phong"}}]})";
    };
    const TransferFunction own =
        parseScene(scene(R"({"preset": "cortex_shell", "boundary": 0.3, "width": 0.2,
                             "opacity": 0.5, "color": [1, 0.5, 0.25]})"),
                   kBase, "s.json")
            .objects[0]
            .transfer;
    // Edges at 0.3 -+ 0.1; halfway up, 0.001 + (0.5 - 0.001) / 2 = 0.2505.
    EXPECT_NEAR(own.opacity(0.25), 0.2505, 1e-12);
    EXPECT_NEAR(own.opacity(0.3), 0.5, 1e-15);
    EXPECT_EQ(own.opacity(0.41), 0.0);
    EXPECT_EQ(own.colour(0.3)[1], 0.5);

    const SceneSpec paper =
        loadSceneFile(std::string(LOBE_SOURCE_DIR) + "/assets/scenes/paper/rendering-01.json");
    const auto& written = paper.objects[1].transfer.points();
    const SceneSpec shell = parseScene(scene(R"({"preset": "cortex_shell"})"), kBase, "s.json");
    const auto& preset = shell.objects[0].transfer.points();
    ASSERT_EQ(paper.objects[1].name, "cortex");
    ASSERT_EQ(written.size(), preset.size());
    for (size_t i = 0; i < written.size(); ++i) {
        EXPECT_NEAR(written[i].value, preset[i].value, 1e-15) << i;
        EXPECT_EQ(written[i].opacity, preset[i].opacity) << i;
        for (int b = 0; b < 3; ++b) EXPECT_EQ(written[i].colour[b], preset[i].colour[b]) << i;
    }

    EXPECT_NE(errorOf(scene(R"({"preset": "cortex_shell", "opacity": 0.0001})"))
                  .find("transfer_function.opacity"),
              std::string::npos);
    EXPECT_NE(
        errorOf(scene(R"({"preset": "cortex_shell", "index": 1})")).find("transfer_function.index"),
        std::string::npos);
}

}  // namespace
}  // namespace lobe

namespace lobe {
namespace {

// Transfer-function values as percentiles "pNN" of the volume's values. The volume: 100 voxels
// holding 1 … 100 (uint8), divided by 100, so its values are 0.01 … 1.00 and the nearest-rank
// p% percentile is the ceil(p)-th value, p / 100 (to within one of the 65 536 bins of
// [0.01, 1], 0.99 / 65536, below it: the bin's lower edge).
class TfPercentiles : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() / ("lobe_tf_percentiles_" + std::to_string(getpid()));
        fs::create_directories(dir_);
        std::ofstream raw(dir_ / "ramp.raw", std::ios::binary);
        for (int v = 1; v <= 100; ++v) raw.put(char(v));
    }
    void TearDown() override { fs::remove_all(dir_); }

    std::string scene(const std::string& tf, const std::string& source = "") const {
        return R"({"camera": {"position": [0, 0, 5]}, "objects": [
            {"kind": "volume", "source": {"path": "ramp.raw", "dims": [10, 10, 1],
                                          "divide_by": 100)" +
               source + R"(},
             "transfer_function": )" +
               tf + R"(, "brdf": {"model": "phong"}}]})";
    }
    TransferFunction resolve(const std::string& text) const {
        const SceneSpec spec = parseScene(text, dir_.string(), "s.json");
        VolumeCache cache;
        return resolvedTransfer(spec.objects[0], *cache.get(spec.objects[0].source));
    }
    std::string resolveError(const std::string& text) const {
        try {
            resolve(text);
        } catch (const Error& e) {
            return e.what();
        }
        return "";
    }

    static constexpr double kBin = 0.99 / 65536;
    fs::path dir_;
};

TEST_F(TfPercentiles, PointsAndABoundaryArePlacedAtTheVolumesPercentiles) {
    const TransferFunction tf = resolve(scene(R"({"points": [
        {"value": "p5", "opacity": 0}, {"value": "P50", "opacity": 0.5}, {"value": 0.9, "opacity": 0.5}]})"));
    ASSERT_EQ(tf.points().size(), 3u);
    EXPECT_LE(tf.points()[0].value, 0.05 + 1e-7);  // 0.05 as a float
    EXPECT_GT(tf.points()[0].value, 0.05 - kBin - 1e-7);
    EXPECT_LE(tf.points()[1].value, 0.50 + 1e-7);
    EXPECT_GT(tf.points()[1].value, 0.50 - kBin - 1e-7);
    EXPECT_EQ(tf.points()[2].value, 0.9);
    EXPECT_NEAR(tf.opacity(0.275), 0.25, 1e-4);  // halfway between p5 and p50
    // p1 is the smallest value, the lowest bin's lower edge: 0.01 exactly (as a float); p99.5 is
    // the 100th value, the top bin's lower edge 1 - 0.99/65536.
    const TransferFunction ends = resolve(scene(
        R"({"points": [{"value": "p1", "opacity": 0}, {"value": "p99.5", "opacity": 0.5}]})"));
    EXPECT_EQ(ends.points()[0].value, double(0.01f));
    EXPECT_NEAR(ends.points()[1].value, 1.0 - kBin, 1e-7);

    // A preset's boundary: the cortex shell around the median, 0.5 -+ 0.1.
    const TransferFunction shell =
        resolve(scene(R"({"preset": "cortex_shell", "boundary": "p50", "width": 0.2})"));
    const double median = shell.points()[2].value;
    EXPECT_NEAR(median, 0.5, kBin + 1e-7);
    EXPECT_NEAR(shell.points()[0].value, median - 0.1, 1e-15);
    EXPECT_NEAR(shell.points()[4].value, median + 0.1, 1e-15);
    EXPECT_EQ(shell.opacity(median), 0.2);
    EXPECT_EQ(resolve(scene(R"({"preset": "cortex", "boundary": "p50"})")).points()[0].value,
              median - 0.05);
}

// After the blur: the number `lobe info --blur-fwhm` prints for 95 % (the blurred ramp has no
// value to compute by hand; the point is that the percentile is of the blurred values).
TEST_F(TfPercentiles, AreOfTheVolumeAfterItsBlur) {
    LoadOptions options;
    options.hasLayout = true;
    options.layout.dims = {10, 10, 1};
    options.normalize = 100;
    const VolumeSummary info = summarizeVolume((dir_ / "ramp.raw").string(), options, 3.0);
    ASSERT_EQ(VolumeSummary::kPercents[3], 95.0);
    const TransferFunction tf = resolve(
        scene(R"({"points": [{"value": "p95", "opacity": 0.5}]})", R"(, "blur_fwhm_mm": 3)"));
    EXPECT_EQ(tf.points()[0].value, info.percentilesAll[3]);
    EXPECT_LT(tf.points()[0].value, 0.95 - 0.01);  // the blur pulled the top down
}

TEST_F(TfPercentiles, BadTextAndDisorderAreNamed) {
    for (const char* bad : {"p0", "p101", "q5", "95", "p", "pp5", ""}) {
        const std::string text =
            scene(std::string(R"({"points": [{"value": 0}, {"value": ")") + bad + R"("}]})");
        const std::string e = resolveError(text);
        EXPECT_NE(e.find("s.json: objects[0].transfer_function.points[1].value: '" +
                         std::string(bad) + "' is not a number or a percentile"),
                  std::string::npos)
            << bad << ": " << e;
    }
    EXPECT_NE(resolveError(scene(R"({"preset": "cortex_shell", "boundary": "median"})"))
                  .find("s.json: objects[0].transfer_function.boundary: 'median'"),
              std::string::npos);
    // Numbers out of order are found in the file; a percentile above a later number when the
    // volume is known, naming the key and the value it took.
    EXPECT_NE(
        resolveError(scene(R"({"points": [{"value": 0.5}, {"value": "p9"}, {"value": 0.4}]})"))
            .find("objects[0].transfer_function.points[2].value: points must be in non-decreasing"),
        std::string::npos);
    const std::string e = resolveError(scene(R"({"points": [{"value": "p90"}, {"value": 0.5}]})"));
    EXPECT_NE(
        e.find("s.json: objects[0].transfer_function, control point 1: values must be sorted"),
        std::string::npos)
        << e;
    EXPECT_NE(e.find("s.json: objects[0].transfer_function.points[0].value \"p90\" = 0.89"),
              std::string::npos)
        << e;
}

}  // namespace
}  // namespace lobe

namespace lobe {

// The camera's own check names the key once ("camera: camera: ..." before).
TEST(SceneFile, CameraErrorNamesTheKeyOnce) {
    std::string text = validScene();
    const size_t at = text.find("\"target\"");
    ASSERT_NE(at, std::string::npos);
    const size_t open = text.find('[', at), close = text.find(']', at);
    const size_t pos = text.find("\"position\"");
    const std::string position =
        text.substr(text.find('[', pos), text.find(']', pos) - text.find('[', pos) + 1);
    text.replace(open, close - open + 1, position);
    EXPECT_EQ(errorOf(text), "scene.json: camera: position and target are the same point");
}

}  // namespace lobe
