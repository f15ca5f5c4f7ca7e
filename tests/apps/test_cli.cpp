// The `lobe` command line as a user meets it: exit codes, one error line naming the thing, no
// output written on bad input, and hand values from `lobe brdf eval`. Each test runs the built
// binary (LOBE_EXE) in a shell with its own temporary folder, so parallel ctest processes never
// share files.
#include "cli_harness.h"
#include "core/image_output.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

const std::string kLobe = LOBE_EXE;
const std::string kSource = LOBE_SOURCE_DIR;

using lobe::test::CliRun;
using lobe::test::quote;
using lobe::test::readFile;

// A folder of the test's own.
fs::path testDir() { return lobe::test::testDir("cli"); }

// Runs `lobe ARGS` with `input` on standard input.
CliRun lobe(const std::string& args, const std::string& input = "") {
    return lobe::test::runShell(quote(kLobe) + " " + args,
                                fs::path(LOBE_BINARY_DIR) / "test-output" / "cli" / "_io", input);
}

// ---- lobe brdf ------------------------------------------------------------------------------

// Hand values: Ward (docs/models.md model 4) with wo the mirror of wi has H = wi + wo along n, so
// the exponential is exp(0) = 1 and f = rho_s / (4π αx αy sqrt(cos θi cos θo)). At the defaults
// αx = 0.05, αy = 0.3 and normal incidence: f = rho_s / (4π·0.015) = 5.305164769729845·rho_s,
// i.e. 0.2652582385, 0.530516477, 1.061032954 (%.10g) for rho_s = 0.05, 0.1, 0.2; at θi = θo = 60°
// (cos = 0.5) twice that. Inputs need not be unit vectors (the second line is the first scaled),
// and blank lines are skipped.
TEST(Cli, BrdfEvalWardHandValues) {
    const CliRun r = lobe("brdf eval ward rho_s=0.05,0.1,0.2",
                          "0,0,1,0,0,1\n 0, 0, 2 ,0,0,5\n\n"
                          "1.7320508075688772,0,1,-1.7320508075688772,0,1\n");
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(r.out,
              "0.2652582385,0.530516477,1.061032954\n0.2652582385,0.530516477,1.061032954\n"
              "0.530516477,1.061032954,2.122065908\n");
}

TEST(Cli, BrdfEvalMalformedLineNamesItsNumber) {
    // Line 3, counting the blank line 2.
    const CliRun r = lobe("brdf eval ward", "0,0,1,0,0,1\n\n0,0,1,0,zero,1\n");
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_EQ(
        r.err.rfind("lobe: error: standard input line 3: expected six comma-separated numbers", 0),
        0u)
        << r.err;
    EXPECT_EQ(r.errLines(), 1);
}

// A NUL byte inside a field ends strtod's reading, not the field: "1\0x" is not a number (it
// was read as 1).
TEST(Cli, BrdfEvalNulInsideAFieldIsRefused) {
    std::string input = "0,0,1,0,0,1\n0,0,1";
    input += '\0';
    input += "x,0,0,1\n";
    const CliRun r = lobe("brdf eval ward", input);
    EXPECT_EQ(r.exitCode, 1) << r.out;
    EXPECT_EQ(
        r.err.rfind("lobe: error: standard input line 2: expected six comma-separated numbers", 0),
        0u)
        << r.err;
    EXPECT_EQ(r.errLines(), 1);
}

// --samples of brdf props is bounded (8 x samples pairs overflowed an int at 300 000 000 and the
// run never ended), and overlap's --threads must not be negative.
TEST(Cli, BrdfPropsSamplesAndOverlapThreadsAreBounded) {
    CliRun r = lobe("brdf props --samples 300000000");
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_EQ(r.err, "lobe: error: --samples 300000000: expected 64 to 16777216\n");
    r = lobe("overlap --threads -1 --quiet --out " + quote((testDir() / "o").string()));
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_EQ(r.err.rfind("lobe: error: --threads -1: must be ≥ 0", 0), 0u) << r.err;
    EXPECT_EQ(r.errLines(), 1) << r.err;
}

TEST(Cli, BrdfEvalUnknownModelAndParameterAreNamed) {
    CliRun r = lobe("brdf eval blinn");
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find("unknown BRDF model 'blinn'"), std::string::npos) << r.err;
    r = lobe("brdf eval ward alpha=0.1");
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find("unknown parameter 'alpha' for ward"), std::string::npos) << r.err;
    // Poulin–Fournier's `intervals` changed nothing in a render: no longer a parameter.
    r = lobe("brdf eval poulin_fournier intervals=64");
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find("intervals"), std::string::npos) << r.err;
}

// Directions are normalised without overflow or underflow (1e308 and 1e-300 components); a
// parameter given twice is refused rather than the last silently winning.
TEST(Cli, BrdfEvalExtremeComponentsAndDuplicateParameters) {
    CliRun r = lobe("brdf eval ward",
                    "1e308,0,1e308,-1e308,0,1e308\n1e-300,0,1e-300,-1e-300,0,1e-300\n"
                    "1,0,1,-1,0,1\n");
    EXPECT_EQ(r.exitCode, 0) << r.err;
    std::istringstream lines(r.out);
    std::string huge, tiny, unit;
    std::getline(lines, huge);
    std::getline(lines, tiny);
    std::getline(lines, unit);
    EXPECT_EQ(huge, unit);
    EXPECT_EQ(tiny, unit);
    EXPECT_NE(unit, "0,0,0");
    r = lobe("brdf eval phong exponent=10 exponent=20", "0,0,1,0,0,1\n");
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find("parameter 'exponent' given twice"), std::string::npos) << r.err;
    // In range, Lafortune (cz = 2, n = 1100) exceeds a double at normal incidence: clamped.
    r = lobe("brdf eval lafortune cz=2 exponent=1100", "0,0,1,0,0,1\n");
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(r.out, "1e+30,1e+30,1e+30\n");
}

TEST(Cli, BrdfListListsAllTenInThePapersOrder) {
    const CliRun r = lobe("brdf list");
    ASSERT_EQ(r.exitCode, 0);
    std::string names;
    std::istringstream lines(r.out);
    for (std::string line; std::getline(lines, line);) {
        const auto sep = line.find("  (");
        if (sep != std::string::npos && line[0] >= 'a' && line[0] <= 'z')
            names += line.substr(0, sep) + " ";
    }
    EXPECT_EQ(names,
              "phong strauss schlick_lewis ward cook_torrance poulin_fournier he_torrance "
              "lafortune ashikhmin_shirley lambert ");
}

// ---- lobe render, demo, contact-sheet ---------------------------------------------------------

// The paper's rendering 1 copied next to the test with a mutation, data paths made absolute.
std::string sceneWith(const fs::path& dir, const std::string& from, const std::string& to) {
    std::string text = readFile(kSource + "/assets/scenes/paper/rendering-01.json");
    for (size_t p; (p = text.find("\"../../")) != std::string::npos;)
        text.replace(p, 7, "\"" + kSource + "/assets/");
    if (!from.empty()) {
        const auto p = text.find(from);
        EXPECT_NE(p, std::string::npos) << from;
        text.replace(p, from.size(), to);
    }
    const fs::path path = dir / "scene.json";
    std::ofstream(path) << text;
    return path.string();
}

