#include "render/scene_file.h"

#include "core/error.h"
#include "core/math.h"
#include "core/nearest_name.h"
#include "materials/albedo.h"
#include "materials/registry.h"
#include "render/framing.h"
#include "render/scene_labels.h"
#include "volume/volume_layout.h"

#include <nlohmann/json.hpp>

#include <cctype>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>

namespace lobe {

// Limits of the scene format (docs/scene-format.md).
constexpr size_t kMaxLights = 1024;
constexpr size_t kMaxObjects = 1024;

namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

// A JSON object being read, with its key path for messages. Every key must be consumed or
// listed; whatever is left is reported as unknown, so a typo is never silently ignored.
class Reader {
public:
    Reader(const Json& j, std::string path, const std::string& file)
        : j_(j), path_(std::move(path)), file_(file) {
        if (!j_.is_object()) fail(path_, "expected an object");
    }

    [[noreturn]] void fail(const std::string& at, const std::string& what) const {
        throw Error(file_ + ": " + (at.empty() ? "top level" : at) + ": " + what);
    }
    std::string at(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }
    bool has(const std::string& key) const {
        asked_.insert(key);  // every key the reader looks for: the suggestions for a typo
        return j_.contains(key);
    }

    const Json& raw(const std::string& key) {
        used_.insert(key);
        return j_.at(key);
    }

    double number(const std::string& key, double def, double lo, double hi) {
        if (!has(key)) return def;
        const Json& v = raw(key);
        if (!v.is_number()) fail(at(key), "expected a number, got " + std::string(v.type_name()));
        const double x = v.get<double>();
        if (!(x >= lo && x <= hi))
            fail(at(key), "value " + v.dump() + " is outside [" + fmt(lo) + ", " + fmt(hi) + "]");
        return x;
    }
    int integer(const std::string& key, int def, int lo, int hi) {
        if (!has(key)) return def;
        const Json& v = raw(key);
        if (!v.is_number_integer()) fail(at(key), "expected a whole number, got " + v.dump());
        const long long x = v.get<long long>();
        if (x < lo || x > hi)
            fail(at(key), "value " + v.dump() + " is outside [" + std::to_string(lo) + ", " +
                              std::to_string(hi) + "]");
        return int(x);
    }
    bool boolean(const std::string& key, bool def) {
        if (!has(key)) return def;
        const Json& v = raw(key);
        if (!v.is_boolean()) fail(at(key), "expected true or false, got " + v.dump());
        return v.get<bool>();
    }
    std::string string(const std::string& key, const std::string& def,
                       const std::vector<std::string>& allowed = {}) {
        if (!has(key)) return def;
        const Json& v = raw(key);
        if (!v.is_string()) fail(at(key), "expected a string, got " + v.dump());
        const std::string s = v.get<std::string>();
        if (!allowed.empty() && std::find(allowed.begin(), allowed.end(), s) == allowed.end()) {
            std::string list;
            for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
            fail(at(key), "'" + s + "' is not one of: " + list);
        }
        return s;
    }
    std::string requiredString(const std::string& key) {
        if (!has(key)) fail(at(key), "missing (a string is required)");
        return string(key, "");
    }
    std::vector<double> numbers(const Json& v, const std::string& where, size_t count) const {
        if (!v.is_array() || v.size() != count)
            fail(where,
                 "expected an array of " + std::to_string(count) + " numbers, got " + v.dump());
        std::vector<double> out;
        for (const Json& x : v) {
            if (!x.is_number()) fail(where, "expected numbers, got " + v.dump());
            out.push_back(x.get<double>());
        }
        return out;
    }
    Vec3 vec3(const std::string& key, const Vec3& def) {
        if (!has(key)) return def;
        const auto v = numbers(raw(key), at(key), 3);
        return Vec3(v[0], v[1], v[2]);
    }
    // One number for all bands or [700, 546.1, 435.8] values.
    Spectrum bands(const std::string& key, const Spectrum& def, double lo, double hi) {
        if (!has(key)) return def;
        const Json& v = raw(key);
        Spectrum s;
        if (v.is_number()) {
            s = Spectrum(v.get<double>());
        } else {
            const auto n = numbers(v, at(key), 3);
            s = Spectrum(n[0], n[1], n[2]);
        }
        for (int b = 0; b < 3; ++b)
            if (!(s[b] >= lo && s[b] <= hi))
                fail(at(key),
                     "value " + v.dump() + " is outside [" + fmt(lo) + ", " + fmt(hi) + "]");
        return s;
    }
    Reader child(const std::string& key) { return Reader(raw(key), at(key), file_); }

