// Volume loaders on small files written here: every voxel type and byte order of raw files,
// NIfTI-1 headers of either byte order with sform / qform / pixdim orientation and value scaling,
// NRRD detached headers, .vdb round trips, and one test per kind of bad input (truncation, size
// contradictions, unknown types, NaN/Inf, wrong magic, damaged gzip) checking that the error names
// the file and the problem and that nothing is written.
#include "core/error.h"
#include "volume/volume.h"
#include "volume/volume_summary.h"

#include <gtest/gtest.h>
#include <openvdb/io/Compression.h>
#include <openvdb/io/File.h>
#include <sys/resource.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

namespace lobe {
namespace {

namespace fs = std::filesystem;
using Bytes = std::vector<unsigned char>;

// One folder per test: ctest runs the tests of this file as parallel processes, and a test that
// checks its folder for leftover temporaries must not see another test's files being written.
fs::path tempDir() {
    const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
    fs::path d = fs::path(LOBE_BINARY_DIR) / "test-output" / "volume" /
                 (std::string(info->test_suite_name()) + "." + info->name());
    fs::create_directories(d);
    return d;
}

std::string writeFile(const std::string& name, const Bytes& bytes) {
    const fs::path p = tempDir() / name;
    std::ofstream out(p, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()),
              static_cast<std::streamsize>(bytes.size()));
    return p.string();
}

std::string writeGz(const std::string& name, const Bytes& bytes) {
    const fs::path p = tempDir() / name;
    gzFile f = gzopen(p.string().c_str(), "wb9");
    gzwrite(f, bytes.data(), static_cast<unsigned>(bytes.size()));
    gzclose(f);
    return p.string();
}

Bytes readAll(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return Bytes(std::istreambuf_iterator<char>(in), {});
}

template <typename T>
void put(Bytes& b, T v, bool big) {
    unsigned char raw[sizeof(T)];
    std::memcpy(raw, &v, sizeof(T));  // this machine is little-endian (x86-64, checked below)
    if (big) std::reverse(raw, raw + sizeof(T));
    b.insert(b.end(), raw, raw + sizeof(T));
}

// Expects `f` to throw lobe::Error whose message contains every one of `parts`.
template <typename F>
void expectError(F&& f, std::initializer_list<std::string> parts) {
    try {
        f();
        FAIL() << "no lobe::Error thrown";
    } catch (const Error& e) {
        const std::string m = e.what();
        for (const std::string& part : parts)
            EXPECT_NE(m.find(part), std::string::npos) << "message: " << m << "\nmissing: " << part;
    }
}

float valueAt(const Volume& v, int i, int j, int k) {
    return v.grid->tree().getValue(openvdb::Coord(i, j, k));
}
bool activeAt(const Volume& v, int i, int j, int k) {
    return v.grid->tree().isValueOn(openvdb::Coord(i, j, k));
}
openvdb::Vec3d world(const Volume& v, double i, double j, double k) {
    return v.grid->transform().indexToWorld(openvdb::Vec3d(i, j, k));
}
void expectNear(const openvdb::Vec3d& a, const openvdb::Vec3d& b) {
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], 1e-5) << "component " << c;
}

RawLayout layout(int x, int y, int z, VoxelType type, Endian endian) {
    RawLayout l;
    l.dims = {x, y, z};
    l.type = type;
    l.endian = endian;
    return l;
}

TEST(VolumeRaw, MachineIsLittleEndian) {
    const std::uint16_t one = 1;
    unsigned char first;
    std::memcpy(&first, &one, 1);
    ASSERT_EQ(first, 1) << "the byte-order tests below write little-endian by memcpy";
}

// A 3×2×2 int16 big-endian volume, x fastest, value at (i,j,k) = 100k + 10j + i − 5 except voxel
// (0,0,0) = 0; spacing (1,1,2) maps index (1,1,1) to world (1,1,2).
TEST(VolumeRaw, Int16BigEndianValuesTransformAndSparsity) {
    Bytes b;
    for (int k = 0; k < 2; ++k)
        for (int j = 0; j < 2; ++j)
            for (int i = 0; i < 3; ++i) {
                std::int16_t v = static_cast<std::int16_t>(100 * k + 10 * j + i - 5);
                if (i == 0 && j == 0 && k == 0) v = 0;
                put<std::int16_t>(b, v, true);
            }
    const std::string path = writeFile("a.raw", b);
    RawLayout l = layout(3, 2, 2, VoxelType::kInt16, Endian::kBig);
    l.spacing = {1, 1, 2};
    const Volume v = loadRaw(path, l);
    EXPECT_EQ(v.dims, (std::array<int, 3>{3, 2, 2}));
    EXPECT_EQ(valueAt(v, 2, 1, 1), 100 + 10 + 2 - 5);
    EXPECT_EQ(valueAt(v, 1, 0, 0), -4);
    EXPECT_EQ(valueAt(v, 0, 0, 0), 0.0f);
    EXPECT_FALSE(activeAt(v, 0, 0, 0)) << "zero is the background";
    EXPECT_FALSE(activeAt(v, 1, 0, 0)) << "negative values are ≤ background 0: stored, inactive";
    EXPECT_FALSE(activeAt(v, 2, 0, 0));  // 2 − 5 = −3
    EXPECT_TRUE(activeAt(v, 0, 1, 0));   // 10 − 5 = 5
    // Inactive: (0,0,0) = 0, (1,0,0) = −4, (2,0,0) = −3; the other 9 are 5..107.
    EXPECT_EQ(v.grid->activeVoxelCount(), 9u);
    EXPECT_DOUBLE_EQ(v.originalMin, -4.0);
    EXPECT_DOUBLE_EQ(v.originalMax, 107.0);  // 100 + 10 + 2 − 5
    expectNear(world(v, 1, 1, 1), {1, 1, 2});
    EXPECT_DOUBLE_EQ(v.spacing[2], 2.0);
}

TEST(VolumeRaw, ByteOrderSwapsBytes) {
    // Bytes 01 02: big-endian 0x0102 = 258, little-endian 0x0201 = 513.
    const std::string path = writeFile("order.raw", Bytes{0x01, 0x02});
    EXPECT_EQ(valueAt(loadRaw(path, layout(1, 1, 1, VoxelType::kUint16, Endian::kBig)), 0, 0, 0),
              258);
    EXPECT_EQ(valueAt(loadRaw(path, layout(1, 1, 1, VoxelType::kUint16, Endian::kLittle)), 0, 0, 0),
              513);
}

