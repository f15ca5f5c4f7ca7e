#include "render/scene_labels.h"

#include "core/error.h"
#include "core/spectrum.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <set>

namespace lobe {

namespace {

using Json = nlohmann::json;

std::string joinInts(const std::vector<int>& v) {
    std::string s;
    for (int x : v) s += (s.empty() ? "" : ", ") + std::to_string(x);
    return s;
}

// A scene table's colour: "#rrggbb" or [r, g, b] in [0, 1], sRGB-encoded → bytes.
std::array<int, 3> sceneColour(const Json& c, const std::string& where) {
    std::array<int, 3> rgb{};
    if (c.is_string()) {
        const std::string t = c.get<std::string>();
        bool hex = t.size() == 7 && t[0] == '#';
        for (size_t i = 1; hex && i < 7; ++i) hex = std::isxdigit(static_cast<unsigned char>(t[i]));
        if (!hex)
            throw Error(where + ": expected \"#rrggbb\" or [r, g, b] in [0, 1], got " + c.dump());
        for (int k = 0; k < 3; ++k)
            rgb[size_t(k)] = std::stoi(t.substr(1 + 2 * size_t(k), 2), nullptr, 16);
        return rgb;
    }
    if (!c.is_array() || c.size() != 3)
        throw Error(where + ": expected \"#rrggbb\" or [r, g, b] in [0, 1], got " + c.dump());
    for (int k = 0; k < 3; ++k) {
        if (!c[size_t(k)].is_number() ||
            !(c[size_t(k)].get<double>() >= 0.0 && c[size_t(k)].get<double>() <= 1.0))
            throw Error(where + ": expected \"#rrggbb\" or [r, g, b] in [0, 1], got " + c.dump());
        rgb[size_t(k)] = int(std::lround(c[size_t(k)].get<double>() * 255.0));
    }
    return rgb;
}

LabelTable sceneTable(const Json& t) {
    LabelTable table;
    table.format = "scene";
    table.source = "the scene's label_table";
    for (auto it = t.begin(); it != t.end(); ++it) {
        const std::string where = "label_table." + it.key();
        char* end = nullptr;
        const long id = std::strtol(it.key().c_str(), &end, 10);
        if (it.key().empty() || *end != '\0' || id < 0 || id > 2147483647L)
            throw Error(where + ": the keys are label numbers (\"37\"), got '" + it.key() + "'");
        LabelEntry e;
        e.id = int(id);
        if (it.value().is_string()) {
            e.name = it.value().get<std::string>();
        } else if (it.value().is_object()) {
            for (auto f = it.value().begin(); f != it.value().end(); ++f)
                if (f.key() != "name" && f.key() != "color")
                    throw Error(where + "." + f.key() + ": unknown key (name or color)");
            if (!it.value().contains("name") || !it.value()["name"].is_string())
                throw Error(where + ".name: missing (a string)");
            e.name = it.value()["name"].get<std::string>();
            if (it.value().contains("color")) {
                e.rgb = sceneColour(it.value()["color"], where + ".color");
                e.hasColour = true;
            }
        } else {
            throw Error(where + ": expected a name or {\"name\": ..., \"color\": ...}, got " +
                        it.value().dump());
        }
        if (e.name.empty()) throw Error(where + ": the name is empty");
        table.entries.emplace(e.id, e);
    }
    if (table.entries.empty()) throw Error("label_table: an empty table");
    return table;
}

}  // namespace

LabelSource openLabelSource(const std::string& mapPath, const Json* tableValue,
                            const std::string& baseDir) {
    return openLabelSource(loadLabelMap(mapPath), mapPath, tableValue, baseDir);
}

LabelSource openLabelSource(std::shared_ptr<const LabelMap> map, const std::string& mapPath,
                            const Json* tableValue, const std::string& baseDir) {
    LabelSource s;
    s.map = std::move(map);
    if (tableValue) {
        if (tableValue->is_string()) {
            const std::filesystem::path p(tableValue->get<std::string>());
            const std::string path =
                p.is_absolute() ? p.string()
                                : (std::filesystem::path(baseDir) / p).lexically_normal().string();
            s.table = readLabelTable(path);
        } else if (tableValue->is_object()) {
            s.table = sceneTable(*tableValue);
        } else {
            throw Error(
                "label_table: expected a table file or an object {\"37\": \"name\", …}, got " +
                tableValue->dump());
        }
    } else if (!mapPath.empty()) {
        s.table = tableBeside(mapPath);
    }
    if (!s.table.empty()) {
        // A table of another atlas names the wrong structures: every label of the map must be in
        // it.
        std::vector<int> missing;
        for (const auto& [id, info] : s.map->labels)
            if (!s.table.find(id)) missing.push_back(id);
        if (!missing.empty()) {
            const size_t n = missing.size();
            if (n > 8) missing.resize(8);
            throw Error("the label table " + s.table.source + " does not match the map " +
                        s.map->path + ": " + std::to_string(n) + " of the map's " +
                        std::to_string(s.map->labels.size()) + " labels are not in it (" +
                        joinInts(missing) + (n > 8 ? ", …" : "") + "); the table lists " +
                        std::to_string(s.table.entries.size()) + " labels from " +
                        std::to_string(s.table.entries.begin()->first) + " to " +
                        std::to_string(s.table.entries.rbegin()->first));
        }
    }
    return s;
}

std::vector<int> labelIdsOf(const Json& value, const LabelSource& s, bool allowAll) {
    const std::string mapPath = s.map->path;
    if (value.is_string() && value.get<std::string>() == "all") {
        if (!allowAll)
            throw Error(
                "\"all\" is for \"kind\": \"segmentation\" (one object per label); an "
                "object's own labels are a list");
        std::vector<int> ids;
        for (const auto& [id, info] : s.map->labels) ids.push_back(id);
        if (ids.empty()) throw Error(mapPath + " holds no label (every voxel is 0)");
        return ids;
    }
    std::vector<Json> items;
    if (value.is_array()) {
        if (value.empty()) throw Error("an empty list (expected label numbers or names)");
        for (const Json& v : value) items.push_back(v);
    } else {
        items.push_back(value);
    }
    std::vector<int> ids;
    for (const Json& v : items) {
        int id;
        if (v.is_number_integer()) {
            const long long x = v.get<long long>();
            if (x < -2147483647LL || x > 2147483647LL || x == 0)
                throw Error("label " + v.dump() + " is not a label (0 is the background)");
            id = int(x);
        } else if (v.is_string()) {
            const std::string name = v.get<std::string>();
            if (s.table.empty())
                throw Error("'" + name + "' is a name, but " + mapPath +
                            " has no label table: "
                            "give source.label_table (FreeSurfer, ITK-SNAP or MRIcron table, or "
                            "{\"37\": \"name\"}) or use label numbers");
            id = s.table.idOf(name);
            if (id < 0) {
                std::string near;
                for (const std::string& n : s.table.nearestNames(name))
                    near += (near.empty() ? "" : ", ") + n;
                throw Error("'" + name + "' is in no label table (" + s.table.source +
                            "; nearest names: " + near + ")");
            }
        } else {
            throw Error("expected label numbers or names" +
                        std::string(allowAll ? " or \"all\"" : "") + ", got " + v.dump());
        }
        if (!s.map->find(id)) {
            std::string near;
            for (int n : s.map->nearestPresent(id)) {
                near += (near.empty() ? "" : ", ") + std::to_string(n);
                if (const LabelEntry* e = s.table.find(n)) near += " " + e->name;
            }
            throw Error("label " + std::to_string(id) +
                        (v.is_string() ? " ('" + v.get<std::string>() + "')" : std::string()) +
                        " is not in " + mapPath + " (no voxel holds it; nearest labels present: " +
                        (near.empty() ? "none" : near) + ")");
        }
        if (std::find(ids.begin(), ids.end(), id) != ids.end())
            throw Error("label " + std::to_string(id) + " is given twice");
        ids.push_back(id);
    }
    return ids;
}

std::string labelName(const LabelSource& s, int id) {
    if (const LabelEntry* e = s.table.find(id)) return e->name;
    return "label " + std::to_string(id);
}

Spectrum labelColour(const LabelSource& s, int id, const Spectrum& fallback) {
    const LabelEntry* e = s.table.find(id);
    if (!e || !e->hasColour) return fallback;
    return linearSrgbToBands(srgbDecode(e->rgb[0] / 255.0), srgbDecode(e->rgb[1] / 255.0),
                             srgbDecode(e->rgb[2] / 255.0));
}

}  // namespace lobe