TEST(Cli, RenderBadSceneWritesNothing) {
    const fs::path d = testDir();
    const std::string scene = sceneWith(d, "\"iso\": 0.5", "\"iso\": 0.5, \"isovalue\": 0.5");
    const CliRun r = lobe("render " + quote(scene) + " --out " + quote((d / "out").string()));
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find("objects[0].isovalue: unknown key"), std::string::npos) << r.err;
    EXPECT_EQ(r.errLines(), 1);
    EXPECT_FALSE(fs::exists(d / "out"));
}

TEST(Cli, RenderOfAVolumeSaysItWantsASceneFile) {
    const fs::path d = testDir();
    const CliRun r =
        lobe("render " + quote(kSource + "/assets/brain/grey_icbm151_smooth8mm_FieldMap.nii.gz") +
             " --out " + quote((d / "out").string()));
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find("is a volume, not a scene file"), std::string::npos) << r.err;
    EXPECT_EQ(r.errLines(), 1);
    EXPECT_FALSE(fs::exists(d / "out"));
}

TEST(Cli, DemoTinyWritesBothImages) {
    const fs::path d = testDir() / "demo";
    const CliRun r = lobe("demo --size 24 --spp 1 --quiet --out " + quote(d.string()));
    EXPECT_EQ(r.exitCode, 0) << r.err;
    for (const char* f : {"rendering-01.png", "rendering-01.exr", "gallery.png", "gallery.exr"}) {
        EXPECT_GT(fs::file_size(d / f), 0u) << f;
        // The provenance `lobe render` records (figure/figure_output.h), here too.
        const lobe::ImageAttributes a = lobe::readImageAttributes((d / f).string());
        ASSERT_TRUE(a.count("lobe:command_line")) << f;
        EXPECT_NE(a.at("lobe:command_line").find(" demo --size 24 --spp 1"), std::string::npos)
            << f;
        EXPECT_FALSE(a.at("lobe:version").empty()) << f;
        EXPECT_EQ(a.at("lobe:seed"), "1") << f;
    }
    const lobe::ImageAttributes scene =
        lobe::readImageAttributes((d / "rendering-01.exr").string());
    EXPECT_EQ(scene.at("lobe:scene_json"),
              readFile(kSource + "/assets/scenes/paper/rendering-01.json"));
    EXPECT_NE(scene.at("lobe:render_settings").find("24x24 spp 1 seed 1"), std::string::npos);
    EXPECT_NE(lobe::readImageAttributes((d / "gallery.png").string())
                  .at("lobe:render_settings")
                  .find("cell 256 spp 4 seed 1"),
              std::string::npos);
}

TEST(Cli, ContactSheetAndAMissingImageNamed) {
    const fs::path d = testDir();
    ASSERT_EQ(
        lobe("gallery --cell 16 --spp 1 --seed 3 --quiet --out " + quote(d.string())).exitCode, 0);
    for (const char* f : {"gallery.png", "gallery.exr"}) {
        const lobe::ImageAttributes a = lobe::readImageAttributes((d / f).string());
        ASSERT_TRUE(a.count("lobe:render_settings")) << f;
        EXPECT_EQ(a.at("lobe:render_settings"), "cell 16 spp 1 seed 3 light 12") << f;
        EXPECT_EQ(a.at("lobe:seed"), "3") << f;
        EXPECT_NE(a.at("lobe:command_line").find(" gallery --cell 16"), std::string::npos) << f;
    }
    CliRun r = lobe("contact-sheet --out " + quote((d / "sheet.jpg").string()) + " --thumb 64 " +
                    quote((d / "gallery.png").string() + "=one") + " " +
                    quote((d / "gallery.exr").string() + "=two"));
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_GT(fs::file_size(d / "sheet.jpg"), 0u);
    // A PNG sheet records its command line and captions (non-ASCII as \uXXXX, as elsewhere).
    r = lobe("contact-sheet --out " + quote((d / "sheet.png").string()) + " --thumb 64 " +
             quote((d / "gallery.png").string() + "=one") + " " +
             quote((d / "gallery.exr").string() + "=tw\xc3\xb6"));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const lobe::ImageAttributes sheet = lobe::readImageAttributes((d / "sheet.png").string());
    ASSERT_TRUE(sheet.count("lobe:sheet_captions"));
    EXPECT_EQ(sheet.at("lobe:sheet_captions"), "one\ntw\\u00f6");
    EXPECT_NE(sheet.at("lobe:command_line").find(" contact-sheet --out "), std::string::npos);
    r = lobe("contact-sheet --out " + quote((d / "bad.png").string()) + " " +
             quote((d / "none.png").string()));
    EXPECT_NE(r.exitCode, 0);
    EXPECT_NE(r.err.find("none.png"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(d / "bad.png"));
}

// A damaged PNG given to contact-sheet is Lobe's one line: libpng's own ("libpng error: IDAT:
// Read error: hit end of file", "PNG library error") are not printed beside it.
TEST(Cli, ADamagedPngIsOneErrorLine) {
    const fs::path d = testDir();
    ASSERT_EQ(
        lobe("gallery --cell 16 --spp 1 --seed 3 --quiet --out " + quote(d.string())).exitCode, 0);
    const std::string whole = readFile(d / "gallery.png");
    std::ofstream(d / "cut.png", std::ios::binary) << whole.substr(0, whole.size() / 2);
    const CliRun r = lobe("contact-sheet --out " + quote((d / "s.png").string()) + " " +
                          quote((d / "cut.png").string()));
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_EQ(r.errLines(), 1) << r.err;
    EXPECT_EQ(r.err.rfind("lobe: error: cannot read image '" + (d / "cut.png").string() + "'", 0),
              0u)
        << r.err;
    EXPECT_FALSE(fs::exists(d / "s.png"));
}

// More threads than cores under --quiet: nothing on stderr (TBB warned "The number of workers is
// currently limited").
TEST(Cli, ManyThreadsUnderQuietPrintNothing) {
    const fs::path d = testDir();
    const CliRun r =
        lobe("gallery --cell 16 --spp 1 --quiet --threads 64 --out " + quote(d.string()));
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(r.err, "");
}

TEST(Cli, RenderPreviewAndRouletteOverrides) {
    const fs::path d = testDir();
    const std::string scene = kSource + "/assets/scenes/paper/rendering-01.json";
    CliRun r = lobe("render " + quote(scene) +
                    " --preview --width 32 --roulette 0 --no-contact-sheets --out " +
                    quote((d / "out").string()));
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.err.find("32x32, 1 spp"), std::string::npos) << r.err;
    // A preview's names cannot replace a full render's.
    EXPECT_GT(fs::file_size(d / "out" / "rendering-01-preview.png"), 0u);
    EXPECT_FALSE(fs::exists(d / "out" / "rendering-01.png"));
    r = lobe("render " + quote(scene) + " --roulette 0.7 --out " + quote((d / "bad").string()));
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_EQ(r.errLines(), 1);
    EXPECT_NE(r.err.find("roulette"), std::string::npos);
    EXPECT_FALSE(fs::exists(d / "bad"));
}

