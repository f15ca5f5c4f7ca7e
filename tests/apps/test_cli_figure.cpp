// `lobe render` figure output from the command line (figure/figure_output.h): -o FILE, the
// transparent and colour backgrounds with alpha checked on pixels whose coverage is known (the
// CThead skull as an opaque surface covers the image centre; the corner sees past it), the
// provenance read back (by OpenImageIO and by `oiiotool --info -v`), the refusals before
// anything renders, and the warnings for an empty image and an invisible volume.
#include "cli_harness.h"
#include "core/image_output.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace {

namespace fs = std::filesystem;

const std::string kLobe = LOBE_EXE;
const std::string kSource = LOBE_SOURCE_DIR;

using lobe::test::CliRun;
using lobe::test::quote;
using lobe::test::readFile;

fs::path testDir() { return lobe::test::testDir("cli_figure"); }

CliRun run(const std::string& command, const fs::path& d) {
    return lobe::test::runShell(command, d);
}

CliRun lobe(const std::string& args, const fs::path& d) {
    return run(quote(kLobe) + " " + args, d);
}

// The CThead skull alone as an opaque surface, seen as in the paper's rendering 1 (the head fills
// the middle; the corners see the backdrop). `cameraAway`: the camera looks the other way.
// `extraObject`: JSON of a second object, appended.
std::string skullScene(const fs::path& d, const std::string& name, bool cameraAway = false,
                       const std::string& extraObject = "") {
    const std::string target = cameraAway ? "[901.96, -660.96, 116.0]" : "[110.0, 131.0, 116.0]";
    std::string text = R"({
 "title": "opaque skull",
 "image": {"width": 32, "height": 32, "samples_per_pixel": 1, "seed": 1},
 "camera": {"position": [505.98, -264.98, 116.0], "target": )" +
                       target + R"(,
            "up": [0, 0, -1], "fov_deg": 30},
 "lights": [{"position": [647.438, -194.233, 266.052], "intensity": 417130.9}],
 "objects": [
  {"name": "skull", "kind": "isosurface",
   "source": {"path": ")" +
                       kSource +
                       R"(/assets/cthead/cthead.nhdr", "divide_by": 3272, "background": 100},
   "iso": 0.5, "opacity": 1.0, "brdf": {"model": "ward"}})" +
                       (extraObject.empty() ? "" : ",\n  " + extraObject) + "\n ]\n}\n";
    const fs::path path = d / name;
    std::ofstream(path) << text;
    return path.string();
}

struct Rgba {
    int width = 0, height = 0, channels = 0;
    std::vector<unsigned char> data;
    const unsigned char* at(int x, int y) const {
        return &data[(size_t(y) * width + x) * channels];
    }
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

// A JPEG that cannot be written — a full disk, simulated by a file-size limit (`ulimit -f 1`,
// 512 bytes) with SIGXFSZ ignored, so a write past it fails (EFBIG) as one on a full disk does
// (ENOSPC) — is one `lobe: error:` line naming the file, exit 1 and nothing left in the folder.
// OpenImageIO's JPEG writer kept libjpeg's default error handler, which printed only libjpeg's
// message and exited inside the library, leaving the hidden temporary file.
TEST(CliFigure, JpegWriteFailureIsOneErrorLineAndLeavesNothing) {
    const fs::path d = testDir();
    const std::string scene = skullScene(d, "skull.json");
    const fs::path out = d / "out";
    fs::create_directories(out);
    const std::string jpg = (out / "skull.jpg").string();
    const CliRun r = run("trap '' XFSZ; ulimit -f 1; exec " + quote(kLobe) + " render " +
                             quote(scene) + " --quiet -o " + quote(jpg),
                         d);
    EXPECT_EQ(r.exitCode, 1) << r.err;
    EXPECT_EQ(r.errLines(), 1) << r.err;
    EXPECT_EQ(r.err.rfind("lobe: error: cannot write '" + jpg + "': ", 0), 0u) << r.err;
    EXPECT_TRUE(fs::is_empty(out)) << fs::directory_iterator(out)->path();
    // The same render without the limit writes the JPEG.
    const CliRun ok = lobe("render " + quote(scene) + " --quiet -o " + quote(jpg), d);
    EXPECT_EQ(ok.exitCode, 0) << ok.err;
    EXPECT_TRUE(fs::is_regular_file(jpg));
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
        EXPECT_NE(a.at("lobe:command_line").find("--seed 5 --png-bits 16"), std::string::npos)
            << file;
        EXPECT_FALSE(a.at("lobe:version").empty()) << file;
        EXPECT_NE(a.at("lobe:render_settings").find("32x32 spp 1 seed 5"), std::string::npos)
            << file;
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
    const std::string cortex =
        R"({"name": "cortex", "kind": "volume",
   "source": {"path": ")" +
        kSource +
        R"(/assets/brain/mni_icbm152_t1_tal_nlin_sym_09a_converted.nii.gz", "divide_by": 255},
   "transfer_function": {"points": [{"value": 5, "opacity": 0}, {"value": 6, "opacity": 0.2}]},
   "brdf": {"model": "ward"}})";
    const std::string scene = skullScene(d, "tf.json", false, cortex);
    r = lobe("render " + quote(scene) + " --quiet -o " + quote((d / "tf.png").string()), d);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(r.err.find("lobe: warning: " + scene +
                         ": objects[1] (cortex): its transfer function "
                         "gives opacity 0 to every voxel of its volume"),
              0u)
        << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