TEST(VolumeRaw, EveryVoxelType) {
    struct Case {
        VoxelType type;
        Bytes bytes;  // big-endian
        float expected;
    };
    const Case cases[] = {
        {VoxelType::kUint8, {0xFF}, 255.0f},
        {VoxelType::kInt8, {0xFF}, -1.0f},
        {VoxelType::kUint16, {0xFF, 0xFE}, 65534.0f},
        {VoxelType::kInt16, {0xFF, 0xFE}, -2.0f},
        {VoxelType::kUint32, {0x00, 0x01, 0x00, 0x01}, 65537.0f},
        {VoxelType::kInt32, {0xFF, 0xFF, 0xFF, 0xFD}, -3.0f},
        {VoxelType::kFloat32, {0x3F, 0xC0, 0x00, 0x00}, 1.5f},  // 1.5 = 0x3FC00000
        {VoxelType::kFloat64,
         {0xC0, 0x02, 0, 0, 0, 0, 0, 0},
         -2.25f},  // -2.25 = 0xC002000000000000
    };
    for (const Case& c : cases) {
        const std::string path =
            writeFile(std::string("t_") + voxelTypeName(c.type) + ".raw", c.bytes);
        EXPECT_EQ(valueAt(loadRaw(path, layout(1, 1, 1, c.type, Endian::kBig)), 0, 0, 0),
                  c.expected)
            << voxelTypeName(c.type);
        EXPECT_EQ(parseVoxelType(voxelTypeName(c.type)), c.type);
    }
    EXPECT_EQ(parseVoxelType("short"), VoxelType::kInt16);
    EXPECT_EQ(parseVoxelType("uchar"), VoxelType::kUint8);
}

TEST(VolumeRaw, BackgroundThresholdKeepsValuesButDeactivates) {
    const std::string path = writeFile("bg.raw", Bytes{0, 10, 50, 200});
    LoadOptions o;
    o.background = 50;
    const Volume v = loadRaw(path, layout(4, 1, 1, VoxelType::kUint8, Endian::kLittle), o);
    EXPECT_EQ(valueAt(v, 1, 0, 0), 10.0f) << "below the threshold, still stored";
    EXPECT_EQ(valueAt(v, 2, 0, 0), 50.0f);
    EXPECT_FALSE(activeAt(v, 1, 0, 0));
    EXPECT_FALSE(activeAt(v, 2, 0, 0)) << "≤ threshold is inactive";
    EXPECT_TRUE(activeAt(v, 3, 0, 0));
    EXPECT_EQ(v.grid->activeVoxelCount(), 1u);
}

TEST(VolumeRaw, NormalisationDividesAndRemembersOriginalRange) {
    const std::string path = writeFile("norm.raw", Bytes{0, 20, 80});
    LoadOptions o;
    o.normalize = 40;
    o.background = 20;  // file units: 20 → stored 0.5, inactive
    const Volume v = loadRaw(path, layout(3, 1, 1, VoxelType::kUint8, Endian::kLittle), o);
    EXPECT_FLOAT_EQ(valueAt(v, 1, 0, 0), 0.5f);
    EXPECT_FLOAT_EQ(valueAt(v, 2, 0, 0), 2.0f);
    EXPECT_FALSE(activeAt(v, 1, 0, 0));
    EXPECT_DOUBLE_EQ(v.originalMax, 80.0);
    EXPECT_DOUBLE_EQ(v.valueScale, 1.0 / 40.0);
    LoadOptions byMax;
    byMax.normalizeByMax = true;
    const Volume m = loadRaw(path, layout(3, 1, 1, VoxelType::kUint8, Endian::kLittle), byMax);
    EXPECT_FLOAT_EQ(valueAt(m, 2, 0, 0), 1.0f);
    EXPECT_FLOAT_EQ(valueAt(m, 1, 0, 0), 0.25f);
}

TEST(VolumeRaw, GzipEqualsPlain) {
    Bytes b;
    for (int n = 0; n < 4 * 3 * 2; ++n)
        put<std::uint16_t>(b, static_cast<std::uint16_t>(n * 97), true);
    const std::string gz = writeGz("g.raw.gz", b);
    LoadOptions o;
    o.hasLayout = true;
    o.layout = layout(4, 3, 2, VoxelType::kUint16, Endian::kBig);
    const Volume v = loadVolume(gz, o);
    EXPECT_EQ(valueAt(v, 3, 2, 1), 23.0f * 97.0f);  // voxel number 3 + 2·4 + 1·12 = 23
    EXPECT_EQ(valueAt(v, 1, 0, 0), 97.0f);
}

TEST(VolumeErrors, RawTruncatedAndTooLong) {
    const std::string shortFile = writeFile("short.raw", Bytes(7, 1));
    expectError([&] { loadRaw(shortFile, layout(2, 2, 2, VoxelType::kUint8, Endian::kLittle)); },
                {shortFile, "truncated", "2x2x2", "8 bytes", "holds 7"});
    const std::string longFile = writeFile("long.raw", Bytes(9, 1));
    expectError([&] { loadRaw(longFile, layout(2, 2, 2, VoxelType::kUint8, Endian::kLittle)); },
                {longFile, "contradicts the data size", "holds 9"});
    RawLayout withOffset = layout(2, 2, 2, VoxelType::kUint8, Endian::kLittle);
    withOffset.offset = 1;
    EXPECT_NO_THROW(loadRaw(longFile, withOffset)) << "1 header byte + 8 voxels = 9";
}

TEST(VolumeErrors, UnknownTypeAndBadOptions) {
    expectError([] { parseVoxelType("int17"); }, {"int17", "unknown voxel type"});
    VolumeOptionText t;
    t.dims = "4,4";
    t.type = "uint8";
    expectError([&] { parseLoadOptions(t); }, {"--dims", "4,4"});
    t.dims = "4,4,4";
    t.type = "int16";
    expectError([&] { parseLoadOptions(t); }, {"--endian"});
    t.endian = "middle";
    expectError([&] { parseLoadOptions(t); }, {"--endian", "middle"});
    t.endian = "big";
    t.type = "complex";
    expectError([&] { parseLoadOptions(t); }, {"--type", "complex"});
    t.type = "int16";
    t.normalize = "zero";
    expectError([&] { parseLoadOptions(t); }, {"--normalize", "zero"});
    t.normalize = "max";
    const LoadOptions o = parseLoadOptions(t);
    EXPECT_TRUE(o.hasLayout && o.normalizeByMax);
    EXPECT_EQ(o.layout.dims, (std::array<int, 3>{4, 4, 4}));
    EXPECT_EQ(o.layout.endian, Endian::kBig);
    const std::string raw = writeFile("nolayout.raw", Bytes(8, 0));
    expectError([&] { loadVolume(raw); }, {raw, "--dims"});
    const std::string absent = (tempDir() / "absent.raw").string();
    expectError([&] { loadVolume(absent); }, {absent, "cannot open"});
}

TEST(VolumeErrors, NonFiniteVoxels) {
    Bytes nan, inf;
    put<float>(nan, 1.0f, false);
    put<float>(nan, std::numeric_limits<float>::quiet_NaN(), false);
    put<double>(inf, 2.0, true);
    put<double>(inf, -std::numeric_limits<double>::infinity(), true);
    const std::string nanPath = writeFile("nan.raw", nan);
    const std::string infPath = writeFile("inf.raw", inf);
    expectError([&] { loadRaw(nanPath, layout(2, 1, 1, VoxelType::kFloat32, Endian::kLittle)); },
                {nanPath, "voxel (1, 0, 0)", "NaN"});
    expectError([&] { loadRaw(infPath, layout(1, 2, 1, VoxelType::kFloat64, Endian::kBig)); },
                {infPath, "voxel (0, 1, 0)", "infinite"});
    // A finite double beyond the float range cannot be stored either.
    Bytes huge;
    put<double>(huge, 1e300, false);
    const std::string hugePath = writeFile("huge.raw", huge);
    expectError([&] { loadRaw(hugePath, layout(1, 1, 1, VoxelType::kFloat64, Endian::kLittle)); },
                {hugePath, "float range"});
}