    // Call when done: every key not consumed is an error.
    void finish() const {
        for (auto it = j_.begin(); it != j_.end(); ++it)
            if (!used_.count(it.key())) {
                const std::string near = nearestName(it.key(), asked_);
                fail(at(it.key()),
                     "unknown key" +
                         (near.empty() ? std::string() : " (did you mean '" + near + "'?)"));
            }
    }
    const std::string& file() const { return file_; }
    const std::string& path() const { return path_; }

private:
    static std::string fmt(double x) {
        std::ostringstream ss;
        ss << x;
        return ss.str();
    }
    const Json& j_;
    std::string path_;
    const std::string& file_;
    std::set<std::string> used_;
    mutable std::set<std::string> asked_;
};

std::string resolvePath(const std::string& p, const std::string& baseDir) {
    const fs::path path(p);
    return path.is_absolute() ? p : (fs::path(baseDir) / path).lexically_normal().string();
}

// "" when `p` can be reached; otherwise why not, to follow the quoted path — " does not exist",
// or ": " and the system's reason (a symbolic link loop: "Too many levels of symbolic links") —
// never an exception.
std::string unreachable(const std::string& p) {
    std::error_code ec;
    if (fs::exists(p, ec)) return "";
    return ec ? ": " + ec.message() : " does not exist";
}

// `segmentation`: the source of a "kind": "segmentation" object, a label map whose labels the
// object lists (its own "labels" key), so label_table and label_smooth need no source.labels.
// Where a source's names lead: the scene file's folder, and the arrays in memory it may name (the
// Python module's; none for a scene file).
struct SourceContext {
    std::string baseDir;
    const SceneArrays* arrays = nullptr;
};

VolumeSourceSpec readSource(Reader r, const SourceContext& context, bool segmentation = false) {
    const std::string& baseDir = context.baseDir;
    VolumeSourceSpec s;
    // "array": an array in memory instead of a file (the Python module), bound now by its name
    // (a label map's labels and names are checked against it below). The file keys describe a
    // file's layout: an array has its own.
    if (r.has("array")) {
        const std::string name = r.requiredString("array");
        for (const char* key : {"path", "series", "dims", "type", "endian", "spacing"})
            if (r.has(key))
                r.fail(r.at(key),
                       "not with \"array\" (an array in memory has its own size, type "
                       "and affine)");
        if (!context.arrays)
            r.fail(r.at("array"),
                   "arrays in memory are given through the Python module (lobe.Scene, "
                   "docs/python.md); a scene file names its data in \"path\"");
        const auto it = context.arrays->find(name);
        if (it == context.arrays->end() || !it->second)
            r.fail(r.at("array"), "no array named '" + name + "'");
        s.array = it->second;
    } else if (r.has("path") && r.raw("path").is_array()) {
        // "path": one file or folder; or an array of files, the slices of one DICOM series.
        const Json& list = r.raw("path");
        if (list.empty())
            r.fail(r.at("path"), "an empty list (expected the files of a DICOM series)");
        for (const Json& item : list) {
            if (!item.is_string())
                r.fail(r.at("path"), "expected a list of file names, got " + item.dump());
            const std::string p = resolvePath(item.get<std::string>(), baseDir);
            const std::string why = unreachable(p);
            if (!why.empty()) r.fail(r.at("path"), "file '" + p + "'" + why);
            if (s.path.empty())
                s.path = p;
            else
                s.morePaths.push_back(p);
        }
    } else {
        s.path = resolvePath(r.requiredString("path"), baseDir);
        const std::string why = unreachable(s.path);
        if (!why.empty()) r.fail(r.at("path"), "file '" + s.path + "'" + why);
    }
    s.series = r.string("series", "");
    if (r.has("dims")) {
        const auto d = r.numbers(r.raw("dims"), r.at("dims"), 3);
        std::array<int, 3> dims{};
        for (int i = 0; i < 3; ++i) {
            if (d[i] < 1 || d[i] > 65536 || d[i] != std::floor(d[i]))
                r.fail(r.at("dims"), "expected three whole numbers in [1, 65536]");
            dims[i] = int(d[i]);
        }
        s.dims = dims;
    }
    s.type = r.string(
        "type", "", {"uint8", "int8", "uint16", "int16", "uint32", "int32", "float32", "float64"});
    s.endian = r.string("endian", "little", {"little", "big"});
    if (r.has("spacing")) {
        const auto v = r.numbers(r.raw("spacing"), r.at("spacing"), 3);
        for (int i = 0; i < 3; ++i) {
            if (!(v[i] > 0)) r.fail(r.at("spacing"), "spacing must be positive");
            s.spacing[i] = v[i];
        }
    }
    if (r.has("divide_by") && r.raw("divide_by").is_string()) {
        // "max", or a percentile "pNN" as `lobe info` prints them
        // (LoadOptions::normalizePercentile).
        const std::string text = r.string("divide_by", "max");
        const double p = parsePercentileText(text);
        if (text == "max")
            s.divideByMax = true;
        else if (p > 0.0)
            s.divideByPercentile = p;
        else
            r.fail(r.at("divide_by"), "'" + text +
                                          "' is not a number, \"max\" or a percentile "
                                          "\"pNN\" with 0 < NN <= 100 (e.g. \"p99\")");
    } else
        s.divideBy = r.number("divide_by", 1.0, 1e-12, 1e12);
    s.blurFwhmMm = r.number("blur_fwhm_mm", 0.0, 0.0, 100.0);
    s.background = r.number("background", 0.0, -1e12, 1e12);
    // A label map (volume/labels.h, render/scene_labels.h): loaded and checked now.
    if (segmentation && r.has("labels"))
        r.fail(r.at("labels"), "a segmentation lists its labels in the object's own \"labels\"");
    if (segmentation || r.has("labels") || r.has("label_table") || r.has("label_smooth")) {
        if (!segmentation && !r.has("labels"))
            r.fail(r.at(r.has("label_table") ? "label_table" : "label_smooth"),
                   "applies to a label map: give \"labels\" too");
        for (const char* key : {"divide_by", "blur_fwhm_mm", "background", "dims", "type", "endian",
                                "spacing", "series"})
            if (r.has(key))
                r.fail(r.at(key),
                       "not with labels: a label map is read as its file stores it (a "
                       "header format: .nii, .nii.gz, .mgh, .mgz, .nhdr, .vdb)");
        if (!s.morePaths.empty()) r.fail(r.at("path"), "a label map is one file");
        s.labelSmooth = r.number("label_smooth", kLabelSmoothDefault, 0.0, 4.0);
        const char* mapKey = s.array ? "array" : "path";
        std::shared_ptr<const LabelMap> map;
        try {
            map = s.array ? loadLabelMap(*s.array) : loadLabelMap(s.path);
        } catch (const Error& e) {
            r.fail(r.at(mapKey), e.what());
        }
        LabelSource labels;
        try {
            labels = openLabelSource(
                map, s.path, r.has("label_table") ? &r.raw("label_table") : nullptr, baseDir);
        } catch (const Error& e) {
            r.fail(r.at(r.has("label_table") ? "label_table" : mapKey), e.what());
        }
        s.labelMap = labels.map;
        s.labelTable = labels.table.source;
        if (r.has("labels")) {
            try {
                s.labels = labelIdsOf(r.raw("labels"), labels, false);
            } catch (const Error& e) {
                r.fail(r.at("labels"), e.what());
            }
        }
    }
    r.finish();
    return s;
}

ObjectTransform readTransform(Reader r) {
    ObjectTransform t;
    if (r.has("matrix")) {
        const Json& m = r.raw("matrix");
        if (!m.is_array() || m.size() != 3)
            r.fail(r.at("matrix"), "expected 3 rows of 4 numbers (linear part | translation)");
        for (int i = 0; i < 3; ++i) {
            const auto row = r.numbers(m[i], r.at("matrix") + "[" + std::to_string(i) + "]", 4);
            for (int j = 0; j < 3; ++j) t.linear[i][j] = row[j];
            t.translation[i] = row[3];
        }
        if (r.has("scale") || r.has("translate"))
            r.fail(r.path(), "give either matrix or scale/translate, not both");
    } else {
        const Vec3 s = r.vec3("scale", Vec3(1, 1, 1));
        const Vec3 tr = r.vec3("translate", Vec3(0, 0, 0));
        t.linear = {{{s.x, 0, 0}, {0, s.y, 0}, {0, 0, s.z}}};
        t.translation = {tr.x, tr.y, tr.z};
    }
    if (nearlySingular(t.linear))
        r.fail(r.path(),
               "the transform is singular, or so nearly (its columns almost parallel) "
               "that it cannot be inverted");
    r.finish();
    return t;
}

void readBrdf(Reader r, ObjectSpec& object) {
    object.brdfModel = r.requiredString("model");
    const std::string context = r.at("model");
    const BrdfModelInfo* model = nullptr;
    try {
        model = &findBrdfModel(object.brdfModel);
    } catch (const Error& e) {
        r.fail(context, e.what());
    }
    ParamValues values(*model->params);
    for (const ParamSpec& spec : *model->params) {
        if (!r.has(spec.name)) continue;
        const Spectrum v = r.bands(spec.name, Spectrum(spec.defaultValue), -1e300, 1e300);
        setBrdfParam(*model, values, spec.name, v, r.file() + ": " + r.path());
    }
    object.material.specular = model->create(values);
    if (r.has(
            "albedo")) {  // the lobe scaled to this albedo at normal incidence (materials/albedo.h)
        const double target = r.number("albedo", 0.1, 1e-6, 1.0);
        try {
            object.material.specularScale = albedoScale(object.material.specular, target);
        } catch (const Error& e) {
            r.fail(r.at("albedo"), e.what());
        }
    }
    r.finish();  // any other key is not a parameter of this model
}

// A transfer-function value: a number, or a percentile "pNN" of the volume's values (0 < NN <=
// 100, as `lobe info` prints them), which sets `percent` and reads as 0 (the point keeps its
// offset from the percentile until render/scene.cpp resolves it).
double readTfValue(Reader& r, const std::string& key, double def, double& percent) {
    percent = 0.0;
    if (r.has(key) && r.raw(key).is_string()) {
        const std::string text = r.raw(key).get<std::string>();
        percent = parsePercentileText(text);
        if (!(percent > 0.0))
            r.fail(r.at(key), "'" + text +
                                  "' is not a number or a percentile of the volume's "
                                  "values \"pNN\" with 0 < NN <= 100 (e.g. \"p95\", \"p99.5\")");
        return 0.0;
    }
    return r.number(key, def, -1e12, 1e12);
}

// Either {"points": [{value, opacity, color}, ...]} or one of the paper's presets:
// {"preset": "density_map", "index": 0..3, "ramp_width": w},
// {"preset": "density_maps", "ramp_width": w} (all four maps in one object),
// {"preset": "cortex", "boundary": b, "width": w, "color": [..]} or
// {"preset": "cortex_shell", "boundary": b, "width": w, "opacity": a, "color": [..]}
// (volume/transfer_function.h). A point's value and a preset's boundary may be a percentile
// "pNN" of the volume's values (ObjectSpec::transferPercentiles).
void readTransfer(Reader r, ObjectSpec& o) {
    constexpr double kInfinity = std::numeric_limits<double>::infinity();
    o.transferName = r.file() + ": " + r.path();
    const std::string preset =
        r.string("preset", "", {"density_map", "density_maps", "cortex", "cortex_shell"});
    if (preset == "density_maps") {
        const double ramp = r.number("ramp_width", 0.02, 1e-6, 0.049);
        r.finish();
        o.transfer = TransferFunction::densityMaps(ramp);
        return;
    }
    if (preset == "density_map") {
        const int index = r.integer("index", 0, 0, 3);
        const double ramp = r.number("ramp_width", 0.02, 1e-6, 0.049);
        r.finish();
        o.transfer = TransferFunction::densityMap(index, ramp);
        return;
    }
    if (preset == "cortex" || preset == "cortex_shell") {
        double percent = 0.0;
        const double boundary = readTfValue(r, "boundary", 0.47, percent);
        const bool shell = preset == "cortex_shell";
        const double width = r.number("width", shell ? 0.14 : 0.1, 1e-9, 1e12);
        const double opacity = shell ? r.number("opacity", 0.2, 0.001, 0.999999) : 0.0;
        const Spectrum color =
            r.bands("color", shell ? Spectrum(0.85, 0.72, 0.62) : linearSrgbToBands(0.8, 0.7, 0.65),
                    0.0, 1e6);
        r.finish();
        // With a percentile the preset is built around 0: every point is an offset from it.
        const TransferFunction tf =
            shell ? TransferFunction::cortexShell(boundary, width, opacity, color)
                  : TransferFunction::cortex(boundary, width, color);
        if (percent > 0.0) {
            o.transferPoints = tf.points();
            ObjectSpec::TfPercentile p{percent, {}, r.file() + ": " + r.at("boundary")};
            for (std::size_t i = 0; i < tf.points().size(); ++i) p.points.push_back(i);
            o.transferPercentiles.push_back(p);
        } else
            o.transfer = tf;
        return;
    }
    std::vector<TfPoint> points;
    if (!r.has("points")) r.fail(r.at("points"), "missing (or give a preset)");
    const Json& pts = r.raw("points");
    const std::string where = r.at("points");
    if (!pts.is_array() || pts.empty())
        r.fail(where, "expected a non-empty array of {value, opacity, color}");
    double lastNumber = -kInfinity;  // percentiles are placed, and checked, at assembly
    for (size_t i = 0; i < pts.size(); ++i) {
        Reader p(pts[i], where + "[" + std::to_string(i) + "]", r.file());
        TfPoint tp;
        if (!p.has("value")) p.fail(p.at("value"), "missing");
        double percent = 0.0;
        tp.value = readTfValue(p, "value", 0.0, percent);
        tp.opacity = p.number("opacity", 0.0, 0.0, 0.999999);
        tp.colour = p.bands("color", Spectrum(1.0), 0.0, 1e6);
        p.finish();
        if (percent > 0.0)
            o.transferPercentiles.push_back({percent, {i}, r.file() + ": " + p.at("value")});
        else if (tp.value < lastNumber)
            p.fail(p.at("value"), "points must be in non-decreasing order of value");
        points.push_back(tp);
        if (percent == 0.0) lastNumber = tp.value;
    }
    r.finish();
    if (o.transferPercentiles.empty())
        o.transfer = TransferFunction(points, o.transferName);
    else
        o.transferPoints = points;
}

// "clip": [{"plane": {"point": [x, y, z], "normal": [nx, ny, nz]}} | {"box": {"min": [...],
// "max": [...]}}, each with optional "invert" and "cap"] (core/clip.h).
std::vector<ClipShape> readClip(Reader& r, const std::string& key) {
    const Json& list = r.raw(key);
    const std::string where = r.at(key);
    if (!list.is_array() || list.size() > size_t(kMaxClipShapes))
        r.fail(where,
               "expected an array of at most " + std::to_string(kMaxClipShapes) +
                   " clip shapes ({\"plane\": {\"point\": [x, y, z], \"normal\": [nx, ny, nz]}} "
                   "or {\"box\": {\"min\": [x, y, z], \"max\": [x, y, z]}})");
    std::vector<ClipShape> shapes;
    for (size_t i = 0; i < list.size(); ++i) {
        Reader c(list[i], where + "[" + std::to_string(i) + "]", r.file());
        ClipShape s;
        if (c.has("plane") == c.has("box")) c.fail(c.path(), "give exactly one of plane or box");
        if (c.has("plane")) {
            Reader p = c.child("plane");
            if (!p.has("point") || !p.has("normal")) p.fail(p.path(), "needs point and normal");
            s.kind = ClipShape::Kind::Plane;
            s.point = p.vec3("point", Vec3(0.0));
            s.normal = p.vec3("normal", Vec3(0.0));
            const double len = s.normal.length();
            if (!(len > 0.0) || !std::isfinite(len))
                p.fail(p.at("normal"), "must be a non-zero vector");
            s.normal /= len;
            p.finish();
        } else {
            Reader b = c.child("box");
            if (!b.has("min") || !b.has("max")) b.fail(b.path(), "needs min and max");
            s.kind = ClipShape::Kind::Box;
            s.lo = b.vec3("min", Vec3(0.0));
            s.hi = b.vec3("max", Vec3(0.0));
            if (!(s.lo.x < s.hi.x && s.lo.y < s.hi.y && s.lo.z < s.hi.z))
                b.fail(b.path(), "expected min < max in every axis");
            b.finish();
        }
        if (!isFinite(s.point) || !isFinite(s.lo) || !isFinite(s.hi))
            c.fail(c.path(), "coordinates must be finite");
        s.invert = c.boolean("invert", false);
        s.cap = c.boolean("cap", false);
        c.finish();
        shapes.push_back(s);
    }
    return shapes;
}

// The keys an object and a segmentation share: transform, brdf (required; `missingBrdf` says
// so), kd, tangent_axis and highlight.
void readLook(Reader& r, ObjectSpec& o, const std::string& missingBrdf) {
    if (r.has("transform")) o.transform = readTransform(r.child("transform"));
    if (!r.has("brdf")) r.fail(r.at("brdf"), missingBrdf);
    readBrdf(r.child("brdf"), o);
    o.material.kd = r.bands("kd", Spectrum(0.2), 0.0, 1.0);
    o.tangentAxis = r.vec3("tangent_axis", Vec3(0, 0, 1));
    if (!(o.tangentAxis.length() > 0)) r.fail(r.at("tangent_axis"), "must not be the zero vector");
    o.tangentAxis.normalize();
    o.highlightTakesLight = r.string("highlight", "light", {"light", "colour"}) == "light";
}

// The keys of an iso-surface that an object and a segmentation's labels share: method (and the
// level-set keys), normals, opacity.
void readSurfaceKeys(Reader& r, ObjectSpec& o) {
    o.method = r.string("method", "exact", {"exact", "mesh", "levelset"});
    o.isoNormals = r.string("normals", "trilinear", {"trilinear", "bspline"});
    if (o.method == "levelset") {
        o.levelSetVoxel = r.number("levelset_voxel", 0.0, 0.0, 1e6);
        o.levelSetHalfWidth = r.number("levelset_half_width", 3.0, 1.0, 64.0);
        o.levelSetSmooth = r.integer("levelset_smooth", 0, 0, 1000);
    }
    o.opacity = r.number("opacity", 1.0, 0.0, 1.0);
}

ObjectSpec readObject(Reader r, const SourceContext& context) {
    ObjectSpec o;
    o.name = r.string("name", r.path());
    const std::string kind = r.string("kind", "", {"isosurface", "volume", "segmentation"});
    if (kind.empty()) r.fail(r.at("kind"), "missing (isosurface, volume or segmentation)");
    o.kind = kind == "volume" ? ObjectSpec::Kind::Volume : ObjectSpec::Kind::IsoSurface;
    if (!r.has("source")) r.fail(r.at("source"), "missing");
    o.source = readSource(r.child("source"), context);
    readLook(r, o, "missing ({\"model\": NAME, parameters...})");
    if (o.kind == ObjectSpec::Kind::IsoSurface && !o.source.labels.empty()) {
        // The surface of a label set is its anti-aliased indicator's 0.5 level (volume/labels.h).
        if (r.has("iso"))
            r.fail(r.at("iso"),
                   "not with source.labels: the surface of a label set is the 0.5 "
                   "level of its smoothed indicator (set source.label_smooth)");
    } else if (o.kind == ObjectSpec::Kind::IsoSurface) {
        if (!r.has("iso")) r.fail(r.at("iso"), "missing (the iso value)");
    }
    if (o.kind == ObjectSpec::Kind::IsoSurface) {
        o.iso = r.number("iso", 0.5, -1e12, 1e12);
        readSurfaceKeys(r, o);
        o.color = r.bands("color", Spectrum(1.0), 0.0, 1e6);
    } else {
        if (!r.has("transfer_function")) r.fail(r.at("transfer_function"), "missing");
        readTransfer(r.child("transfer_function"), o);
        o.reconstruction =
            r.string("reconstruction", "trilinear", {"trilinear", "bspline", "nearest"});
        o.gradient = r.string("gradient", "central", {"central", "bspline"});
    }
    if (r.has("clip")) o.clip = readClip(r, "clip");
    o.castsShadows = r.boolean("casts_shadows", true);
    if (r.has("mask")) {
        // {"source": {...}, "iso": v, "invert": bool}, or a label set of a label map:
        // {"source": {"path": MAP, "label_table": …}, "labels": [numbers or names], …}.
        Reader m = r.child("mask");
        o.mask.enabled = true;
        if (!m.has("source"))
            m.fail(m.at("source"), "missing (the mask's volume, as an object's source)");
        const Json& sourceJson = m.raw("source");
        if (sourceJson.is_object() && sourceJson.contains("labels"))
            m.fail(m.at("source") + ".labels",
                   "a mask lists its labels in the mask's own \"labels\"");
        if (m.has("labels")) {
            if (m.has("iso"))
                m.fail(m.at("iso"),
                       "not with labels (a label set's mask is the 0.5 level of its smoothed "
                       "indicator; set source.label_smooth)");
            o.mask.source = readSource(m.child("source"), context, true);
            // The map (loaded once per process) and the table readSource accepted, for names.
            const LabelSource named = openLabelSource(
                o.mask.source.labelMap, o.mask.source.path,
                sourceJson.contains("label_table") ? &sourceJson["label_table"] : nullptr,
                context.baseDir);
            try {
                o.mask.labels = labelIdsOf(m.raw("labels"), named, false);
            } catch (const Error& e) {
                m.fail(m.at("labels"), e.what());
            }
            o.mask.source.labels = o.mask.labels;  // loaded as a label map (render/scene.cpp)
        } else {
            o.mask.source = readSource(m.child("source"), context);
            if (!m.has("iso"))
                m.fail(m.at("iso"),
                       "missing (the object exists where the mask's value is above "
                       "it; or \"labels\" for a label map)");
            o.mask.iso = m.number("iso", 0.5, -1e12, 1e12);
        }
        o.mask.invert = m.boolean("invert", false);
        m.finish();
    }
    r.finish();
    return o;
}

// "kind": "segmentation": one iso-surface object per label of a label map, named and coloured
// from its label table, with per-label "overrides" by name (docs/scene-format.md, "Labels").
void readSegmentation(Reader r, const SourceContext& context, std::vector<ObjectSpec>& out) {
    r.string("kind", "");
    const std::string where = r.path();
    const std::string prefix = r.string("name", "");
    if (!r.has("source")) r.fail(r.at("source"), "missing (the label map)");
    ObjectSpec base;
    base.kind = ObjectSpec::Kind::IsoSurface;
    base.source = readSource(r.child("source"), context, true);
    base.segmentation = where;
    // The map readSource loaded and the table it accepted, for the names and colours.
    const Json& sourceJson = r.raw("source");
    const LabelSource named = openLabelSource(
        base.source.labelMap, base.source.path,
        sourceJson.contains("label_table") ? &sourceJson["label_table"] : nullptr, context.baseDir);
    if (!r.has("labels"))
        r.fail(r.at("labels"), "missing (\"all\" or a list of label numbers or names)");
    std::vector<int> ids;
    try {
        ids = labelIdsOf(r.raw("labels"), named, true);
    } catch (const Error& e) {
        r.fail(r.at("labels"), e.what());
    }
    readLook(r, base, "missing (the labels' BRDF: {\"model\": NAME, …})");
    readSurfaceKeys(r, base);
    const bool colourGiven = r.has("color");
    base.color = r.bands("color", Spectrum(1.0), 0.0, 1e6);
    // Overrides by label name (or number): {"Hippocampus_L": {"brdf": …, "opacity": …}}.
    std::map<int, std::string> overrides;  // label → key
    if (r.has("overrides")) {
        const Json& o = r.raw("overrides");
        if (!o.is_object()) r.fail(r.at("overrides"), "expected an object {\"label name\": {…}}");
        for (auto it = o.begin(); it != o.end(); ++it) {
            const std::string& key = it.key();
            const bool number =
                !key.empty() && key.find_first_not_of("0123456789") == std::string::npos;
            int id = -1;
            try {
                id = labelIdsOf(number ? Json(std::stoll(key)) : Json(key), named, false).front();
            } catch (const Error& e) {
                r.fail(r.at("overrides") + "." + key, e.what());
            } catch (const std::out_of_range&) {
                r.fail(r.at("overrides") + "." + key, "not a label number");
            }
            if (std::find(ids.begin(), ids.end(), id) == ids.end())
                r.fail(r.at("overrides") + "." + key,
                       "label " + std::to_string(id) + " is not one of this segmentation's labels");
            if (overrides.count(id))
                r.fail(r.at("overrides") + "." + key,
                       "label " + std::to_string(id) + " is overridden twice");
            overrides[id] = key;
        }
    }
    for (int id : ids) {
        ObjectSpec o = base;
        o.name = (prefix.empty() ? "" : prefix + ": ") + labelName(named, id);
        o.source.labels = {id};
        if (!colourGiven) o.color = labelColour(named, id, Spectrum(1.0));
        const auto ov = overrides.find(id);
        if (ov != overrides.end()) {
            Reader v(r.raw("overrides").at(ov->second), r.at("overrides") + "." + ov->second,
                     r.file());
            if (v.has("brdf")) readBrdf(v.child("brdf"), o);
            o.material.kd = v.bands("kd", o.material.kd, 0.0, 1.0);
            o.opacity = v.number("opacity", o.opacity, 0.0, 1.0);
            o.color = v.bands("color", o.color, 0.0, 1e6);
            o.highlightTakesLight =
                v.string("highlight", o.highlightTakesLight ? "light" : "colour",
                         {"light", "colour"}) == "light";
            if (v.has("tangent_axis")) {
                o.tangentAxis = v.vec3("tangent_axis", o.tangentAxis);
                if (!(o.tangentAxis.length() > 0))
                    v.fail(v.at("tangent_axis"), "must not be the zero vector");
                o.tangentAxis.normalize();
            }
            v.finish();
        }
        out.push_back(std::move(o));
    }
    r.finish();
}

// "fit": {"view": NAME} or {"azimuth_deg": a, "elevation_deg": e}, with optional "objects",
// "margin" and "method" (render/framing.h). Position and target are then computed, not given.
void readFit(Reader& cam, CameraFitSpec& fit) {
    Reader f = cam.child("fit");
    fit.enabled = true;
    fit.view =
        f.string("view", "", {"anterior", "posterior", "left", "right", "superior", "inferior"});
    if (!fit.view.empty() && (f.has("azimuth_deg") || f.has("elevation_deg")))
        f.fail(f.path(), "give either view or azimuth_deg/elevation_deg, not both");
    fit.azimuthDeg = f.number("azimuth_deg", 0.0, -360.0, 360.0);
    fit.elevationDeg = f.number("elevation_deg", 0.0, -90.0, 90.0);
    if (f.has("objects")) {
        const Json& o = f.raw("objects");
        if (o.is_string()) {
            fit.objects.push_back(o.get<std::string>());
        } else {
            if (!o.is_array() || o.empty())
                f.fail(f.at("objects"), "expected an object's name or a non-empty array of names");
            for (const Json& n : o) {
                if (!n.is_string())
                    f.fail(f.at("objects"), "expected names (strings), got " + n.dump());
                fit.objects.push_back(n.get<std::string>());
            }
        }
    }
    fit.margin = f.number("margin", 1.1, 0.1, 100.0);
    fit.method = f.string("method", "box", {"box", "sphere"});
    f.finish();
    fit.upGiven = cam.has("up");
    for (const char* key : {"position", "target"})
        if (cam.has(key))
            cam.fail(cam.at(key),
                     "a fitted camera (camera.fit) computes position and target: give "
                     "either fit or position/target");
}

// A crop with unequal normalised extents would show a region of another aspect than the image
// in the image, stretched (core/camera.cpp maps the crop onto the whole image).
void checkCropAspect(const Reader& cam, const CropWindow& c) {
    const double stretch = cropStretch(c);
    if (std::abs(stretch - 1.0) <= 1e-3) return;
    const double e = std::min(c.x1 - c.x0, c.y1 - c.y0);
    const double cx = 0.5 * (c.x0 + c.x1), cy = 0.5 * (c.y0 + c.y1);
    char buf[400];
    std::snprintf(buf, sizeof buf,
                  "the window spans %.4g of the view's width and %.4g of its height: the image "
                  "would be stretched %.4g times horizontally. A crop keeps the image's aspect "
                  "only with x1 - x0 = y1 - y0, e.g. [%.4g, %.4g, %.4g, %.4g] (the same centre), "
                  "or use \"zoom\"",
                  c.x1 - c.x0, c.y1 - c.y0, stretch, cx - e / 2, cy - e / 2, cx + e / 2,
                  cy + e / 2);
    cam.fail(cam.at("crop"), buf);
}

// "zoom": {"point": [x, y, z], "size": s} or {"box": [[x0, y0, z0], [x1, y1, z1]], "margin": m}
// in world coordinates (render/framing.h, zoomCrop).
void readZoom(Reader z, ZoomSpec& zoom) {
    if (int(z.has("point")) + int(z.has("box")) + int(z.has("objects")) != 1)
        z.fail(z.path(), "give either point (with size), box or objects");
    if (z.has("objects")) {  // the world box of these objects (e.g. a label of an atlas)
        zoom.kind = ZoomSpec::Kind::Box;
        const Json& o = z.raw("objects");
        if (o.is_string())
            zoom.objects.push_back(o.get<std::string>());
        else if (o.is_array() && !o.empty())
            for (const Json& n : o) {
                if (!n.is_string())
                    z.fail(z.at("objects"), "expected names (strings), got " + n.dump());
                zoom.objects.push_back(n.get<std::string>());
            }
        else
            z.fail(z.at("objects"), "expected an object's name or a non-empty array of names");
        zoom.margin = z.number("margin", 1.1, 1.0, 100.0);
        z.finish();
        return;
    }
    if (z.has("point")) {
        zoom.kind = ZoomSpec::Kind::Point;
        zoom.center = z.vec3("point", Vec3(0));
        if (!z.has("size"))
            z.fail(z.at("size"), "missing (the width of the close-up in world units)");
        zoom.size = z.number("size", 1.0, 1e-9, 1e12);
    } else {
        zoom.kind = ZoomSpec::Kind::Box;
        const Json& b = z.raw("box");
        if (!b.is_array() || b.size() != 2)
            z.fail(z.at("box"), "expected two corners [[x0, y0, z0], [x1, y1, z1]]");
        const auto a = z.numbers(b[0], z.at("box") + "[0]", 3);
        const auto c = z.numbers(b[1], z.at("box") + "[1]", 3);
        zoom.lo = Vec3(std::min(a[0], c[0]), std::min(a[1], c[1]), std::min(a[2], c[2]));
        zoom.hi = Vec3(std::max(a[0], c[0]), std::max(a[1], c[1]), std::max(a[2], c[2]));
        if (zoom.lo == zoom.hi) z.fail(z.at("box"), "the two corners are the same point");
        zoom.margin = z.number("margin", 1.1, 1.0, 100.0);
    }
    z.finish();
}

// "lights": {"rig": "headlight" | "paper", "irradiance": E, "angle_deg": a, "behind": b}
// (render/framing.h, lightRig).
void readLightRig(Reader l, LightRigSpec& rig) {
    if (!l.has("rig"))
        l.fail(l.at("rig"), "missing (headlight or paper; or give an array of lights)");
    rig.rig = l.string("rig", "", {"headlight", "paper"});
    rig.irradiance = l.bands("irradiance", Spectrum(1.0), 0.0, 1e12);
    if (rig.rig == "paper") {
        rig.angleDeg = l.number("angle_deg", 0.0, 0.0, 89.0);
        rig.behind = l.number("behind", rig.behind, 0.0, 100.0);
    } else {
        for (const char* key : {"angle_deg", "behind"})
            if (l.has(key)) l.fail(l.at(key), "applies to the paper rig only");
    }
    l.finish();
}

// The checks made while the text is read, before any value is built (nlohmann's SAX interface):
// a key given twice in one object (JSON lets the last silently win), nesting deeper than any
// scene needs (deep enough nesting would overflow the stack later, when the value is walked or
// destroyed), and more elements in the top-level "lights" or "objects" array than a scene holds
// — refused at the first element too many. Linear in the text's length: nlohmann's callback
// parser (json::parse with a callback, used before) rescans the enclosing array each time an
// object in it ends (json_sax_dom_callback_parser::end_object), which made 600 000 lights take
// 101 s before their count was looked at.
class SceneTextCheck final : public nlohmann::json_sax<Json> {
public:
    static constexpr int kMaxDepth = 64;
    std::string problem;    // a scene-format problem, "key: what" or "what"
    std::string syntax;     // a JSON error (nlohmann's text)
    size_t syntaxByte = 0;  // where, for a syntax error (0: not a syntax error)

