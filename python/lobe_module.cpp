// The Python module `lobe` (docs/python.md): scenes from dicts or files, with volumes from NumPy
// arrays or nibabel images in memory; renders returned as NumPy arrays; the separation score, the
// BRDF assignment and the reflection models. It only converts between Python and the libraries'
// API (render/, analysis/, materials/, volume/): the same scene parser and validation as scene
// files, the same render as `lobe render` (the beauty holds the floats its EXR holds).
//
// Rendering runs on a thread of its own with the GIL released, while the calling thread waits:
// every 50 ms it takes the GIL, runs Python's signal handlers (PyErr_CheckSignals: Ctrl-C raises
// KeyboardInterrupt there) and the progress callback. An interrupt or an exception of the
// callback stops the render at the next tile (the tile source hands out no more), and the render
// returns nothing.
#include "analysis/assign.h"
#include "analysis/scene_passes.h"
#include "analysis/separation.h"
#include "core/error.h"
#include "core/image_output.h"
#include "core/math.h"
#include "core/tile_scheduler.h"
#include "materials/registry.h"
#include "render/aov.h"
#include "render/background.h"
#include "render/framing.h"
#include "render/render_scene.h"
#include "render/scene.h"
#include "render/scene_file.h"
#include "render/scene_overrides.h"
#include "volume/volume_array.h"

#include <nlohmann/json.hpp>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <sstream>
#include <thread>

namespace py = pybind11;
namespace fs = std::filesystem;
using Json = nlohmann::json;