// A volume whose transfer function sees only values its voxels never hold — CThead's 0..3272
// given to the cortex preset made for 0..1, divide_by forgotten — is warned about by name (it
// vanished without a word: the reconstruction blends the data with the background through the
// visible values, so the empty-space table did not find it invisible).
TEST(CliFigure, AForgottenDivideByIsWarnedAbout) {
    const fs::path d = testDir();
    const std::string scene =
        skullScene(d, "head.json", false,
                   R"({"name": "head", "kind": "volume", "source": {"path": ")" + kSource +
                       R"(/assets/cthead/cthead.nhdr", "background": 100},
   "transfer_function": {"preset": "cortex_shell"}, "brdf": {"model": "ward"}})");
    const CliRun r =
        lobe("render " + quote(scene) + " --quiet --out " + quote((d / "out").string()), d);
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.err.find("lobe: warning: " + scene +
                         ": objects[1] (head): its transfer function is "
                         "visible only for values "),
              std::string::npos)
        << r.err;
    EXPECT_NE(r.err.find("but the volume's active voxels hold 101 to 3272"), std::string::npos)
        << r.err;
    EXPECT_NE(r.err.find("(a divide_by missing?)"), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

// ---- posters: bands of rows ---------------------------------------------------------------------

// Every sample of an image file as stored: an EXR's floats (all channels, with their names), a
// PNG's or TIFF's integers (read as 16-bit: 8-bit values × 257, exact either way).
struct Stored {
    std::vector<std::string> names;
    std::vector<float> floats;
    std::vector<unsigned short> integers;
};
Stored stored(const fs::path& p) {
    Stored s;
    if (p.extension() == ".exr") {
        const lobe::FloatImage image = lobe::readFloatImage(p.string());
        s.names = image.channels.names;
        s.floats = image.channels.data;
        return s;
    }
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    auto in = OIIO::ImageInput::open(p.string(), &config);
    if (!in) return s;
    const OIIO::ImageSpec& spec = in->spec();
    s.names = spec.channelnames;
    s.integers.resize(size_t(spec.width) * spec.height * spec.nchannels);
    in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::UINT16, s.integers.data());
    return s;
}

void expectSamePixels(const fs::path& a, const fs::path& b) {
    const Stored x = stored(a), y = stored(b);
    ASSERT_FALSE(x.floats.empty() && x.integers.empty()) << a;
    EXPECT_EQ(x.names, y.names) << b;
    EXPECT_EQ(x.floats, y.floats) << b;
    EXPECT_EQ(x.integers, y.integers) << b;
}

// The skull scene at 2 samples a pixel, in the contact-sheet group "poster".
std::string posterScene(const fs::path& d, const std::string& name, int size, int spp) {
    std::string text = readFile(skullScene(d, name));
    const auto replace = [&](const std::string& from, const std::string& to) {
        text.replace(text.find(from), from.size(), to);
    };
    replace("\"width\": 32, \"height\": 32, \"samples_per_pixel\": 1",
            "\"width\": " + std::to_string(size) + ", \"height\": " + std::to_string(size) +
                ", \"samples_per_pixel\": " + std::to_string(spp));
    replace("\"title\": \"opaque skull\",", "\"title\": \"opaque skull\", \"group\": \"poster\",");
    std::ofstream(d / name) << text;
    return (d / name).string();
}