TEST(Cli, RenderRefusesOutOfRangeOverridesBeforeWriting) {
    const fs::path d = testDir();
    const std::string scene = kSource + "/assets/scenes/paper/rendering-01.json";
    for (const char* bad : {"--width 0", "--spp 0", "--seed -1", "--step nan", "--step 1e-9",
                            "--threads -1", "--height 20000"}) {
        const CliRun r =
            lobe("render " + quote(scene) + " " + bad + " --out " + quote((d / "out").string()));
        EXPECT_NE(r.exitCode, 0) << bad;
        EXPECT_FALSE(r.err.empty()) << bad;
        EXPECT_FALSE(fs::exists(d / "out")) << bad;
    }
}

// A bad output folder or contact-sheet size is an input error (exit 1, one line naming it)
// found before anything renders — not an internal error after the renders.
TEST(Cli, RenderRefusesBadOutputFoldersAndSheetSizesFirst) {
    const fs::path d = testDir();
    const std::string scene = kSource + "/assets/scenes/paper/rendering-01.json";
    std::ofstream(d / "afile") << "x";
    const struct {
        std::string args, message;
    } cases[] = {
        {"--out " + quote((d / "afile").string()), "is a file, not a folder"},
        {"--out ''", "the output folder's name is empty"},
        {"--out " + quote((d / "afile" / "sub").string()), "cannot create the folder"},
        {"--sheet-thumb -5 --out " + quote((d / "o1").string()), "--sheet-thumb"},
        {"--sheet-thumb 100000000 --out " + quote((d / "o2").string()), "--sheet-thumb"},
    };
    for (const auto& c : cases) {
        const CliRun r = lobe("render " + quote(scene) + " --width 16 --spp 1 --quiet " + c.args);
        EXPECT_EQ(r.exitCode, 1) << c.args << ": " << r.err;
        EXPECT_NE(r.err.find(c.message), std::string::npos) << c.args << ": " << r.err;
        EXPECT_EQ(r.err.find("internal error"), std::string::npos) << c.args << ": " << r.err;
    }
    EXPECT_FALSE(fs::exists(d / "o1"));
    EXPECT_FALSE(fs::exists(d / "o2"));
}

// A key given twice in one JSON object, and nesting deeper than a scene needs (75 000 levels
// overflowed the stack), are one error naming the file.
TEST(Cli, SceneWithDuplicateKeysOrDeepNestingIsRefused) {
    const fs::path d = testDir();
    const std::string dup = sceneWith(d, "\"iso\": 0.5", "\"iso\": 0.5, \"iso\": 0.6");
    CliRun r = lobe("render " + quote(dup) + " --check");
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find("key 'iso' given twice in one object"), std::string::npos) << r.err;
    std::string deep;
    for (int i = 0; i < 75000; ++i) deep += "{\"a\":";
    deep += "1";
    deep += std::string(75000, '}');
    std::ofstream(d / "deep.json") << deep;
    r = lobe("render " + quote((d / "deep.json").string()) + " --check");
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find("deep.json: nested more than 64 levels deep"), std::string::npos) << r.err;
}

// Parameters in range whose highlight exceeds any float: the EXR holds finite values only and
// the PNG shows the highlight white (an Inf used to become a black disc).
TEST(Cli, AnOverflowingHighlightIsFiniteAndWhite) {
    const fs::path d = testDir();
    const std::string scene = sceneWith(d, "\"model\": \"ward\"",
                                        "\"model\": \"lafortune\", \"cz\": 2, \"exponent\": 1100");
    const CliRun r = lobe("render " + quote(scene) + " --width 48 --spp 1 --quiet --out " +
                          quote((d / "out").string()));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const lobe::FloatImage exr = lobe::readFloatImage((d / "out" / "scene.exr").string());
    size_t huge = 0;
    for (const float v : exr.channels.data) {
        ASSERT_TRUE(std::isfinite(v));
        if (v > 1e20f) ++huge;
    }
    EXPECT_GT(huge, 0u);  // the highlight is there, clamped, not zeroed
    const lobe::RgbImage png = lobe::readImage((d / "out" / "scene.png").string());
    size_t white = 0;
    for (size_t p = 0; p < png.rgb.size() / 3; ++p)
        if (png.rgb[p * 3] >= 1.0f && png.rgb[p * 3 + 1] >= 1.0f && png.rgb[p * 3 + 2] >= 1.0f)
            ++white;
    EXPECT_GT(white, 0u);
}

// A later scene's damaged volume is found before the first scene renders (volumes are loaded
// for the whole batch first, each file once): no output, one message naming scene and object.
TEST(Cli, BatchFindsALaterScenesBadVolumeBeforeRendering) {
    const fs::path d = testDir();
    fs::create_directories(d / "a");
    fs::create_directories(d / "b");
    const std::string good = sceneWith(d / "a", "", "");
    std::string brain =
        readFile(kSource + "/assets/brain/mni_icbm152_t1_tal_nlin_sym_09a_converted.nii.gz");
    std::ofstream(d / "b" / "broken.nii.gz", std::ios::binary) << brain.substr(0, 1000);
    const std::string bad = sceneWith(
        d / "b", kSource + "/assets/brain/mni_icbm152_t1_tal_nlin_sym_09a_converted.nii.gz",
        (d / "b" / "broken.nii.gz").string());
    fs::rename(bad, d / "b" / "later.json");
    const CliRun r = lobe("render " + quote(good) + " " + quote((d / "b" / "later.json").string()) +
                          " --width 16 --spp 1 --quiet --out " + quote((d / "out").string()));
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find("later.json: objects[1] (cortex)"), std::string::npos) << r.err;
    EXPECT_EQ(r.errLines(), 1) << r.err;
    EXPECT_FALSE(fs::exists(d / "out"));
}

// A full disk, simulated by a file-size limit (ulimit -f, SIGXFSZ ignored so that writes fail
// with EFBIG as they would with ENOSPC): every writer says so, exits 1 and leaves no file — not a
// truncated PNG or .vdb with exit 0, and no PNG without its EXR.
TEST(Cli, AFullDiskIsAnErrorAndLeavesNoFile) {
    const fs::path d = testDir();
    const auto limited = [&](const std::string& args, int kilobytes) {
        const std::string cmd = "bash -c " +
                                quote("trap '' XFSZ; ulimit -f " + std::to_string(kilobytes) +
                                      "; exec " + quote(kLobe) + " " + args) +
                                " 2>" + quote((d / "err").string());
        const int status = std::system(cmd.c_str());
        return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    };
    const std::string scene = kSource + "/assets/scenes/paper/rendering-01.json";
    fs::create_directories(d / "render");
    EXPECT_EQ(limited("render " + quote(scene) + " --width 256 --spp 1 --quiet --out " +
                          quote((d / "render").string()),
                      20),
              1);
    EXPECT_NE(readFile(d / "err").find("cannot write"), std::string::npos) << readFile(d / "err");
    EXPECT_TRUE(fs::is_empty(d / "render"));
    fs::create_directories(d / "sheet");
    EXPECT_EQ(limited("contact-sheet --out " + quote((d / "sheet" / "s.png").string()) + " " +
                          quote(kSource + "/docs/images/gallery.jpg"),
                      20),
              1);
    EXPECT_NE(readFile(d / "err").find("incomplete"), std::string::npos) << readFile(d / "err");
    EXPECT_TRUE(fs::is_empty(d / "sheet"));
    fs::create_directories(d / "vdb");
    EXPECT_EQ(limited("convert " + quote(kSource + "/assets/cthead/cthead.nhdr") + " " +
                          quote((d / "vdb" / "x.vdb").string()),
                      30),
              1);
    EXPECT_NE(readFile(d / "err").find("cannot write the OpenVDB file"), std::string::npos)
        << readFile(d / "err");
    EXPECT_TRUE(fs::is_empty(d / "vdb"));
}