namespace lobe {
namespace {

// ---- Python values → scene JSON ---------------------------------------------------------------

[[noreturn]] void fail(const std::string& name, const std::string& at, const std::string& what) {
    throw Error(name + ": " + (at.empty() ? "top level" : at) + ": " + what);
}

std::string typeName(const py::handle& h) {
    return py::str(py::type::handle_of(h).attr("__name__"));
}

bool isNibabelImage(const py::handle& h) {
    return py::hasattr(h, "dataobj") && py::hasattr(h, "affine") && py::hasattr(h, "header");
}

// The in-memory arrays of one scene: their descriptions for the parser and the Python objects
// whose memory they point into, held as long as the scene.
struct MemorySources {
    SceneArrays arrays;
    std::vector<py::object> keepAlive;
    // What each array came from in the dict, to give it back in Scene.to_dict().
    std::map<std::string, py::dict> given;
};

std::atomic<int> arrayCounter{0};

// NumPy dtype → the voxel type read as it is; other numeric types are converted by NumPy first
// (int64/uint64 and bool to float64 — exact up to 2^53 — and float16 to float32).
py::array voxelArray(py::object value, const std::string& name, const std::string& at,
                     VoxelType& type) {
    py::module_ np = py::module_::import("numpy");
    py::array a = np.attr("asanyarray")(value);
    py::dtype dt = a.dtype();
    const char kind = dt.kind();
    const py::ssize_t size = dt.itemsize();
    if (kind == 'b') {
        a = a.attr("astype")("float64");
    } else if (kind == 'f' && size == 2) {
        a = a.attr("astype")("float32");
    } else if ((kind == 'i' || kind == 'u') && size == 8) {
        a = a.attr("astype")("float64");
    } else if (!(kind == 'i' || kind == 'u' || kind == 'f') || (kind == 'f' && size > 8)) {
        fail(name, at, "expected an array of numbers, got dtype " + std::string(py::str(dt)));
    }
    // The machine's byte order (an array read from a big-endian file may keep the file's).
    if (!py::bool_(a.dtype().attr("isnative")))
        a = a.attr("astype")(a.dtype().attr("newbyteorder")("="));
    dt = a.dtype();
    const char k = dt.kind();
    const py::ssize_t s = dt.itemsize();
    if (k == 'f')
        type = s == 4 ? VoxelType::kFloat32 : VoxelType::kFloat64;
    else if (k == 'u')
        type = s == 1 ? VoxelType::kUint8 : s == 2 ? VoxelType::kUint16 : VoxelType::kUint32;
    else
        type = s == 1 ? VoxelType::kInt8 : s == 2 ? VoxelType::kInt16 : VoxelType::kInt32;
    // (i, j, k) as nibabel gives them; trailing axes of length 1 (a 4-D image of one volume)
    // dropped.
    std::vector<py::ssize_t> shape(a.shape(), a.shape() + a.ndim());
    while (shape.size() > 3 && shape.back() == 1) shape.pop_back();
    if (shape.size() != 3) {
        std::string text;
        for (py::ssize_t d = 0; d < a.ndim(); ++d)
            text += (d ? ", " : "") + std::to_string(a.shape(d));
        fail(name, at, "expected a 3-D array (i, j, k), got shape (" + text + ")");
    }
    return a;
}

// A 4 × 4 affine (or its top 3 × 4) into the array's index → world rows.
void readAffine(py::object value, const std::string& name, const std::string& at,
                VolumeArray& out) {
    py::module_ np = py::module_::import("numpy");
    py::array_t<double, py::array::c_style | py::array::forcecast> m;
    try {
        m = np.attr("asarray")(value, "float64");
    } catch (const py::error_already_set&) {
        fail(name, at, "expected a 4 x 4 matrix of numbers, got a " + typeName(value));
    }
    if (!(m.ndim() == 2 && m.shape(1) == 4 && (m.shape(0) == 4 || m.shape(0) == 3)))
        fail(name, at, "expected a 4 x 4 matrix (a NIfTI affine)");
    auto r = m.unchecked<2>();
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 4; ++j) {
            out.affine[size_t(i)][size_t(j)] = r(i, j);
            if (!std::isfinite(r(i, j))) fail(name, at, "holds a non-finite number");
        }
    if (m.shape(0) == 4 && !(r(3, 0) == 0 && r(3, 1) == 0 && r(3, 2) == 0 && r(3, 3) == 1))
        fail(name, at, "the last row must be 0, 0, 0, 1 (an affine map)");
}

Json toJson(py::handle value, const std::string& name, const std::string& at,
            MemorySources& memory);

// A source in memory — {"array": ndarray, "affine": 4 × 4, …}, {"image": nibabel image, …} or a
// nibabel image itself — as {"array": NAME, …} for the parser, the array described in `memory`.
Json memorySource(py::handle source, const std::string& name, const std::string& at,
                  MemorySources& memory) {
    py::dict given;
    if (isNibabelImage(source))
        given["image"] = source;
    else
        given = py::reinterpret_borrow<py::dict>(source);
    auto array = std::make_shared<VolumeArray>();
    array->name = "array " + std::to_string(++arrayCounter) + " (" + at + ")";
    py::object data;
    if (given.contains("image")) {
        if (given.contains("array") || given.contains("affine"))
            fail(name, at, "give either \"image\" (a nibabel image) or \"array\" with \"affine\"");
        py::object image = given["image"];
        if (!isNibabelImage(image))
            fail(name, at + ".image",
                 "expected a nibabel image (with dataobj and affine), got a " + typeName(image));
        py::object proxy = image.attr("dataobj");
        // The stored values and the file's scaling, applied as Lobe's NIfTI reader applies them
        // (raw · slope + inter in double): a file's proxy, or an image made from an array.
        if (py::hasattr(proxy, "get_unscaled") && py::hasattr(proxy, "slope")) {
            data = proxy.attr("get_unscaled")();
            array->slope = py::float_(proxy.attr("slope"));
            array->inter = py::float_(proxy.attr("inter"));
        } else {
            data = proxy;
        }
        readAffine(image.attr("affine"), name, at + ".image", *array);
    } else {
        data = given["array"];
        if (given.contains("affine")) readAffine(given["affine"], name, at + ".affine", *array);
    }
    const std::string arrayAt = at + (given.contains("image") ? ".image" : ".array");
    py::array a = voxelArray(data, name, arrayAt, array->type);
    for (int d = 0; d < 3; ++d) {
        if (a.shape(d) < 1 || a.shape(d) > (1 << 20))
            fail(name, arrayAt, "each dimension must be between 1 and 1048576");
        array->dims[size_t(d)] = int(a.shape(d));
        array->strides[size_t(d)] = a.strides(d);
    }
    array->data = a.data();
    memory.keepAlive.push_back(a);
    memory.arrays[array->name] = array;
    memory.given[array->name] = given;
    Json out = Json::object();
    for (auto item : given) {
        const std::string key = py::str(item.first);
        if (key == "array" || key == "affine" || key == "image") continue;
        out[key] = toJson(item.second, name, at + "." + key, memory);
    }
    out["array"] = array->name;
    return out;
}

Json toJson(py::handle value, const std::string& name, const std::string& at,
            MemorySources& memory) {
    if (value.is_none()) return nullptr;
    if (py::isinstance<py::bool_>(value)) return value.cast<bool>();
    if (py::isinstance<py::int_>(value)) return value.cast<long long>();
    if (py::isinstance<py::float_>(value)) return value.cast<double>();
    if (py::isinstance<py::str>(value)) return value.cast<std::string>();
    // A source of an object: a nibabel image or a dict with an array in memory.
    const bool isSource = at.size() > 7 && at.compare(at.size() - 7, 7, ".source") == 0 &&
                          at.rfind("objects[", 0) == 0 && at.find('.') == at.size() - 7;
    if (isSource && (isNibabelImage(value) || (py::isinstance<py::dict>(value) &&
                                               (value.cast<py::dict>().contains("array") ||
                                                value.cast<py::dict>().contains("image")))))
        return memorySource(value, name, at, memory);
    if (py::isinstance<py::dict>(value)) {
        Json out = Json::object();
        for (auto item : value.cast<py::dict>()) {
            // Whole numbers as keys are their decimal text, as JSON writes them: a label table
            // {37: "Hippocampus_L"} or overrides by label number.
            // (NumPy integers too: labels from np.unique).
            const bool number = !py::isinstance<py::str>(item.first) &&
                                PyIndex_Check(item.first.ptr()) &&
                                !py::isinstance<py::bool_>(item.first);
            if (!py::isinstance<py::str>(item.first) && !number)
                fail(name, at,
                     "keys must be strings or whole numbers, got a " + typeName(item.first));
            const std::string key =
                number
                    ? std::string(py::str(py::int_(py::reinterpret_borrow<py::object>(item.first))))
                    : item.first.cast<std::string>();
            out[key] = toJson(item.second, name, at.empty() ? key : at + "." + key, memory);
        }
        return out;
    }
    if (py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value)) {
        Json out = Json::array();
        size_t i = 0;
        for (py::handle item : value)
            out.push_back(toJson(item, name, at + "[" + std::to_string(i++) + "]", memory));
        return out;
    }
    // NumPy scalars and small arrays (a position given as np.array([x, y, z])).
    py::module_ np = py::module_::import("numpy");
    if (py::isinstance(value, np.attr("ndarray")) || py::isinstance(value, np.attr("generic"))) {
        py::object plain = value.attr("tolist")();
        if (!plain.is(value) && !py::isinstance(plain, np.attr("generic")))
            return toJson(plain, name, at, memory);
    }
    fail(name, at,
         "cannot be given as a " + typeName(value) +
             " (expected a number, string, bool, list or dict)");
}