TEST(CliFigure, BandedRenderIsTheWholeRenderBitForBit) {
    const fs::path d = testDir();
    const std::string scene = posterScene(d, "skull.json", 32, 2);
    // Transparent, with every pass: the EXR (colour, bands, A, passes), the PNG and the contact
    // sheet of the whole image against bands of 5 rows (7 bands, the last of 2; tiles of 16 cut
    // across bands) on 1 thread and of 16 rows on 2 threads.
    const std::string common = "render " + quote(scene) + " --quiet --background none --aov all ";
    ASSERT_EQ(lobe(common + "--threads 2 --out " + quote((d / "whole").string()), d).exitCode, 0);
    for (const std::string bands : {"5", "16"}) {
        const fs::path out = d / ("bands" + bands);
        const CliRun r = lobe(common + "--threads " + (bands == "5" ? "1" : "2") + " --band-rows " +
                                  bands + " --out " + quote(out.string()),
                              d);
        ASSERT_EQ(r.exitCode, 0) << r.err;
        EXPECT_EQ(r.err, "");
        for (const char* file : {"skull.exr", "skull.png", "contact-sheet-poster.png"})
            expectSamePixels(d / "whole" / file, out / file);
    }
    // A resumed batch builds the sheet from the EXR on disk, a band at a time: the same sheet.
    fs::rename(d / "whole" / "contact-sheet-poster.png", d / "rendered-sheet.png");
    const CliRun resumed =
        lobe(common + "--skip-existing --out " + quote((d / "whole").string()), d);
    ASSERT_EQ(resumed.exitCode, 0) << resumed.err;
    // By pixels: the sheet's provenance names its own command line.
    expectSamePixels(d / "whole" / "contact-sheet-poster.png", d / "rendered-sheet.png");
    // The comparison means something: coverage 1 at the centre and 0 in the corner, passes there.
    const Stored exr = stored(d / "whole" / "skull.exr");
    const size_t k = exr.names.size();
    ASSERT_EQ(exr.names[3], "A");
    EXPECT_GT(k, 7u);  // R, G, B, A, three bands and the passes
    EXPECT_EQ(exr.floats[(16 * 32 + 16) * k + 3], 1.0f);
    EXPECT_EQ(exr.floats[3], 0.0f);

    // A colour background into a 16-bit TIFF and its EXR (-o), bands of 3 rows.
    const std::string colour =
        "render " + quote(scene) + " --quiet --background '#336699' --png-bits 16 --exr -o ";
    ASSERT_EQ(lobe(colour + quote((d / "whole.tif").string()), d).exitCode, 0);
    ASSERT_EQ(lobe(colour + quote((d / "bands.tif").string()) + " --band-rows 3", d).exitCode, 0);
    expectSamePixels(d / "whole.tif", d / "bands.tif");
    expectSamePixels(d / "whole.exr", d / "bands.exr");
}

TEST(CliFigure, BandRowsAreCheckedAndTheEmptyWarningSeesEveryBand) {
    const fs::path d = testDir();
    const std::string scene = skullScene(d, "skull.json");
    CliRun r = lobe("render " + quote(scene) + " --quiet --band-rows 4 --shard 0/2", d);
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find("--band-rows: not with --shard"), std::string::npos) << r.err;
    r = lobe("render " + quote(scene) + " --quiet --band-rows -3", d);
    EXPECT_NE(r.exitCode, 0);
    EXPECT_NE(r.err.find("--band-rows"), std::string::npos) << r.err;
    // Covered only in the middle bands: no warning; covered nowhere: one.
    r = lobe("render " + quote(scene) + " --quiet --background none --band-rows 3 -o " +
                 quote((d / "a.png").string()),
             d);
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(r.err, "");
    const std::string away = skullScene(d, "away.json", true);
    r = lobe("render " + quote(away) + " --quiet --background none --band-rows 3 -o " +
                 quote((d / "b.png").string()),
             d);
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_NE(r.err.find("the image is empty"), std::string::npos) << r.err;
}