TEST(Cli, BatchCollisionsCheckSkipExistingAndKeepGoing) {
    const fs::path d = testDir();
    // Two scenes with the same file name in different folders: refused before anything renders.
    fs::create_directories(d / "a");
    fs::create_directories(d / "b");
    const std::string one = sceneWith(d / "a", "", "");
    fs::copy_file(one, d / "b" / "scene.json");
    CliRun r = lobe("render " + quote(one) + " " + quote((d / "b" / "scene.json").string()) +
                    " --width 8 --spp 1 --quiet --out " + quote((d / "out").string()));
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find("would both write"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(d / "out"));
    // --check names every bad scene and renders nothing.
    fs::create_directories(d / "c");
    const std::string bad = sceneWith(d / "c", "\"iso\": 0.5", "\"iso\": 0.5, \"isovalue\": 1");
    fs::rename(bad, d / "c" / "bad.json");
    r = lobe("render " + quote(one) + " " + quote((d / "c" / "bad.json").string()) +
             " --check --out " + quote((d / "out").string()));
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find("bad.json: objects[0].isovalue: unknown key"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("1 of 2 scenes have errors"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(d / "out"));
    r = lobe("render " + quote(one) + " --check");
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("1 scene valid"), std::string::npos) << r.out;
    // --keep-going renders the good scene, reports the bad one, exits 1.
    r = lobe("render " + quote(one) + " " + quote((d / "c" / "bad.json").string()) +
             " --keep-going --width 8 --spp 1 --quiet --out " + quote((d / "out").string()));
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_TRUE(fs::exists(d / "out" / "scene.exr"));
    EXPECT_NE(r.err.find("1 of 2 scenes failed"), std::string::npos) << r.err;
    // --skip-existing leaves a finished scene alone.
    const auto before = fs::last_write_time(d / "out" / "scene.exr");
    r = lobe("render " + quote(one) + " --skip-existing --width 8 --spp 1 --out " +
             quote((d / "out").string()));
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.err.find("exists, skipped"), std::string::npos) << r.err;
    EXPECT_EQ(fs::last_write_time(d / "out" / "scene.exr"), before);
}

TEST(Cli, RenderAovWritesNamedChannelsAndRefusesABadPass) {
    const fs::path d = testDir();
    const std::string scene = kSource + "/assets/scenes/paper/rendering-01.json";
    CliRun r = lobe("render " + quote(scene) +
                    " --width 16 --spp 1 --aov all --quiet --no-contact-sheets --out " +
                    quote((d / "out").string()));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const std::string exr = readFile(d / "out" / "rendering-01.exr");
    for (const char* ch : {"skull.specular.R", "cortex.lambert.G", "density_map_3.specular.B",
                           "backdrop.R", "depth.Z", "N.X", "object.id"})
        EXPECT_NE(exr.find(ch), std::string::npos) << ch;
    r = lobe("render " + quote(scene) + " --aov objects,specularity --out " +
             quote((d / "bad").string()));
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find("--aov: unknown pass 'specularity'"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(d / "bad"));
}

// ---- shards and merge -------------------------------------------------------------------------

// Same pixels in every channel of two EXRs: OpenImageIO's idiff with no tolerance.
bool samePixels(const fs::path& a, const fs::path& b) {
    const std::string cmd = "idiff -a -fail 0 -failpercent 0 -warn 0 " + quote(a.string()) + " " +
                            quote(b.string()) + " >/dev/null 2>&1";
    return std::system(cmd.c_str()) == 0;
}

// --exact-brdf: He–Torrance from its series. A full render reads the fine table by default
// (render/scene.cpp), so the two images differ — slightly: by far less than 1e-3 in any band of
// rendering 1, whose density maps are He–Torrance.
TEST(Cli, ExactBrdfSumsTheSeriesAndTheTableIsClose) {
    const fs::path d = testDir();
    const std::string scene = kSource + "/assets/scenes/paper/rendering-01.json";
    const std::string common = " --width 48 --spp 1 --no-contact-sheets --quiet -o ";
    ASSERT_EQ(lobe("render " + quote(scene) + common + quote((d / "table.exr").string())).exitCode,
              0);
    ASSERT_EQ(lobe("render " + quote(scene) + " --exact-brdf" + common +
                   quote((d / "series.exr").string()))
                  .exitCode,
              0);
    EXPECT_FALSE(samePixels(d / "table.exr", d / "series.exr"));
    const std::string close = "idiff -a -fail 1e-3 -warn 1e-3 " +
                              quote((d / "table.exr").string()) + " " +
                              quote((d / "series.exr").string()) + " >/dev/null 2>&1";
    EXPECT_EQ(std::system(close.c_str()), 0);
}

TEST(Cli, RowShardsMergeIntoTheSingleRunsImageBitForBit) {
    const fs::path d = testDir();
    const std::string scene = kSource + "/assets/scenes/paper/rendering-01.json";
    const std::string common = " --width 40 --spp 2 --aov objects --quiet ";
    ASSERT_EQ(
        lobe("render " + quote(scene) + common + "--out " + quote((d / "one").string())).exitCode,
        0);
    for (int i = 0; i < 3; ++i)
        ASSERT_EQ(lobe("render " + quote(scene) + common + "--shard " + std::to_string(i) +
                       "/3 --threads " + std::to_string(1 + i % 2) + " --out " +
                       quote((d / "parts").string()))
                      .exitCode,
                  0);
    EXPECT_FALSE(fs::exists(d / "parts" / "rendering-01.png"));  // parts only, until merged
    CliRun r = lobe("merge " + quote(scene) + common + "--out " + quote((d / "parts").string()));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_TRUE(samePixels(d / "one" / "rendering-01.exr", d / "parts" / "rendering-01.exr"));
    // Pixels, not bytes: the PNGs' provenance names their own command lines.
    EXPECT_TRUE(samePixels(d / "one" / "rendering-01.png", d / "parts" / "rendering-01.png"));
    // Parts of other settings, or a missing part, are refused by name.
    r = lobe("merge " + quote(scene) + " --width 40 --spp 4 --aov objects --out " +
             quote((d / "parts").string()));
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find("rendered with other settings"), std::string::npos) << r.err;
    fs::remove(d / "parts" / "rendering-01.part-1-of-3.exr");
    r = lobe("merge " + quote(scene) + common + "--out " + quote((d / "parts").string()));
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find("part 1 of 3 is missing"), std::string::npos) << r.err;
    r = lobe("render " + quote(scene) + " --shard 3/3 --out " + quote((d / "bad").string()));
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find("--shard: expected I/N"), std::string::npos) << r.err;
}

