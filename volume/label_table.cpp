// Reading label tables (label_table.h): FreeSurfer colour tables, ITK-SNAP label descriptions,
// MRIcron's .txt + .lut pair.
#include "volume/label_table.h"

#include "core/error.h"
#include "core/nearest_name.h"
#include "volume/volume_file.h"

#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

namespace lobe {

namespace {

std::string lowerCase(std::string s) {
    for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

bool fileExists(const std::string& path) {
    struct stat st;
    return ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

// A whole number token (optionally signed), in int range.
bool wholeNumber(const std::string& t, long& out) {
    if (t.empty()) return false;
    char* end = nullptr;
    errno = 0;
    out = std::strtol(t.c_str(), &end, 10);
    return end && *end == '\0' && errno == 0 && out >= -2147483647L && out <= 2147483647L;
}

bool realNumber(const std::string& t, double& out) {
    if (t.empty()) return false;
    char* end = nullptr;
    out = std::strtod(t.c_str(), &end);
    return end && *end == '\0';
}

// Splits on white space; a double-quoted token (ITK-SNAP's label) is one token without quotes.
// `quoted` tells whether the last token was quoted.
std::vector<std::string> tokens(const std::string& line, bool& quoted, bool& unterminated) {
    std::vector<std::string> out;
    quoted = unterminated = false;
    size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
        if (i >= line.size()) break;
        if (line[i] == '"') {
            const size_t close = line.find('"', i + 1);
            if (close == std::string::npos) {
                unterminated = true;
                out.push_back(line.substr(i + 1));
                break;
            }
            out.push_back(line.substr(i + 1, close - i - 1));
            quoted = true;
            i = close + 1;
        } else {
            const size_t b = i;
            while (i < line.size() && !std::isspace(static_cast<unsigned char>(line[i]))) ++i;
            out.push_back(line.substr(b, i - b));
            quoted = false;
        }
    }
    return out;
}

void addEntry(LabelTable& table, LabelEntry e, const std::string& where) {
    if (table.entries.count(e.id))
        throw Error(where + ": label " + std::to_string(e.id) + " is listed twice");
    table.entries.emplace(e.id, std::move(e));
}

int colourByte(const std::string& t, const std::string& where, const char* what) {
    long v;
    if (!wholeNumber(t, v) || v < 0 || v > 255)
        throw Error(where + ": the " + what + " component '" + t + "' is not a whole number 0–255");
    return int(v);
}

}  // namespace

const LabelEntry* LabelTable::find(int id) const {
    const auto it = entries.find(id);
    return it == entries.end() ? nullptr : &it->second;
}

int LabelTable::idOf(const std::string& name) const {
    for (const auto& [id, e] : entries)
        if (e.name == name) return id;
    const std::string low = lowerCase(name);
    for (const auto& [id, e] : entries)
        if (lowerCase(e.name) == low) return id;
    return -1;
}

std::vector<std::string> LabelTable::nearestNames(const std::string& name) const {
    std::vector<std::pair<int, std::string>> scored;
    for (const auto& [id, e] : entries)
        scored.emplace_back(editDistance(lowerCase(name), lowerCase(e.name)), e.name);
    std::stable_sort(scored.begin(), scored.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<std::string> out;
    for (size_t i = 0; i < scored.size() && i < 3; ++i) out.push_back(scored[i].second);
    return out;
}

LabelTable readMricronTable(const std::string& txtPath, const std::string& lutPath) {
    LabelTable table;
    table.format = "mricron";
    if (!txtPath.empty()) {
        std::ifstream in(txtPath);
        if (!in)
            throw Error(txtPath + ": cannot open the label table (" + std::strerror(errno) + ")");
        std::string line;
        int lineNo = 0;
        while (std::getline(in, line)) {
            ++lineNo;
            bool quoted, open;
            const std::vector<std::string> t = tokens(line, quoted, open);
            if (t.empty() || t[0][0] == '#') continue;
            const std::string where = txtPath + ", line " + std::to_string(lineNo);
            long id, code;
            if (t.size() < 2 || t.size() > 3 || !wholeNumber(t[0], id) || id < 0 ||
                (t.size() == 3 && !wholeNumber(t[2], code)))
                throw Error(where +
                            ": expected 'index name' or 'index name code' (MRIcron's "
                            "atlas table), got '" +
                            line + "'");
            LabelEntry e;
            e.id = int(id);
            e.name = t[1];
            addEntry(table, e, where);
        }
        table.source = txtPath;
    }
    if (!lutPath.empty()) {
        const std::vector<unsigned char> bytes = detail::readFileBytes(lutPath, false);
        if (bytes.size() != 768)
            throw Error(lutPath +
                        ": an MRIcron colour table (.lut) holds 768 bytes (256 red, 256 "
                        "green, 256 blue values), this file holds " +
                        std::to_string(bytes.size()));
        // Indices the .txt names get their colour; without a .txt every index 1–255 is a label.
        for (int i = 1; i < 256; ++i) {
            if (!txtPath.empty() && !table.entries.count(i)) continue;
            LabelEntry& e = table.entries[i];
            if (e.name.empty()) {
                e.id = i;
                e.name = "label " + std::to_string(i);
            }
            e.hasColour = true;
            e.rgb = {bytes[size_t(i)], bytes[size_t(256 + i)], bytes[size_t(512 + i)]};
        }
        table.source += (table.source.empty() ? "" : " + ") + lutPath;
    }
    return table;
}

LabelTable readLabelTable(const std::string& path) {
    if (detail::endsWith(path, ".lut")) {
        const std::string stem = path.substr(0, path.size() - 4);
        return readMricronTable(fileExists(stem + ".txt") ? stem + ".txt" : "", path);
    }
    std::ifstream in(path);
    if (!in) throw Error(path + ": cannot open the label table (" + std::strerror(errno) + ")");
    LabelTable table;
    table.source = path;
    std::string line;
    int lineNo = 0;
    while (std::getline(in, line)) {
        ++lineNo;
        if (line.find('\0') != std::string::npos)
            throw Error(path +
                        ": not a text label table (it holds binary data; an MRIcron colour "
                        "table must be named .lut)");
        bool quoted, open;
        const std::vector<std::string> t = tokens(line, quoted, open);
        if (t.empty() || t[0][0] == '#') continue;
        const std::string where = path + ", line " + std::to_string(lineNo);
        if (open) throw Error(where + ": a label in double quotes is not closed");
        if (table.format.empty()) {
            // The first data line decides the format.
            if (quoted && t.size() == 8)
                table.format = "itksnap";
            else if (t.size() == 6)
                table.format = "freesurfer";
            else if (t.size() == 2 || t.size() == 3)
                table.format = "mricron";
            else
                throw Error(where +
                            ": not a label table line: expected 'index name R G B A' "
                            "(FreeSurfer), 'IDX R G B A VIS MSH \"LABEL\"' (ITK-SNAP) or "
                            "'index name [code]' (MRIcron), got '" +
                            line + "'");
        }
        long id;
        if (!wholeNumber(t[0], id) || id < 0)
            throw Error(where + ": the label index '" + t[0] + "' is not a whole number >= 0");
        LabelEntry e;
        e.id = int(id);
        if (table.format == "itksnap") {
            double a;
            if (t.size() != 8 || !quoted)
                throw Error(where + ": expected 'IDX R G B A VIS MSH \"LABEL\"' (ITK-SNAP), got '" +
                            line + "'");
            e.rgb = {colourByte(t[1], where, "red"), colourByte(t[2], where, "green"),
                     colourByte(t[3], where, "blue")};
            if (!realNumber(t[4], a) || !(a >= 0.0 && a <= 1.0))
                throw Error(where + ": the opacity '" + t[4] + "' is not a number 0–1");
            e.opacity = a;
            e.hasColour = true;
            e.name = t[7];
        } else if (table.format == "freesurfer") {
            if (t.size() != 6)
                throw Error(where +
                            ": expected 'index name R G B A' (FreeSurfer colour table), "
                            "got '" +
                            line + "'");
            e.name = t[1];
            e.rgb = {colourByte(t[2], where, "red"), colourByte(t[3], where, "green"),
                     colourByte(t[4], where, "blue")};
            colourByte(t[5], where, "fourth (A)");
            e.hasColour = true;
        } else {
            long code;
            if (t.size() < 2 || t.size() > 3 || (t.size() == 3 && !wholeNumber(t[2], code)))
                throw Error(where +
                            ": expected 'index name' or 'index name code' (MRIcron's "
                            "atlas table), got '" +
                            line + "'");
            e.name = t[1];
        }
        addEntry(table, e, where);
    }
    if (table.entries.empty()) throw Error(path + ": the label table lists no label");
    if (table.format == "mricron") {  // its colours, when the .lut sits beside it
        const std::string stem =
            detail::endsWith(path, ".txt") ? path.substr(0, path.size() - 4) : "";
        if (!stem.empty() && fileExists(stem + ".lut")) {
            LabelTable colours = readMricronTable("", stem + ".lut");
            for (auto& [id, e] : table.entries)
                if (const LabelEntry* c = colours.find(id)) {
                    e.hasColour = true;
                    e.rgb = c->rgb;
                }
            table.source += " + " + stem + ".lut";
        }
    }
    return table;
}

LabelTable tableBeside(const std::string& mapPath) {
    const std::string stem =
        detail::endsWith(mapPath, ".gz") ? mapPath.substr(0, mapPath.size() - 3) : mapPath;
    const bool txt = fileExists(stem + ".txt"), lut = fileExists(stem + ".lut");
    if (!txt && !lut) return LabelTable();
    return readMricronTable(txt ? stem + ".txt" : "", lut ? stem + ".lut" : "");
}

}  // namespace lobe