    bool null() override { return element(); }
    bool boolean(bool) override { return element(); }
    bool number_integer(number_integer_t) override { return element(); }
    bool number_unsigned(number_unsigned_t) override { return element(); }
    bool number_float(number_float_t, const string_t&) override { return element(); }
    bool string(string_t&) override { return element(); }
    bool binary(binary_t&) override { return element(); }
    bool start_object(std::size_t) override { return open(true); }
    bool end_object() override { return close(); }
    bool start_array(std::size_t) override { return open(false); }
    bool end_array() override { return close(); }
    bool key(string_t& k) override {
        Open& o = stack_.back();
        if (!o.keys.insert(k).second) return fail("key '" + k + "' given twice in one object");
        if (stack_.size() == 1) topKey_ = k;
        return true;
    }
    bool parse_error(std::size_t, const std::string&,
                     const nlohmann::detail::exception& e) override {
        syntax = e.what();
        if (const auto* p = dynamic_cast<const Json::parse_error*>(&e))
            syntaxByte = std::max<size_t>(1, p->byte);
        return false;
    }

private:
    struct Open {
        bool object = false;
        std::set<std::string> keys;  // an object's keys so far
        size_t elements = 0;         // an array's elements so far
        size_t limit = 0;            // 0: none
        std::string what;            // "lights", "objects": the limited array's key
    };
    std::vector<Open> stack_;
    std::string topKey_;  // the top-level key whose value is being read