// A 16³ uint8 ball (radius `radius` voxels about the centre) and a scene of it as an opaque
// surface, written into `folder`.
std::string ballScene(const fs::path& folder, double radius) {
    fs::create_directories(folder);
    std::string voxels;
    for (int z = 0; z < 16; ++z)
        for (int y = 0; y < 16; ++y)
            for (int x = 0; x < 16; ++x) {
                const double dx = x - 7.5, dy = y - 7.5, dz = z - 7.5;
                voxels += char(dx * dx + dy * dy + dz * dz <= radius * radius ? 200 : 0);
            }
    std::ofstream(folder / "ball.raw", std::ios::binary) << voxels;
    std::ofstream(folder / "ball.json") << R"({
 "image": {"width": 24, "height": 24, "samples_per_pixel": 1, "seed": 1},
 "camera": {"position": [40, 30, 35], "target": [7.5, 7.5, 7.5], "up": [0, 0, 1], "fov_deg": 40},
 "lights": [{"position": [40, 30, 35], "intensity": 3000}],
 "objects": [{"name": "ball", "kind": "isosurface",
   "source": {"path": "ball.raw", "dims": [16, 16, 16], "type": "uint8"},
   "iso": 100, "opacity": 1.0, "brdf": {"model": "ward"}}]
}
)";
    return (folder / "ball.json").string();
}

// `lobe info --histogram` of a volume mostly 0 (a skull-stripped brain's background): the bars
// are scaled without the bin of 0, whose bar is cut ('>'); scaled by it, the data's bins were
// nearly empty. The ball: 552 voxels of 200, 3544 of 0.
TEST(Cli, InfoHistogramIsNotScaledByTheBackground) {
    const fs::path d = testDir();
    ballScene(d, 5.0);
    const CliRun r = lobe("info " + quote((d / "ball.raw").string()) +
                          " --dims 16,16,16 --type uint8 --histogram --bins 4");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("bars scaled without the bin of 0, whose bar is cut (>)"),
              std::string::npos)
        << r.out;
    EXPECT_NE(r.out.find("3544   86.52 %  " + std::string(40, '#') + ">\n"), std::string::npos)
        << r.out;
    EXPECT_NE(r.out.find("552   13.48 %  " + std::string(40, '#') + "\n"), std::string::npos)
        << r.out;
}

// Parts rendered from different volume data (the file re-exported between two array tasks)
// are refused by `lobe merge`, naming the part and the file: each part's header carries a
// content hash of every volume it loaded. Only the scene text and settings were compared, and
// the merge joined them (15 % of the pixels differed from a single render).
TEST(Cli, MergeRefusesPartsOfDifferentVolumeData) {
    const fs::path d = testDir();
    const std::string scene = ballScene(d, 5.0);
    const std::string common = " --quiet --out " + quote((d / "parts").string());
    ASSERT_EQ(lobe("render " + quote(scene) + " --shard 0/2" + common).exitCode, 0);
    ballScene(d, 6.0);  // re-exported: a larger ball, same scene text
    ASSERT_EQ(lobe("render " + quote(scene) + " --shard 1/2" + common).exitCode, 0);
    CliRun r = lobe("merge " + quote(scene) + common);
    EXPECT_EQ(r.exitCode, 1) << r.err;
    EXPECT_EQ(r.errLines(), 1) << r.err;
    EXPECT_NE(r.err.find("ball.part-1-of-2.exr: rendered from other volume data than "),
              std::string::npos)
        << r.err;
    EXPECT_NE(r.err.find((d / "ball.raw").string() + " (content hash "), std::string::npos)
        << r.err;
    EXPECT_FALSE(fs::exists(d / "parts" / "ball.png"));
    // Part 0 rendered again from the same data as part 1: merged.
    ASSERT_EQ(lobe("render " + quote(scene) + " --shard 0/2" + common).exitCode, 0);
    r = lobe("merge " + quote(scene) + common);
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_TRUE(fs::exists(d / "parts" / "ball.png"));
}

// A transparent or solid background with --shard: the parts keep the coverage (channel A) or
// the composited colour, and the merge writes the single run's EXR (A included) and RGBA PNG.
// Rendering 1 has the shoulder tone, whose display divides by the coverage.
TEST(Cli, RowShardsWithABackgroundMergeIntoTheSingleRunsImage) {
    const fs::path d = testDir();
    const std::string scene = kSource + "/assets/scenes/paper/rendering-01.json";
    for (const std::string background : {"none", "'#336699'"}) {
        const std::string common = " --width 40 --spp 1 --quiet --background " + background + " ";
        const fs::path one = d / ("one" + std::to_string(background.size()));
        const fs::path parts = d / ("parts" + std::to_string(background.size()));
        ASSERT_EQ(lobe("render " + quote(scene) + common + "--out " + quote(one.string())).exitCode,
                  0);
        for (int i = 0; i < 2; ++i)
            ASSERT_EQ(
                lobe("render " + quote(scene) + common + "--shard " + std::to_string(i) +
                     "/2 --threads " + std::to_string(1 + i) + " --out " + quote(parts.string()))
                    .exitCode,
                0);
        // Merged without --background: the parts say which.
        const CliRun r = lobe("merge " + quote(scene) + " --width 40 --spp 1 --quiet --out " +
                              quote(parts.string()));
        ASSERT_EQ(r.exitCode, 0) << r.err;
        EXPECT_TRUE(samePixels(one / "rendering-01.exr", parts / "rendering-01.exr")) << background;
        EXPECT_TRUE(samePixels(one / "rendering-01.png", parts / "rendering-01.png")) << background;
        auto in = OIIO::ImageInput::open((parts / "rendering-01.png").string());
        ASSERT_TRUE(in);
        EXPECT_EQ(in->spec().nchannels, background == "none" ? 4 : 3) << background;
        EXPECT_NE(lobe::readImageAttributes((parts / "rendering-01.exr").string())
                      .at("lobe:render_settings")
                      .find("background " + std::string(background == "none" ? "none" : "#336699")),
                  std::string::npos);
    }
    // Parts of different backgrounds are not joined.
    const fs::path mixed = d / "mixed";
    for (int i = 0; i < 2; ++i)
        ASSERT_EQ(lobe("render " + quote(scene) + " --width 40 --spp 1 --quiet --background " +
                       (i ? "none" : "backdrop") + " --shard " + std::to_string(i) + "/2 --out " +
                       quote(mixed.string()))
                      .exitCode,
                  0);
    const CliRun r = lobe("merge " + quote(scene) + " --width 40 --spp 1 --quiet --out " +
                          quote(mixed.string()));
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find("rendered with --background none, part 0 with backdrop"),
              std::string::npos)
        << r.err;
}

