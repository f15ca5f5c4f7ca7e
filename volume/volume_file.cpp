// Reading volume files into dense float arrays: raw bytes (plain or gzip, through zlib's
// gzopen/gzread), the NIfTI-1 header, simple detached NRRD headers. No OpenVDB here.
#include "volume/volume_file.h"

#include "core/error.h"
#include "core/math.h"
#include "core/memory.h"

#include <zlib.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>

namespace lobe {

namespace {

bool hostIsLittleEndian() {
    const std::uint16_t one = 1;
    unsigned char first;
    std::memcpy(&first, &one, 1);
    return first == 1;
}

std::string lower(std::string s) {
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

std::string trim(const std::string& s) {
    const size_t b = s.find_first_not_of(" \t\r\n");
    if (b == std::string::npos) return "";
    const size_t e = s.find_last_not_of(" \t\r\n");
    return s.substr(b, e - b + 1);
}

std::string dimsText(const std::array<int, 3>& d) {
    return std::to_string(d[0]) + "x" + std::to_string(d[1]) + "x" + std::to_string(d[2]);
}

}  // namespace

VoxelType parseVoxelType(const std::string& name) {
    const std::string n = lower(trim(name));
    if (n == "uint8" || n == "uchar" || n == "unsigned char" || n == "uint8_t")
        return VoxelType::kUint8;
    if (n == "int8" || n == "signed char" || n == "int8_t") return VoxelType::kInt8;
    if (n == "uint16" || n == "ushort" || n == "unsigned short" || n == "unsigned short int" ||
        n == "uint16_t")
        return VoxelType::kUint16;
    if (n == "int16" || n == "short" || n == "short int" || n == "signed short" ||
        n == "signed short int" || n == "int16_t")
        return VoxelType::kInt16;
    if (n == "uint32" || n == "uint" || n == "unsigned int" || n == "uint32_t")
        return VoxelType::kUint32;
    if (n == "int32" || n == "int" || n == "signed int" || n == "int32_t") return VoxelType::kInt32;
    if (n == "float32" || n == "float") return VoxelType::kFloat32;
    if (n == "float64" || n == "double") return VoxelType::kFloat64;
    throw Error("unknown voxel type '" + name +
                "': expected uint8, int8, uint16, int16, uint32, int32, float32 or float64");
}

const char* voxelTypeName(VoxelType type) {
    switch (type) {
        case VoxelType::kUint8:
            return "uint8";
        case VoxelType::kInt8:
            return "int8";
        case VoxelType::kUint16:
            return "uint16";
        case VoxelType::kInt16:
            return "int16";
        case VoxelType::kUint32:
            return "uint32";
        case VoxelType::kInt32:
            return "int32";
        case VoxelType::kFloat32:
            return "float32";
        case VoxelType::kFloat64:
            return "float64";
    }
    return "?";
}

int voxelTypeSize(VoxelType type) {
    switch (type) {
        case VoxelType::kUint8:
        case VoxelType::kInt8:
            return 1;
        case VoxelType::kUint16:
        case VoxelType::kInt16:
            return 2;
        case VoxelType::kUint32:
        case VoxelType::kInt32:
        case VoxelType::kFloat32:
            return 4;
        case VoxelType::kFloat64:
            return 8;
    }
    return 1;
}

Endian parseEndian(const std::string& name) {
    const std::string n = lower(trim(name));
    if (n == "little" || n == "le") return Endian::kLittle;
    if (n == "big" || n == "be") return Endian::kBig;
    throw Error("unknown byte order '" + name + "': expected little or big");
}

std::array<double, 3> parseTriple(const std::string& text, const std::string& option) {
    std::string s = text;
    for (char& c : s)
        if (c == ',' || c == 'x' || c == 'X' || c == ':') c = ' ';
    std::istringstream in(s);
    std::array<double, 3> v{};
    std::string extra;
    if (!(in >> v[0] >> v[1] >> v[2]) || (in >> extra) || !std::isfinite(v[0]) ||
        !std::isfinite(v[1]) || !std::isfinite(v[2]))
        throw Error(option + " '" + text + "': expected three numbers such as 256,256,113");
    return v;
}

double parsePercentileText(const std::string& text) {
    const std::string t = lower(trim(text));
    if (t.size() < 2 || t[0] != 'p') return -1.0;
    char* end = nullptr;
    const double p = std::strtod(t.c_str() + 1, &end);
    if (end == t.c_str() + 1 || *end != '\0' || !std::isfinite(p)) return -1.0;
    return p > 0.0 && p <= 100.0 ? p : 0.0;
}

LoadOptions parseLoadOptions(const VolumeOptionText& text) {
    LoadOptions o;
    const bool anyLayout = !text.dims.empty() || !text.type.empty() || !text.endian.empty() ||
                           !text.spacing.empty() || text.offset != 0;
    if (anyLayout) {
        if (text.dims.empty() || text.type.empty())
            throw Error("a raw layout needs at least --dims X,Y,Z and --type");
        o.hasLayout = true;
        const std::array<double, 3> d = parseTriple(text.dims, "--dims");
        for (int a = 0; a < 3; ++a) {
            if (d[a] < 1 || d[a] > (1 << 20) || d[a] != std::floor(d[a]))
                throw Error("--dims '" + text.dims + "': expected three whole numbers ≥ 1");
            o.layout.dims[a] = static_cast<int>(d[a]);
        }
        try {
            o.layout.type = parseVoxelType(text.type);
        } catch (const Error& e) {
            throw Error(std::string("--type: ") + e.what());
        }
        // A single byte has no order; multi-byte types must say theirs.
        if (!text.endian.empty()) {
            try {
                o.layout.endian = parseEndian(text.endian);
            } catch (const Error& e) {
                throw Error(std::string("--endian: ") + e.what());
            }
        } else if (voxelTypeSize(o.layout.type) > 1)
            throw Error("--type " + text.type +
                        " has more than one byte per voxel: give "
                        "--endian little or --endian big");
        if (!text.spacing.empty()) {
            o.layout.spacing = parseTriple(text.spacing, "--spacing");
            for (double s : o.layout.spacing)
                if (!(s > 0.0))
                    throw Error("--spacing '" + text.spacing + "': spacings must be positive");
        }
        if (text.offset < 0) throw Error("--offset must be ≥ 0");
        o.layout.offset = text.offset;
    }
    if (!(text.scale > 0.0) || !std::isfinite(text.scale))
        throw Error("--scale must be a positive number");
    o.scale = text.scale;
    if (!text.normalize.empty()) {
        if (lower(trim(text.normalize)) == "max") {
            o.normalizeByMax = true;
        } else if (const double p = parsePercentileText(text.normalize); p >= 0.0) {
            if (p == 0.0)
                throw Error("--normalize '" + text.normalize +
                            "': a percentile must be above 0 and at most 100 (e.g. p99)");
            o.normalizePercentile = p;
        } else {
            char* end = nullptr;
            o.normalize = std::strtod(text.normalize.c_str(), &end);
            if (end == text.normalize.c_str() || *end != '\0' || !(o.normalize > 0.0) ||
                !std::isfinite(o.normalize))
                throw Error("--normalize '" + text.normalize +
                            "': expected a positive divisor, 'max' or a percentile such as 'p99'");
        }
    }
    if (!std::isfinite(text.background)) throw Error("--background must be a finite number");
    o.background = text.background;
    o.gridName = text.gridName;
    o.series = text.series;
    return o;
}

namespace detail {

bool endsWith(const std::string& s, const std::string& suffix) {
    return s.size() >= suffix.size() && lower(s.substr(s.size() - suffix.size())) == lower(suffix);
}

std::vector<unsigned char> readFileBytes(const std::string& path, bool gzip, size_t maxBytes,
                                         const std::string& what, bool prefix) {
    std::ifstream probe(path, std::ios::binary);
    if (!probe) throw Error(path + ": cannot open the file (" + std::strerror(errno) + ")");
    if (!gzip) {
        probe.seekg(0, std::ios::end);
        std::streamoff size = probe.tellg();
        probe.seekg(0, std::ios::beg);
        if (prefix)
            size = std::min<std::streamoff>(size,
                                            std::streamoff(std::min<size_t>(maxBytes, 1ull << 62)));
        checkFits(double(size), path);
        std::vector<unsigned char> bytes(static_cast<size_t>(std::max<std::streamoff>(size, 0)));
        if (!bytes.empty() &&
            !probe.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(size)))
            throw Error(path + ": read error");
        return bytes;
    }
    // gzread passes non-gzip files through unchanged; a name ending in .gz promises gzip, so a
    // missing magic (1f 8b, RFC 1952 §2.3.1) is an error rather than silently raw data.
    unsigned char magic[2] = {0, 0};
    probe.read(reinterpret_cast<char*>(magic), 2);
    if (probe.gcount() < 2 || magic[0] != 0x1f || magic[1] != 0x8b)
        throw Error(path +
                    ": not a gzip file (the name ends in .gz but the gzip magic 1f 8b is "
                    "missing)");
    probe.close();

