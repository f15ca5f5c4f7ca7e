// The command line with label maps: `lobe info MAP --labels`, `lobe assign` on a segmentation
// (its choices written into the segmentation's overrides), and a bad label map refused.
#include "../render/label_test_maps.h"
#include "cli_harness.h"

#include <gtest/gtest.h>

namespace {

namespace fs = std::filesystem;
using lobe::test::CliRun;
using lobe::test::quote;
using lobe::test::readFile;

CliRun lobe(const std::string& args) {
    return lobe::test::runShell(quote(LOBE_EXE) + " " + args,
                                fs::path(LOBE_BINARY_DIR) / "test-output" / "cli-labels" / "_io");
}

TEST(CliLabels, InfoListsLabelsWithCountsBoxesAndNames) {
    const std::string map = lobe::test::writeSyntheticMap("cli-labels.nii");
    std::ofstream(map + ".txt")
        << "1 Left\n2 Ball\n3 Right\n4 Cube\n";  // MRIcron's table beside it
    CliRun r = lobe("info " + quote(map) + " --labels");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("labels present  4"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("       4        216  (21.5, 21.5, 21.5) .. (27.5, 27.5, 27.5)"),
              std::string::npos)
        << r.out;
    EXPECT_NE(r.out.find("Cube"), std::string::npos) << r.out;
    fs::remove(map + ".txt");
    const std::string fractional = lobe::test::writeSyntheticMap("cli-fractional.nii", true);
    r = lobe("info " + quote(fractional) + " --labels");
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_EQ(r.errLines(), 1) << r.err;
    EXPECT_NE(r.err.find("not a label map"), std::string::npos) << r.err;
}

TEST(CliLabels, AssignTreatsEachLabelAsAnObject) {
    const fs::path d = lobe::test::testDir("cli-labels");
    const std::string map = lobe::test::writeSyntheticMap("cli-assign.nii");
    const std::string scene = (d / "seg.json").string();
    std::ofstream(scene)
        << R"({"image": {"width": 16, "height": 16, "samples_per_pixel": 1},
      "camera": {"fit": {"view": "left"}}, "lights": {"rig": "headlight"},
      "objects": [{"name": "seg", "kind": "segmentation", "labels": [2, 4], "brdf": {"model": "phong"},
        "source": {"path": ")"
        << map << R"(", "label_table": {"1": "Left", "2": "Ball", "3": "Right", "4": "Cube"}},
        "overrides": {"2": {"opacity": 0.8}}}]})";
    const std::string best = (d / "best.json").string();
    CliRun r = lobe("assign " + quote(scene) + " --out " + quote(best) + " --quiet");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const std::string text = readFile(best);
    // One segmentation still, each label's choice in its overrides (label 2 under its own key).
    for (const char* key : {"\"Cube\": {", "\"2\": {"})
        EXPECT_NE(text.find(key), std::string::npos) << key << "\n" << text;
    EXPECT_EQ(text.find("\"Ball\": {"), std::string::npos) << text;
    EXPECT_NE(text.find("\"opacity\": 0.8"), std::string::npos) << text;
    r = lobe("render " + quote(best) + " --check");
    EXPECT_EQ(r.exitCode, 0) << r.err;
    const std::string report = readFile(d / "best-assign.md");
    EXPECT_NE(report.find("Cube"), std::string::npos) << report;
}

TEST(CliLabels, BadLabelsAreOneLineAndWriteNothing) {
    const fs::path d = lobe::test::testDir("cli-labels");
    const std::string map = lobe::test::writeSyntheticMap("cli-bad.nii");
    const auto sceneWith = [&](const std::string& objects) {
        const std::string path = (d / "bad.json").string();
        std::ofstream(path)
            << R"({"image": {"width": 8, "height": 8}, "camera": {"fit": {"view": "left"}},
          "objects": [)"
            << objects << "]}";
        return path;
    };
    const std::string src =
        R"("source": {"path": ")" + map +
        R"(", "label_table": {"1": "Left", "2": "Ball", "3": "Right", "4": "Cube"}})";
    for (const auto& [objects, message] : std::vector<std::pair<std::string, std::string>>{
             {R"({"kind": "segmentation", "labels": [2, 7], "brdf": {"model": "phong"}, )" + src +
                  "}",
              "label 7 is not in"},
             {R"({"kind": "segmentation", "labels": ["Bal"], "brdf": {"model": "phong"}, )" + src +
                  "}",
              "'Bal' is in no label table"},
             {R"({"kind": "segmentation", "labels": [2], "brdf": {"model": "phong"}, )" + src +
                  "}, " +
                  R"({"kind": "segmentation", "labels": ["Ball"], "brdf": {"model": "phong"}, )" +
                  src + "}",
              "both claim label 2"}}) {
        const CliRun r =
            lobe("render " + quote(sceneWith(objects)) + " --out " + quote((d / "out").string()));
        EXPECT_EQ(r.exitCode, 1);
        EXPECT_EQ(r.errLines(), 1) << r.err;
        EXPECT_NE(r.err.find(message), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(d / "out" / "bad.png"));
    }
}

}  // namespace