TEST(Cli, BatchShardsAndMergeWriteTheSingleRunsFilesAndContactSheet) {
    const fs::path d = testDir();
    const std::string k = kSource + "/assets/scenes/skull/";
    const std::string scenes = quote(k + "skull-ward.json") + " " + quote(k + "skull-phong.json") +
                               " " + quote(k + "skull-lafortune.json") +
                               " --width 24 --spp 1 --quiet ";
    ASSERT_EQ(lobe("render " + scenes + "--out " + quote((d / "one").string())).exitCode, 0);
    for (int i = 0; i < 2; ++i)
        ASSERT_EQ(lobe("render " + scenes + "--shard " + std::to_string(i) + "/2 --out " +
                       quote((d / "sh").string()))
                      .exitCode,
                  0);
    ASSERT_EQ(lobe("merge " + scenes + "--out " + quote((d / "sh").string())).exitCode, 0);
    // By pixels: every PNG's provenance names its own command line (the sheets' too).
    for (const char* f :
         {"skull-ward.png", "skull-phong.png", "skull-lafortune.png", "contact-sheet-skull.png"})
        EXPECT_TRUE(samePixels(d / "one" / f, d / "sh" / f)) << f;
    EXPECT_EQ(lobe::readImageAttributes((d / "one" / "contact-sheet-skull.png").string())
                  .at("lobe:sheet_captions"),
              lobe::readImageAttributes((d / "sh" / "contact-sheet-skull.png").string())
                  .at("lobe:sheet_captions"));
    EXPECT_TRUE(samePixels(d / "one" / "skull-phong.exr", d / "sh" / "skull-phong.exr"));
}

// ---- lobe separation, assign --------------------------------------------------------------------

TEST(Cli, SeparationWritesItsReportAndRefusesCollidingScenes) {
    const fs::path d = testDir();
    const std::string scene = kSource + "/assets/scenes/paper/rendering-01.json";
    CliRun r =
        lobe("separation " + quote(scene) + " --width 24 --spp 1 --quiet --out " +
             quote((d / "sep").string()) +
             " --merge 'density maps=density map 0,density map 1,density map 2,density map 3'");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const std::string md = readFile(d / "sep" / "rendering-01.md");
    EXPECT_NE(md.find("| skull / cortex |"), std::string::npos) << md;
    EXPECT_NE(md.find("| cortex / density maps |"), std::string::npos) << md;
    EXPECT_TRUE(fs::exists(d / "sep" / "rendering-01" / "skull_vs_cortex.png"));
    EXPECT_TRUE(fs::exists(d / "sep" / "separation.csv"));
    // The same file name from two folders would write the same files: refused before rendering.
    fs::create_directories(d / "other");
    fs::copy_file(sceneWith(d, "", ""), d / "other" / "rendering-01.json");
    r = lobe("separation " + quote(scene) + " " +
             quote((d / "other" / "rendering-01.json").string()) + " --out " +
             quote((d / "sep2").string()));
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find("would write the same files"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(d / "sep2"));
    r = lobe("separation " + quote(scene) +
             " --merge 'maps=density map 9' --width 8 --spp 1 --quiet --out " +
             quote((d / "sep3").string()));
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find("no object 'density map 9'"), std::string::npos) << r.err;
}

TEST(Cli, AssignWritesALoadableSceneAndNeverOverwrites) {
    const fs::path d = testDir();
    const std::string scene = kSource + "/assets/scenes/paper/rendering-01.json";
    const std::string best = (d / "best.json").string();
    CliRun r = lobe("assign " + quote(scene) + " --out " + quote(best) +
                    " --width 24 --spp 1 --keep skull --exclude he_torrance --quiet");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const std::string report = readFile(d / "best-assign.md");
    EXPECT_NE(report.find("| 1 |"), std::string::npos) << report;
    EXPECT_NE(report.find("skull as in the scene"), std::string::npos) << report;
    // The chosen scene loads and renders from its own folder; the skull kept its model.
    const std::string text = readFile(best);
    EXPECT_NE(text.find("\"model\": \"ward\""), std::string::npos);
    r = lobe("render " + quote(best) + " --width 16 --spp 1 --quiet --no-contact-sheets --out " +
             quote((d / "render").string()));
    EXPECT_EQ(r.exitCode, 0) << r.err;
    // Never overwritten without --force; bad options named.
    r = lobe("assign " + quote(scene) + " --out " + quote(best) + " --width 24 --spp 1 --quiet");
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find("exists (use --force"), std::string::npos) << r.err;
    r = lobe("assign " + quote(scene) + " --out " + quote((d / "x.json").string()) +
             " --keep brain");
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find("no object 'brain'"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(d / "x.json"));
}

TEST(Cli, AssignNamesItsModelsAndKeepsTheRules) {
    const fs::path d = testDir();
    const std::string scene = kSource + "/assets/scenes/paper/rendering-01.json";
    const std::string best = (d / "distinct.json").string();
    CliRun r = lobe("assign " + quote(scene) + " --out " + quote(best) +
                    " --width 32 --spp 1 --distinct --equal-albedo --keep-visible 0 --quiet");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const std::string text = readFile(best);
    // Six objects, nine models, --distinct: six different "model" values; every lobe at albedo 0.1.
    std::vector<std::string> models;
    for (size_t at = 0; (at = text.find("\"model\": \"", at)) != std::string::npos;) {
        at += 10;
        models.push_back(text.substr(at, text.find('"', at) - at));
    }
    ASSERT_EQ(models.size(), 6u) << text;
    std::sort(models.begin(), models.end());
    EXPECT_EQ(std::unique(models.begin(), models.end()), models.end()) << text;
    size_t albedos = 0;
    for (size_t at = 0; (at = text.find("\"albedo\": 0.1", at)) != std::string::npos; ++at)
        ++albedos;
    EXPECT_EQ(albedos, 6u) << text;
    // The title and group name the chosen models, not the input's "1: Ward / Ashikhmin / …", "A".
    EXPECT_EQ(text.find("1: Ward / Ashikhmin"), std::string::npos);
    const size_t title = text.find("\"title\": \"assign: skull ");
    ASSERT_NE(title, std::string::npos) << text;
    const size_t group = text.find("\"group\": \"assign-");
    ASSERT_NE(group, std::string::npos) << text;
    const std::string titleLine = text.substr(title, text.find('\n', title) - title);
    const std::string groupLine = text.substr(group, text.find('\n', group) - group);
    for (const std::string& m : models)
        EXPECT_NE(groupLine.find(m), std::string::npos) << groupLine;
    EXPECT_NE(titleLine.find("density map 3 "), std::string::npos) << titleLine;
    // The report gives every object's visibility and chroma before and after.
    const std::string report = readFile(d / "distinct-assign.md");
    EXPECT_NE(report.find("| object | input model | chosen model | V before | V after |"),
              std::string::npos)
        << report;
    EXPECT_NE(report.find("no two objects share a model"), std::string::npos) << report;
    // Bad values are named, nothing written.
    r = lobe("assign " + quote(scene) + " --out " + quote((d / "y.json").string()) +
             " --equal-albedo 2 --width 8 --spp 1 --quiet");
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find("--equal-albedo: expected an albedo in (0, 1], got '2'"),
              std::string::npos)
        << r.err;
    EXPECT_FALSE(fs::exists(d / "y.json"));
}

// ---- lobe convert, info ----------------------------------------------------------------------