TEST(VolumeErrors, GzipDamage) {
    Bytes b(5000);
    for (size_t n = 0; n < b.size(); ++n) b[n] = static_cast<unsigned char>((n * n) % 251);
    const std::string good = writeGz("good.raw.gz", b);
    const Bytes gz = readAll(good);
    LoadOptions o;
    o.hasLayout = true;
    o.layout = layout(50, 100, 1, VoxelType::kUint8, Endian::kLittle);
    EXPECT_NO_THROW(loadVolume(good, o));

    const std::string cut = writeFile("cut.raw.gz", Bytes(gz.begin(), gz.begin() + gz.size() / 2));
    expectError([&] { loadVolume(cut, o); }, {cut, "gzip"});
    Bytes flipped = gz;
    for (size_t n = 20; n < 60 && n < flipped.size(); ++n) flipped[n] ^= 0x5A;
    const std::string bad = writeFile("flipped.raw.gz", flipped);
    expectError([&] { loadVolume(bad, o); }, {bad, "gzip"});
    const std::string notGz = writeFile("plain.raw.gz", b);
    expectError([&] { loadVolume(notGz, o); }, {notGz, "not a gzip file"});
    expectError([&] { loadVolume((tempDir() / "missing.raw.gz").string(), o); },
                {"missing.raw.gz", "cannot open"});
}

// ---- NIfTI-1 -----------------------------------------------------------------------------------

struct NiftiSpec {
    bool big = false;
    std::int16_t dims[4] = {3, 2, 2, 2};  // dim[0..3]
    std::int16_t dim4 = 1;
    std::int16_t datatype = 2;  // uint8
    std::int16_t bitpix = 8;
    float pixdim[4] = {1, 1, 1, 1};
    float voxOffset = 352;
    float slope = 1, inter = 0;
    std::int16_t qformCode = 0, sformCode = 0;
    float quat[3] = {0, 0, 0}, qoffset[3] = {0, 0, 0};
    float srow[3][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}};
    const char* magic = "n+1";
    std::int32_t sizeofHdr = 348;
};

// The 348-byte header laid out as nifti1.h says (offsets in volume_file.cpp), 4 extension bytes,
// then the voxel bytes.
Bytes niftiFile(const NiftiSpec& s, const Bytes& voxels) {
    Bytes h;
    put<std::int32_t>(h, s.sizeofHdr, s.big);
    h.resize(40, 0);
    put<std::int16_t>(h, s.dims[0], s.big);
    for (int a = 1; a <= 3; ++a) put<std::int16_t>(h, s.dims[a], s.big);
    put<std::int16_t>(h, s.dim4, s.big);
    for (int a = 5; a < 8; ++a) put<std::int16_t>(h, 1, s.big);
    h.resize(70, 0);
    put<std::int16_t>(h, s.datatype, s.big);
    put<std::int16_t>(h, s.bitpix, s.big);
    put<std::int16_t>(h, 0, s.big);
    for (int a = 0; a < 4; ++a) put<float>(h, s.pixdim[a], s.big);
    for (int a = 4; a < 8; ++a) put<float>(h, 1.0f, s.big);
    put<float>(h, s.voxOffset, s.big);  // 108
    put<float>(h, s.slope, s.big);      // 112
    put<float>(h, s.inter, s.big);      // 116
    h.resize(252, 0);
    put<std::int16_t>(h, s.qformCode, s.big);
    put<std::int16_t>(h, s.sformCode, s.big);
    for (float q : s.quat) put<float>(h, q, s.big);
    for (float q : s.qoffset) put<float>(h, q, s.big);
    for (const auto& row : s.srow)
        for (float x : row) put<float>(h, x, s.big);
    h.resize(344, 0);
    for (int c = 0; c < 4; ++c) h.push_back(static_cast<unsigned char>(s.magic[c]));  // incl. '\0'
    h.resize(352, 0);  // the 4-byte extension flag, all zero
    h.insert(h.end(), voxels.begin(), voxels.end());
    return h;
}

Bytes ramp(int n) {
    Bytes b;
    for (int v = 1; v <= n; ++v) b.push_back(static_cast<unsigned char>(v));
    return b;
}

TEST(VolumeNifti, SformLittleEndian) {
    NiftiSpec s;
    s.sformCode = 2;
    // x = −2 i + 90, y = 2 j − 126, z = 2 k − 72 (the SPM priors' LAS affine).
    s.srow[0][0] = -2;
    s.srow[0][3] = 90;
    s.srow[1][1] = 2;
    s.srow[1][3] = -126;
    s.srow[2][2] = 2;
    s.srow[2][3] = -72;
    const std::string path = writeFile("sform.nii", niftiFile(s, ramp(8)));
    const Volume v = loadNifti(path);
    expectNear(world(v, 0, 0, 0), {90, -126, -72});
    expectNear(world(v, 1, 1, 1), {88, -124, -70});
    EXPECT_EQ(valueAt(v, 1, 1, 1), 8.0f);  // x fastest: voxel number 1 + 2 + 4 = 7 → value 8
    EXPECT_EQ(valueAt(v, 1, 0, 0), 2.0f);
    EXPECT_DOUBLE_EQ(v.spacing[0], 2.0);
}

// qform (nifti1.h METHOD 2) for the quaternion of a 90° rotation about z: b = c = 0,
// d = sin 45° = √½, a = √(1 − d²) = √½. R = [[a²−d², −2ad, 0], [2ad, a²−d², 0], [0, 0, a²+d²]]
// = [[0, −1, 0], [1, 0, 0], [0, 0, 1]]. With pixdim (2, 3, 4) and qoffset (10, 20, 30):
// world(i, j, k) = (−3 j + 10, 2 i + 20, qfac·4 k + 30). Big-endian header, int16 data.
TEST(VolumeNifti, QformBigEndianWithQfac) {
    for (float qfac : {1.0f, -1.0f}) {
        NiftiSpec s;
        s.big = true;
        s.datatype = 4;
        s.bitpix = 16;
        s.qformCode = 1;
        s.quat[2] = static_cast<float>(std::sqrt(0.5));
        s.qoffset[0] = 10;
        s.qoffset[1] = 20;
        s.qoffset[2] = 30;
        s.pixdim[0] = qfac;
        s.pixdim[1] = 2;
        s.pixdim[2] = 3;
        s.pixdim[3] = 4;
        Bytes voxels;
        for (int n = 0; n < 8; ++n)
            put<std::int16_t>(voxels, static_cast<std::int16_t>(-300 * n), true);
        const std::string path = writeFile("qform.nii", niftiFile(s, voxels));
        const Volume v = loadNifti(path);
        expectNear(world(v, 0, 0, 0), {10, 20, 30});
        expectNear(world(v, 1, 0, 0), {10, 22, 30});
        expectNear(world(v, 0, 1, 0), {7, 20, 30});
        expectNear(world(v, 0, 0, 1), {10, 20, 30 + 4 * qfac});
        EXPECT_EQ(valueAt(v, 1, 1, 1), -2100.0f);
    }
}