// Scene JSON → Python (the inverse of toJson; arrays given back as they came).
py::object fromJson(const Json& j, const MemorySources& memory) {
    switch (j.type()) {
        case Json::value_t::null:
            return py::none();
        case Json::value_t::boolean:
            return py::bool_(j.get<bool>());
        case Json::value_t::number_integer:
            return py::int_(j.get<long long>());
        case Json::value_t::number_unsigned:
            return py::int_(j.get<unsigned long long>());
        case Json::value_t::number_float:
            return py::float_(j.get<double>());
        case Json::value_t::string:
            return py::str(j.get<std::string>());
        case Json::value_t::array: {
            py::list out;
            for (const Json& item : j) out.append(fromJson(item, memory));
            return std::move(out);
        }
        case Json::value_t::object: {
            py::dict out;
            const bool inMemory = j.contains("array") && j["array"].is_string() &&
                                  memory.given.count(j["array"].get<std::string>());
            if (inMemory)
                for (auto item : memory.given.at(j["array"].get<std::string>()))
                    out[item.first] = item.second;
            for (auto it = j.begin(); it != j.end(); ++it)
                if (!(inMemory && it.key() == "array"))
                    out[py::str(it.key())] = fromJson(*it, memory);
            return std::move(out);
        }
        default:
            return py::none();
    }
}

// ---- Scenes -------------------------------------------------------------------------------------

struct PyScene {
    std::string name;  // the file, or the name given to a dict scene (messages)
    Json json;         // the scene as given, in-memory sources by name
    std::shared_ptr<MemorySources> memory;
    SceneSpec spec;
    std::shared_ptr<VolumeCache> cache;  // each source loaded once, for every render

    // Loads every source and checks what the command line checks before it renders: fitted
    // views and percentile transfer functions. With the GIL released (the caller holds none).
    void load() {
        cache = std::make_shared<VolumeCache>();
        const std::vector<std::string> errors = cache->preload({&spec});
        if (!errors.front().empty()) throw Error(errors.front());
        std::string error = computedViewError(spec, *cache);
        if (error.empty()) error = transferError(spec, *cache);
        if (!error.empty()) throw Error(error);
    }
};

std::shared_ptr<PyScene> sceneFromDict(py::dict scene, const std::string& name,
                                       const std::string& baseDir) {
    auto s = std::make_shared<PyScene>();
    s->name = name;
    s->memory = std::make_shared<MemorySources>();
    s->json = toJson(scene, name, "", *s->memory);
    const std::string dir = baseDir.empty() ? fs::current_path().string() : baseDir;
    s->spec = parseScene(s->json.dump(), dir, name, &s->memory->arrays);
    py::gil_scoped_release release;
    s->load();
    return s;
}

std::shared_ptr<PyScene> sceneFromFile(const std::string& path) {
    auto s = std::make_shared<PyScene>();
    s->name = path;
    s->memory = std::make_shared<MemorySources>();
    s->spec = loadSceneFile(path);  // every check of `lobe render`
    std::ifstream in(path, std::ios::binary);
    s->json = Json::parse(in);
    py::gil_scoped_release release;
    s->load();
    return s;
}

// The scene as a dict, every file path absolute (so the dict means the same from any folder).
py::dict sceneDict(const PyScene& s) {
    Json j = s.json;
    if (j.contains("objects") && j["objects"].is_array())
        for (size_t i = 0; i < j["objects"].size() && i < s.spec.objects.size(); ++i) {
            const VolumeSourceSpec& source = s.spec.objects[i].source;
            Json& src = j["objects"][i]["source"];
            if (source.array || !src.is_object()) continue;
            if (source.morePaths.empty()) {
                src["path"] = fs::absolute(source.path).lexically_normal().string();
            } else {
                Json list = Json::array({fs::absolute(source.path).lexically_normal().string()});
                for (const std::string& p : source.morePaths)
                    list.push_back(fs::absolute(p).lexically_normal().string());
                src["path"] = list;
            }
        }
    return fromJson(j, *s.memory);
}

// ---- Rendering ----------------------------------------------------------------------------------