TEST(Cli, ConvertWithALayoutContradictingTheDataWritesNothing) {
    const fs::path d = testDir();
    const CliRun r = lobe(
        "convert " + quote(kSource + "/assets/cthead/cthead_256x256x113_int16be.raw.gz") + " " +
        quote((d / "bad.vdb").string()) + " --dims 256,256,112 --type int16 --endian big");
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find("cthead_256x256x113_int16be.raw.gz: the layout contradicts the data size"),
              std::string::npos)
        << r.err;
    EXPECT_EQ(r.errLines(), 1);
    EXPECT_TRUE(fs::is_empty(d));
}

TEST(Cli, ConvertThenInfoRoundTrips) {
    const fs::path d = testDir();
    const std::string vdb = (d / "fieldmap.vdb").string();
    CliRun r =
        lobe("convert " + quote(kSource + "/assets/brain/grey_icbm151_smooth8mm_FieldMap.nii.gz") +
             " " + quote(vdb) + " --name grey");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    r = lobe("info " + quote(vdb));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    for (const char* line : {"dimensions", "grid", "active voxels", "voxel (0,0,0)"})
        EXPECT_NE(r.out.find(line), std::string::npos) << line;
    EXPECT_NE(r.out.find("91 x 109 x 91"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("grey"), std::string::npos);
    EXPECT_NE(r.out.find("338634"), std::string::npos);
    EXPECT_NE(r.out.find("at world (90, -126, -72)"), std::string::npos);
    EXPECT_NE(r.out.find("percentiles     1 %:"), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("histogram"), std::string::npos);

    // --bins N: N rows after the histogram's header; --blur-fwhm blurs first; bad values fail.
    r = lobe("info " + quote(vdb) + " --bins 8 --blur-fwhm 4");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("histogram       8 bins"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("FWHM 4"), std::string::npos) << r.out;
    const std::string rows = r.out.substr(r.out.find("histogram"));
    EXPECT_EQ(std::count(rows.begin(), rows.end(), '\n'), 9) << rows;
    r = lobe("info " + quote(vdb) + " --bins 0");
    EXPECT_NE(r.exitCode, 0);
}

// ---- framing (render/framing.h) -------------------------------------------------------------

// A fitted scene prints its computed camera and lights; --orbit N writes N numbered frames and
// their contact sheet, and a bad framing key writes nothing.
TEST(Cli, FittedSceneOrbitWritesNumberedFramesAndASheet) {
    const fs::path d = testDir();
    std::string text = readFile(kSource + "/assets/scenes/framing/brain-left.json");
    for (size_t p; (p = text.find("\"../../")) != std::string::npos;)
        text.replace(p, 7, "\"" + kSource + "/assets/");
    const fs::path scene = d / "brain-left.json";
    std::ofstream(scene) << text;
    CliRun r = lobe("render " + quote(scene.string()) +
                    " --orbit 3 --width 16 --spp 1 --quiet --out " + quote((d / "out").string()));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    for (const char* name :
         {"brain-left-orbit-000", "brain-left-orbit-001", "brain-left-orbit-002"}) {
        EXPECT_TRUE(fs::exists(d / "out" / (std::string(name) + ".exr"))) << name;
        EXPECT_TRUE(fs::exists(d / "out" / (std::string(name) + ".png"))) << name;
    }
    EXPECT_FALSE(fs::exists(d / "out" / "brain-left-orbit-003.exr"));
    EXPECT_FALSE(fs::exists(d / "out" / "brain-left.exr"));
    EXPECT_TRUE(fs::exists(d / "out" / "contact-sheet-brain-left-orbit.png"));
    const lobe::ImageAttributes sheet =
        lobe::readImageAttributes((d / "out" / "contact-sheet-brain-left-orbit.png").string());
    ASSERT_TRUE(sheet.count("lobe:command_line"));
    EXPECT_NE(sheet.at("lobe:command_line").find(" --orbit 3 "), std::string::npos);
    EXPECT_EQ(std::count(sheet.at("lobe:sheet_captions").begin(),
                         sheet.at("lobe:sheet_captions").end(), '\n'),
              2);  // three frames' captions
    EXPECT_NE(r.out.find("0 deg: fitted view:\n\"camera\": {\"position\": ["), std::string::npos)
        << r.out;
    EXPECT_NE(r.out.find("\"lights\": [\n  {\"position\": "), std::string::npos) << r.out;
    // An unknown object to fit: one error naming the key, nothing written.
    const size_t p = text.find("\"objects\": [\"cortex\"]");
    ASSERT_NE(p, std::string::npos);
    text.replace(p, 21, "\"objects\": [\"cortx\"]");
    std::ofstream(scene) << text;
    r = lobe("render " + quote(scene.string()) + " --width 16 --spp 1 --quiet --out " +
             quote((d / "bad").string()));
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find("camera.fit.objects: no object is named 'cortx'"), std::string::npos)
        << r.err;
    EXPECT_FALSE(fs::exists(d / "bad"));
    // A close-up outside the fitted view, second in a batch: found (and by --check) before the
    // first scene renders.
    text.replace(p, 20, "\"objects\": [\"cortex\"]");  // "cortx" is 20 characters
    std::ofstream(scene) << text;
    std::string far = text;
    const size_t c = far.find("\"fov_deg\": 30");
    ASSERT_NE(c, std::string::npos);
    far.insert(c, "\"zoom\": {\"point\": [0, 2000, 0], \"size\": 10}, ");
    std::ofstream(d / "far.json") << far;
    const std::string batch = quote(scene.string()) + " " + quote((d / "far.json").string());
    r = lobe("render " + batch + " --width 16 --spp 1 --quiet --out " +
             quote((d / "bad").string()));
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find("far.json: camera.zoom: the zoom's centre is outside the view"),
              std::string::npos)
        << r.err;
    EXPECT_FALSE(fs::exists(d / "bad"));
    r = lobe("render " + batch + " --check");
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find("far.json: camera.zoom:"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("1 of 2 scenes have errors"), std::string::npos) << r.err;
}

// ---- scene key typos ------------------------------------------------------------------------

// An unknown key one or two edits from a key the reader looks for at that place is named with
// it; a key far from every valid one gets no guess (RenderBadSceneWritesNothing: "isovalue").
TEST(Cli, AnUnknownSceneKeySuggestsTheNearestValidOne) {
    const fs::path d = testDir();
    const struct {
        std::string from, to, message;
    } cases[] = {
        {"\"iso\": 0.5", "\"iso\": 0.5, \"opactiy\": 1",
         "objects[0].opactiy: unknown key (did you mean 'opacity'?)"},
        {"\"fov_deg\"", "\"fovdeg\"", "camera.fovdeg: unknown key (did you mean 'fov_deg'?)"},
        // The model's own parameters are the candidates inside "brdf".
        {"\"model\": \"ward\"", "\"model\": \"ward\", \"alpha_z\": 0.1",
         "objects[0].brdf.alpha_z: unknown key (did you mean 'alpha_x'?)"},
        {"\"iso\": 0.5", "\"iso\": 0.5, \"shininess\": 1", "objects[0].shininess: unknown key\n"},
    };
    for (const auto& c : cases) {
        const std::string scene = sceneWith(d, c.from, c.to);
        const CliRun r = lobe("render " + quote(scene) + " --check");
        EXPECT_EQ(r.exitCode, 1) << c.to;
        EXPECT_NE(r.err.find(c.message), std::string::npos) << c.to << ": " << r.err;
    }
}