    bool fail(const std::string& why) {
        problem = why;
        return false;
    }
    bool element() {
        if (stack_.empty() || stack_.back().object) return true;
        Open& a = stack_.back();
        if (a.limit != 0 && ++a.elements > a.limit)
            return fail(a.what + ": more than " + std::to_string(a.limit) + " " + a.what +
                        "; a scene holds at most " + std::to_string(a.limit));
        return true;
    }
    bool open(bool object) {
        if (!element()) return false;
        if (stack_.size() >= size_t(kMaxDepth))
            return fail("nested more than " + std::to_string(kMaxDepth) + " levels deep");
        Open o;
        o.object = object;
        // Every light is evaluated at every shaded point: 600 000 lights made a render that
        // never ends. The paper uses 4.
        if (!object && stack_.size() == 1 && (topKey_ == "lights" || topKey_ == "objects")) {
            o.limit = topKey_ == "lights" ? kMaxLights : kMaxObjects;
            o.what = topKey_;
        }
        stack_.push_back(std::move(o));
        return true;
    }
    bool close() {
        stack_.pop_back();
        return true;
    }
};

}  // namespace

SceneSpec parseScene(const std::string& text, const std::string& baseDir, const std::string& name,
                     const SceneArrays* arrays) {
    // First the checks (SceneTextCheck), then the value, built without a callback: both linear.
    SceneTextCheck check;
    if (!Json::sax_parse(text, &check)) {
        if (!check.problem.empty()) throw Error(name + ": " + check.problem);
        if (check.syntaxByte == 0)  // not a syntax error but a number JSON cannot hold (1e400)
            throw Error(name + ": invalid JSON: " + check.syntax);
        // Translate the byte offset into a line and column people can find.
        size_t line = 1, column = 1;
        for (size_t i = 0; i + 1 < check.syntaxByte && i < text.size(); ++i) {
            if (text[i] == '\n') {
                ++line;
                column = 1;
            } else {
                ++column;
            }
        }
        throw Error(name + ": invalid JSON at line " + std::to_string(line) + ", column " +
                    std::to_string(column));
    }
    Json root;
    try {
        root = Json::parse(text);
    } catch (const Json::exception& e) {
        throw Error(name + ": invalid JSON: " + e.what());  // not expected after the check
    }
    SceneSpec scene;
    scene.path = name;
    Reader r(root, "", name);
    scene.title = r.string("title", fs::path(name).stem().string());
    scene.group = r.string("group", "");
    // The group names a file (contact-sheet-GROUP.png): found here, not after the batch rendered.
    for (const char c : scene.group)
        if (c == '/' || c == '\\' || (unsigned char)c < 32)
            r.fail("group", "'" + scene.group +
                                "' names a file (contact-sheet-GROUP.png): no '/', "
                                "'\\' or control characters");
    if (r.has("image")) {
        Reader img = r.child("image");
        scene.width = img.integer("width", scene.width, 1, 16384);
        scene.height = img.integer("height", scene.height, 1, 16384);
        scene.samplesPerPixel = img.integer("samples_per_pixel", scene.samplesPerPixel, 1, 4096);
        scene.seed = uint64_t(img.integer("seed", 1, 0, 2147483647));
        scene.exposure = img.number("exposure", 1.0, 1e-6, 1e6);
        scene.tone = img.string("tone", "clip", {"clip", "shoulder"});
        img.finish();
    }
    if (!r.has("camera")) r.fail("camera", "missing");
    {
        Reader cam = r.child("camera");
        if (cam.has("fit")) readFit(cam, scene.fit);
        scene.cameraPosition = cam.vec3("position", scene.cameraPosition);
        scene.cameraTarget = cam.vec3("target", scene.cameraTarget);
        scene.cameraUp = cam.vec3("up", scene.cameraUp);
        scene.fovDegrees = cam.number("fov_deg", scene.fovDegrees, 0.01, 179.0);
        if (cam.has("crop")) {
            const auto c = cam.numbers(cam.raw("crop"), cam.at("crop"), 4);
            scene.crop = CropWindow{c[0], c[1], c[2], c[3]};
            if (!(c[0] >= 0 && c[2] <= 1 && c[1] >= 0 && c[3] <= 1 && c[0] < c[2] && c[1] < c[3]))
                cam.fail(cam.at("crop"),
                         "expected [x0, y0, x1, y1] with 0 <= x0 < x1 <= 1 and "
                         "0 <= y0 < y1 <= 1");
            checkCropAspect(cam, scene.crop);
        }
        if (cam.has("zoom")) {
            if (cam.has("crop")) cam.fail(cam.at("zoom"), "give either zoom or crop, not both");
            readZoom(cam.child("zoom"), scene.zoom);
        }
        cam.finish();
        if (!scene.fit.enabled) {
            try {  // the camera's own checks (position = target, up parallel to the view)
                PinholeCamera(scene.cameraPosition, scene.cameraTarget, scene.cameraUp,
                              scene.fovDegrees, double(scene.width) / scene.height, scene.crop);
            } catch (const Error& e) {
                std::string what = e.what();  // "camera: …": the key is named once
                if (what.rfind("camera: ", 0) == 0) what.erase(0, 8);
                r.fail("camera", what);
            }
        } else if (!(scene.cameraUp.length() > 0.0)) {
            cam.fail(cam.at("up"), "must not be the zero vector");
        }
    }
    if (r.has("lights") && r.raw("lights").is_object()) {
        readLightRig(r.child("lights"), scene.lightRig);
    } else if (r.has("lights")) {
        const Json& lights = r.raw("lights");
        if (!lights.is_array())
            r.fail("lights", "expected an array of lights or a rig ({\"rig\": \"paper\"})");
        // Every light is evaluated at every shaded point: 600 000 lights made a render that
        // never ends. The paper uses 4.
        if (lights.size() > kMaxLights)
            r.fail("lights", std::to_string(lights.size()) + " lights; a scene holds at most " +
                                 std::to_string(kMaxLights));
        for (size_t i = 0; i < lights.size(); ++i) {
            Reader l(lights[i], "lights[" + std::to_string(i) + "]", name);
            PointLight light;
            if (!l.has("position")) l.fail(l.at("position"), "missing");
            light.position = l.vec3("position", Vec3(0));
            light.intensity = l.bands("intensity", Spectrum(1.0), 0.0, 1e12);
            l.finish();
            scene.lights.push_back(light);
        }
    }
    if (r.has("background")) {  // render/background.h
        const Json& v = r.raw("background");
        const std::string where = name + ": background";
        if (v.is_string()) {
            scene.background = parseBackground(v.get<std::string>(), where);
        } else {
            const std::vector<double> c = r.numbers(v, "background", 3);
            scene.background = backgroundFromColour({c[0], c[1], c[2]}, where);
        }
    }
    if (r.has("backdrop")) {
        Reader b = r.child("backdrop");
        scene.backdrop.enabled = b.boolean("enabled", true);
        scene.backdrop.seed = uint64_t(b.integer("seed", 7, 0, 2147483647));
        scene.backdrop.ambient = b.number("ambient", 0.2, 0.0, 10.0);
        scene.backdrop.diffuse = b.number("diffuse", 0.3, 0.0, 10.0);
        scene.backdrop.cells = b.integer("cells", 24, 1, 1024);
        scene.backdrop.blur = b.number("blur", 1.5, 0.0, 100.0);
        scene.backdrop.grey = b.string("colours", "random", {"random", "grey"}) == "grey";
        b.finish();
    }
    if (r.has("volume")) {
        Reader v = r.child("volume");
        scene.volumeStepVoxels = v.number("step_voxels", 0.05, 1e-3, 16.0);
        scene.terminationTransmittance = v.number("termination_transmittance", 1e-3, 0.0, 0.5);
        scene.emptySpaceSkipping = v.boolean("empty_space_skipping", true);
        scene.shadingRoulette = v.number("shading_roulette", 0.03, 0.0, 0.5);
        scene.volumePreIntegrated = v.boolean("pre_integrated", false);
        v.finish();
    }
    if (r.has("clip")) scene.clip = readClip(r, "clip");
    if (r.has("shadows")) {  // "exact" or {"mode": "cached", "cache_voxels": 2}
        if (r.raw("shadows").is_string()) {
            scene.shadows = r.string("shadows", "off", {"off", "exact", "cached"});
        } else {
            Reader sh = r.child("shadows");
            scene.shadows = sh.string("mode", "exact", {"off", "exact", "cached"});
            scene.shadowCacheVoxels = sh.number("cache_voxels", 4.0, 0.25, 64.0);
            scene.shadowCacheStepVoxels = sh.number("cache_step_voxels", 0.5, 1e-3, 16.0);
            scene.shadowCacheSurfaces =
                sh.string("surfaces", "cached", {"cached", "exact"}) == "cached";
            sh.finish();
        }
    }
    if (!r.has("objects")) r.fail("objects", "missing (an array of objects)");
    const Json& objects = r.raw("objects");
    if (!objects.is_array()) r.fail("objects", "expected an array");
    if (objects.size() > kMaxObjects)
        r.fail("objects", std::to_string(objects.size()) + " objects; a scene holds at most " +
                              std::to_string(kMaxObjects));
    const SourceContext context{baseDir, arrays};
    for (size_t i = 0; i < objects.size(); ++i) {
        const Reader o(objects[i], "objects[" + std::to_string(i) + "]", name);
        if (objects[i].contains("kind") && objects[i]["kind"] == "segmentation")
            readSegmentation(o, context, scene.objects);
        else
            scene.objects.push_back(readObject(o, context));
    }
    if (scene.objects.size() > kMaxObjects)
        r.fail("objects", "the segmentations expand to " + std::to_string(scene.objects.size()) +
                              " objects; a scene holds at most " + std::to_string(kMaxObjects));
    {  // A label is one object's: two objects claiming it would draw one region twice.
        std::map<std::pair<std::string, int>, size_t> claimed;
        for (size_t i = 0; i < scene.objects.size(); ++i)
            for (int id : scene.objects[i].source.labels) {
                const VolumeSourceSpec& source = scene.objects[i].source;
                const auto key =
                    std::make_pair(source.array ? source.array->name : source.path, id);
                const auto [it, fresh] = claimed.emplace(key, i);
                if (!fresh)
                    r.fail("objects", "'" + scene.objects[it->second].name + "' and '" +
                                          scene.objects[i].name + "' both claim label " +
                                          std::to_string(id) + " of " + key.first +
                                          " (a label belongs to one object)");
            }
    }
    std::vector<std::string> named = scene.fit.objects;
    named.insert(named.end(), scene.zoom.objects.begin(), scene.zoom.objects.end());
    for (const std::string& wanted : named) {
        std::string names;
        bool found = false;
        for (const ObjectSpec& o : scene.objects) {
            found = found || o.name == wanted;
            names += (names.empty() ? "" : ", ") + o.name;
        }
        if (!found)
            r.fail(std::find(scene.fit.objects.begin(), scene.fit.objects.end(), wanted) !=
                           scene.fit.objects.end()
                       ? "camera.fit.objects"
                       : "camera.zoom.objects",
                   "no object is named '" + wanted + "' (objects: " + names + ")");
    }
    r.finish();
    return scene;
}

