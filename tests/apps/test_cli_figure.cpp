// `lobe render` figure output from the command line (apps/figure_output.h): -o FILE, the
// transparent and colour backgrounds with alpha checked on pixels whose coverage is known (the
// CThead skull as an opaque surface covers the image centre; the corner sees past it), the
// provenance read back (by OpenImageIO and by `oiiotool --info -v`), the refusals before
// anything renders, and the warnings for an empty image and an invisible volume.
#include "core/image_output.h"
#include "cli_harness.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

namespace {

namespace fs = std::filesystem;

const std::string kLobe = LOBE_EXE;
const std::string kSource = LOBE_SOURCE_DIR;

using lobe::test::CliRun;
using lobe::test::quote;
using lobe::test::readFile;

fs::path testDir() { return lobe::test::testDir("cli_figure"); }

CliRun run(const std::string& command, const fs::path& d) { return lobe::test::runShell(command, d); }

CliRun lobe(const std::string& args, const fs::path& d) { return run(quote(kLobe) + " " + args, d); }

// The CThead skull alone as an opaque surface, seen as in the paper's rendering 1 (the head fills
// the middle; the corners see the backdrop). `cameraAway`: the camera looks the other way.
// `extraObject`: JSON of a second object, appended.
std::string skullScene(const fs::path& d, const std::string& name, bool cameraAway = false,
                       const std::string& extraObject = "") {
    const std::string target = cameraAway ? "[901.96, -660.96, 116.0]" : "[110.0, 131.0, 116.0]";
    std::string text = R"({
 "title": "opaque skull",
 "image": {"width": 32, "height": 32, "samples_per_pixel": 1, "seed": 1},
 "camera": {"position": [505.98, -264.98, 116.0], "target": )" + target + R"(,
            "up": [0, 0, -1], "fov_deg": 30},
 "lights": [{"position": [647.438, -194.233, 266.052], "intensity": 417130.9}],
 "objects": [
  {"name": "skull", "kind": "isosurface",
   "source": {"path": ")" + kSource + R"(/assets/cthead/cthead.nhdr", "divide_by": 3272, "background": 100},
   "iso": 0.5, "opacity": 1.0, "brdf": {"model": "ward"}})" +
                       (extraObject.empty() ? "" : ",\n  " + extraObject) + "\n ]\n}\n";
    const fs::path path = d / name;
    std::ofstream(path) << text;
    return path.string();
}

struct Rgba {
    int width = 0, height = 0, channels = 0;
    std::vector<unsigned char> data;
    const unsigned char* at(int x, int y) const { return &data[(size_t(y) * width + x) * channels]; }
};

Rgba readPng(const fs::path& p) {
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    auto in = OIIO::ImageInput::open(p.string(), &config);
    Rgba img;
    if (!in) return img;
    img.width = in->spec().width;
    img.height = in->spec().height;
    img.channels = in->spec().nchannels;
    img.data.resize(size_t(img.width) * img.height * img.channels);
    in->read_image(0, 0, 0, img.channels, OIIO::TypeDesc::UINT8, img.data.data());
    return img;
}

TEST(CliFigure, TransparentBackgroundHasCoverageAsAlpha) {
    const fs::path d = testDir();
    const std::string scene = skullScene(d, "skull.json");
    const CliRun r = lobe("render " + quote(scene) + " --quiet --background none -o " +
                              quote((d / "fig.png").string()) + " --exr",
                          d);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(r.err, "");
    // Only the files asked for: no out/ folder, no NAME.png.
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(d)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    EXPECT_EQ(names, (std::vector<std::string>{"fig.exr", "fig.png", "skull.json"}));

    const Rgba png = readPng(d / "fig.png");
    ASSERT_EQ(png.channels, 4);
    ASSERT_EQ(png.width, 32);
    // Centre: behind the opaque skull surface, T = 0: alpha exactly 1. Corner: no object, alpha 0
    // and no colour.
    EXPECT_EQ(png.at(16, 16)[3], 255);
    EXPECT_GT(int(png.at(16, 16)[0]) + png.at(16, 16)[1] + png.at(16, 16)[2], 0);
    for (int c = 0; c < 4; ++c) EXPECT_EQ(png.at(0, 0)[c], 0) << c;
    // The EXR: channel A with the same coverage, colour premultiplied (0 where alpha is 0).
    const lobe::FloatImage exr = lobe::readFloatImage((d / "fig.exr").string());
    ASSERT_GE(exr.channels.names.size(), 4u);
    EXPECT_EQ(exr.channels.names[3], "A");
    const size_t k = exr.channels.names.size();
    EXPECT_EQ(exr.channels.data[(16 * 32 + 16) * k + 3], 1.0f);
    for (size_t c = 0; c < k; ++c) EXPECT_EQ(exr.channels.data[c], 0.0f) << exr.channels.names[c];
    // Every alpha in [0, 1], and PNG alpha = EXR alpha to 8-bit rounding.
    for (int p = 0; p < 32 * 32; ++p) {
        const float a = exr.channels.data[size_t(p) * k + 3];
        ASSERT_TRUE(a >= 0.0f && a <= 1.0f);
        EXPECT_EQ(png.data[size_t(p) * 4 + 3], std::lround(a * 255.0f)) << p;
    }

    // A colour background: white where nothing covers, the same pixel where the skull covers.
    const CliRun w = lobe("render " + quote(scene) + " --quiet --background '#ffffff' -o " +
                              quote((d / "white.png").string()),
                          d);
    ASSERT_EQ(w.exitCode, 0) << w.err;
    const Rgba white = readPng(d / "white.png");
    ASSERT_EQ(white.channels, 3);
    for (int c = 0; c < 3; ++c) {
        EXPECT_EQ(white.at(0, 0)[c], 255) << c;
        EXPECT_EQ(white.at(16, 16)[c], png.at(16, 16)[c]) << c;
    }
}

TEST(CliFigure, ProvenanceReadsBackFromPngAndExr) {
    const fs::path d = testDir();
    const std::string scene = skullScene(d, "skull.json");
    const CliRun r = lobe("render " + quote(scene) + " --quiet --seed 5 --png-bits 16 --out " +
                              quote((d / "out").string()),
                          d);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    for (const char* file : {"skull.png", "skull.exr"}) {
        const fs::path path = d / "out" / file;
        const lobe::ImageAttributes a = lobe::readImageAttributes(path.string());
        ASSERT_TRUE(a.count("lobe:scene_json")) << file;
        EXPECT_EQ(a.at("lobe:scene_json"), readFile(scene)) << file;
        EXPECT_EQ(a.at("lobe:seed"), "5") << file;
        EXPECT_EQ(a.at("lobe:scene_file"), scene) << file;
        EXPECT_NE(a.at("lobe:command_line").find(" render "), std::string::npos) << file;
        EXPECT_NE(a.at("lobe:command_line").find("--seed 5 --png-bits 16"), std::string::npos) << file;
        EXPECT_FALSE(a.at("lobe:version").empty()) << file;
        EXPECT_NE(a.at("lobe:render_settings").find("32x32 spp 1 seed 5"), std::string::npos) << file;
        // The same through OpenImageIO's command-line tool.
        const CliRun info = run("oiiotool --info -v " + quote(path.string()), d);
        ASSERT_EQ(info.exitCode, 0) << info.err;
        EXPECT_NE(info.out.find("lobe:seed: \"5\""), std::string::npos) << info.out;
        EXPECT_NE(info.out.find("lobe:scene_json:"), std::string::npos) << info.out;
    }
    auto in = OIIO::ImageInput::open((d / "out" / "skull.png").string());
    ASSERT_TRUE(in);
    EXPECT_EQ(in->spec().format, OIIO::TypeDesc::UINT16);
}

TEST(CliFigure, BadFigureOptionsAreRefusedBeforeRendering) {
    const fs::path d = testDir();
    const std::string a = skullScene(d, "a.json"), b = skullScene(d, "b.json");
    const struct {
        std::string args, message;
    } cases[] = {
        {quote(a) + " " + quote(b) + " -o " + quote((d / "x.png").string()), "2 scenes were given"},
        {quote(a) + " -o " + quote((d / "x.bmp").string()), "unsupported image extension '.bmp'"},
        {quote(a) + " -o " + quote((d / "no" / "x.png").string()), "does not exist"},
        {quote(a) + " --exr", "--exr goes with -o"},
        {quote(a) + " --background none -o " + quote((d / "x.jpg").string()), "JPEG"},
        {quote(a) + " --png-bits 16 -o " + quote((d / "x.jpg").string()), "--png-bits 16 needs"},
        {quote(a) + " --background '#12345'", "is not one of backdrop, none"},
    };
    for (const auto& c : cases) {
        const CliRun r = lobe("render " + c.args + " --quiet", d);
        EXPECT_EQ(r.exitCode, 1) << c.args;
        EXPECT_NE(r.err.find(c.message), std::string::npos) << c.args << "\n" << r.err;
        EXPECT_FALSE(fs::exists(d / "x.png") || fs::exists(d / "x.jpg") || fs::exists(d / "out"))
            << c.args;
    }
    // A scene's "background" key is checked like every key.
    std::string text = readFile(a);
    text.replace(text.find("\"title\""), 7, "\"background\": [0.5, 2, 0], \"title\"");
    std::ofstream(d / "c.json") << text;
    const CliRun r = lobe("render " + quote((d / "c.json").string()) + " --check", d);
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find("c.json: background: background colour [0.5, 2, 0] has a component "
                         "outside [0, 1]"),
              std::string::npos)
        << r.err;
}

