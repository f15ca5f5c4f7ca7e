// `lobe render --clip` and `--shadows` as a user meets them: each gives exactly the image of the
// scene with the same key written in its file (the command line replaces the scene's top-level
// "clip" and its "shadows"), changes the image, and a bad value is one error line with nothing
// written. Each test runs the built binary (LOBE_EXE) in a folder of its own.
//
// Scene (unit voxels, world = index): a floor — a 32×32×8 grid of ones at k = 1…3 inside
// i, j = 1…30, whose iso-0.5 top face is the plane z = 3.5 — and a ball of radius 5 about
// (16, 16, 13) (a 32³ grid of 6 − |x − c| at iso 1) above it, lit from straight above, seen from
// the side and above: the ball's shadow falls on the floor under it.
#include "cli_harness.h"
#include "core/image_output.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using lobe::test::CliRun;
using lobe::test::quote;

fs::path testDir() { return lobe::test::testDir("cli-clip-shadows"); }

CliRun lobe(const std::string& args) {
    return lobe::test::runShell(
        quote(LOBE_EXE) + " " + args,
        fs::path(LOBE_BINARY_DIR) / "test-output" / "cli-clip-shadows" / "_io");
}

void writeFloats(const fs::path& p, const std::vector<float>& v) {
    std::ofstream(p, std::ios::binary)
        .write(reinterpret_cast<const char*>(v.data()), std::streamsize(v.size() * sizeof(float)));
}

// The scene file NAME.json in d with `top` added at the top level (e.g. a "clip" or "shadows"
// key with its trailing comma); the volumes beside it.
std::string sceneFile(const fs::path& d, const std::string& name, const std::string& top) {
    if (!fs::exists(d / "floor.raw")) {
        std::vector<float> floor(32 * 32 * 8, 0.0f), ball(32 * 32 * 32);
        for (int k = 1; k <= 3; ++k)
            for (int j = 1; j <= 30; ++j)
                for (int i = 1; i <= 30; ++i) floor[(k * 32 + j) * 32 + i] = 1.0f;
        for (int k = 0; k < 32; ++k)
            for (int j = 0; j < 32; ++j)
                for (int i = 0; i < 32; ++i)
                    ball[(k * 32 + j) * 32 + i] =
                        float(6.0 - std::sqrt((i - 16.0) * (i - 16.0) + (j - 16.0) * (j - 16.0) +
                                              (k - 13.0) * (k - 13.0)));
        writeFloats(d / "floor.raw", floor);
        writeFloats(d / "ball.raw", ball);
    }
    const fs::path path = d / (name + ".json");
    std::ofstream(path) << R"({"image": {"width": 24, "height": 20, "samples_per_pixel": 1},
      "camera": {"position": [-20, 16, 34], "target": [16, 16, 6], "up": [0, 0, 1], "fov_deg": 55},
      "lights": [{"position": [16, 16, 60], "intensity": 3000}],
      "backdrop": {"enabled": false}, )"
                        << top << R"(
      "objects": [
        {"name": "floor", "kind": "isosurface", "source": {"path": "floor.raw", "dims": [32, 32, 8],
         "type": "float32"}, "iso": 0.5, "brdf": {"model": "lambert", "kd": 0}, "kd": 0.6},
        {"name": "ball", "kind": "isosurface", "source": {"path": "ball.raw", "dims": [32, 32, 32],
         "type": "float32"}, "iso": 1, "brdf": {"model": "ward"}, "kd": 0.4}]})";
    return path.string();
}

// Renders `scene` with `args` into d/NAME and returns its EXR's floats.
std::vector<float> render(const fs::path& d, const std::string& scene, const std::string& args,
                          const std::string& name) {
    const fs::path out = d / name;
    const CliRun r =
        lobe("render " + quote(scene) + " " + args + " --quiet --out " + quote(out.string()));
    EXPECT_EQ(r.exitCode, 0) << args << "\n" << r.err;
    const std::string stem = fs::path(scene).stem().string();
    if (!fs::exists(out / (stem + ".exr"))) return {};
    return lobe::readFloatImage((out / (stem + ".exr")).string()).channels.data;
}

double sum(const std::vector<float>& v) {
    double s = 0.0;
    for (const float x : v) s += x;
    return s;
}