// The tiles of one image in the order the pixel loop uses (LocalTileSource), counting the pixels
// done and handing out no more once stopped.
class WatchedTiles : public TileSource {
public:
    void begin(const std::vector<Tile>& tiles, ProgressReporter& progress) override {
        tiles_ = &tiles;
        local_.begin(tiles, progress);
    }
    int next(int slot, int finished) override {
        if (finished >= 0) done += tilePixels((*tiles_)[size_t(finished)]);
        if (stop) return -1;
        return local_.next(slot, finished);
    }
    void end() override {}

    std::atomic<int64_t> done{0};
    std::atomic<bool> stop{false};

private:
    const std::vector<Tile>* tiles_ = nullptr;
    LocalTileSource local_;
};

// Runs `work` (a render) on its own thread with the GIL released; the calling thread runs the
// signal handlers and the progress callback every 50 ms. Raises what they raise (the render
// stopped first), or what `work` threw.
void runInterruptible(const std::function<void()>& work, WatchedTiles& tiles, int64_t total,
                      const py::object& progress) {
    std::mutex mutex;
    std::condition_variable changed;
    bool finished = false;
    std::exception_ptr failure;
    std::optional<py::error_already_set> raised;
    {
        py::gil_scoped_release release;
        std::thread worker([&] {
            try {
                work();
            } catch (...) {
                failure = std::current_exception();
            }
            std::lock_guard<std::mutex> lock(mutex);
            finished = true;
            changed.notify_all();
        });
        std::unique_lock<std::mutex> lock(mutex);
        int64_t reported = -1;
        while (!finished) {
            changed.wait_for(lock, std::chrono::milliseconds(50));
            if (finished || raised) continue;
            lock.unlock();
            {
                py::gil_scoped_acquire acquire;
                try {
                    if (PyErr_CheckSignals() != 0) throw py::error_already_set();
                    const int64_t done = tiles.done;
                    if (!progress.is_none() && done != reported) {
                        reported = done;
                        progress(done, total);
                    }
                } catch (py::error_already_set& e) {
                    raised.emplace(std::move(e));
                    tiles.stop = true;
                }
            }
            lock.lock();
        }
        lock.unlock();
        worker.join();
    }
    if (raised) throw std::move(*raised);
    if (failure) std::rethrow_exception(failure);
    if (!progress.is_none()) progress(int64_t(tiles.done), total);
}

// aov=: a name or a list of names.
std::vector<std::string> aovNames(const py::object& aov) {
    if (aov.is_none()) return {};
    if (py::isinstance<py::str>(aov)) return {aov.cast<std::string>()};
    return aov.cast<std::vector<std::string>>();
}

AovRequest parseAovs(const std::vector<std::string>& items, bool& alpha) {
    AovRequest request;
    alpha = false;
    std::string list;
    for (const std::string& item : items) {
        if (item == "alpha") {
            alpha = true;
            continue;
        }
        list += (list.empty() ? "" : ",") + item;
    }
    if (!list.empty()) {
        try {
            request = AovRequest::parse(list);
        } catch (const Error&) {
            throw Error(
                "aov: expected a list of: all, objects, backdrop, depth, normal, id, "
                "alpha; got '" +
                list + "'");
        }
    }
    return request;
}

struct RenderArgs {
    RenderOverrides overrides;
    int threads = 0;
};

SceneSpec renderSpec(const PyScene& scene, const RenderArgs& args) {
    args.overrides.validate();
    if (args.threads < 0 || args.threads > 1024) throw Error("threads must be in [0, 1024]");
    SceneSpec spec = scene.spec;
    args.overrides.apply(spec);
    return spec;
}

// Renders `spec` with `request`'s passes as `lobe render` does before it writes (the background
// composited); the film and the passes in `film` and `aovs`.
void renderFilm(const PyScene& scene, const SceneSpec& spec, const AovRequest& request,
                const RenderArgs& args, const py::object& progress, Film& film, AovImage& aovs) {
    WatchedTiles tiles;
    RenderOptions options;
    options.threads = args.threads;
    options.progress = false;
    options.tileSource = &tiles;
    runInterruptible(
        [&] {
            const RenderScene assembled(spec, false, scene.cache.get());
            film = assembled.render(options, nullptr, &request, &aovs);
        },
        tiles, int64_t(spec.width) * spec.height, progress);
}

py::array_t<float> imageArray(int height, int width, int depth) {
    std::vector<py::ssize_t> shape{py::ssize_t(height), py::ssize_t(width)};
    if (depth > 1) shape.push_back(py::ssize_t(depth));
    return py::array_t<float>(shape);
}

