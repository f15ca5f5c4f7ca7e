// The DICOM series loader (volume/dicom_file.h) on series written at test time by
// tests/volume/make_dicom_series.py (pydicom), checked against NIfTI files of the same volumes the
// script writes from an independent path (the generating numbers; for pydicom's shipped CT5N
// series, pydicom's own parse of the files): every DICOM voxel's world position must be a voxel
// of the NIfTI with the same value. Plus hand values, and one error for each kind of bad series.
#include "core/error.h"
#include "volume/dicom_file.h"
#include "volume/volume.h"
#include "volume/volume_summary.h"

#include <gdcmImageChangeTransferSyntax.h>
#include <gdcmImageReader.h>
#include <gdcmImageWriter.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <string>
#include <vector>

namespace lobe {
namespace {

namespace fs = std::filesystem;

// The series, written once per test process (ctest runs each test as its own process: each
// gets its own folder).
const fs::path& data() {
    static const fs::path dir = [] {
        const fs::path d = fs::path(LOBE_BINARY_DIR) / "test-output" / "dicom" /
                           ("p" + std::to_string(::getpid()));
        fs::remove_all(d);
        fs::create_directories(d);
        const std::string cmd = std::string(LOBE_SYSTEM_PYTHON) + " '" + LOBE_SOURCE_DIR +
                                "/tests/volume/make_dicom_series.py' '" + d.string() + "'";
        if (std::system(cmd.c_str()) != 0)
            throw std::runtime_error("cannot write the test series (" + cmd +
                                     "); scripts/setup.sh installs python3-pydicom");
        return d;
    }();
    return dir;
}

std::string at(const std::string& name) { return (data() / name).string(); }

void expectError(const std::function<void()>& f, const std::vector<std::string>& parts) {
    try {
        f();
        ADD_FAILURE() << "no error; expected one naming: " << parts.front();
    } catch (const Error& e) {
        const std::string m = e.what();
        for (const std::string& p : parts)
            EXPECT_NE(m.find(p), std::string::npos) << "'" << p << "' not in: " << m;
    }
}

// Every voxel of `dicom` at its world position is a voxel of `nifti` (to 1e-3 of an index),
// holding the same value (to 1e-3), and the two have the same voxel count.
void expectSameByWorld(const Volume& dicom, const Volume& nifti) {
    ASSERT_EQ(double(dicom.dims[0]) * dicom.dims[1] * dicom.dims[2],
              double(nifti.dims[0]) * nifti.dims[1] * nifti.dims[2]);
    const auto a = dicom.grid->getConstAccessor();
    const auto b = nifti.grid->getConstAccessor();
    int mismatches = 0;
    for (int k = 0; k < dicom.dims[2]; ++k)
        for (int j = 0; j < dicom.dims[1]; ++j)
            for (int i = 0; i < dicom.dims[0]; ++i) {
                const openvdb::Vec3d w =
                    dicom.grid->transform().indexToWorld(openvdb::Vec3d(i, j, k));
                const openvdb::Vec3d n = nifti.grid->transform().worldToIndex(w);
                const openvdb::Coord c(int(std::lround(n[0])), int(std::lround(n[1])),
                                       int(std::lround(n[2])));
                bool ok = true;
                for (int x = 0; x < 3; ++x)
                    ok = ok && std::abs(n[x] - c[x]) < 1e-3 && c[x] >= 0 && c[x] < nifti.dims[x];
                ok = ok && std::abs(a.getValue(openvdb::Coord(i, j, k)) - b.getValue(c)) < 1e-3;
                if (!ok && ++mismatches <= 5)
                    ADD_FAILURE() << "DICOM voxel (" << i << ", " << j << ", " << k
                                  << ") = " << a.getValue(openvdb::Coord(i, j, k)) << " at world "
                                  << w << " is NIfTI index " << n << " = " << b.getValue(c);
            }
    EXPECT_EQ(mismatches, 0);
}

openvdb::Vec3d world(const Volume& v, double i, double j, double k) {
    return v.grid->transform().indexToWorld(openvdb::Vec3d(i, j, k));
}

// The synthetic oblique CT (make_dicom_series.py, synthetic()): 5 × 4 × 6 voxels, PixelSpacing
// 0.8 (between rows) \ 0.6 (between columns), slices 2.5 mm apart, files out of slice order.
TEST(Dicom, SyntheticObliqueSeriesMatchesItsNifti) {
    const Volume d = loadVolume(at("ct"));
    EXPECT_EQ(d.dims, (std::array<int, 3>{5, 4, 6}));
    EXPECT_NEAR(d.spacing[0], 0.6, 1e-6);  // columns apart: PixelSpacing[1]
    EXPECT_NEAR(d.spacing[1], 0.8, 1e-6);  // rows apart: PixelSpacing[0]
    EXPECT_NEAR(d.spacing[2], 2.5, 1e-5);
    // Voxel (0, 0, 0) at ImagePositionPatient LPS (−40, 25, 110) of the first slice: RAS (40, −25,
    // 110).
    const openvdb::Vec3d o = world(d, 0, 0, 0);
    EXPECT_NEAR(o[0], 40.0, 1e-5);
    EXPECT_NEAR(o[1], -25.0, 1e-5);
    EXPECT_NEAR(o[2], 110.0, 1e-5);
    // Hounsfield units: stored 37 i − 53 j + 211 k − 300 + (i j k mod 7), times slope 2, plus
    // intercept −1024: voxel (0,0,0) stored −300 → −1624; (2,1,3) stored 74 − 53 + 633 − 300 + 6
    // = 360 → −304; (4,3,5) stored 148 − 159 + 1055 − 300 + 4 = 748 → 472.
    const auto acc = d.grid->getConstAccessor();
    EXPECT_EQ(acc.getValue(openvdb::Coord(0, 0, 0)), -1624.0f);
    EXPECT_EQ(acc.getValue(openvdb::Coord(2, 1, 3)), -304.0f);
    EXPECT_EQ(acc.getValue(openvdb::Coord(4, 3, 5)), 472.0f);
    // The smallest: (0, 3, 0), stored −159 − 300 = −459 → −1942.
    EXPECT_EQ(d.originalMin, -1942.0);

    const Volume n = loadVolume(at("ct.nii"));
    expectSameByWorld(d, n);
    // The same set of world points: both world boxes agree (each to float precision).
    const VolumeStats sd = computeStats(d), sn = computeStats(n);
    for (int a = 0; a < 3; ++a) {
        EXPECT_NEAR(sd.worldBox.min()[a], sn.worldBox.min()[a], 1e-3);
        EXPECT_NEAR(sd.worldBox.max()[a], sn.worldBox.max()[a], 1e-3);
    }
}

TEST(Dicom, AListOfFilesIsTheSeriesTheFolderIs) {
    std::vector<std::string> files;
    for (int n = 6; n >= 1; --n) files.push_back(at("ct/IM000" + std::to_string(n)));
    const Volume list = loadVolume(files);
    const Volume folder = loadVolume(at("ct"));
    expectSameByWorld(list, folder);
    // A list naming a file that is not DICOM is refused by name, never read as raw.
    files.push_back(at("ct/README.txt"));
    expectError([&] { loadVolume(files); }, {"README.txt", "not a DICOM file"});
}

TEST(Dicom, ShippedPydicomCtSeriesMatchesPydicomsNifti) {
    const fs::path shipped =
        "/usr/lib/python3/dist-packages/pydicom/data/test_files/dicomdirtests/98892001/CT5N";
    ASSERT_TRUE(fs::is_directory(shipped)) << "python3-pydicom's test data (scripts/setup.sh)";
    const Volume d = loadVolume(shipped.string());
    // Facts about the series (docs/dependencies.md): 16 × 16 × 5, 2.5 mm apart, intercept −1024.
    EXPECT_EQ(d.dims, (std::array<int, 3>{16, 16, 5}));
    EXPECT_NEAR(d.spacing[2], 2.5, 1e-4);
    EXPECT_LT(d.originalMin, 0.0);
    expectSameByWorld(d, loadVolume(at("ct5n.nii")));
    // The other shipped series of docs/dependencies.md: CT2 has a gap, CT2N two orientations.
    const fs::path dirs = shipped.parent_path().parent_path();
    expectError([&] { loadVolume((dirs / "77654033/CT2").string()); }, {"CT2", "missing slices"});
    expectError([&] { loadVolume((dirs / "98892001/CT2N").string()); },
                {"CT2N", "mixed orientations"});
}

TEST(Dicom, SeveralSeriesArePickedByUidOrListed) {
    expectError(
        [&] { loadVolume(at("two_series")); },
        {at("two_series"), "2 series", "1.2.826.0.1.3680043.8.498.1111", "'first series', 3 slices",
         "1.2.826.0.1.3680043.8.498.2222", "'second series', 4 slices", "--series"});
    LoadOptions o;
    o.series = "1.2.826.0.1.3680043.8.498.2222";
    const Volume v = loadVolume(at("two_series"), o);
    EXPECT_EQ(v.dims, (std::array<int, 3>{3, 2, 4}));
    EXPECT_NEAR(v.spacing[2], 1.0, 1e-9);
    // Slice n holds stored value n everywhere, intercept −1024: the top slice (z = 3) is −1021.
    EXPECT_EQ(v.grid->getConstAccessor().getValue(openvdb::Coord(2, 1, 3)), -1021.0f);
    o.series = "1.2.3";
    expectError([&] { loadVolume(at("two_series"), o); },
                {"no series with SeriesInstanceUID '1.2.3'", "'second series', 4 slices"});
    const std::vector<detail::DicomSeriesInfo> list = detail::listDicomSeries({at("two_series")});
    ASSERT_EQ(list.size(), 2u);
    EXPECT_EQ(list[1].description, "second series");
    EXPECT_EQ(list[1].slices, 4);
}

TEST(Dicom, EachBadSeriesHasItsOwnError) {
    expectError([&] { loadVolume(at("gap")); },
                {at("gap"), "missing slices: 5 mm between", "axial_03.dcm", "axial_04.dcm",
                 "2.5 mm elsewhere", "1 slice missing"});
    expectError([&] { loadVolume(at("uneven")); },
                {at("uneven"), "unevenly spaced slices: 2.5 to 3 mm"});
    expectError([&] { loadVolume(at("duplicate")); },
                {at("duplicate"), "two slices at the same position"});
    expectError([&] { loadVolume(at("mixed")); },
                {at("mixed"), "mixed orientations", "axial_03.dcm", "1\\0\\0\\0\\0\\-1"});
    expectError(
        [&] { loadVolume(at("compressed")); },
        {"mpeg2.dcm", "GDCM cannot decode the pixel data", "MPEG2", "1.2.840.10008.1.2.4.100"});
    fs::create_directories(data() / "empty" / "sub");
    expectError([&] { loadVolume(at("empty")); },
                {at("empty"), "no DICOM image file", "subfolders"});
}

// Standard error while `f` runs (fd 2 to a temporary file): what a user would see beside the
// error message.
std::string stderrOf(const std::function<void()>& f) {
    std::fflush(stderr);
    std::FILE* file = std::tmpfile();
    const int saved = ::dup(2);
    ::dup2(::fileno(file), 2);
    f();
    std::fflush(stderr);
    ::dup2(saved, 2);
    ::close(saved);
    std::string text(size_t(std::ftell(file)), '\0');
    std::rewind(file);
    text.resize(std::fread(text.data(), 1, text.size(), file));
    std::fclose(file);
    return text;
}

// good64's second slice re-encoded by GDCM as JPEG lossless (process 14, selection value 1),
// then 512 bytes in the middle of its compressed stream zeroed; alone in its folder.
std::string damagedJpegLossless() {
    const fs::path folder = data() / "jpeg_damaged";
    fs::create_directories(folder);
    const std::string out = (folder / "slice.dcm").string();
    gdcm::ImageReader reader;
    reader.SetFileName(at("good64/slice_02.dcm").c_str());
    EXPECT_TRUE(reader.Read());
    gdcm::ImageChangeTransferSyntax change;
    change.SetTransferSyntax(gdcm::TransferSyntax::JPEGLosslessProcess14_1);
    change.SetInput(reader.GetImage());
    EXPECT_TRUE(change.Change());
    gdcm::ImageWriter writer;
    writer.SetFile(reader.GetFile());
    writer.SetImage(change.GetOutput());
    writer.SetFileName(out.c_str());
    EXPECT_TRUE(writer.Write());
    std::string bytes;
    {
        std::ifstream in(out, std::ios::binary);
        bytes.assign(std::istreambuf_iterator<char>(in), {});
    }
    const size_t soi = bytes.find("\xff\xd8\xff"), eoi = bytes.rfind("\xff\xd9");
    EXPECT_NE(soi, std::string::npos);
    EXPECT_GT(eoi, soi + 1024);  // a stream long enough to lose 512 bytes from its middle
    const size_t middle = (soi + eoi) / 2;
    std::fill(bytes.begin() + long(middle - 256), bytes.begin() + long(middle + 256), '\0');
    std::ofstream(out, std::ios::binary) << bytes;
    return out;
}

// Damaged pixel data is refused with one error naming the file, and GDCM prints nothing (it
// zero-filled the missing voxels, or decoded garbage, and the load succeeded).
TEST(Dicom, DamagedPixelDataIsRefusedByName) {
    const Volume good = loadVolume(at("good64"));  // the undamaged series loads
    EXPECT_EQ(good.dims, (std::array<int, 3>{64, 64, 3}));
    const std::string said = stderrOf([&] {
        expectError([&] { loadVolume(at("short_pixels")); },
                    {"short_pixels/slice_02.dcm", "pixel data holds 8190 bytes, expected 8192"});
        expectError([&] { loadVolume(at("cut_file")); },
                    {"cut_file/slice_02.dcm", "damaged or cut short", "Incomplete Pixel Data"});
        const std::string jpeg = damagedJpegLossless();
        expectError([&] { loadVolume(jpeg); },
                    {jpeg, "does not decode cleanly", "JPEG Lossless", "Corrupt JPEG data"});
    });
    EXPECT_EQ(said, "");
}

TEST(Dicom, ADicomFileIsNeverReadAsRawVoxels) {
    // Named like a raw file: read as DICOM (one slice) by its magic, whatever the name.
    const fs::path renamed = data() / "slice.raw";
    fs::copy_file(at("ct/IM0001"), renamed, fs::copy_options::overwrite_existing);
    EXPECT_TRUE(detail::hasDicomMagic(renamed.string()));
    EXPECT_FALSE(detail::hasDicomMagic(at("ct.nii")));
    const Volume one = loadVolume(renamed.string());
    EXPECT_EQ(one.dims, (std::array<int, 3>{5, 4, 1}));
    EXPECT_NEAR(one.spacing[2], 2.5, 1e-9);  // one slice: SliceThickness
    // ... which `lobe render` warns of (it rendered as a slab without a word).
    EXPECT_EQ(one.note, renamed.string() +
                            ": a single slice, drawn as a slab 2.5 mm thick "
                            "(SliceThickness); give the folder of the whole series for a volume");
    EXPECT_EQ(loadVolume(at("ct")).note, "");
    // A raw layout given for a DICOM file or folder is an error, not a reinterpretation.
    LoadOptions raw;
    raw.hasLayout = true;
    raw.layout.dims = {5, 4, 1};
    raw.layout.type = VoxelType::kInt16;
    expectError([&] { loadVolume(renamed.string(), raw); }, {renamed.string(), "DICOM", "--dims"});
    expectError([&] { loadVolume(at("ct"), raw); }, {at("ct"), "DICOM", "--dims"});
    // A series asked of a file that is not DICOM.
    LoadOptions series;
    series.series = "1.2";
    expectError([&] { loadVolume(at("ct/README.txt"), series); }, {"README.txt", "not a DICOM"});
}

TEST(Dicom, InfoAndConvertReadAFolder) {
    const VolumeSummary s = summarizeVolume(at("ct"), {});
    EXPECT_EQ(s.dims, (std::array<int, 3>{5, 4, 6}));
    EXPECT_NEAR(s.worldOfFirstVoxel[0], 40.0, 1e-5);
    const std::string out = (data() / "ct.vdb").string();
    const VolumeSummary c = convertVolume(at("ct"), out, {}, "");
    expectSameByWorld(loadVolume(out), loadVolume(at("ct.nii")));
}

}  // namespace
}  // namespace lobe
