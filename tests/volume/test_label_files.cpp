// FreeSurfer .mgh/.mgz against nibabel's reading of files nibabel wrote at test time
// (make_mgh_files.py), files that are not what their names say, and the label table formats
// (volume/label_table.h): FreeSurfer, ITK-SNAP, MRIcron .txt + .lut, and their errors.
#include "core/error.h"
#include "volume/label_table.h"
#include "volume/volume.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace lobe {
namespace {

namespace fs = std::filesystem;

const std::string& mghDir() {
    static const std::string dir = [] {
        const std::string d =
            (fs::temp_directory_path() / ("lobe-mgh-tests-" + std::to_string(::getpid()))).string();
        const std::string cmd = std::string(LOBE_SYSTEM_PYTHON) + " '" + LOBE_SOURCE_DIR +
                                "/tests/volume/make_mgh_files.py' '" + d + "'";
        if (std::system(cmd.c_str()) != 0) throw std::runtime_error("make_mgh_files.py failed");
        return d;
    }();
    return dir;
}

std::string writeText(const std::string& name, const std::string& text) {
    const fs::path dir =
        fs::temp_directory_path() / ("lobe-table-tests-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const std::string path = (dir / name).string();
    std::ofstream(path, std::ios::binary) << text;
    return path;
}

std::string errorOf(const std::function<void()>& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

TEST(Mgh, ValuesAndAffineEqualNibabels) {
    for (const char* name : {"labels.mgz", "labels_uint8.mgh", "short.mgz", "float.mgz"}) {
        const std::string path = mghDir() + "/" + name;
        std::ifstream ref(path + ".txt");
        int n[3];
        ref >> n[0] >> n[1] >> n[2];
        double affine[4][4];
        for (auto& row : affine)
            for (double& x : row) ref >> x;
        const Volume v = loadVolume(path);
        ASSERT_EQ(v.dims, (std::array<int, 3>{n[0], n[1], n[2]})) << name;
        // world = affine · (i, j, k, 1): compare the map at the corners of the lattice.
        for (int c = 0; c < 8; ++c) {
            const openvdb::Vec3d idx((c & 1) ? n[0] - 1 : 0, (c & 2) ? n[1] - 1 : 0,
                                     (c & 4) ? n[2] - 1 : 0);
            const openvdb::Vec3d w = v.grid->transform().indexToWorld(idx);
            for (int r = 0; r < 3; ++r)
                EXPECT_NEAR(w[r],
                            affine[r][0] * idx[0] + affine[r][1] * idx[1] + affine[r][2] * idx[2] +
                                affine[r][3],
                            1e-5)
                    << name << " corner " << c << " row " << r;
        }
        auto acc = v.grid->getConstAccessor();
        for (int k = 0; k < n[2]; ++k)
            for (int j = 0; j < n[1]; ++j)
                for (int i = 0; i < n[0]; ++i) {
                    double want;
                    ref >> want;
                    ASSERT_EQ(acc.getValue(openvdb::Coord(i, j, k)), float(want))
                        << name << " " << i << "," << j << "," << k;
                }
    }
}

TEST(Mgh, FilesNotWhatTheirNamesSay) {
    // A NIfTI named .mgz: not gzip; an uncompressed file named .mgh that is not MGH.
    const std::string notGzip = writeText("fake.mgz", std::string(400, 'x'));
    std::string e = errorOf([&] { loadVolume(notGzip); });
    EXPECT_NE(e.find("not a gzip-compressed FreeSurfer volume"), std::string::npos) << e;
    EXPECT_EQ(e.find("--dims"), std::string::npos) << e;  // not the raw-volume advice
    const std::string notMgh = writeText("fake.mgh", std::string(400, '\x02'));
    e = errorOf([&] { loadVolume(notMgh); });
    EXPECT_NE(e.find("not a FreeSurfer MGH file (its version field is"), std::string::npos) << e;
    const std::string shortFile = writeText("short.mgh", std::string(100, '\0'));
    e = errorOf([&] { loadVolume(shortFile); });
    EXPECT_NE(e.find("shorter than the 284-byte FreeSurfer MGH header"), std::string::npos) << e;
    // A real MGH header with its data cut short.
    std::ifstream in(mghDir() + "/labels_uint8.mgh", std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string cut = writeText("cut.mgh", bytes.substr(0, 284 + 100));
    e = errorOf([&] { loadVolume(cut); });
    EXPECT_NE(e.find("truncated"), std::string::npos) << e;
}

TEST(LabelTables, FreeSurferColorLut) {
    const LabelTable t =
        readLabelTable(writeText("FreeSurferColorLUT.txt",
                                 "#$Id: FreeSurferColorLUT.txt\n"
                                 "#No. Label Name:                            R   G   B   A\n\n"
                                 "  0  Unknown                                 0   0   0   0\n"
                                 " 17  Left-Hippocampus                      220 216  20   0\n"
                                 " 53  Right-Hippocampus                     220 216  20   0\n"));
    EXPECT_EQ(t.format, "freesurfer");
    ASSERT_EQ(t.entries.size(), 3u);
    EXPECT_EQ(t.find(17)->name, "Left-Hippocampus");
    EXPECT_EQ(t.find(17)->rgb, (std::array<int, 3>{220, 216, 20}));
    EXPECT_EQ(t.idOf("right-hippocampus"), 53);
    EXPECT_EQ(t.idOf("Hippocampus"), -1);
    EXPECT_EQ(t.nearestNames("Left-Hipocampus").front(), "Left-Hippocampus");
}

TEST(LabelTables, ItkSnapDescription) {
    const LabelTable t =
        readLabelTable(writeText("labels.label",
                                 "################################################\n"
                                 "# ITK-SnAP Label Description File\n"
                                 "# IDX   -R-  -G-  -B-  -A--  VIS MSH  LABEL\n"
                                 "    0     0    0    0        0  0  0    \"Clear Label\"\n"
                                 "    1   255    0    0        1  1  1    \"Left hippocampus\"\n"
                                 "    2     0  255    0      0.5  1  1    \"Tumour core\"\n"));
    EXPECT_EQ(t.format, "itksnap");
    EXPECT_EQ(t.find(1)->name, "Left hippocampus");
    EXPECT_EQ(t.find(2)->rgb, (std::array<int, 3>{0, 255, 0}));
    EXPECT_EQ(t.find(2)->opacity, 0.5);
    EXPECT_TRUE(t.find(2)->hasColour);
}

TEST(LabelTables, MricronTextAndLut) {
    const std::string txt = writeText(
        "atlas.nii.txt", "1 Precentral_L 2001\n2 Precentral_R 2002\n37 Hippocampus_L 4101\n");
    std::string lut(768, '\0');
    lut[37] = char(200);        // red of index 37
    lut[256 + 37] = char(100);  // green
    lut[512 + 37] = char(50);   // blue
    lut[1] = char(10);
    writeText("atlas.nii.lut", lut);
    for (const LabelTable& t :
         {readLabelTable(txt), readLabelTable(txt.substr(0, txt.size() - 4) + ".lut"),
          tableBeside(txt.substr(0, txt.size() - 4) + ".gz")}) {
        EXPECT_EQ(t.format, "mricron");
        ASSERT_EQ(t.entries.size(), 3u) << t.source;
        EXPECT_EQ(t.find(37)->name, "Hippocampus_L");
        EXPECT_TRUE(t.find(37)->hasColour);
        EXPECT_EQ(t.find(37)->rgb, (std::array<int, 3>{200, 100, 50}));
        EXPECT_EQ(t.find(1)->rgb, (std::array<int, 3>{10, 0, 0}));
    }
    EXPECT_TRUE(tableBeside(writeText("nothing.nii", "")).empty());
}

TEST(LabelTables, TheInstalledAalTable) {
    const std::string txt = "/usr/share/mricron/templates/aal.nii.txt";
    if (!fs::exists(txt)) GTEST_SKIP() << "mricron-data is not installed (scripts/setup.sh)";
    const LabelTable t = readLabelTable(txt);
    EXPECT_EQ(t.entries.size(), 116u);
    EXPECT_EQ(t.find(37)->name, "Hippocampus_L");
    EXPECT_EQ(t.find(116)->name, "Vermis_10");
    EXPECT_TRUE(t.find(37)->hasColour);
    // The .lut is planar: left/right pairs share colours, so indices 1 and 2 read alike.
    EXPECT_EQ(t.find(1)->rgb, t.find(2)->rgb);
}

TEST(LabelTables, ErrorsNameTheFileAndLine) {
    std::string e = errorOf([] { readLabelTable(writeText("bad1.txt", "1 a 2 3 4\n")); });
    EXPECT_NE(e.find("bad1.txt, line 1: not a label table line"), std::string::npos) << e;
    e = errorOf([] { readLabelTable(writeText("bad2.txt", "1 a 255 0 0 0\n2 b 300 0 0 0\n")); });
    EXPECT_NE(e.find("bad2.txt, line 2: the red component '300' is not a whole number 0–255"),
              std::string::npos)
        << e;
    e = errorOf([] { readLabelTable(writeText("bad3.txt", "1 a\n1 b\n")); });
    EXPECT_NE(e.find("line 2: label 1 is listed twice"), std::string::npos) << e;
    e = errorOf([] { readLabelTable(writeText("bad4.lut", std::string(100, 'x'))); });
    EXPECT_NE(e.find("holds 768 bytes"), std::string::npos) << e;
    e = errorOf([] { readLabelTable(writeText("bad5.txt", "# nothing\n")); });
    EXPECT_NE(e.find("lists no label"), std::string::npos) << e;
}

}  // namespace
}  // namespace lobe