py::dict render(const PyScene& scene, const RenderArgs& args, const std::vector<std::string>& aov,
                const py::object& progress) {
    const SceneSpec spec = renderSpec(scene, args);
    bool wantAlpha = false;
    const AovRequest asked = parseAovs(aov, wantAlpha);
    AovRequest request = asked;
    request.alpha = wantAlpha || spec.background.needsAlpha();
    Film film(1, 1);
    AovImage aovs;
    renderFilm(scene, spec, request, args, progress, film, aovs);
    // The floats `lobe render` writes to the EXR (figure/figure_output.cpp, FigureWriter::write).
    std::vector<std::string> names;
    for (const ObjectSpec& o : spec.objects) names.push_back(o.name);
    ImageChannels extra;
    if (asked.any()) appendAovChannels(asked, aovs, names, spec.exposure, extra);
    compositeBackground(film, aovs.alpha, spec.background, spec.exposure);
    const std::vector<float> data = filmChannels(film, spec.exposure, extra);
    const size_t stride = 6 + extra.names.size();
    const size_t pixels = size_t(spec.width) * spec.height;

    py::dict out;
    auto layer = [&](const std::string& key, size_t first, int depth) {
        py::array_t<float> a = imageArray(spec.height, spec.width, depth);
        float* dst = a.mutable_data();
        for (size_t p = 0; p < pixels; ++p)
            for (int c = 0; c < depth; ++c)
                dst[p * size_t(depth) + size_t(c)] = data[p * stride + first + size_t(c)];
        out[py::str(key)] = a;
    };
    layer("beauty", 0, 3);
    if (wantAlpha || spec.background.mode == Background::Mode::None) {
        py::array_t<float> a = imageArray(spec.height, spec.width, 1);
        std::memcpy(a.mutable_data(), aovs.alpha.data(), pixels * sizeof(float));
        out["alpha"] = a;
    }
    // The passes by layer: "<object>.lambert", "<object>.specular", "backdrop" (× 3), "depth",
    // "normal" (× 3), "id" — the EXR's channels <layer>.R/G/B, depth.Z, N.X/Y/Z, object.id. The
    // object layers come first, two per object in scene order, keyed by the object's own name
    // (the EXR's channel-safe name where a name repeats).
    size_t objectLayer = 0;
    for (size_t c = 0; c < extra.names.size();) {
        const std::string& n = extra.names[c];
        const std::string prefix = n.substr(0, n.rfind('.'));
        size_t depth = 1;
        while (c + depth < extra.names.size() &&
               extra.names[c + depth].substr(0, extra.names[c + depth].rfind('.')) == prefix)
            ++depth;
        std::string key = prefix == "N" ? "normal" : prefix == "object" ? "id" : prefix;
        if (asked.objects && objectLayer < 2 * names.size()) {
            const std::string own =
                names[objectLayer / 2] + (objectLayer % 2 == 0 ? ".lambert" : ".specular");
            if (!out.contains(own)) key = own;
            ++objectLayer;
        }
        layer(key, 6 + c, int(depth));
        c += depth;
    }
    return out;
}

py::dict separation(const PyScene& scene, const RenderArgs& args, double contrast,
                    const py::object& progress) {
    if (!(contrast > 0.0 && contrast < 1.0))
        throw Error("contrast must be in (0, 1), got " + std::to_string(contrast));
    const SceneSpec spec = renderSpec(scene, args);
    if (spec.objects.size() < 2)
        throw Error(spec.path + ": the separation score needs at least two objects");
    AovRequest request;
    request.objects = request.backdrop = true;
    Film film(1, 1);
    AovImage aovs;
    renderFilm(scene, spec, request, args, progress, film, aovs);
    const SeparationLayers layers = separationLayers(spec, aovs);
    const SeparationReport report = measureSeparation(layers, contrast);
    py::dict out;
    out["score"] = report.score;
    out["threshold"] = report.threshold;
    py::list objects;
    for (const ObjectVisibility& v : report.objects) {
        py::dict o;
        o["name"] = v.name;
        o["visible_share"] = v.visibleShare;
        o["specular_share"] = v.specularShare;
        o["mean_specular_contrast"] = v.meanSpecularContrast;
        o["visibility"] = v.visibility;
        o["veiling"] = v.veiling;
        o["identity"] = v.identity;
        o["chroma"] = v.chroma;
        o["quality"] = v.quality;
        objects.append(o);
    }
    out["objects"] = objects;
    py::list pairs;
    for (const PairSeparation& p : report.pairs) {
        py::dict d;
        d["a"] = layers.objects[size_t(p.a)];
        d["b"] = layers.objects[size_t(p.b)];
        d["highlight"] = p.metric.eSum;
        d["score"] = p.score;
        d["area_a"] = p.metric.areaA;
        d["area_b"] = p.metric.areaB;
        pairs.append(d);
    }
    out["pairs"] = pairs;
    out["highlight"] = report.highlight;
    return out;
}

// A candidate as the scene's "brdf" value: {"model": …, parameter: value or [3 bands]}.
py::dict candidateBrdf(const BrdfCandidate& c) {
    py::dict brdf;
    brdf["model"] = c.model;
    if (c.brdf) return brdf;  // an object kept as it is: its own brdf (to_dict has it)
    for (const std::string& kv : c.settings) {
        const auto eq = kv.find('=');
        const Spectrum v = parseBandValue(kv.substr(eq + 1), kv);
        if (v[0] == v[1] && v[1] == v[2])
            brdf[py::str(kv.substr(0, eq))] = v[0];
        else
            brdf[py::str(kv.substr(0, eq))] = py::make_tuple(v[0], v[1], v[2]);
    }
    return brdf;
}