TEST(VolumeNifti, PixdimFallbackAndScaling) {
    NiftiSpec s;
    s.pixdim[1] = 0.5;
    s.pixdim[2] = 0.75;
    s.pixdim[3] = 3;
    s.slope = 0;  // nifti1.h: slope 0 means no scaling
    s.inter = 7;
    Volume v = loadNifti(writeFile("pixdim.nii", niftiFile(s, ramp(8))));
    expectNear(world(v, 1, 1, 1), {0.5, 0.75, 3});
    EXPECT_EQ(valueAt(v, 1, 0, 0), 2.0f);
    s.slope = 0.5;
    s.inter = -1;  // y = 0.5 x − 1
    v = loadNifti(writeFile("scaled.nii", niftiFile(s, ramp(8))));
    EXPECT_FLOAT_EQ(valueAt(v, 1, 1, 1), 3.0f);  // 0.5·8 − 1
    EXPECT_FLOAT_EQ(valueAt(v, 1, 0, 0), 0.0f);  // 0.5·2 − 1: zero, the background
    EXPECT_FALSE(activeAt(v, 1, 0, 0));
    EXPECT_DOUBLE_EQ(v.originalMin, -0.5);
}

// Slopes that are 0, NaN or infinite mean "not scaled" (nifti1.h; nibabel for NaN and Inf); a
// usable slope with a NaN or infinite intercept is refused, and so is a product beyond float.
TEST(VolumeNifti, NonFiniteScalingIsReadAsNibabelReadsIt) {
    NiftiSpec s;
    for (const float slope : {std::nanf(""), INFINITY, -INFINITY}) {
        s.slope = slope;
        s.inter = 5;
        const Volume v = loadNifti(writeFile("unscaled.nii", niftiFile(s, ramp(8))));
        EXPECT_EQ(valueAt(v, 1, 0, 0), 2.0f);  // the raw value, intercept unused
    }
    s.slope = 2;
    for (const float inter : {std::nanf(""), INFINITY}) {
        s.inter = inter;
        expectError([&] { loadNifti(writeFile("badinter.nii", niftiFile(s, ramp(8)))); },
                    {"badinter.nii", "scl_inter is not finite"});
    }
    s.slope = 3e38f;
    s.inter = 0;
    expectError([&] { loadNifti(writeFile("overflow.nii", niftiFile(s, ramp(8)))); },
                {"overflow.nii", "outside the float range"});
}

// A small gzip file whose data inflates far past what its header describes (a gzip bomb: 1 GB
// of zeros in ~1 MB) is refused once the inflated data passes the header's size, not after
// inflating it all.
TEST(VolumeErrors, GzipBombStopsAtTheHeadersSize) {
    const Bytes head = niftiFile(NiftiSpec(), ramp(8));
    const fs::path path = tempDir() / "bomb.nii.gz";
    gzFile f = gzopen(path.string().c_str(), "wb1");
    gzwrite(f, head.data(), static_cast<unsigned>(head.size()));
    const Bytes zeros(size_t(1) << 24, 0);
    for (int i = 0; i < 64; ++i) gzwrite(f, zeros.data(), static_cast<unsigned>(zeros.size()));
    gzclose(f);
    rusage before{};
    getrusage(RUSAGE_SELF, &before);
    expectError([&] { loadNifti(path.string()); }, {"bomb.nii.gz", "goes on past the 360 bytes"});
    rusage after{};
    getrusage(RUSAGE_SELF, &after);
    // The peak grew by far less than the 1 GB the file inflates to (ru_maxrss in KB).
    EXPECT_LT(after.ru_maxrss - before.ru_maxrss, 256 * 1024);
}

TEST(VolumeNifti, GzippedEqualsPlain) {
    NiftiSpec s;
    s.big = true;
    const Bytes file = niftiFile(s, ramp(8));
    const Volume plain = loadVolume(writeFile("z.nii", file));
    const Volume gz = loadVolume(writeGz("z.nii.gz", file));
    for (int k = 0; k < 2; ++k)
        for (int j = 0; j < 2; ++j)
            for (int i = 0; i < 2; ++i) EXPECT_EQ(valueAt(plain, i, j, k), valueAt(gz, i, j, k));
    EXPECT_EQ(valueAt(gz, 0, 1, 1), 7.0f);
}

TEST(VolumeErrors, NiftiHeaders) {
    const Bytes voxels = ramp(8);
    auto check = [&](const std::string& name, const NiftiSpec& s, const Bytes& data,
                     std::initializer_list<std::string> parts) {
        const std::string path = writeFile(name, niftiFile(s, data));
        expectError([&] { loadNifti(path); }, parts);
        expectError([&] { loadNifti(path); }, {path});
    };
    NiftiSpec s;
    check("trunc.nii", s, ramp(7), {"truncated", "8 bytes", "holds 7"});
    check("long.nii", s, ramp(9), {"contradicts the data size", "holds 9"});
    NiftiSpec wrongMagic;
    wrongMagic.magic = "abc";
    check("magic.nii", wrongMagic, voxels, {"wrong magic"});
    NiftiSpec pair;
    pair.magic = "ni1";
    check("pair.nii", pair, voxels, {"two-file"});
    NiftiSpec type;
    type.datatype = 32;  // complex64
    check("type.nii", type, voxels, {"unknown or unsupported NIfTI datatype 32"});
    NiftiSpec bitpix;
    bitpix.bitpix = 16;
    check("bitpix.nii", bitpix, voxels, {"bitpix 16"});
    NiftiSpec size;
    size.sizeofHdr = 349;
    check("sizeof.nii", size, voxels, {"not a NIfTI-1 file"});
    NiftiSpec fourD;
    fourD.dims[0] = 4;
    fourD.dim4 = 2;
    check("4d.nii", fourD, voxels, {"only 3-D"});
    NiftiSpec nanSpec;
    nanSpec.datatype = 16;
    nanSpec.bitpix = 32;
    Bytes floats;
    for (int n = 0; n < 8; ++n)
        put<float>(floats, n == 5 ? std::numeric_limits<float>::infinity() : 1.0f, false);
    check("inf.nii", nanSpec, floats, {"voxel (1, 0, 1)", "infinite"});
    const std::string tiny = writeFile("tiny.nii", Bytes(100, 0));
    expectError([&] { loadNifti(tiny); }, {tiny, "truncated", "348"});
}

// ---- NRRD --------------------------------------------------------------------------------------

TEST(VolumeNrrd, DetachedHeaderWithSpacingsAndDirections) {
    Bytes b;
    for (int n = 0; n < 8; ++n) put<std::int16_t>(b, static_cast<std::int16_t>(n + 1), true);
    writeGz("n.raw.gz", b);
    const std::string header =
        "NRRD0004\n# a comment\ntype: short\ndimension: 3\n"
        "sizes: 2 2 2\nspacings: 1 1 2\nendian: big\nencoding: gzip\n"
        "data file: n.raw.gz\n";
    const std::string path = writeFile("n.nhdr", Bytes(header.begin(), header.end()));
    const Volume v = loadVolume(path);
    EXPECT_EQ(valueAt(v, 1, 1, 1), 8.0f);
    expectNear(world(v, 1, 1, 1), {1, 1, 2});

    const std::string dirs =
        "NRRD0005\ntype: int16\ndimension: 3\nsizes: 2 2 2\n"
        "space directions: (0,2,0) (-1,0,0) (0,0,3)\n"
        "space origin: (5,6,7)\nendian: big\nencoding: gzip\n"
        "data file: n.raw.gz\n";
    const Volume d = loadVolume(writeFile("d.nhdr", Bytes(dirs.begin(), dirs.end())));
    expectNear(world(d, 1, 0, 0), {5, 8, 7});  // origin + first direction
    expectNear(world(d, 0, 1, 1), {4, 6, 10});
}

