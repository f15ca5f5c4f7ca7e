// Reading a DICOM series through GDCM (see dicom_file.h for what is read and the conventions).
// Two passes: every file's header up to the pixel data (series, geometry, pixel module), checked
// and sorted before any pixel is decoded; then the chosen series' pixel data, slice by slice.
#include "volume/dicom_file.h"

#include "core/error.h"
#include "core/memory.h"
#include "core/stderr_capture.h"

#include <gdcmAttribute.h>
#include <gdcmImage.h>
#include <gdcmImageReader.h>
#include <gdcmReader.h>
#include <gdcmTrace.h>
#include <gdcmTransferSyntax.h>
#include <gdcmUIDs.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <sstream>

namespace fs = std::filesystem;

namespace lobe {
namespace detail {

bool hasDicomMagic(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    char magic[4];
    if (!in || !in.seekg(128) || !in.read(magic, 4)) return false;
    return std::memcmp(magic, "DICM", 4) == 0;
}

bool isDicomInput(const std::string& path) {
    std::error_code ec;
    return fs::is_directory(path, ec) || hasDicomMagic(path);
}

namespace {

using Vec3d = std::array<double, 3>;

// What GDCM says while it reads, caught instead of printed: its own warnings and errors
// (gdcm::Trace, several lines each with its source position) and those of the libjpeg it
// decodes JPEG with, which go straight to the process's standard error ("Corrupt JPEG data:
// ...", caught by core/stderr_capture.h). Both are process-wide, so one capture at a time. A
// damaged file then gives Lobe's one error line with GDCM's words folded in, and a sound one
// prints nothing.
class GdcmMessages {
public:
    GdcmMessages() {
        gdcm::Trace::SetWarningStream(trace_);
        gdcm::Trace::SetErrorStream(trace_);
    }
    ~GdcmMessages() {
        gdcm::Trace::SetWarningStream(std::cerr);
        gdcm::Trace::SetErrorStream(std::cerr);
    }
    GdcmMessages(const GdcmMessages&) = delete;
    GdcmMessages& operator=(const GdcmMessages&) = delete;