// ---- lobe cost and render --stats -------------------------------------------------------------

// Fields of the CSV row of `run` and `name` (an object, a part or "cpu").
std::vector<std::string> csvRow(const std::string& csv, const std::string& run,
                                const std::string& row, const std::string& name) {
    std::istringstream in(csv);
    std::string line;
    while (std::getline(in, line)) {
        std::vector<std::string> f;
        std::stringstream ss(line);
        std::string field;
        while (std::getline(ss, field, ',')) f.push_back(field);
        if (f.size() >= 3 && f[0] == run && f[1] == row && f[2] == name) return f;
    }
    ADD_FAILURE() << "no row " << run << "," << row << "," << name << " in\n" << csv;
    return std::vector<std::string>(8);
}

// `lobe cost`: the tables, and the counts every run shares — a model swapped onto the cortex
// evaluates at the same points with the same lights, the other objects are untouched, and
// `render --stats` counts the same evaluations for the same settings.
TEST(Cli, CostTablesAndEvaluationsAcrossModels) {
    const fs::path d = testDir();
    const std::string scene = kSource + "/assets/scenes/paper/rendering-01.json";
    const std::string csv = (d / "cost.csv").string();
    CliRun r = lobe("cost " + quote(scene) +
                    " --width 24 --spp 1 --quiet --object cortex --models ward,he_torrance --csv " +
                    quote(csv));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    for (const char* text : {"| part | CPU s | share |", "| shading (BRDF + light loop) |",
                             "| cortex | ashikhmin_shirley |", "### Models on 'cortex'",
                             "| ashikhmin_shirley (scene) |", "| he_torrance |"})
        EXPECT_NE(r.out.find(text), std::string::npos) << text << "\n" << r.out;
    const std::string table = readFile(csv);
    const auto own = csvRow(table, "scene", "object", "cortex");
    EXPECT_EQ(own[3], "ashikhmin_shirley");
    EXPECT_GT(std::stoll(own[5]), 0);
    for (const char* model : {"ward", "he_torrance"}) {
        const auto swapped = csvRow(table, model, "object", "cortex");
        EXPECT_EQ(swapped[3], model);
        EXPECT_EQ(swapped[4], own[4]) << model;  // shaded points
        EXPECT_EQ(swapped[5], own[5]) << model;  // BRDF evaluations
        EXPECT_EQ(csvRow(table, model, "object", "skull")[5],
                  csvRow(table, "scene", "object", "skull")[5]);
    }
    // The objects' evaluations add up to the run's total.
    long long sum = 0;
    for (const char* o :
         {"skull", "cortex", "density map 0", "density map 1", "density map 2", "density map 3"})
        sum += std::stoll(csvRow(table, "scene", "object", o)[5]);
    EXPECT_EQ(std::to_string(sum), csvRow(table, "scene", "total", "cpu")[5]);

    r = lobe("render " + quote(scene) +
             " --width 24 --spp 1 --quiet --stats --no-contact-sheets --out " +
             quote((d / "out").string()));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("cortex (ashikhmin_shirley): " + own[5] + " BRDF evaluations"),
              std::string::npos)
        << r.out;
    EXPECT_NE(r.out.find("shading"), std::string::npos) << r.out;
}

TEST(Cli, CostRefusesBadModelsAndObjectsBeforeRendering) {
    const fs::path d = testDir();
    const std::string scene = kSource + "/assets/scenes/paper/rendering-01.json";
    const struct {
        std::string args, message;
    } cases[] = {
        {"--models ward", "--models needs --object NAME: the scene has 6 objects (skull, cortex"},
        {"--models ward --object nose", "has no object 'nose'"},
        {"--models nosuch --object skull", "unknown BRDF model 'nosuch'"},
        {"--object skull", "give --models too"},
        {"--models , --object skull", "expected a comma list"},
        {"--width 0", "--width"},
    };
    for (const auto& c : cases) {
        const std::string csv = (d / "c.csv").string();
        const CliRun r =
            lobe("cost " + quote(scene) + " --quiet --csv " + quote(csv) + " " + c.args);
        EXPECT_EQ(r.exitCode, 1) << c.args << ": " << r.err;
        EXPECT_NE(r.err.find(c.message), std::string::npos) << c.args << ": " << r.err;
        EXPECT_EQ(r.errLines(), 1) << c.args << ": " << r.err;
        EXPECT_TRUE(r.out.empty()) << c.args;
        EXPECT_FALSE(fs::exists(csv)) << c.args;
    }
}

// DICOM series (tests/volume/make_dicom_series.py): info and convert take a folder or the files
// of a series; several series are listed with their UIDs and picked by --series; a bad series
// writes nothing.
TEST(Cli, InfoAndConvertReadDicomSeries) {
    const fs::path d = testDir();
    const fs::path data = d / "series";
    ASSERT_EQ(std::system((std::string(LOBE_SYSTEM_PYTHON) + " " +
                           quote(kSource + "/tests/volume/make_dicom_series.py") + " " +
                           quote(data.string()))
                              .c_str()),
              0);
    CliRun r = lobe("info " + quote((data / "two_series").string()));
    EXPECT_EQ(r.exitCode, 1);
    for (const char* part :
         {"2 series", "--series", "1.2.826.0.1.3680043.8.498.1111  'first series', 3 slices",
          "1.2.826.0.1.3680043.8.498.2222  'second series', 4 slices"})
        EXPECT_NE(r.err.find(part), std::string::npos) << part << " not in: " << r.err;
    r = lobe("info " + quote((data / "two_series").string()) +
             " --series 1.2.826.0.1.3680043.8.498.2222");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("3 x 2 x 4"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("spacing         1 x 1 x 1"), std::string::npos) << r.out;

    // The files of a series, in any order, then OUT: the oblique CT's first voxel at RAS (40, -25,
    // 110).
    std::string files;
    for (int n = 6; n >= 1; --n)
        files += quote((data / "ct" / ("IM000" + std::to_string(n))).string()) + " ";
    const std::string vdb = (d / "ct.vdb").string();
    r = lobe("convert " + files + quote(vdb));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    r = lobe("info " + quote(vdb));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("5 x 4 x 6"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("at world (40, -25, 110)"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("file values     -1942 .."), std::string::npos) << r.out;

    const std::string bad = (d / "gap.vdb").string();
    r = lobe("convert " + quote((data / "gap").string()) + " " + quote(bad));
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find("missing slices"), std::string::npos) << r.err;
    EXPECT_EQ(r.errLines(), 1);
    EXPECT_FALSE(fs::exists(bad));
    r = lobe("convert " + quote((data / "ct").string()));
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find("convert needs an input and an output"), std::string::npos) << r.err;
    // A DICOM file with a raw layout: refused, not read as voxels.
    r = lobe("info " + quote((data / "ct" / "IM0001").string()) +
             " --dims 5,4,1 --type int16 --endian little");
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find("a DICOM series has its own layout"), std::string::npos) << r.err;
}

}  // namespace