TEST(VolumeErrors, NrrdHeaders) {
    const std::string bad = "NRRX0004\ntype: short\n";
    const std::string badPath = writeFile("bad.nhdr", Bytes(bad.begin(), bad.end()));
    expectError([&] { loadVolume(badPath); }, {badPath, "wrong magic"});
    const std::string missing =
        "NRRD0004\ntype: short\ndimension: 3\nsizes: 2 2 2\n"
        "endian: big\ndata file: nowhere.raw\n";
    const std::string missingPath =
        writeFile("missing.nhdr", Bytes(missing.begin(), missing.end()));
    expectError([&] { loadVolume(missingPath); }, {"nowhere.raw", "cannot open"});
    const std::string type =
        "NRRD0004\ntype: block\ndimension: 3\nsizes: 2 2 2\n"
        "data file: n.raw.gz\n";
    const std::string typePath = writeFile("type.nhdr", Bytes(type.begin(), type.end()));
    expectError([&] { loadVolume(typePath); }, {typePath, "unknown voxel type 'block'"});
}

// ---- .vdb --------------------------------------------------------------------------------------

TEST(VolumeVdb, RoundTripKeepsValuesTransformAndMetadata) {
    Bytes b;
    for (int n = 0; n < 24; ++n)
        put<std::int16_t>(b, static_cast<std::int16_t>(n % 5 == 0 ? 0 : n * 10), false);
    RawLayout l = layout(4, 3, 2, VoxelType::kInt16, Endian::kLittle);
    l.spacing = {0.5, 1, 2};
    LoadOptions o;
    o.normalize = 230;
    o.background = 40;
    const Volume a = loadRaw(writeFile("rt.raw", b), l, o);
    const std::string out = (tempDir() / "rt.vdb").string();
    writeVdb(a, out, "ct");
    LoadOptions byName;
    byName.gridName = "ct";
    const Volume c = loadVolume(out, byName);
    EXPECT_EQ(c.grid->getName(), "ct");
    EXPECT_EQ(c.dims, a.dims);
    EXPECT_DOUBLE_EQ(c.originalMax, 230.0);
    EXPECT_DOUBLE_EQ(c.valueScale, 1.0 / 230.0);
    EXPECT_DOUBLE_EQ(c.background, 40.0);
    EXPECT_EQ(c.grid->activeVoxelCount(), a.grid->activeVoxelCount());
    for (int k = 0; k < 2; ++k)
        for (int j = 0; j < 3; ++j)
            for (int i = 0; i < 4; ++i) {
                EXPECT_EQ(valueAt(c, i, j, k), valueAt(a, i, j, k));
                EXPECT_EQ(activeAt(c, i, j, k), activeAt(a, i, j, k));
            }
    expectNear(world(c, 3, 2, 1), {1.5, 2, 2});
    LoadOptions wrong;
    wrong.gridName = "nope";
    expectError([&] { loadVdb(out, wrong); }, {out, "no grid named 'nope'", "ct"});
}

// Lobe's metadata in a .vdb is input like any other: a NaN or infinite value scale, range or
// background, or dims beyond 2^30 a side, is refused by name (a NaN scale was read as 1).
TEST(VolumeErrors, VdbMetadataMustBeFiniteAndInRange) {
    const Volume v = loadRaw(writeFile("m.raw", Bytes{1, 2}),
                             layout(2, 1, 1, VoxelType::kUint8, Endian::kLittle));
    const std::string good = (tempDir() / "meta.vdb").string();
    writeVdb(v, good);
    const auto withMeta = [&](const std::string& name, const std::string& key,
                              const openvdb::Metadata& value) {
        openvdb::io::File in(good);
        in.open();
        openvdb::GridBase::Ptr grid = in.readGrid("density");
        in.close();
        grid->insertMeta(key, value);
        const std::string path = (tempDir() / name).string();
        openvdb::io::File(path).write({grid});
        return path;
    };
    for (const char* key : {"lobe_value_scale", "lobe_original_min", "lobe_background"}) {
        const std::string path =
            withMeta(std::string(key) + ".vdb", key, openvdb::DoubleMetadata(std::nan("")));
        expectError([&] { loadVdb(path); }, {path, std::string("metadata ") + key, "not a finite"});
    }
    const std::string huge =
        withMeta("dims.vdb", "lobe_dims", openvdb::Vec3IMetadata(openvdb::Vec3i(2, 1, 2000000000)));
    expectError([&] { loadVdb(huge); }, {huge, "lobe_dims", "2^30"});
    // Each side within 2^30 but the box beyond 2^53 voxels (a fuzz finding: the voxel count
    // overflowed int64 in computeStats).
    const std::string cube = withMeta(
        "cube.vdb", "lobe_dims", openvdb::Vec3IMetadata(openvdb::Vec3i(1 << 30, 1 << 30, 1 << 30)));
    expectError([&] { loadVdb(cube); }, {cube, "more than 2^53"});
}