    // Everything said since the last call, as one line: GDCM's messages without their source
    // positions ("Warning: In FILE, line N, function F"), each once, "; " between them.
    std::string take() {
        std::string raw = trace_.str() + "\n" + stderr_.take();
        trace_.str("");
        std::vector<std::string> said;
        std::istringstream lines(raw);
        for (std::string line; std::getline(lines, line);) {
            while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
            if (line.empty() || line.rfind("Warning: In ", 0) == 0 ||
                line.rfind("Error: In ", 0) == 0 || line.rfind("Debug: In ", 0) == 0)
                continue;
            if (std::find(said.begin(), said.end(), line) == said.end()) said.push_back(line);
        }
        std::string out;
        for (const std::string& l : said) out += (out.empty() ? "" : "; ") + l;
        if (out.size() > 240) out = out.substr(0, 237) + "...";
        return out;
    }

private:
    StderrCapture stderr_;  // first: its lock serialises the trace streams' use too
    std::ostringstream trace_;
};

// " (GDCM: what it said)", or "" when it said nothing.
std::string gdcmSaid(const std::string& said) {
    return said.empty() ? "" : " (GDCM: " + said + ")";
}

// What the first pass keeps of one file.
struct SliceHeader {
    std::string path;
    std::string seriesUid, seriesDescription;
    bool hasPosition = false, hasOrientation = false, hasSpacing = false;
    Vec3d position{0, 0, 0};                 // ImagePositionPatient (0020,0032), LPS mm
    Vec3d rowDir{1, 0, 0}, colDir{0, 1, 0};  // ImageOrientationPatient (0020,0037)
    double rowSpacing = 1.0,
           colSpacing = 1.0;  // PixelSpacing (0028,0030): rows apart, columns apart
    double sliceThickness = 0.0, spacingBetweenSlices = 0.0;  // (0018,0050), (0018,0088)
    int rows = 0, columns = 0, frames = 1, samples = 1;
    double slope = 1.0, intercept = 0.0;  // RescaleSlope (0028,1053), RescaleIntercept (0028,1052)
    std::string transferSyntax;           // its name and UID, for messages
    double distance = 0.0;                // along the slice normal, set when sorting
};

std::string trimValue(std::string s) {
    while (!s.empty() && (s.back() == ' ' || s.back() == '\0')) s.pop_back();
    const size_t b = s.find_first_not_of(' ');
    return b == std::string::npos ? "" : s.substr(b);
}

// The text of a string-valued element (DS, IS, UI, LO, CS), "" when absent or empty.
std::string text(const gdcm::DataSet& ds, std::uint16_t group, std::uint16_t element) {
    const gdcm::Tag tag(group, element);
    if (!ds.FindDataElement(tag)) return "";
    const gdcm::ByteValue* bv = ds.GetDataElement(tag).GetByteValue();
    if (!bv || !bv->GetPointer()) return "";
    return trimValue(std::string(bv->GetPointer(), bv->GetLength()));
}

// The backslash-separated numbers of a DS/IS element (PS3.5 6.2, value multiplicity).
std::vector<double> numbers(const std::string& path, const gdcm::DataSet& ds, std::uint16_t group,
                            std::uint16_t element, const char* name) {
    const std::string t = text(ds, group, element);
    std::vector<double> out;
    if (t.empty()) return out;
    std::stringstream in(t);
    std::string item;
    while (std::getline(in, item, '\\')) {
        item = trimValue(item);
        char* end = nullptr;
        const double v = std::strtod(item.c_str(), &end);
        if (item.empty() || *end != '\0' || !std::isfinite(v))
            throw Error(path + ": " + name + " '" + t + "' is not a list of numbers");
        out.push_back(v);
    }
    return out;
}

// A US (unsigned short) element of the image pixel module, or `fallback` when absent.
template <std::uint16_t G, std::uint16_t E>
int ushort(const gdcm::DataSet& ds, int fallback) {
    gdcm::Attribute<G, E> a;
    if (!ds.FindDataElement(a.GetTag()) || ds.GetDataElement(a.GetTag()).IsEmpty()) return fallback;
    a.SetFromDataSet(ds);
    return int(a.GetValue());
}

// "name (UID)" of a transfer syntax, from GDCM's table of DICOM UIDs (PS3.6 Annex A).
std::string transferSyntaxText(const gdcm::TransferSyntax& ts) {
    const char* uid = ts.GetString();
    if (!uid) return "unknown";
    gdcm::UIDs uids;
    const char* name = uids.SetFromUID(uid) ? uids.GetName() : nullptr;
    return name && *name ? std::string(name) + " (" + uid + ")" : std::string(uid);
}

Vec3d cross(const Vec3d& a, const Vec3d& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot(const Vec3d& a, const Vec3d& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

std::string vecText(const Vec3d& v, int n = 3) {
    std::ostringstream s;
    s.precision(6);
    for (int i = 0; i < n; ++i) s << (i ? "\\" : "") << v[i];
    return s.str();
}

// The first pass over one file: its header up to the pixel data.
SliceHeader readHeader(const std::string& path) {
    gdcm::Reader reader;
    reader.SetFileName(path.c_str());
    GdcmMessages messages;  // the header's warnings are not printed: a damaged header fails below
    if (!reader.ReadUpToTag(gdcm::Tag(0x7fe0, 0x0010)))
        throw Error(path + ": GDCM cannot read this DICOM file (damaged, or not a DICOM data set)" +
                    gdcmSaid(messages.take()));
    const gdcm::File& file = reader.GetFile();
    const gdcm::DataSet& ds = file.GetDataSet();
    SliceHeader h;
    h.path = path;
    h.transferSyntax = transferSyntaxText(file.GetHeader().GetDataSetTransferSyntax());
    h.seriesUid = text(ds, 0x0020, 0x000e);
    h.seriesDescription = text(ds, 0x0008, 0x103e);
    const std::vector<double> ipp =
        numbers(path, ds, 0x0020, 0x0032, "ImagePositionPatient (0020,0032)");
    if (!ipp.empty()) {
        if (ipp.size() != 3)
            throw Error(path + ": ImagePositionPatient (0020,0032) has " +
                        std::to_string(ipp.size()) + " values, expected 3");
        h.position = {ipp[0], ipp[1], ipp[2]};
        h.hasPosition = true;
    }
    const std::vector<double> iop =
        numbers(path, ds, 0x0020, 0x0037, "ImageOrientationPatient (0020,0037)");
    if (!iop.empty()) {
        if (iop.size() != 6)
            throw Error(path + ": ImageOrientationPatient (0020,0037) has " +
                        std::to_string(iop.size()) + " values, expected 6");
        h.rowDir = {iop[0], iop[1], iop[2]};
        h.colDir = {iop[3], iop[4], iop[5]};
        h.hasOrientation = true;
        // C.7.6.2.1.1: two orthogonal unit vectors. DS values carry few digits: 1e-3.
        const double lr = std::sqrt(dot(h.rowDir, h.rowDir)),
                     lc = std::sqrt(dot(h.colDir, h.colDir));
        if (std::abs(lr - 1.0) > 1e-3 || std::abs(lc - 1.0) > 1e-3 ||
            std::abs(dot(h.rowDir, h.colDir)) > 1e-3)
            throw Error(path + ": ImageOrientationPatient (0020,0037) '" +
                        text(ds, 0x0020, 0x0037) + "' is not two orthogonal unit vectors");
        for (int a = 0; a < 3; ++a) {
            h.rowDir[a] /= lr;
            h.colDir[a] /= lc;
        }
    }
    const std::vector<double> ps = numbers(path, ds, 0x0028, 0x0030, "PixelSpacing (0028,0030)");
    if (!ps.empty()) {
        if (ps.size() != 2 || !(ps[0] > 0.0) || !(ps[1] > 0.0))
            throw Error(path + ": PixelSpacing (0028,0030) '" + text(ds, 0x0028, 0x0030) +
                        "' is not two positive numbers");
        h.rowSpacing = ps[0];
        h.colSpacing = ps[1];
        h.hasSpacing = true;
    }
    const auto single = [&](std::uint16_t g, std::uint16_t e, const char* name, double fallback) {
        const std::vector<double> v = numbers(path, ds, g, e, name);
        if (v.empty()) return fallback;
        if (v.size() != 1) throw Error(path + ": " + name + " has several values, expected one");
        return v[0];
    };
    h.sliceThickness = single(0x0018, 0x0050, "SliceThickness (0018,0050)", 0.0);
    h.spacingBetweenSlices = single(0x0018, 0x0088, "SpacingBetweenSlices (0018,0088)", 0.0);
    h.slope = single(0x0028, 0x1053, "RescaleSlope (0028,1053)", 1.0);
    h.intercept = single(0x0028, 0x1052, "RescaleIntercept (0028,1052)", 0.0);
    if (h.slope == 0.0)
        throw Error(path + ": RescaleSlope (0028,1053) is 0: every value would be the intercept");
    h.frames = int(single(0x0028, 0x0008, "NumberOfFrames (0028,0008)", 1.0));
    h.rows = ushort<0x0028, 0x0010>(ds, 0);
    h.columns = ushort<0x0028, 0x0011>(ds, 0);
    h.samples = ushort<0x0028, 0x0002>(ds, 1);
    return h;
}

bool isDicomDir(const std::string& path) {
    // A DICOMDIR (PS3.10 8.6) is an index of a file set, not an image: Media Storage SOP Class
    // 1.2.840.10008.1.3.10. Read its meta header only.
    gdcm::Reader reader;
    reader.SetFileName(path.c_str());
    GdcmMessages messages;  // not printed: the header pass reports a file GDCM cannot read
    if (!reader.ReadUpToTag(gdcm::Tag(0x0008, 0x0000))) return false;
    return text(reader.GetFile().GetHeader(), 0x0002, 0x0002) == "1.2.840.10008.1.3.10";
}

// The DICOM image files of the inputs: a folder's regular files with the magic (sorted by
// name; DICOMDIR indexes left out), or the files listed, each of which must be DICOM.
std::vector<std::string> collectFiles(const std::vector<std::string>& inputs) {
    if (inputs.empty()) throw Error("no DICOM input given");
    std::vector<std::string> files;
    for (const std::string& in : inputs) {
        std::error_code ec;
        if (fs::is_directory(in, ec)) {
            std::vector<std::string> found;
            bool subfolders = false;
            for (const fs::directory_entry& e : fs::directory_iterator(in, ec)) {
                if (e.is_directory(ec)) subfolders = true;
                if (!e.is_regular_file(ec)) continue;
                const std::string p = e.path().string();
                if (hasDicomMagic(p) && !isDicomDir(p)) found.push_back(p);
            }
            if (ec) throw Error(in + ": cannot list the folder (" + ec.message() + ")");
            if (found.empty())
                throw Error(in +
                            ": the folder holds no DICOM image file (none with 'DICM' at byte "
                            "128" +
                            std::string(subfolders ? "; its subfolders are not searched: "
                                                     "give the folder of one series"
                                                   : "") +
                            ")");
            std::sort(found.begin(), found.end());
            files.insert(files.end(), found.begin(), found.end());
        } else {
            if (!fs::exists(in, ec)) throw Error(in + ": no such file or folder");
            if (!hasDicomMagic(in))
                throw Error(in +
                            ": not a DICOM file (no 'DICM' at byte 128; files without the "
                            "DICOM Part 10 preamble are not read)");
            if (isDicomDir(in))
                throw Error(in + ": a DICOMDIR index, not an image: give the folder of the series");
            files.push_back(in);
        }
    }
    return files;
}

std::string inputsText(const std::vector<std::string>& inputs) {
    if (inputs.size() == 1) return inputs[0];
    return inputs[0] + " (and " + std::to_string(inputs.size() - 1) + " more files)";
}

// Headers of every file, grouped by SeriesInstanceUID (ordered by UID).
std::map<std::string, std::vector<SliceHeader>> readSeries(const std::vector<std::string>& inputs) {
    std::map<std::string, std::vector<SliceHeader>> series;
    for (const std::string& f : collectFiles(inputs)) {
        SliceHeader h = readHeader(f);
        series[h.seriesUid].push_back(std::move(h));
    }
    return series;
}

std::string seriesListText(const std::map<std::string, std::vector<SliceHeader>>& series) {
    std::string s;
    for (const auto& [uid, slices] : series) {
        const std::string& d = slices.front().seriesDescription;
        s += "\n  " + (uid.empty() ? std::string("(no SeriesInstanceUID)") : uid) + "  " +
             (d.empty() ? "(no description)" : "'" + d + "'") + ", " +
             std::to_string(slices.size()) + (slices.size() == 1 ? " slice" : " slices");
    }
    return s;
}

// Checks one series' geometry (one orientation, size and spacing; evenly spaced positions) and
// sorts it along the slice normal. Returns the k step (LPS) between consecutive slices.
Vec3d sortAndCheck(const std::string& where, std::vector<SliceHeader>& slices) {
    const SliceHeader& first = slices.front();
    for (const SliceHeader& s : slices) {
        if (s.samples != 1)
            throw Error(s.path + ": " + std::to_string(s.samples) +
                        " samples per pixel (colour); "
                        "only grey-level images (1 sample) make a volume");
        if (s.frames != 1)
            throw Error(s.path + ": a multi-frame image (" + std::to_string(s.frames) +
                        " frames); only series of single-frame slices are read");
        if (s.rows < 1 || s.columns < 1)
            throw Error(s.path +
                        ": no image size (Rows (0028,0010) and Columns (0028,0011) missing "
                        "or 0)");
        if (!s.hasPosition || !s.hasOrientation)
            throw Error(s.path + ": no " +
                        std::string(!s.hasPosition ? "ImagePositionPatient (0020,0032)"
                                                   : "ImageOrientationPatient (0020,0037)") +
                        ": the slice cannot be placed (PS3.3 C.7.6.2, Image Plane Module)");
        if (!s.hasSpacing)
            throw Error(s.path +
                        ": no PixelSpacing (0028,0030): the slice's pixel size is unknown");
        if (s.rows != first.rows || s.columns != first.columns)
            throw Error(where + ": slices of different sizes: " + first.path + " is " +
                        std::to_string(first.columns) + "x" + std::to_string(first.rows) + ", " +
                        s.path + " is " + std::to_string(s.columns) + "x" + std::to_string(s.rows));
        for (int a = 0; a < 3; ++a)
            if (std::abs(s.rowDir[a] - first.rowDir[a]) > 1e-4 ||
                std::abs(s.colDir[a] - first.colDir[a]) > 1e-4) {
                throw Error(where + ": mixed orientations: " + first.path +
                            " has "
                            "ImageOrientationPatient " +
                            vecText(first.rowDir) + "\\" + vecText(first.colDir) + ", " + s.path +
                            " has " + vecText(s.rowDir) + "\\" + vecText(s.colDir) +
                            "; a volume needs one orientation");
            }
        if (std::abs(s.rowSpacing - first.rowSpacing) > 1e-4 * first.rowSpacing ||
            std::abs(s.colSpacing - first.colSpacing) > 1e-4 * first.colSpacing)
            throw Error(where + ": slices of different pixel spacings: " + first.path + " and " +
                        s.path);
    }
    const Vec3d normal = cross(first.rowDir, first.colDir);
    for (SliceHeader& s : slices) s.distance = dot(s.position, normal);
    std::stable_sort(slices.begin(), slices.end(), [](const SliceHeader& a, const SliceHeader& b) {
        return a.distance < b.distance;
    });
    const size_t n = slices.size();
    if (n == 1) {
        const double t = first.spacingBetweenSlices > 0.0 ? first.spacingBetweenSlices
                         : first.sliceThickness > 0.0     ? first.sliceThickness
                                                          : 1.0;
        return {normal[0] * t, normal[1] * t, normal[2] * t};
    }
    // Consecutive distances: none zero (two slices at one place), all equal (to 1 % plus
    // 1 µm, as DS values carry at most 16 characters); a gap that is a whole multiple of the
    // smallest distance is reported as missing slices.
    double smallest = std::numeric_limits<double>::infinity(), largest = 0.0;
    for (size_t k = 1; k < n; ++k) {
        const double d = slices[k].distance - slices[k - 1].distance;
        if (d < 1e-3)
            throw Error(
                where + ": two slices at the same position (" + vecText(slices[k].position) +
                " mm): " + slices[k - 1].path + " and " + slices[k].path +
                " (several acquisitions, echoes or time points in one series are not read)");
        smallest = std::min(smallest, d);
        largest = std::max(largest, d);
    }
    const double tolerance = 0.01 * smallest + 1e-3;
    if (largest - smallest > tolerance) {
        for (size_t k = 1; k < n; ++k) {
            const double d = slices[k].distance - slices[k - 1].distance;
            const double ratio = d / smallest;
            const double whole = std::round(ratio);
            if (whole >= 2.0 && std::abs(d - whole * smallest) <= tolerance * whole) {
                std::ostringstream s;
                s << where << ": missing slices: " << d << " mm between " << slices[k - 1].path
                  << " and " << slices[k].path << ", " << smallest << " mm elsewhere ("
                  << int(whole) - 1 << (whole == 2.0 ? " slice" : " slices") << " missing)";
                throw Error(s.str());
            }
        }
        std::ostringstream s;
        s << where << ": unevenly spaced slices: " << smallest << " to " << largest
          << " mm apart along the slice normal; a volume needs one spacing";
        throw Error(s.str());
    }
    // The step between consecutive positions as a vector (it may lean, for a gantry tilt); every
    // position must lie on that line, within the same tolerance.
    Vec3d step;
    for (int a = 0; a < 3; ++a)
        step[a] = (slices.back().position[a] - slices.front().position[a]) / double(n - 1);
    for (size_t k = 0; k < n; ++k) {
        double off = 0.0;
        for (int a = 0; a < 3; ++a) {
            const double e =
                slices[k].position[a] - (slices.front().position[a] + double(k) * step[a]);
            off += e * e;
        }
        if (std::sqrt(off) > tolerance)
            throw Error(where + ": the slice positions do not lie on one line: " + slices[k].path +
                        " at " + vecText(slices[k].position) + " mm is " +
                        std::to_string(std::sqrt(off)) +
                        " mm off the line through the first and last slice");
    }
    return step;
}

// Picks the series asked for, or the only one.
std::vector<SliceHeader> chooseSeries(const std::string& where,
                                      std::map<std::string, std::vector<SliceHeader>>& series,
                                      const std::string& uid) {
    if (!uid.empty()) {
        const auto it = series.find(uid);
        if (it == series.end())
            throw Error(where + ": no series with SeriesInstanceUID '" + uid +
                        "'; the files hold:" + seriesListText(series));
        return std::move(it->second);
    }
    if (series.size() > 1)
        throw Error(where + ": the files hold " + std::to_string(series.size()) +
                    " series; choose one by its SeriesInstanceUID (scene source \"series\", or "
                    "--series):" +
                    seriesListText(series));
    return std::move(series.begin()->second);
}

// The second pass over one slice: its decoded stored values, rescaled, into out[0 … rows·cols).
void decodeSlice(const SliceHeader& h, float* out, double& lo, double& hi) {
    gdcm::ImageReader reader;
    reader.SetFileName(h.path.c_str());
    GdcmMessages messages;
    if (!reader.Read())
        throw Error(h.path + ": GDCM cannot read the image (transfer syntax " + h.transferSyntax +
                    ")" + gdcmSaid(messages.take()));
    // What GDCM says while reading the pixel data is damage it worked around: a file cut short
    // ("Incomplete Pixel Data found, use file at own risk", the rest zero-filled). Other warnings
    // (about the header) are dropped.
    const std::string readSaid = messages.take();
    if (readSaid.find("Pixel Data") != std::string::npos)
        throw Error(h.path + ": the pixel data is damaged or cut short (GDCM: " + readSaid + ")");
    const gdcm::Image& image = reader.GetImage();
    const gdcm::PixelFormat& pf = image.GetPixelFormat();
    if (image.GetDimension(0) != unsigned(h.columns) || image.GetDimension(1) != unsigned(h.rows))
        throw Error(h.path + ": the image's size differs from its Rows and Columns");
    const int allocated = pf.GetBitsAllocated(), stored = pf.GetBitsStored(),
              highBit = pf.GetHighBit();
    const bool isSigned = pf.GetPixelRepresentation() == 1;
    if (allocated != 8 && allocated != 16 && allocated != 32)
        throw Error(h.path + ": " + std::to_string(allocated) +
                    " bits allocated per pixel; "
                    "8, 16 and 32 are read");
    // PS3.5 8.1.1: the stored bits end at HighBit. Lobe reads the usual layout, HighBit =
    // BitsStored − 1 (the stored value in the low bits, anything above it ignored).
    if (stored < 1 || stored > allocated || highBit != stored - 1)
        throw Error(h.path + ": BitsStored " + std::to_string(stored) + " and HighBit " +
                    std::to_string(highBit) +
                    " are not the layout read here (HighBit = BitsStored - 1)");
    const size_t count = size_t(h.rows) * size_t(h.columns);
    const size_t bytes = count * size_t(allocated / 8);
    if (image.GetBufferLength() != bytes)
        throw Error(h.path + ": the decoded image holds " +
                    std::to_string(image.GetBufferLength()) + " bytes, expected " +
                    std::to_string(bytes) + " for " + std::to_string(h.columns) + "x" +
                    std::to_string(h.rows) + " pixels of " + std::to_string(allocated) + " bits");
    // Uncompressed pixel data must hold every pixel: GDCM zero-fills a short element (PS3.5
    // A.4: only encapsulated pixel data is fragmented; native data is one value of the full size).
    const gdcm::DataElement& pixelData =
        reader.GetFile().GetDataSet().GetDataElement(gdcm::Tag(0x7fe0, 0x0010));
    if (!pixelData.GetSequenceOfFragments()) {
        const gdcm::ByteValue* value = pixelData.GetByteValue();
        const size_t held = value ? size_t(value->GetLength()) : 0;
        if (held < bytes)
            throw Error(h.path + ": the pixel data holds " + std::to_string(held) +
                        " bytes, expected " + std::to_string(bytes) + " for " +
                        std::to_string(h.columns) + "x" + std::to_string(h.rows) + " pixels of " +
                        std::to_string(allocated) + " bits (the file is damaged or cut short)");
    }
    std::vector<char> buffer(bytes);
    if (!image.GetBuffer(buffer.data()))
        throw Error(h.path + ": GDCM cannot decode the pixel data (transfer syntax " +
                    h.transferSyntax +
                    "); convert the series to an uncompressed transfer syntax "
                    "first, e.g. with gdcmconv --raw" +
                    gdcmSaid(messages.take()));
    // Any message while decoding is a decoder working around damage ("Corrupt JPEG data: ...",
    // "Requesting too much data. Truncating result"): its pixels are not the image.
    const std::string decodeSaid = messages.take();
    if (!decodeSaid.empty())
        throw Error(h.path +
                    ": the pixel data is damaged: it does not decode cleanly (transfer syntax " +
                    h.transferSyntax + "; GDCM: " + decodeSaid + ")");
    // GetBuffer gives the stored values in the machine's byte order. Keep the low BitsStored
    // bits and sign-extend them when PixelRepresentation is 1 (two's complement, PS3.5 8.1.1).
    const std::uint64_t mask = stored == 64 ? ~0ull : ((1ull << stored) - 1);
    const std::uint64_t signBit = 1ull << (stored - 1);
    for (size_t n = 0; n < count; ++n) {
        std::uint64_t raw = 0;
        if (allocated == 8) {
            raw = static_cast<unsigned char>(buffer[n]);
        } else if (allocated == 16) {
            std::uint16_t v;
            std::memcpy(&v, buffer.data() + 2 * n, 2);
            raw = v;
        } else {
            std::uint32_t v;
            std::memcpy(&v, buffer.data() + 4 * n, 4);
            raw = v;
        }
        raw &= mask;
        const double value = isSigned && (raw & signBit)
                                 ? double(std::int64_t(raw) - std::int64_t(mask) - 1)
                                 : double(raw);
        // C.11.1.1.2: output units = m · SV + b.
        const float f = static_cast<float>(value * h.slope + h.intercept);
        if (!std::isfinite(f))
            throw Error(h.path + ": a rescaled value is outside the float range (RescaleSlope " +
                        std::to_string(h.slope) + ")");
        out[n] = f;
        lo = std::min(lo, double(f));
        hi = std::max(hi, double(f));
    }
}

}  // namespace

std::vector<DicomSeriesInfo> listDicomSeries(const std::vector<std::string>& inputs) {
    std::vector<DicomSeriesInfo> out;
    for (const auto& [uid, slices] : readSeries(inputs))
        out.push_back({uid, slices.front().seriesDescription, int(slices.size())});
    return out;
}

DenseVolume readDicomDense(const std::vector<std::string>& inputs, const std::string& seriesUid) {
    const std::string where = inputsText(inputs);
    std::map<std::string, std::vector<SliceHeader>> series = readSeries(inputs);
    std::vector<SliceHeader> slices = chooseSeries(where, series, seriesUid);
    const Vec3d step = sortAndCheck(where, slices);
    const SliceHeader& first = slices.front();

    DenseVolume v;
    v.dims = {first.columns, first.rows, int(slices.size())};
    const double voxels = double(first.columns) * first.rows * double(slices.size());
    checkFits(voxels * sizeof(float), where + ": the series (" + std::to_string(first.columns) +
                                          "x" + std::to_string(first.rows) + "x" +
                                          std::to_string(slices.size()) + " voxels)");
    v.values.resize(size_t(voxels));
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    const size_t perSlice = size_t(first.columns) * size_t(first.rows);
    for (size_t k = 0; k < slices.size(); ++k)
        decodeSlice(slices[k], v.values.data() + k * perSlice, lo, hi);
    v.min = lo;
    v.max = hi;
    if (slices.size() == 1) {
        std::ostringstream note;
        note << first.path << ": a single slice, drawn as a slab " << std::sqrt(dot(step, step))
             << " mm thick ("
             << (first.spacingBetweenSlices > 0.0 ? "SpacingBetweenSlices"
                 : first.sliceThickness > 0.0     ? "SliceThickness"
                                                  : "no thickness given: 1 mm")
             << "); give the folder of the whole series for a volume";
        v.note = note.str();
    }

    // C.7.6.2.1.1, equation C.7.6.2.1-1: columns X·Δi (Δi = column spacing, PixelSpacing[1]),
    // Y·Δj (Δj = row spacing, PixelSpacing[0]), the slice step, and S of the first slice — in
    // LPS; then rows x and y negated for RAS (dicom_file.h).
    const Vec3d colX = {first.rowDir[0] * first.colSpacing, first.rowDir[1] * first.colSpacing,
                        first.rowDir[2] * first.colSpacing};
    const Vec3d colY = {first.colDir[0] * first.rowSpacing, first.colDir[1] * first.rowSpacing,
                        first.colDir[2] * first.rowSpacing};
    for (int row = 0; row < 3; ++row) {
        const double sign = row < 2 ? -1.0 : 1.0;
        v.affine[row] = {sign * colX[row], sign * colY[row], sign * step[row],
                         sign * first.position[row]};
    }
    return v;
}

}  // namespace detail
}  // namespace lobe