TEST(CliFigure, InterruptedPosterLeavesNoFileAndKeepsTheOldOne) {
    const fs::path d = testDir();
    // 128² × 64 samples on one thread (seconds), stopped by SIGTERM once its first band of 2 rows
    // is in the temporary files.
    const std::string scene = posterScene(d, "skull.json", 128, 64);
    fs::create_directories(d / "out");
    std::ofstream(d / "out" / "fig.png") << "an earlier figure";
    const std::string script =
        quote(kLobe) + " render " + quote(scene) + " --quiet --threads 1 --band-rows 2 --exr -o " +
        quote((d / "out" / "fig.png").string()) + " & pid=$!\n" +
        "for i in $(seq 1 1200); do ls -a " + quote((d / "out").string()) +
        " | grep -q '^\\.fig\\.partial-' && { echo seen; break; }; sleep 0.025; done\n" +
        "kill -TERM $pid; wait $pid; echo status $?\n";
    const CliRun r = run("bash -c " + quote(script), d);
    EXPECT_NE(r.out.find("seen"), std::string::npos) << r.out << r.err;
    EXPECT_NE(r.out.find("status 143"), std::string::npos) << r.out << r.err;  // ended by SIGTERM
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(d / "out"))
        names.push_back(e.path().filename().string());
    EXPECT_EQ(names, std::vector<std::string>{"fig.png"});
    EXPECT_EQ(readFile(d / "out" / "fig.png"), "an earlier figure");
}

// A poster killed by SIGKILL (an out-of-memory killer, a scheduler after its grace period: no
// handler runs) leaves its temporary files, named with the host and PID of their owner; the next
// run that writes into the folder removes them (the owner is dead) and says so in one line.
// They stayed before, with a random number for a name, never removed nor mentioned.
TEST(CliFigure, KilledPostersTemporariesAreRemovedByTheNextRun) {
    const fs::path d = testDir();
    const std::string scene = posterScene(d, "skull.json", 128, 64);
    fs::create_directories(d / "out");
    const std::string script =
        quote(kLobe) + " render " + quote(scene) + " --quiet --threads 1 --band-rows 2 --exr -o " +
        quote((d / "out" / "fig.png").string()) + " & pid=$!\n" +
        "for i in $(seq 1 1200); do ls -a " + quote((d / "out").string()) +
        " | grep -q '^\\.fig\\.partial-' && { echo seen; break; }; sleep 0.025; done\n" +
        "kill -KILL $pid; wait $pid; echo status $?\n";
    const CliRun r = run("bash -c " + quote(script), d);
    EXPECT_NE(r.out.find("seen"), std::string::npos) << r.out << r.err;
    EXPECT_NE(r.out.find("status 137"), std::string::npos) << r.out << r.err;  // SIGKILL
    int left = 0;
    for (const auto& e : fs::directory_iterator(d / "out"))
        left += e.path().filename().string().rfind(".fig.partial-", 0) == 0;
    EXPECT_EQ(left, 2);  // the PNG's and the EXR's
    // Another figure into the same folder: the dead run's files go, with one line.
    const CliRun next = lobe("render " + quote(skullScene(d, "small.json")) + " --quiet -o " +
                                 quote((d / "out" / "other.png").string()),
                             d);
    EXPECT_EQ(next.exitCode, 0) << next.err;
    EXPECT_EQ(next.errLines(), 1) << next.err;
    EXPECT_NE(next.err.find("lobe: removed 2 temporary files"), std::string::npos) << next.err;
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(d / "out"))
        names.push_back(e.path().filename().string());
    EXPECT_EQ(names, std::vector<std::string>{"other.png"});
}

// The PNG and EXR of a render are put in place together: with NAME.exr a folder, the run fails
// naming it and NAME.png is neither created nor replaced (before, the new PNG was already in
// place when the EXR's rename failed).
TEST(CliFigure, OutputPairIsCheckedBeforeTheFirstRename) {
    const fs::path d = testDir();
    const std::string scene = skullScene(d, "skull.json");
    fs::create_directories(d / "out" / "skull.exr");
    const CliRun fresh =
        lobe("render " + quote(scene) + " --quiet --out " + quote((d / "out").string()), d);
    EXPECT_EQ(fresh.exitCode, 1) << fresh.err;
    EXPECT_EQ(fresh.errLines(), 1) << fresh.err;
    EXPECT_NE(fresh.err.find("skull.exr': a folder of that name exists"), std::string::npos)
        << fresh.err;
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(d / "out"))
        names.push_back(e.path().filename().string());
    EXPECT_EQ(names, std::vector<std::string>{"skull.exr"});
    // An earlier PNG is kept as it was.
    std::ofstream(d / "out" / "skull.png") << "an earlier figure";
    EXPECT_EQ(lobe("render " + quote(scene) + " --quiet --out " + quote((d / "out").string()), d)
                  .exitCode,
              1);
    EXPECT_EQ(readFile(d / "out" / "skull.png"), "an earlier figure");
}

}  // namespace