py::dict assign(const PyScene& scene, RenderArgs args, const std::vector<std::string>& keep,
                const std::vector<std::string>& exclude, bool tune, int top,
                const py::object& progress) {
    if (top < 1 || top > 1000) throw Error("top must be in [1, 1000]");
    // Reduced size by default, as `lobe assign`: the layers only show where highlights lie.
    if (args.overrides.width <= 0 && args.overrides.height <= 0) args.overrides.width = 256;
    if (args.overrides.spp <= 0) args.overrides.spp = 2;
    const SceneSpec spec = renderSpec(scene, args);
    std::vector<BrdfCandidate> candidates;
    for (const BrdfCandidate& c : brdfCandidates(tune))
        if (std::find(exclude.begin(), exclude.end(), c.model) == exclude.end())
            candidates.push_back(c);
    for (const std::string& m : exclude) findBrdfModel(m);
    std::vector<bool> allowed(candidates.size(), true);
    std::vector<int> fixed(spec.objects.size(), -1);
    for (const std::string& name : keep) {
        bool found = false;
        for (size_t i = 0; i < spec.objects.size(); ++i)
            if (spec.objects[i].name == name) {
                found = true;
                fixed[i] = int(candidates.size());
                candidates.push_back({spec.objects[i].brdfModel,
                                      {},
                                      spec.objects[i].material.specular,
                                      "(" + name + " as in the scene)"});
                allowed.push_back(false);
            }
        if (!found) throw Error("keep: the scene has no object '" + name + "'");
    }
    if (std::count(allowed.begin(), allowed.end(), true) == 0)
        throw Error("exclude leaves no BRDF to choose from");
    AovRequest request;
    request.objects = request.backdrop = true;
    requestCandidateLayers(candidates, request);
    Film film(1, 1);
    AovImage aovs;
    renderFilm(scene, spec, request, args, progress, film, aovs);
    const AssignmentLayers layers = assignmentLayers(spec, aovs, candidates);
    // The same layers at the next seed, as `lobe assign`: glints are what changes between the two.
    SceneSpec nextSeed = spec;
    nextSeed.seed = spec.seed + 1;
    AovImage aovsNextSeed;
    renderFilm(scene, nextSeed, request, args, progress, film, aovsNextSeed);
    const AssignmentLayers layersNextSeed = assignmentLayers(nextSeed, aovsNextSeed, candidates);
    AssignOptions search;
    search.fixed = fixed;
    search.allowed = allowed;
    search.top = top;
    // No sparkle and no glints, as `lobe assign` (analysis/assign.h excludeSparkle).
    std::vector<bool> reference(candidates.size());
    for (size_t c = 0; c < candidates.size(); ++c)
        reference[c] = candidates[c].settings.empty() && !candidates[c].brdf;
    const std::vector<std::string> notOffered =
        excludeSparkle(layers, reference, search, &layersNextSeed);
    std::vector<int> current(spec.objects.size(), -1);
    for (size_t i = 0; i < spec.objects.size(); ++i) {
        if (fixed[i] >= 0)
            current[i] = fixed[i];
        else
            for (size_t c = 0; c < candidates.size(); ++c)
                if (candidates[c].model == spec.objects[i].brdfModel &&
                    candidates[c].settings.empty() && !candidates[c].brdf)
                    current[i] = int(c);
    }
    const bool hasCurrent = std::find(current.begin(), current.end(), -1) == current.end();
    if (hasCurrent) search.start = current;
    AssignResult result;
    {
        py::gil_scoped_release release;
        result = searchAssignments(layers, search);
    }
    py::dict out;
    py::list ranked;
    for (const ScoredAssignment& a : result.ranked) {
        py::dict row, brdfs;
        row["score"] = a.score;
        for (size_t i = 0; i < spec.objects.size(); ++i)
            brdfs[py::str(spec.objects[i].name)] = candidates[size_t(a.assignment[i])].label();
        row["brdfs"] = brdfs;
        ranked.append(row);
    }
    out["ranked"] = ranked;
    py::dict best;
    for (size_t i = 0; i < spec.objects.size(); ++i)
        if (fixed[i] < 0)
            best[py::str(spec.objects[i].name)] =
                candidateBrdf(candidates[size_t(result.ranked.front().assignment[i])]);
    out["best"] = best;
    out["current_score"] =
        hasCurrent ? py::object(py::float_(assignmentScore(layers, current))) : py::none();
    out["exhaustive"] = result.exhaustive;
    out["not_offered"] = notOffered;  // "object: candidate (…% in specks, …% glints …)"
    out["evaluated"] = result.evaluated;
    out["space"] = result.space;
    return out;
}

// ---- BRDFs --------------------------------------------------------------------------------------

Brdf brdfFrom(const std::string& model, const py::dict& params) {
    const BrdfModelInfo& info = findBrdfModel(model);
    ParamValues values(*info.params);
    for (auto item : params) {
        const std::string key = py::str(item.first);
        Spectrum v;
        py::object value = py::reinterpret_borrow<py::object>(item.second);
        if (py::isinstance<py::float_>(value) || py::isinstance<py::int_>(value) ||
            py::isinstance(value, py::module_::import("numpy").attr("number"))) {
            v = Spectrum(py::float_(value));
        } else {
            const std::vector<double> bands = value.cast<std::vector<double>>();
            if (bands.size() != 3)
                throw Error(model + ": " + key + ": expected a number or three band values");
            v = Spectrum(bands[0], bands[1], bands[2]);
        }
        setBrdfParam(info, values, key, v, model);
    }
    return info.create(values);
}