// A .vdb whose size fields claim more than the file holds is refused before OpenVDB builds a
// buffer of that size (a 4 GB metadata string took seconds and gigabytes before the read
// failed). Every registered metadata type of a valid file passes the same walk.
TEST(VolumeErrors, VdbSizeFieldsBeyondTheFileAreRefusedUpFront) {
    const Volume v = loadRaw(writeFile("s.raw", Bytes{1, 2}),
                             layout(2, 1, 1, VoxelType::kUint8, Endian::kLittle));
    const std::string plain = (tempDir() / "sizes_plain.vdb").string();
    writeVdb(v, plain);
    openvdb::io::File in(plain);
    in.open();
    openvdb::GridBase::Ptr grid = in.readGrid("density");
    in.close();
    grid->insertMeta("comment", openvdb::StringMetadata("abc"));
    grid->insertMeta("m_bool", openvdb::BoolMetadata(true));
    grid->insertMeta("m_float", openvdb::FloatMetadata(1.5f));
    grid->insertMeta("m_vec3d", openvdb::Vec3DMetadata(openvdb::Vec3d(1, 2, 3)));
    grid->insertMeta("m_vec4s", openvdb::Vec4SMetadata(openvdb::Vec4s(1, 2, 3, 4)));
    grid->insertMeta("m_mat4d", openvdb::Mat4DMetadata(openvdb::Mat4d::identity()));
    const std::string good = (tempDir() / "sizes_good.vdb").string();
    openvdb::MetaMap fileMeta;
    fileMeta.insertMeta("note", openvdb::StringMetadata("file level"));
    openvdb::io::File(good).write({grid}, fileMeta);
    EXPECT_EQ(loadVdb(good).dims, v.dims);

    std::ifstream f(good, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    // Patch the uint32 found LEAD bytes after the first occurrence of KEY to VALUE.
    const auto patched = [&](const std::string& name, const std::string& key, size_t lead,
                             std::uint32_t value) {
        std::string b = bytes;
        const size_t at = b.find(key);
        EXPECT_NE(at, std::string::npos) << key;
        std::memcpy(&b[at + key.size() + lead], &value, 4);
        const std::string path = (tempDir() / name).string();
        std::ofstream(path, std::ios::binary) << b;
        return path;
    };
    // "comment", then the type name "string" (4 + 6 bytes), then the value's byte count.
    const std::string longString = patched("long_string.vdb", "comment", 10, 0xF0000000u);
    expectError([&] { loadVdb(longString); }, {longString, "metadata 'comment' value", "damaged"});
    // The type name's own length.
    const std::string longType = patched("long_type.vdb", "comment", 0, 0x7FFFFFFFu);
    expectError([&] { loadVdb(longType); }, {longType, "metadata 'comment' type name", "damaged"});
    // A fixed-size value whose byte count disagrees with its type.
    const std::string badFloat = patched("bad_float.vdb", "m_float", 9, 3000000000u);
    expectError([&] { loadVdb(badFloat); }, {badFloat, "'m_float' of type float", "instead of 4"});
    // The file-level metadata and the grid's name.
    const std::string fileNote = patched("file_note.vdb", "note", 10, 0x10000000u);
    expectError([&] { loadVdb(fileNote); }, {fileNote, "file metadata 'note'", "damaged"});
    // The grid's name: its length is the uint32 before the first "density".
    std::string b = bytes;
    const size_t nameAt = b.find("density") - 4;
    const std::uint32_t hugeName = 0xFFFFFFF0u;
    std::memcpy(&b[nameAt], &hugeName, 4);
    const std::string badName = (tempDir() / "bad_name.vdb").string();
    std::ofstream(badName, std::ios::binary) << b;
    expectError([&] { loadVdb(badName); }, {badName, "grid 1 name", "damaged"});

    // Format versions: before OpenVDB 2.0 refused by name, beyond this OpenVDB's too (it only
    // warned, then read garbage); and a file cut short ends in one error, not a read that goes
    // on allocating (the topology reader does not stop at the end of the file by itself).
    const auto withVersion = [&](const std::string& name, std::uint32_t version) {
        std::string v = bytes;
        std::memcpy(&v[8], &version, 4);
        const std::string path = (tempDir() / name).string();
        std::ofstream(path, std::ios::binary) << v;
        return path;
    };
    const std::string old = withVersion("old.vdb", 213);
    expectError([&] { loadVdb(old); }, {old, "version 213", "OpenVDB 2.0"});
    const std::string future = withVersion("future.vdb", 5964000);
    expectError([&] { loadVdb(future); }, {future, "version 5964000", "newer"});
    const std::string cut = (tempDir() / "cut.vdb").string();
    std::ofstream(cut, std::ios::binary) << bytes.substr(0, bytes.size() * 3 / 4);
    expectError([&] { loadVdb(cut); }, {cut, "cannot read the OpenVDB file"});
    const std::string notVdb = writeFile("zeros.vdb", Bytes(200, 0));
    expectError([&] { loadVdb(notVdb); }, {notVdb, "no OpenVDB magic number"});
}

// The walk over a grid's tree (vdb_size_check.h) must agree with OpenVDB's reader on every
// valid layout: each compression (none, zip, Blosc, with and without active-mask compression),
// full and half floats, and every way a leaf's inactive values are stored (io/Compression.h:
// none, -background, one value, a selection mask between two, all values), with tiles at the
// root and in internal nodes, and root children on both sides of the origin.
TEST(VolumeVdb, TreeWalkAcceptsEveryValidLayout) {
    const float bg = 0.5f;
    openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(bg);
    grid->setName("density");
    auto& tree = grid->tree();
    // Leaf k holds one active voxel (value 1 + k) and inactive voxels in pattern k.
    const std::vector<std::vector<float>> inactive = {
        {bg}, {-bg}, {7.f}, {bg, -bg}, {bg, 7.f}, {7.f, 9.f}, {7.f, 9.f, 11.f}};
    for (int k = 0; k < int(inactive.size()); ++k)
        for (int v = 0; v < 512; ++v) {
            const openvdb::Coord c(8 * k + v % 8, v / 8 % 8, v / 64);
            if (v == 0)
                tree.setValueOn(c, 1.f + k);
            else
                tree.setValueOff(c, inactive[k][v % inactive[k].size()]);
        }
    // A fully active leaf of incompressible values, one across the origin.
    std::uint32_t state = 12345;
    for (int v = 0; v < 512; ++v) {
        state = state * 1664525u + 1013904223u;
        tree.setValueOn(openvdb::Coord(-8 + v % 8, v / 8 % 8, v / 64), float(state >> 8) * 1e-6f);
    }
    tree.addTile(1, openvdb::Coord(64, 0, 0), 3.f, true);     // an active 8³ tile
    tree.addTile(1, openvdb::Coord(72, 0, 0), 4.f, false);    // an inactive one
    tree.addTile(3, openvdb::Coord(8192, 0, 0), 5.f, false);  // a root tile
    const openvdb::Index64 active = tree.activeVoxelCount();

    using namespace openvdb::io;
    const std::uint32_t compressions[] = {
        COMPRESS_NONE,        COMPRESS_ZIP,
        COMPRESS_ACTIVE_MASK, COMPRESS_ZIP | COMPRESS_ACTIVE_MASK,
        COMPRESS_BLOSC,       COMPRESS_BLOSC | COMPRESS_ACTIVE_MASK};
    for (const bool half : {false, true})
        for (const std::uint32_t compression : compressions) {
            grid->setSaveFloatAsHalf(half);
            const std::string path = (tempDir() / ("layout_" + std::to_string(compression) +
                                                   (half ? "_half" : "") + ".vdb"))
                                         .string();
            openvdb::io::File out(path);
            out.setCompression(compression);
            out.write({grid});
            SCOPED_TRACE(path);
            Volume v;
            ASSERT_NO_THROW(v = loadVdb(path));
            EXPECT_EQ(v.grid->tree().activeVoxelCount(), active);
            const double tolerance = half ? 1e-2 : 0.0;
            for (const openvdb::Coord c : {openvdb::Coord(0, 0, 0), openvdb::Coord(8 * 6, 0, 0),
                                           openvdb::Coord(-3, 5, 7), openvdb::Coord(66, 1, 1)})
                EXPECT_NEAR(v.grid->tree().getValue(c), tree.getValue(c),
                            tolerance * std::abs(tree.getValue(c)))
                    << c;
        }
}

// A value chunk whose stated size differs from what its node holds is refused before OpenVDB
// reads it: OpenVDB 10 copies an uncompressed chunk of the stated size into the node's buffer
// first (a heap overflow, found by fuzz_vdb; the file is kept in fuzz/openvdb-findings/). Also a
// Blosc header that claims more bytes than its chunk, and a leaf whose mask differs between the
// topology and the buffers.
TEST(VolumeErrors, VdbValueChunksAreCheckedAgainstTheirNodes) {
    const std::string finding =
        std::string(LOBE_SOURCE_DIR) + "/fuzz/openvdb-findings/blosc-negative-chunk-overflow.vdb";
    expectError([&] { loadVdb(finding); }, {finding, "uncompressed chunk", "damaged"});

    // Two leaves: one with 4 active voxels (with active-mask compression 16 bytes of values,
    // too few to compress: zip and Blosc both store them as they are, under the size -16), one
    // fully active.
    openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(0.f);
    grid->setName("density");
    std::uint32_t state = 99;
    for (int v = 0; v < 512; ++v) {
        state = state * 1664525u + 1013904223u;
        grid->tree().setValueOn(openvdb::Coord(v % 8, v / 8 % 8, v / 64), 1.f + float(state >> 8));
    }
    for (int v = 0; v < 4; ++v) grid->tree().setValueOn(openvdb::Coord(100 + v, 0, 0), 2.f + v);
    const auto written = [&](const std::string& name, std::uint32_t compression) {
        const std::string path = (tempDir() / name).string();
        openvdb::io::File out(path);
        out.setCompression(compression);
        out.write({grid});
        EXPECT_NO_THROW(loadVdb(path));
        std::ifstream in(path, std::ios::binary);
        return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    };
    const auto saved = [&](const std::string& name, const std::string& bytes) {
        const std::string path = (tempDir() / name).string();
        std::ofstream(path, std::ios::binary) << bytes;
        return path;
    };
    const auto findInt64 = [](const std::string& bytes, std::int64_t value) {
        char raw[8];
        std::memcpy(raw, &value, 8);
        return bytes.find(std::string(raw, 8));
    };

    // A Blosc chunk holding `nbytes`: its int64 size S, then the header with nbytes at +4 and
    // cbytes = S at +12 (Blosc 1.x, blosc.h).
    const auto findBlosc = [](const std::string& bytes, std::uint32_t want) {
        for (size_t i = 0; i + 24 <= bytes.size(); ++i) {
            std::int64_t stored = 0;
            std::uint32_t nbytes = 0, cbytes = 0;
            std::memcpy(&stored, &bytes[i], 8);
            std::memcpy(&nbytes, &bytes[i + 8 + 4], 4);
            std::memcpy(&cbytes, &bytes[i + 8 + 12], 4);
            if (stored > 16 && nbytes == want && cbytes == stored) return i;
        }
        return std::string::npos;
    };

    // An uncompressed chunk's size lies (zip writes the 16 bytes as they are, under -16; Blosc
    // always compresses, so its chunk's size is replaced by a negative one).
    using namespace openvdb::io;
    for (const std::uint32_t codec : {COMPRESS_ZIP, COMPRESS_BLOSC}) {
        const std::string name = codec == COMPRESS_ZIP ? "zip" : "blosc";
        const std::string bytes = written(name + ".vdb", codec | COMPRESS_ACTIVE_MASK);
        const size_t at = codec == COMPRESS_ZIP ? findInt64(bytes, -16) : findBlosc(bytes, 16);
        ASSERT_NE(at, std::string::npos) << name;
        for (const std::int64_t lie :
             {std::int64_t(-4096), std::int64_t(-8), std::numeric_limits<std::int64_t>::min()}) {
            std::string b = bytes;
            std::memcpy(&b[at], &lie, 8);
            const std::string path = saved(name + "_lie" + std::to_string(lie % 1000) + ".vdb", b);
            expectError([&] { loadVdb(path); }, {path, "uncompressed chunk", "its node takes 16"});
        }
    }

    // A Blosc header claiming more bytes than its chunk holds.
    const std::string blosc = written("blosc_full.vdb", COMPRESS_BLOSC);
    const size_t chunk = findBlosc(blosc, 2048);
    ASSERT_NE(chunk, std::string::npos);
    std::string b = blosc;
    const std::uint32_t cbytes = 100000;
    std::memcpy(&b[chunk + 8 + 12], &cbytes, 4);
    const std::string longHeader = saved("blosc_cbytes.vdb", b);
    expectError([&] { loadVdb(longHeader); }, {longHeader, "Blosc chunk whose header states"});

    // The delayed-load table ("__delayedload", which OpenVDB's writer adds to every grid) is
    // left out of what OpenVDB reads: its reader trusts its own size fields over the entry's
    // stated size, so a damaged one shifted every later read (a fuzz finding). With its mask
    // block's size made absurd, the grid still loads, value for value.
    {
        std::string d = written("delayed.vdb", COMPRESS_BLOSC);
        const std::string type = "__delayedload";
        const size_t at = d.find(type);
        ASSERT_NE(at, std::string::npos);
        // the type name, then the entry's uint32 size, the leaf count, the mask block's size
        const std::uint32_t absurd = 0x7FFFFFF0u;
        std::memcpy(&d[at + type.size() + 4 + 4], &absurd, 4);
        const std::string path = saved("delayed_damaged.vdb", d);
        Volume v;
        ASSERT_NO_THROW(v = loadVdb(path));
        EXPECT_EQ(v.grid->tree().activeVoxelCount(), grid->tree().activeVoxelCount());
        EXPECT_EQ(v.grid->tree().getValue(openvdb::Coord(3, 4, 5)),
                  grid->tree().getValue(openvdb::Coord(3, 4, 5)));
    }

    const std::string zipped = written("zip_full.vdb", COMPRESS_ZIP);
    // The leaf's mask, all 64 bytes on, appears in the topology and again before its values.
    const std::string ones(64, '\xff');
    const size_t second = zipped.find(ones, zipped.find(ones) + 64);
    ASSERT_NE(second, std::string::npos);
    std::string m = zipped;
    m[second] = '\x7f';
    const std::string masks = saved("mask.vdb", m);
    expectError([&] { loadVdb(masks); }, {masks, "value mask differs", "512 on", "511 on"});
}

// `lobe info`'s percentiles (nearest rank, to within one of 65 536 bins) and histogram on 100
// voxels holding 0 … 99 in shuffled order: the k-th smallest value is k − 1.
TEST(VolumeSummary, PercentilesHistogramAndBlur) {
    Bytes b(100);
    for (int i = 0; i < 100; ++i)
        b[std::size_t(i)] = std::uint8_t((i * 37) % 100);  // a permutation
    const std::string path = writeFile("hundred.raw", b);
    LoadOptions o;
    o.hasLayout = true;
    o.layout = layout(10, 10, 1, VoxelType::kUint8, Endian::kLittle);
    const VolumeSummary s = summarizeVolume(path, o, 0.0, 10);
    const double bin = 99.0 / 65536.0;
    // Every voxel: ranks ceil(p N) = 1, 5, 50, 95, 99 → values 0, 4, 49, 94, 98.
    const double all[5] = {0, 4, 49, 94, 98};
    // Active voxels (the 0 is at the background threshold, inactive): 99 values 1 … 99, ranks
    // 1, 5, 50, 95, 99 → 1, 5, 50, 95, 99.
    const double active[5] = {1, 5, 50, 95, 99};
    for (int i = 0; i < 5; ++i) {
        EXPECT_LE(s.percentilesAll[i], all[i]);
        EXPECT_GT(s.percentilesAll[i], all[i] - bin - 1e-9);
        EXPECT_LE(s.percentilesActive[i], active[i]);
        EXPECT_GT(s.percentilesActive[i], active[i] - bin - 1e-9);
    }
    ASSERT_EQ(s.histogram.counts.size(), 10u);
    for (std::int64_t c : s.histogram.counts) EXPECT_EQ(c, 10);  // bins of 9.9 over 0 … 99
    EXPECT_EQ(s.histogram.lo, 0.0);
    EXPECT_EQ(s.histogram.hi, 99.0);
    // Blurred first (as a scene's source): the extremes move in, the values stay finite.
    const VolumeSummary blurred = summarizeVolume(path, o, 2.0, 0);
    EXPECT_LT(blurred.max, 99.0);
    EXPECT_TRUE(std::isfinite(blurred.percentilesAll[2]));
    EXPECT_TRUE(blurred.histogram.counts.empty());
    expectError([&] { summarizeVolume(path, o, -1.0, 0); }, {path, "blur"});
}

// Normalising by a percentile (--normalize pNN, a scene's "divide_by": "pNN") divides by the very
// number `lobe info` prints for it: on the 100 voxels 0 … 99, p99 is the 99th smallest value, 98,
// and p50 is 49 (nearest rank, to within one of 65 536 bins: the bin's lower edge). The same from a
// .vdb; p1 is 0 here, which cannot divide; out-of-range or malformed percentiles are named.
TEST(VolumeSummary, NormaliseByAPercentileAsInfoPrintsIt) {
    Bytes b(100);
    for (int i = 0; i < 100; ++i) b[std::size_t(i)] = std::uint8_t((i * 37) % 100);
    const std::string path = writeFile("hundred-p.raw", b);
    VolumeOptionText t;
    t.dims = "10,10,1";
    t.type = "uint8";
    t.normalize = "p99";
    const LoadOptions o = parseLoadOptions(t);
    EXPECT_EQ(o.normalizePercentile, 99.0);
    LoadOptions plain = o;
    plain.normalizePercentile = 0.0;
    const VolumeSummary info = summarizeVolume(path, plain);
    const double bin = 99.0 / 65536.0;
    const Volume v = loadVolume(path, o);
    EXPECT_EQ(v.valueScale, 1.0 / info.percentilesAll[4]);  // the number info prints for 99 %
    EXPECT_LE(1.0 / v.valueScale, 98.0);
    EXPECT_GT(1.0 / v.valueScale, 98.0 - bin);
    EXPECT_NEAR(valueAt(v, 1, 0, 0), 37.0 / 98.0, 1e-4);  // voxel 1 holds 37
    LoadOptions median = plain;
    median.normalizePercentile = 50.0;
    EXPECT_EQ(loadVolume(path, median).valueScale, 1.0 / info.percentilesAll[2]);
    // From a .vdb written without scaling: the same divisor.
    const std::string vdb = (tempDir() / "hundred-p.vdb").string();
    writeVdb(loadVolume(path, plain), vdb);
    LoadOptions fromVdb;
    fromVdb.normalizePercentile = 99.0;
    EXPECT_EQ(loadVolume(vdb, fromVdb).valueScale, v.valueScale);
    LoadOptions first = plain;
    first.normalizePercentile = 1.0;
    expectError([&] { loadVolume(path, first); }, {path, "1 % percentile", "not positive"});
    for (const char* bad : {"p0", "p101", "p", "pmax", "q99"}) {
        t.normalize = bad;
        expectError([&] { parseLoadOptions(t); }, {"--normalize", bad});
    }
}

TEST(VolumeErrors, VdbWriteAndReadFailuresLeaveNothing) {
    const Volume v = loadRaw(writeFile("w.raw", Bytes{1, 2}),
                             layout(2, 1, 1, VoxelType::kUint8, Endian::kLittle));
    const fs::path dir = tempDir() / "no_such_dir";
    expectError([&] { writeVdb(v, (dir / "x.vdb").string()); }, {"x.vdb", "cannot write"});
    EXPECT_FALSE(fs::exists(dir));
    const std::string notVdb = writeFile("fake.vdb", Bytes(64, 7));
    expectError([&] { loadVdb((tempDir() / "absent.vdb").string()); }, {"absent.vdb"});

    // A .vdb written by someone else holding a NaN voxel is refused like any other file.
    openvdb::FloatGrid::Ptr nanGrid = openvdb::FloatGrid::create(0.0f);
    nanGrid->tree().setValue(openvdb::Coord(3, 4, 5), std::numeric_limits<float>::quiet_NaN());
    const std::string nanVdb = (tempDir() / "nan.vdb").string();
    openvdb::io::File(nanVdb).write({nanGrid});
    expectError([&] { loadVdb(nanVdb); }, {nanVdb, "non-finite value at (3, 4, 5)"});
    expectError([&] { loadVdb(notVdb); }, {notVdb, "cannot read the OpenVDB file"});

    // convert: a bad input writes no output and leaves no temporary file behind.
    const std::string out = (tempDir() / "convert_out.vdb").string();
    fs::remove(out);
    const std::string shortRaw = writeFile("conv.raw", Bytes(5, 1));
    LoadOptions o;
    o.hasLayout = true;
    o.layout = layout(2, 2, 2, VoxelType::kUint8, Endian::kLittle);
    expectError([&] { convertVolume(shortRaw, out, o, ""); }, {shortRaw, "truncated"});
    EXPECT_FALSE(fs::exists(out));
    expectError([&] { convertVolume(shortRaw, (tempDir() / "x.nii").string(), o, ""); },
                {"x.nii", ".vdb"});
    for (const auto& entry : fs::directory_iterator(tempDir())) {
        EXPECT_EQ(entry.path().filename().string().find(".tmp"), std::string::npos) << entry.path();
        EXPECT_EQ(entry.path().filename().string().find(".partial-"), std::string::npos)
            << entry.path();
    }
    const std::string goodRaw = writeFile("conv_ok.raw", Bytes{0, 3, 0, 4, 5, 0, 0, 9});
    const VolumeSummary s = convertVolume(goodRaw, out, o, "");
    EXPECT_TRUE(fs::exists(out));
    EXPECT_EQ(s.activeVoxels, 4);
    EXPECT_DOUBLE_EQ(s.mean, 21.0 / 8.0);
    EXPECT_DOUBLE_EQ(s.max, 9.0);
}

// writeVdb's temporary is the project's (core/temporary_file.h): named after this host and PID, so
// one a killed conversion left (a SIGKILL no handler sees) is removed by the next writer into that
// folder. It used to be "NAME.tmpPID", which no later run recognised.
TEST(VolumeVdb, WriteReclaimsADeadRunsTemporary) {
    const Volume v = loadRaw(writeFile("d.raw", Bytes{1, 2}),
                             layout(2, 1, 1, VoxelType::kUint8, Endian::kLittle));
    const fs::path dir = tempDir() / "out";
    fs::remove_all(dir);
    fs::create_directories(dir);
    char host[256] = {0};
    ASSERT_EQ(::gethostname(host, sizeof host - 1), 0);
    // PID 999999999 is above any pid_max (at most 2^22 on Linux): no process has it.
    const fs::path stale = dir / (std::string(".brain.partial-") + host + "~999999999~42.vdb");
    std::ofstream(stale) << "half a file";
    ASSERT_TRUE(fs::exists(stale));
    const std::string out = (dir / "brain.vdb").string();
    writeVdb(v, out);
    EXPECT_FALSE(fs::exists(stale));
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(dir))
        names.push_back(entry.path().filename().string());
    EXPECT_EQ(names, std::vector<std::string>{"brain.vdb"});
    EXPECT_EQ(loadVdb(out).dims, v.dims);
}

}  // namespace
}  // namespace lobe