    gzFile file = gzopen(path.c_str(), "rb");
    if (!file) throw Error(path + ": cannot open the gzip file");
    gzbuffer(file, 1 << 18);
    std::vector<unsigned char> bytes;
    std::vector<unsigned char> chunk(1 << 20);
    for (;;) {
        const int n = gzread(file, chunk.data(), static_cast<unsigned>(chunk.size()));
        int code = Z_OK;
        const char* message = gzerror(file, &code);
        if (n < 0 || (code != Z_OK && code != Z_STREAM_END)) {
            const std::string text = message ? message : "unknown zlib error";
            gzclose(file);
            throw Error(path + ": gzip data is damaged or truncated (" + text + ")");
        }
        if (n == 0) break;
        bytes.insert(bytes.end(), chunk.begin(), chunk.begin() + n);
        if (bytes.size() > maxBytes) {
            gzclose(file);
            if (!prefix)
                throw Error(path + ": the " + what +
                            " contradicts the data size: the gzip data goes "
                            "on past the " +
                            std::to_string(maxBytes) +
                            " bytes it describes "
                            "(stopped inflating there)");
            bytes.resize(maxBytes);
            return bytes;
        }
    }
    gzclose(file);
    return bytes;
}

namespace {

template <typename T>
T loadSwapped(const unsigned char* p, bool swap) {
    unsigned char b[sizeof(T)];
    std::memcpy(b, p, sizeof(T));
    if (swap) std::reverse(b, b + sizeof(T));
    T v;
    std::memcpy(&v, b, sizeof(T));
    return v;
}

double loadVoxel(const unsigned char* p, VoxelType type, bool swap) {
    switch (type) {
        case VoxelType::kUint8:
            return *p;
        case VoxelType::kInt8:
            return static_cast<signed char>(*p);
        case VoxelType::kUint16:
            return loadSwapped<std::uint16_t>(p, swap);
        case VoxelType::kInt16:
            return loadSwapped<std::int16_t>(p, swap);
        case VoxelType::kUint32:
            return loadSwapped<std::uint32_t>(p, swap);
        case VoxelType::kInt32:
            return loadSwapped<std::int32_t>(p, swap);
        case VoxelType::kFloat32:
            return loadSwapped<float>(p, swap);
        case VoxelType::kFloat64:
            return loadSwapped<double>(p, swap);
    }
    return 0.0;
}

// Voxel count of dims, refusing non-positive or absurd sizes before anything is allocated.
std::int64_t voxelCount(const std::string& path, const std::array<int, 3>& dims,
                        const std::string& what) {
    std::int64_t n = 1;
    for (int a = 0; a < 3; ++a) {
        if (dims[a] < 1 || dims[a] > (1 << 20))
            throw Error(path + ": " + what + " gives dimensions " + dimsText(dims) +
                        "; each must be between 1 and 1048576");
        n *= dims[a];
    }
    if (n > (std::int64_t(1) << 34))
        throw Error(path + ": " + what + " gives " + dimsText(dims) + " voxels, too many to load");
    return n;
}

}  // namespace

DenseVolume decodeVoxels(const std::string& path, const std::vector<unsigned char>& bytes,
                         std::int64_t offset, const std::array<int, 3>& dims, VoxelType type,
                         Endian endian, double slope, double inter, const std::string& what) {
    const std::int64_t count = voxelCount(path, dims, what);
    const std::int64_t size = voxelTypeSize(type);
    const std::int64_t need = count * size;
    const std::int64_t have = static_cast<std::int64_t>(bytes.size()) - offset;
    const std::string layoutText = dimsText(dims) + " " + voxelTypeName(type) + " = " +
                                   std::to_string(need) + " bytes of voxel data from byte offset " +
                                   std::to_string(offset);
    if (have < need)
        throw Error(path + ": truncated: the " + what + " says " + layoutText + ", but the " +
                    "file holds " + std::to_string(std::max<std::int64_t>(have, 0)) +
                    " bytes there");
    if (have > need)
        throw Error(path + ": the " + what + " contradicts the data size: it says " + layoutText +
                    ", but the file holds " + std::to_string(have) + " bytes there");
    if (!std::isfinite(slope) || !std::isfinite(inter))
        throw Error(path + ": the " + what + " has a non-finite value scaling");

    DenseVolume v;
    v.dims = dims;
    v.values.resize(static_cast<size_t>(count));
    const bool swap = (endian == Endian::kLittle) != hostIsLittleEndian();
    const unsigned char* p = bytes.data() + offset;
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (std::int64_t n = 0; n < count; ++n, p += size) {
        const double raw = loadVoxel(p, type, swap);
        const double value = raw * slope + inter;
        const float stored = static_cast<float>(value);
        if (!std::isfinite(raw) || !std::isfinite(stored)) {
            const std::int64_t i = n % dims[0], j = (n / dims[0]) % dims[1],
                               k = n / (std::int64_t(dims[0]) * dims[1]);
            throw Error(path + ": voxel (" + std::to_string(i) + ", " + std::to_string(j) + ", " +
                        std::to_string(k) + ") is " +
                        (std::isnan(raw)   ? "NaN"
                         : std::isinf(raw) ? "infinite"
                                           : "outside the float range") +
                        "; volumes must hold finite values");
        }
        v.values[static_cast<size_t>(n)] = stored;
        lo = std::min(lo, double(stored));
        hi = std::max(hi, double(stored));
    }
    v.min = lo;
    v.max = hi;
    return v;
}

// Where a layout's voxel data ends: what a gzip stream may inflate to (see readFileBytes).
static size_t dataEnd(std::int64_t offset, const std::array<int, 3>& dims, VoxelType type) {
    const double end = double(offset) + double(std::max(dims[0], 0)) * std::max(dims[1], 0) *
                                            std::max(dims[2], 0) * voxelTypeSize(type);
    return end < 1e15 ? size_t(end) : size_t(1e15);
}

DenseVolume readRawDense(const std::string& path, const RawLayout& layout) {
    for (int a = 0; a < 3; ++a)
        if (!(layout.spacing[a] > 0.0) || !std::isfinite(layout.spacing[a]))
            throw Error(path + ": the layout's spacing must be three positive numbers");
    if (layout.offset < 0) throw Error(path + ": the layout's byte offset is negative");
    const std::vector<unsigned char> bytes = readFileBytes(
        path, layout.gzip, dataEnd(layout.offset, layout.dims, layout.type), "layout");
    DenseVolume v = decodeVoxels(path, bytes, layout.offset, layout.dims, layout.type,
                                 layout.endian, 1.0, 0.0, "layout");
    v.affine = {
        {{layout.spacing[0], 0, 0, 0}, {0, layout.spacing[1], 0, 0}, {0, 0, layout.spacing[2], 0}}};
    return v;
}

// ---- NIfTI-1 ----------------------------------------------------------------------------------
// Field offsets and meanings from the NIfTI-1 header definition, nifti1.h (NIfTI Data Format
// Working Group, 2004; https://nifti.nimh.nih.gov/pub/dist/src/niftilib/nifti1.h):
//   0 sizeof_hdr (int32, 348)      40 dim[8] (int16)        70 datatype (int16)  72 bitpix
//   76 pixdim[8] (float)           108 vox_offset (float)   112 scl_slope        116 scl_inter
//   252 qform_code (int16)         254 sform_code (int16)   256 quatern_b, c, d  268 qoffset_x, y,
//   z 280 srow_x[4], 296 srow_y[4], 312 srow_z[4] (float)     344 magic "n+1\0" (single file)
// The byte order is whatever makes sizeof_hdr read 348 (nifti1.h, "byte ordering").
namespace {

class HeaderReader {
public:
    HeaderReader(const unsigned char* h, bool swap) : h_(h), swap_(swap) {}
    std::int16_t i16(int at) const { return loadSwapped<std::int16_t>(h_ + at, swap_); }
    std::int32_t i32(int at) const { return loadSwapped<std::int32_t>(h_ + at, swap_); }
    double f32(int at) const { return loadSwapped<float>(h_ + at, swap_); }

private:
    const unsigned char* h_;
    bool swap_;
};

bool niftiType(int code, VoxelType& type);

// The bytes a NIfTI-1 file holds according to its header (vox_offset + the voxels), or 352 when
// the header is unusable (then only the header is read, and its parse names the problem).
size_t niftiFileBytes(const std::vector<unsigned char>& head) {
    if (head.size() < 352) return 352;
    std::int32_t sizeofHdr;
    std::memcpy(&sizeofHdr, head.data(), 4);
    const bool swap = sizeofHdr != 348;
    const HeaderReader r(head.data(), swap);
    VoxelType type;
    const int ndim = r.i16(40);
    if (r.i32(0) != 348 || ndim < 1 || ndim > 7 || !niftiType(r.i16(70), type)) return 352;
    double count = 1.0;
    for (int a = 0; a < ndim; ++a) count *= std::max(1, int(r.i16(42 + 2 * a)));
    const double offset = r.f32(108);
    if (!(offset >= 348.0 && offset <= 1e12)) return 352;
    const double bytes = offset + count * voxelTypeSize(type);
    return bytes < 1e15 ? size_t(bytes) : 352;
}

bool niftiType(int code, VoxelType& type) {
    switch (code) {  // nifti1.h, NIFTI_TYPE_* codes
        case 2:
            type = VoxelType::kUint8;
            return true;
        case 4:
            type = VoxelType::kInt16;
            return true;
        case 8:
            type = VoxelType::kInt32;
            return true;
        case 16:
            type = VoxelType::kFloat32;
            return true;
        case 64:
            type = VoxelType::kFloat64;
            return true;
        case 256:
            type = VoxelType::kInt8;
            return true;
        case 512:
            type = VoxelType::kUint16;
            return true;
        case 768:
            type = VoxelType::kUint32;
            return true;
        default:
            return false;
    }
}

// A header's voxel-to-world map (NIfTI, MGH) must be finite and invertible.
void checkHeaderAffine(const std::string& path, const decltype(DenseVolume::affine)& affine) {
    for (const auto& row : affine)
        for (double x : row)
            if (!std::isfinite(x)) throw Error(path + ": the header's orientation is not finite");
    if (nearlySingular(affine))
        throw Error(path +
                    ": the header's voxel-to-world map is singular or nearly so (a zero "
                    "voxel size, or axes almost parallel)");
}

}  // namespace

DenseVolume readNiftiDense(const std::string& path) {
    const bool gz = endsWith(path, ".gz");
    // The header first, then no more data than it describes (a gzip bomb stops there).
    const std::vector<unsigned char> head = readFileBytes(path, gz, 352, "header", true);
    const std::vector<unsigned char> bytes =
        readFileBytes(path, gz, niftiFileBytes(head), "header");
    if (bytes.size() < 348)
        throw Error(path + ": truncated: " + std::to_string(bytes.size()) +
                    " bytes, shorter than the 348-byte NIfTI-1 header");
    const unsigned char* h = bytes.data();
    std::int32_t sizeofHdr;
    std::memcpy(&sizeofHdr, h, 4);
    bool swap = false;
    if (sizeofHdr != 348) {
        swap = true;
        if (loadSwapped<std::int32_t>(h, true) != 348) {
            if (sizeofHdr == 540 || loadSwapped<std::int32_t>(h, true) == 540)
                throw Error(path +
                            ": NIfTI-2 files are not supported (sizeof_hdr 540); "
                            "convert to NIfTI-1");
            throw Error(path +
                        ": not a NIfTI-1 file (sizeof_hdr is neither 348 nor 348 "
                        "byte-swapped)");
        }
    }
    if (std::memcmp(h + 344, "ni1\0", 4) == 0)
        throw Error(path +
                    ": two-file NIfTI (.hdr/.img, magic 'ni1') is not supported; use a "
                    "single .nii file");
    if (std::memcmp(h + 344, "n+1\0", 4) != 0)
        throw Error(path + ": wrong magic: expected 'n+1' at byte 344 of a NIfTI-1 header");
    const HeaderReader r(h, swap);
    const int ndim = r.i16(40);
    if (ndim < 1 || ndim > 7)
        throw Error(path + ": the header's dim[0] is " + std::to_string(ndim) +
                    ", expected 1 to 7");
    std::array<int, 3> dims{1, 1, 1};
    for (int a = 0; a < 3 && a < ndim; ++a) dims[a] = r.i16(42 + 2 * a);
    for (int a = 3; a < ndim; ++a)
        if (r.i16(42 + 2 * a) > 1)
            throw Error(path + ": the header describes a " + std::to_string(ndim) +
                        "-D image with dim[" + std::to_string(a + 1) + "] = " +
                        std::to_string(r.i16(42 + 2 * a)) + "; only 3-D volumes are supported");
    const int code = r.i16(70);
    VoxelType type;
    if (!niftiType(code, type))
        throw Error(path + ": unknown or unsupported NIfTI datatype " + std::to_string(code) +
                    " (supported: 2 uint8, 4 int16, 8 int32, 16 float32, 64 float64, 256 int8, "
                    "512 uint16, 768 uint32)");
    const int bitpix = r.i16(72);
    if (bitpix != 8 * voxelTypeSize(type))
        throw Error(path + ": the header contradicts itself: datatype " + std::to_string(code) +
                    " (" + voxelTypeName(type) + ") but bitpix " + std::to_string(bitpix));
    const double voxOffset = r.f32(108);
    if (!(voxOffset >= 348.0) || voxOffset != std::floor(voxOffset) || voxOffset > 1e12)
        throw Error(path + ": the header's vox_offset " + std::to_string(voxOffset) +
                    " is not a whole byte offset at or after the 348-byte header");
    // nifti1.h: "If the scl_slope field is nonzero, then each voxel value in the dataset should
    // be scaled as y = scl_slope * x + scl_inter".
    // A slope of 0 — and, as nibabel reads it, a NaN or infinite slope — means "not scaled"
    // (some writers leave NaN for "unset"); a usable slope with a non-finite intercept has no
    // meaning and is refused (as nibabel does).
    double slope = r.f32(112), inter = r.f32(116);
    if (slope == 0.0 || !std::isfinite(slope)) {
        slope = 1.0;
        inter = 0.0;
    } else if (!std::isfinite(inter)) {
        throw Error(path + ": the header's scl_slope is " + std::to_string(slope) +
                    " but its scl_inter is not finite: the values cannot be scaled");
    }

    DenseVolume v = decodeVoxels(path, bytes, static_cast<std::int64_t>(voxOffset), dims, type,
                                 swap == hostIsLittleEndian() ? Endian::kBig : Endian::kLittle,
                                 slope, inter, "header");

    const int qformCode = r.i16(252), sformCode = r.i16(254);
    double pixdim[4];
    for (int a = 0; a < 4; ++a) pixdim[a] = r.f32(76 + 4 * a);
    if (sformCode > 0) {
        // nifti1.h METHOD 3: x = srow_x[0] i + srow_x[1] j + srow_x[2] k + srow_x[3], etc.
        for (int row = 0; row < 3; ++row)
            for (int c = 0; c < 4; ++c) v.affine[row][c] = r.f32(280 + 16 * row + 4 * c);
    } else if (qformCode > 0) {
        // nifti1.h METHOD 2: [x y z]ᵀ = R [i, j, qfac·k]ᵀ ∘ pixdim + qoffset, with R the rotation
        // of the unit quaternion (a, b, c, d), a = sqrt(1 − b² − c² − d²), and qfac = pixdim[0]
        // (−1 or 1; 0 is taken as 1).
        const double b = r.f32(256), c = r.f32(260), d = r.f32(264);
        double a = 1.0 - (b * b + c * c + d * d);
        a = a > 1e-7 ? std::sqrt(a) : 0.0;  // nifti1_io.c: a slightly negative a² means a = 0
        const double qfac = pixdim[0] < 0.0 ? -1.0 : 1.0;
        const double R[3][3] = {
            {a * a + b * b - c * c - d * d, 2 * (b * c - a * d), 2 * (b * d + a * c)},
            {2 * (b * c + a * d), a * a + c * c - b * b - d * d, 2 * (c * d - a * b)},
            {2 * (b * d - a * c), 2 * (c * d + a * b), a * a + d * d - c * c - b * b}};
        const double scale[3] = {pixdim[1], pixdim[2], qfac * pixdim[3]};
        for (int row = 0; row < 3; ++row) {
            for (int col = 0; col < 3; ++col) v.affine[row][col] = R[row][col] * scale[col];
            v.affine[row][3] = r.f32(268 + 4 * row);
        }
    } else {
        // nifti1.h METHOD 1 (old ANALYZE): x = pixdim[1] i, y = pixdim[2] j, z = pixdim[3] k.
        v.affine = {{{pixdim[1], 0, 0, 0}, {0, pixdim[2], 0, 0}, {0, 0, pixdim[3], 0}}};
    }
    checkHeaderAffine(path, v.affine);
    return v;
}

// ---- FreeSurfer MGH / MGZ ----------------------------------------------------------------------
// The layout of FreeSurfer's mghRead/mghWrite (utils/mriio.c; the same fields as nibabel's
// nibabel/freesurfer/mghformat.py), all big-endian, the voxels at byte 284:
//   0 version (int32, 1)   4 width, height, depth, nframes (int32)   20 type (int32: 0 uchar,
//   1 int32, 3 float32, 4 int16)   24 dof   28 goodRASFlag (int16)   30 delta[3] (float, voxel
//   sizes)   42 Mdc[3][3] (float: row i the direction cosines of index axis i)   78 Pxyz_c[3]
//   (float, the RAS of the volume's centre).
// The voxel data is x fastest (column-major), then an optional footer (scan parameters, tags),
// which is not read. .mgz is the same gzip-compressed.
// vox2ras (nibabel's MGHHeader.get_affine, FreeSurfer's extract_i_to_r): M = Mdcᵀ · diag(delta),
// translation Pxyz_c − M · dims/2 (FreeSurfer's centre voxel is dims/2, not (dims − 1)/2).
// With goodRASFlag 0 the fields are not valid and FreeSurfer's default applies: delta 1,
// Mdc rows (−1, 0, 0), (0, 0, 1), (0, −1, 0), Pxyz_c 0 (a coronal conformed volume).
DenseVolume readMghDense(const std::string& path) {
    constexpr std::int64_t kDataOffset = 284;
    const bool gz = endsWith(path, ".mgz") || endsWith(path, ".gz");
    if (gz) {  // the name promises gzip (RFC 1952 §2.3.1 magic 1f 8b)
        std::ifstream probe(path, std::ios::binary);
        if (!probe) throw Error(path + ": cannot open the file (" + std::strerror(errno) + ")");
        unsigned char magic[2] = {0, 0};
        probe.read(reinterpret_cast<char*>(magic), 2);
        if (probe.gcount() < 2 || magic[0] != 0x1f || magic[1] != 0x8b)
            throw Error(path +
                        ": not a gzip-compressed FreeSurfer volume: the name says .mgz but "
                        "the gzip magic 1f 8b is missing (an uncompressed MGH file is "
                        "named .mgh)");
    }
    const std::vector<unsigned char> head =
        readFileBytes(path, gz, size_t(kDataOffset), "header", true);
    if (head.size() < size_t(kDataOffset))
        throw Error(path + ": truncated: " + std::to_string(head.size()) +
                    " bytes, shorter than the 284-byte FreeSurfer MGH header");
    const HeaderReader r(head.data(), hostIsLittleEndian());  // MGH is big-endian
    if (r.i32(0) != 1)
        throw Error(path + ": not a FreeSurfer MGH" + std::string(gz ? "Z" : "") +
                    " file (its version field is " + std::to_string(r.i32(0)) + ", expected 1)");
    const std::array<int, 3> dims{r.i32(4), r.i32(8), r.i32(12)};
    const int frames = r.i32(16);
    if (frames != 1)
        throw Error(path + ": the header describes " + std::to_string(frames) +
                    " frames; only 3-D volumes (1 frame) are supported");
    const int code = r.i32(20);
    VoxelType type;
    switch (code) {
        case 0:
            type = VoxelType::kUint8;
            break;
        case 1:
            type = VoxelType::kInt32;
            break;
        case 3:
            type = VoxelType::kFloat32;
            break;
        case 4:
            type = VoxelType::kInt16;
            break;
        default:
            throw Error(path + ": unknown or unsupported MGH data type " + std::to_string(code) +
                        " (supported: 0 uchar, 1 int, 3 float, 4 short)");
    }
    const size_t end = dataEnd(kDataOffset, dims, type);
    std::vector<unsigned char> bytes = readFileBytes(path, gz, end, "header", true);
    if (bytes.size() > end) bytes.resize(end);  // the footer
    DenseVolume v =
        decodeVoxels(path, bytes, kDataOffset, dims, type, Endian::kBig, 1.0, 0.0, "header");
    double delta[3] = {1, 1, 1}, mdc[3][3] = {{-1, 0, 0}, {0, 0, 1}, {0, -1, 0}}, c[3] = {0, 0, 0};
    if (r.i16(28) != 0) {
        for (int a = 0; a < 3; ++a) delta[a] = r.f32(30 + 4 * a);
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) mdc[i][j] = r.f32(42 + 12 * i + 4 * j);
        for (int a = 0; a < 3; ++a) c[a] = r.f32(78 + 4 * a);
    }
    for (int row = 0; row < 3; ++row) {
        double centre = 0.0;
        for (int col = 0; col < 3; ++col) {
            v.affine[row][col] = mdc[col][row] * delta[col];
            centre += v.affine[row][col] * dims[col] / 2.0;
        }
        v.affine[row][3] = c[row] - centre;
    }
    checkHeaderAffine(path, v.affine);
    return v;
}

// ---- NRRD (detached header, the simple kind) ---------------------------------------------------
// Teem's NRRD format, version 4/5 (http://teem.sourceforge.net/nrrd/format.html): a magic line
// "NRRD000n", then "field: value" lines up to a blank line or the end. We read type, dimension
// (3), sizes, endian, encoding (raw or gzip), data file, byte skip, spacings, and space
// directions / space origin (which win over spacings). Voxel centres are at integer indices, as
// in the format's default cell-centring for "space origin".
namespace {

std::array<double, 3> parseVector(const std::string& path, const std::string& text) {
    std::string s = trim(text);
    if (s.size() < 2 || s.front() != '(' || s.back() != ')')
        throw Error(path + ": expected a vector '(x,y,z)', got '" + text + "'");
    s = s.substr(1, s.size() - 2);
    return parseTriple(s, path + ": vector");
}

}  // namespace

DenseVolume readNrrdDense(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw Error(path + ": cannot open the file (" + std::strerror(errno) + ")");
    std::string line;
    if (!std::getline(in, line) || line.rfind("NRRD000", 0) != 0)
        throw Error(path + ": wrong magic: a NRRD header starts with 'NRRD000n'");
    std::string typeName, endianName = "little", encoding = "raw", dataFile;
    int dimension = 0;
    std::int64_t byteSkip = 0;
    std::array<int, 3> sizes{0, 0, 0};
    std::array<double, 3> spacings{1, 1, 1};
    bool haveDirections = false, haveSizes = false;
    std::array<std::array<double, 3>, 3> directions{};
    std::array<double, 3> origin{0, 0, 0};
    int lineNo = 1;
    while (std::getline(in, line)) {
        ++lineNo;
        const std::string t = trim(line);
        if (t.empty()) break;
        if (t[0] == '#') continue;
        if (t.find(":=") != std::string::npos) continue;  // key/value pairs carry no layout
        const size_t colon = t.find(": ");
        if (colon == std::string::npos)
            throw Error(path + ", line " + std::to_string(lineNo) + ": expected 'field: value'");
        const std::string key = lower(trim(t.substr(0, colon)));
        const std::string value = trim(t.substr(colon + 2));
        const std::string where = path + ", line " + std::to_string(lineNo) + " (" + key + ")";
        std::istringstream vs(value);
        if (key == "type") {
            typeName = value;
        } else if (key == "dimension") {
            if (!(vs >> dimension) || dimension != 3)
                throw Error(where + ": only 3-D volumes are supported, got '" + value + "'");
        } else if (key == "sizes") {
            std::string extra;
            if (!(vs >> sizes[0] >> sizes[1] >> sizes[2]) || (vs >> extra))
                throw Error(where + ": expected three sizes, got '" + value + "'");
            haveSizes = true;
        } else if (key == "spacings") {
            std::string extra;
            if (!(vs >> spacings[0] >> spacings[1] >> spacings[2]) || (vs >> extra))
                throw Error(where + ": expected three spacings, got '" + value + "'");
            for (double s : spacings)
                if (!(s > 0.0) || !std::isfinite(s))
                    throw Error(where + ": spacings must be positive, got '" + value + "'");
        } else if (key == "endian") {
            endianName = value;
        } else if (key == "encoding") {
            encoding = lower(value);
        } else if (key == "data file" || key == "datafile") {
            dataFile = value;
        } else if (key == "byte skip" || key == "byteskip") {
            if (!(vs >> byteSkip) || byteSkip < 0)
                throw Error(where + ": expected a byte count ≥ 0, got '" + value + "'");
        } else if (key == "line skip" || key == "lineskip") {
            int skip = 0;
            if (!(vs >> skip) || skip != 0) throw Error(where + ": line skip is not supported");
        } else if (key == "space directions") {
            std::istringstream ds(value);
            for (int a = 0; a < 3; ++a) {
                std::string vec;
                if (!(ds >> vec)) throw Error(where + ": expected three vectors");
                directions[a] = parseVector(where, vec);
            }
            haveDirections = true;
        } else if (key == "space origin") {
            origin = parseVector(where, value);
        }
        // Other fields (content, kinds, space, centers, …) do not change where voxels are.
    }
    if (typeName.empty() || dimension != 3 || !haveSizes || dataFile.empty())
        throw Error(path + ": a NRRD header needs type, dimension: 3, sizes and data file");
    VoxelType type;
    try {
        type = parseVoxelType(typeName);
    } catch (const Error& e) {
        throw Error(path + ": " + e.what());
    }
    Endian endian;
    try {
        endian = parseEndian(endianName);
    } catch (const Error& e) {
        throw Error(path + ": " + e.what());
    }
    bool gzip;
    if (encoding == "raw")
        gzip = false;
    else if (encoding == "gzip" || encoding == "gz")
        gzip = true;
    else
        throw Error(path + ": unsupported NRRD encoding '" + encoding + "' (raw or gzip)");
    if (dataFile == "LIST" || dataFile.find('%') != std::string::npos)
        throw Error(path + ": multi-file NRRD data is not supported");
    std::string dataPath = dataFile;
    if (dataPath.empty() || dataPath[0] != '/') {
        const size_t slash = path.find_last_of('/');
        if (slash != std::string::npos) dataPath = path.substr(0, slash + 1) + dataFile;
    }
    const std::vector<unsigned char> bytes =
        readFileBytes(dataPath, gzip, dataEnd(byteSkip, sizes, type), "header " + path);
    DenseVolume v =
        decodeVoxels(dataPath, bytes, byteSkip, sizes, type, endian, 1.0, 0.0, "header " + path);
    for (int row = 0; row < 3; ++row) {
        for (int col = 0; col < 3; ++col)
            v.affine[row][col] =
                haveDirections ? directions[col][row] : (row == col ? spacings[col] : 0.0);
        v.affine[row][3] = origin[row];
    }
    return v;
}

}  // namespace detail
}  // namespace lobe