SceneSpec loadSceneFile(const std::string& path) {
    // A volume given where a scene is expected: say what is wanted instead of a JSON error.
    std::string lower = path;
    for (char& c : lower) c = char(std::tolower(static_cast<unsigned char>(c)));
    for (const char* ext : {".nii", ".nii.gz", ".nhdr", ".nrrd", ".vdb", ".raw", ".raw.gz", ".dcm"})
        if (lower.size() >= std::strlen(ext) &&
            lower.compare(lower.size() - std::strlen(ext), std::string::npos, ext) == 0)
            throw Error("'" + path +
                        "' is a volume, not a scene file: a scene (JSON) names its "
                        "volumes, camera and lights (docs/scene-format.md; "
                        "assets/scenes/paper/rendering-01.json is an example); `lobe info` "
                        "describes a volume");
    {
        std::error_code ec;
        if (fs::is_directory(path, ec)) throw Error("'" + path + "' is a folder, not a scene file");
        const std::string why = unreachable(path);
        if (!why.empty()) throw Error("scene file '" + path + "'" + why);
    }
    {  // A DICOM file by its magic ('DICM' at byte 128, PS3.10 7.1), whatever its name.
        std::ifstream probe(path, std::ios::binary);
        char magic[4] = {};
        if (probe && probe.seekg(128) && probe.read(magic, 4) && std::memcmp(magic, "DICM", 4) == 0)
            throw Error("'" + path +
                        "' is a DICOM file, not a scene file: a scene (JSON) names "
                        "its volumes in objects[].source.path (a DICOM folder or files there; "
                        "docs/scene-format.md); `lobe info` describes a DICOM series");
    }
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error("cannot open scene file '" + path + "'");
    std::stringstream ss;
    ss << in.rdbuf();
    return parseScene(ss.str(), fs::path(path).parent_path().string(), path);
}

}  // namespace lobe