TEST(CliClipShadows, ClipOnTheCommandLineIsTheScenesClip) {
    const fs::path d = testDir();
    const std::string plain = sceneFile(d, "plain", "");
    const std::vector<float> whole = render(d, plain, "", "whole");
    ASSERT_FALSE(whole.empty());
    // A plane through the ball's centre keeping +x (the half facing away from the camera), and a
    // capped cut-away box over the ball's top front corner.
    const std::string plane = "plane:16,0,0,1,0,0";
    const std::string planeJson =
        R"("clip": [{"plane": {"point": [16, 0, 0], "normal": [1, 0, 0]}}],)";
    const std::string box = "box:0,0,13,16,32,40:invert:cap";
    const std::string boxJson =
        R"("clip": [{"box": {"min": [0, 0, 13], "max": [16, 32, 40]}, "invert": true, "cap": true}],)";
    for (const auto& [option, json] :
         std::vector<std::pair<std::string, std::string>>{{plane, planeJson}, {box, boxJson}}) {
        SCOPED_TRACE(option);
        const std::vector<float> cut = render(d, plain, "--clip " + option, "cut");
        const std::vector<float> file = render(d, sceneFile(d, "file", json), "", "file");
        ASSERT_EQ(cut.size(), whole.size());
        EXPECT_EQ(cut, file);   // the same shapes as the scene's own key
        EXPECT_NE(cut, whole);  // and they cut
        // --clip replaces the scene's top-level shapes: the other cut in the file is gone.
        const std::string other = option == plane ? boxJson : planeJson;
        const std::vector<float> replaced =
            render(d, sceneFile(d, "other", other), "--clip " + option, "replaced");
        EXPECT_EQ(replaced, cut);
    }
    // Two shapes: an object keeps what both keep.
    const std::vector<float> both = render(d, plain, "--clip " + plane + " --clip " + box, "both");
    const std::vector<float> bothFile =
        render(d,
               sceneFile(d, "bothfile",
                         R"("clip": [{"plane": {"point": [16, 0, 0], "normal": [1, 0, 0]}},
                      {"box": {"min": [0, 0, 13], "max": [16, 32, 40]}, "invert": true, "cap": true}],)"),
               "", "bothfile");
    EXPECT_EQ(both, bothFile);
}

TEST(CliClipShadows, ShadowsOnTheCommandLineAreTheScenesShadows) {
    const fs::path d = testDir();
    const std::string plain = sceneFile(d, "plain", "");
    const std::vector<float> off = render(d, plain, "", "off");
    ASSERT_FALSE(off.empty());
    for (const std::string mode : {"exact", "cached"}) {
        SCOPED_TRACE(mode);
        const std::vector<float> cli = render(d, plain, "--shadows " + mode, "cli-" + mode);
        const std::vector<float> file =
            render(d, sceneFile(d, "file-" + mode, R"("shadows": ")" + mode + R"(",)"), "",
                   "file-" + mode);
        ASSERT_EQ(cli.size(), off.size());
        EXPECT_EQ(cli, file);
        // The ball's shadow darkens the floor: less light in the image, never more per value.
        EXPECT_LT(sum(cli), 0.99 * sum(off));
        for (size_t i = 0; i < off.size(); ++i) ASSERT_LE(cli[i], off[i] * (1 + 1e-6f) + 1e-9f);
        // --shadows off overrides a scene's shadows.
        EXPECT_EQ(render(d, sceneFile(d, "file-" + mode, R"("shadows": ")" + mode + R"(",)"),
                         "--shadows off", "off-" + mode),
                  off);
    }
}

TEST(CliClipShadows, BadClipAndShadowsAreOneLineAndWriteNothing) {
    const fs::path d = testDir();
    const std::string plain = sceneFile(d, "plain", "");
    std::string nine;
    for (int i = 0; i < 9; ++i) nine += " --clip plane:0,0,0,0,0,1";
    for (const auto& [args, message] : std::vector<std::pair<std::string, std::string>>{
             {"--shadows soft", "--shadows"},
             {"--clip plane:1,2,3", "--clip: expected plane:x,y,z,nx,ny,nz"},
             {"--clip box:0,0,0,1,1,1:flip", "got 'box:0,0,0,1,1,1:flip'"},
             {"--clip plane:0,0,0,0,0,0", "normal must not be zero"},
             {"--clip box:1,0,0,0,1,1", "x0 < x1"},
             {"--clip sphere:1,2,3,4,5,6", "--clip: expected"},
             {"--clip plane:0,0,0,nan,0,1", "--clip: expected"},
             {nine, "at most 8 shapes"}}) {
        const CliRun r =
            lobe("render " + quote(plain) + " " + args + " --out " + quote((d / "out").string()));
        EXPECT_EQ(r.exitCode, 1) << args;
        EXPECT_EQ(r.errLines(), 1) << args << "\n" << r.err;
        EXPECT_EQ(r.err.rfind("lobe: error: ", 0), 0u) << r.err;
        EXPECT_NE(r.err.find(message), std::string::npos) << args << "\n" << r.err;
        EXPECT_FALSE(fs::exists(d / "out")) << args;
    }
}

}  // namespace