py::array_t<double> brdfEval(const std::string& model, const py::object& params, py::object wi,
                             py::object wo) {
    const Brdf brdf = brdfFrom(model, params.is_none() ? py::dict() : py::dict(params));
    py::module_ np = py::module_::import("numpy");
    py::tuple both = np.attr("broadcast_arrays")(np.attr("asarray")(wi, "float64"),
                                                 np.attr("asarray")(wo, "float64"));
    using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;
    const Array a = Array::ensure(both[0]), b = Array::ensure(both[1]);
    if (a.ndim() < 1 || a.shape(a.ndim() - 1) != 3)
        throw Error("brdf.eval: wi and wo must be directions (..., 3)");
    std::vector<py::ssize_t> shape(a.shape(), a.shape() + a.ndim());
    Array out(shape);
    const size_t n = size_t(a.size()) / 3;
    const double* pa = a.data();
    const double* pb = b.data();
    double* po = out.mutable_data();
    long bad = -1;
    {
        py::gil_scoped_release release;
        for (size_t i = 0; i < n && bad < 0; ++i) {
            Vec3 u, v;
            // Directions normalised as `lobe brdf eval` normalises its input lines.
            if (!unitDirection(pa[3 * i], pa[3 * i + 1], pa[3 * i + 2], u) ||
                !unitDirection(pb[3 * i], pb[3 * i + 1], pb[3 * i + 2], v) || !isFinite(u) ||
                !isFinite(v)) {
                bad = long(i);
                break;
            }
            const Spectrum f = evalBrdf(brdf, u, v);
            for (int c = 0; c < 3; ++c) po[3 * i + size_t(c)] = f[c];
        }
    }
    if (bad >= 0)
        throw Error("brdf.eval: direction pair " + std::to_string(bad) +
                    " (flat index) is the zero vector or not finite");
    return out;
}

py::list brdfModelList() {
    py::list out;
    for (const BrdfModelInfo& m : brdfModels()) {
        py::dict d;
        d["name"] = m.name;
        d["title"] = m.title;
        d["citation"] = m.citation;
        d["reciprocal"] = m.flags.reciprocal;
        py::list params;
        for (const ParamSpec& p : *m.params) {
            py::dict q;
            q["name"] = p.name;
            q["default"] = p.defaultValue;
            q["min"] = p.minValue;
            q["max"] = p.maxValue;
            q["integer"] = p.integer;
            q["doc"] = p.doc;
            params.append(q);
        }
        d["params"] = params;
        out.append(d);
    }
    return out;
}

RenderArgs renderArgs(std::optional<int> width, std::optional<int> height, std::optional<int> spp,
                      std::optional<long long> seed, std::optional<double> step, int threads) {
    RenderArgs a;
    if (width) {
        if (*width < 1) throw Error("width must be in [1, 16384]");
        a.overrides.width = *width;
    }
    if (height) {
        if (*height < 1) throw Error("height must be in [1, 16384]");
        a.overrides.height = *height;
    }
    if (spp) {
        if (*spp < 1) throw Error("spp must be in [1, 4096]");
        a.overrides.spp = *spp;
    }
    if (seed) {
        if (*seed < 0) throw Error("seed must be in [0, 2147483647]");
        a.overrides.seed = *seed;
    }
    if (step) {
        if (!(*step >= 0.001)) throw Error("step must be in [0.001, 16] voxels");
        a.overrides.step = *step;
    }
    a.threads = threads;
    return a;
}

}  // namespace
}  // namespace lobe