TEST(CliFigure, EmptyImageAndInvisibleVolumeAreWarnedAbout) {
    const fs::path d = testDir();
    // The camera looking away from the skull: every pixel is backdrop.
    const std::string away = skullScene(d, "away.json", true);
    CliRun r = lobe("render " + quote(away) + " --quiet -o " + quote((d / "away.png").string()), d);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(r.err, "lobe: warning: " + away +
                         ": the image is empty: no object covers any pixel (every pixel is "
                         "background; check the camera and the objects)\n");
    // A volume whose transfer function starts far above the data's values (the T1 divided by 255
    // is within [0, 1]): opacity 0 at every voxel.
    const std::string cortex = R"({"name": "cortex", "kind": "volume",
   "source": {"path": ")" + kSource + R"(/assets/brain/mni_icbm152_t1_tal_nlin_sym_09a_converted.nii.gz", "divide_by": 255},
   "transfer_function": {"points": [{"value": 5, "opacity": 0}, {"value": 6, "opacity": 0.2}]},
   "brdf": {"model": "ward"}})";
    const std::string scene = skullScene(d, "tf.json", false, cortex);
    r = lobe("render " + quote(scene) + " --quiet -o " + quote((d / "tf.png").string()), d);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(r.err.find("lobe: warning: " + scene + ": objects[1] (cortex): its transfer function "
                         "gives opacity 0 to every voxel of its volume"),
              0u)
        << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

}  // namespace