PYBIND11_MODULE(lobe, m) {
    using namespace lobe;
    m.doc() = "Lobe: render medical volumes with a BRDF per object (docs/python.md)";
    m.attr("__version__") = LOBE_VERSION;
    py::register_exception<Error>(m, "Error", PyExc_ValueError);

    py::class_<PyScene, std::shared_ptr<PyScene>>(m, "Scene", R"doc(
A scene: the JSON of a scene file (docs/scene-format.md) as a dict, or read from a file.
A source may be {"array": ndarray, "affine": 4x4, ...} or {"image": nibabel image, ...} (or the
nibabel image itself) instead of {"path": ...}. Every source is loaded when the scene is made;
errors raise lobe.Error naming the key path (objects[2].brdf.alpha_x).)doc")
        .def(py::init([](py::dict scene, const std::string& name, const std::string& baseDir) {
                 return sceneFromDict(scene, name, baseDir);
             }),
             py::arg("scene"), py::kw_only(), py::arg("name") = "scene", py::arg("base_dir") = "",
             "A scene from a dict; relative paths resolve against base_dir (default: the current "
             "folder); name is used in error messages.")
        .def_static("from_file", &sceneFromFile, py::arg("path"),
                    "A scene from a scene file (JSON).")
        .def("to_dict", &sceneDict,
             "The scene as a dict (file paths absolute, in-memory sources as given): edit it and "
             "make a new Scene.")
        .def_property_readonly("name", [](const PyScene& s) { return s.name; })
        .def_property_readonly("width", [](const PyScene& s) { return s.spec.width; })
        .def_property_readonly("height", [](const PyScene& s) { return s.spec.height; })
        .def_property_readonly("spp", [](const PyScene& s) { return s.spec.samplesPerPixel; })
        .def_property_readonly("seed", [](const PyScene& s) { return s.spec.seed; })
        .def_property_readonly(
            "objects",
            [](const PyScene& s) {
                std::vector<std::string> names;
                for (const ObjectSpec& o : s.spec.objects) names.push_back(o.name);
                return names;
            },
            "The objects' names, in scene order.")
        .def(
            "render",
            [](const PyScene& s, std::optional<int> width, std::optional<int> height,
               std::optional<int> spp, std::optional<long long> seed, std::optional<double> step,
               const py::object& aov, int threads, const py::object& progress) {
                return render(s, renderArgs(width, height, spp, seed, step, threads), aovNames(aov),
                              progress);
            },
            py::kw_only(), py::arg("width") = py::none(), py::arg("height") = py::none(),
            py::arg("spp") = py::none(), py::arg("seed") = py::none(), py::arg("step") = py::none(),
            py::arg("aov") = py::none(), py::arg("threads") = 0, py::arg("progress") = py::none(),
            R"doc(
Render the scene; returns a dict of float32 NumPy arrays: "beauty" (H x W x 3, linear sRGB x
exposure: the R, G, B `lobe render` writes to its EXR), "alpha" (H x W) when aov holds "alpha" or
the background is none, and the passes aov asks for ("all", "objects", "backdrop", "depth",
"normal", "id"): "<object>.lambert", "<object>.specular", "backdrop" (H x W x 3), "depth",
"id" (H x W), "normal" (H x W x 3), objects by their names in the scene. width alone keeps the
aspect; unset values are the scene's.
progress(done_pixels, total_pixels) is called about every 50 ms. Ctrl-C stops the render
(KeyboardInterrupt) and returns nothing.)doc")
        .def(
            "separation",
            [](const PyScene& s, std::optional<int> width, std::optional<int> height,
               std::optional<int> spp, std::optional<long long> seed, std::optional<double> step,
               double contrast, int threads, const py::object& progress) {
                return separation(s, renderArgs(width, height, spp, seed, step, threads), contrast,
                                  progress);
            },
            py::kw_only(), py::arg("width") = py::none(), py::arg("height") = py::none(),
            py::arg("spp") = py::none(), py::arg("seed") = py::none(), py::arg("step") = py::none(),
            py::arg("contrast") = kWeberContrast, py::arg("threads") = 0,
            py::arg("progress") = py::none(),
            "The separation score of the rendered scene (`lobe separation`, docs/separation.md): "
            "a dict with score, threshold, objects (visible and highlight shares) and pairs.");

    m.def(
        "assign",
        [](const PyScene& s, const std::vector<std::string>& keep,
           const std::vector<std::string>& exclude, bool tune, int top, std::optional<int> width,
           std::optional<int> height, std::optional<int> spp, std::optional<long long> seed,
           std::optional<double> step, int threads, const py::object& progress) {
            return assign(s, renderArgs(width, height, spp, seed, step, threads), keep, exclude,
                          tune, top, progress);
        },
        py::arg("scene"), py::kw_only(), py::arg("keep") = std::vector<std::string>{},
        py::arg("exclude") = std::vector<std::string>{}, py::arg("tune") = false,
        py::arg("top") = 10, py::arg("width") = py::none(), py::arg("height") = py::none(),
        py::arg("spp") = py::none(), py::arg("seed") = py::none(), py::arg("step") = py::none(),
        py::arg("threads") = 0, py::arg("progress") = py::none(),
        R"doc(
Choose each object's BRDF to maximise the separation score (`lobe assign`): two renders (256
wide, 2 spp unless given; seeds s and s + 1, the second to find glints) with every candidate's
layers, then every assignment scored. Returns
a dict: ranked (best first: score and each object's BRDF label), best (object name -> "brdf"
dict for the scene, kept objects left out), current_score (the scene's own assignment, or None),
exhaustive, evaluated, space.)doc");

    py::module_ brdf = m.def_submodule("brdf", "The reflection models (docs/models.md)");
    brdf.def("models", &brdfModelList,
             "Every model: name, title, citation, reciprocal, params (name, default, min, max, "
             "integer, doc).");
    brdf.def("eval", &brdfEval, py::arg("model"), py::arg("params"), py::arg("wi"), py::arg("wo"),
             "f_s(wi, wo) per band (700, 546.1, 435.8 nm) without the cosine, for directions in "
             "the local frame (x tangent, y bitangent, z normal; normalised here) as arrays "
             "(..., 3) broadcast against each other: what `lobe brdf eval` prints. params: "
             "{name: value or [3 bands]} over the defaults.");
    py::module_::import("sys").attr("modules")["lobe.brdf"] = brdf;
}
