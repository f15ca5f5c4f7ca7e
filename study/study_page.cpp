#include "study/study_page.h"

#include "analysis/study.h"
#include "batch/batch.h"
#include "core/error.h"
#include "core/image_output.h"
#include "core/interrupt.h"
#include "core/output_folder.h"
#include "core/rng.h"
#include "core/temporary_file.h"
#include "render/scene_file.h"

#include <nlohmann/json.hpp>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>

namespace lobe {

extern const char kStudyPageHtml[];  // generated from study/study_page.html (apps/CMakeLists.txt)

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr const char* kMarker = "/*LOBE_STUDY_JSON*/null";

// The study's fingerprint: its JSON text hashed with core/rng.h's SplitMix64 finaliser, 8 bytes
// at a time, in hex. Answers files carry it, so `lobe study analyse` joins answers of one study.
std::string fingerprint(const std::string& text) {
    uint64_t h = 0x6c6f62652d737475ull;
    for (size_t i = 0; i < text.size(); i += 8) {
        uint64_t word = 0;
        for (size_t k = 0; k < 8 && i + k < text.size(); ++k)
            word |= uint64_t(static_cast<unsigned char>(text[i + k])) << (8 * k);
        h = mixBits(h ^ word);
    }
    char buf[17];
    std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
    return buf;
}

// Object o's specular luminance from the EXR's per-object passes (render/aov.h: for each object
// <name>.lambert.R/G/B then <name>.specular.R/G/B, in the scene's object order, linear sRGB);
// Y = 0.2126 R + 0.7152 G + 0.0722 B (ITU-R BT.709, whose primaries sRGB shares).
std::vector<std::vector<float>> specularLuminance(const std::string& exr, size_t objects) {
    const FloatImage image = readFloatImage(exr);
    const auto& names = image.channels.names;
    const size_t k = names.size(), pixels = size_t(image.width) * size_t(image.height);
    std::vector<size_t> red;
    for (size_t c = 0; c + 2 < k; ++c) {
        const std::string& n = names[c];
        if (n.size() > 11 && n.compare(n.size() - 11, 11, ".specular.R") == 0) red.push_back(c);
    }
    if (red.size() != objects)
        throw Error(exr + ": " + std::to_string(red.size()) + " specular passes for " +
                    std::to_string(objects) + " objects");
    std::vector<std::vector<float>> layers;
    for (size_t c : red) {
        std::vector<float> y(pixels);
        for (size_t p = 0; p < pixels; ++p) {
            const float* v = &image.channels.data[p * k + c];
            y[p] = 0.2126f * v[0] + 0.7152f * v[1] + 0.0722f * v[2];
        }
        layers.push_back(std::move(y));
    }
    return layers;
}

std::string instructions(const std::string& task) {
    const std::string pair =
        "You will see two renderings of the same data side by side; they differ only in how each "
        "structure reflects light. For each pair, click \u201cLeft\u201d or \u201cRight\u201d (or "
        "press the arrow keys) for the image that answers the question above the images.";
    const std::string marker =
        "Some trials show one rendering with a green ring, the marker. Click the name of the "
        "structure whose highlight (the shiny spot) is inside the ring.";
    if (task == "pair") return pair;
    if (task == "which-object") return marker;
    return pair + " " + marker;
}

}  // namespace

const char* studyPageTemplate() { return kStudyPageHtml; }

std::string studyPage(const std::string& studyJson) {
    std::string page = kStudyPageHtml;
    const size_t at = page.find(kMarker);
    if (at == std::string::npos)
        throw Error("internal: the study page template has no study marker");
    std::string safe;
    for (size_t i = 0; i < studyJson.size(); ++i) {
        if (studyJson[i] == '<' && i + 1 < studyJson.size() && studyJson[i + 1] == '/') {
            safe += "<\\/";
            ++i;
        } else {
            safe += studyJson[i];
        }
    }
    return page.replace(at, std::string(kMarker).size(), safe);
}

void buildStudy(const StudyRequest& r) {
    const bool pairs = r.task == "pair" || r.task == "both";
    const bool markers = r.task == "which-object" || r.task == "both";
    if (!pairs && !markers)
        throw Error("--task: expected pair, which-object or both, got '" + r.task + "'");
    if (pairs && r.scenes.size() < 2)
        throw Error("a pair study needs at least two scene files (one per condition), got " +
                    std::to_string(r.scenes.size()));
    if (r.repeats < 1) throw Error("--repeats must be at least 1");
    if (r.checks < 0) throw Error("--checks must be at least 0");
    r.overrides.validate();
    // Conditions: one per scene file, named by the file (the names the answers carry).
    std::vector<SceneSpec> specs;
    std::map<std::string, std::string> nameOf;
    for (const std::string& scene : r.scenes) {
        if (fs::is_directory(scene))
            throw Error("'" + scene + "' is a folder: give the study's scene files one by one");
        if (!fs::exists(scene)) throw Error("scene file '" + scene + "' does not exist");
        SceneSpec spec = loadSceneFile(scene);
        r.overrides.apply(spec);
        const std::string name = fs::path(scene).stem().string();
        if (nameOf.count(name))
            throw Error("scenes '" + nameOf[name] + "' and '" + scene + "' are both called '" +
                        name + "': a study's conditions need distinct file names");
        nameOf[name] = scene;
        specs.push_back(std::move(spec));
    }
    for (const SceneSpec& s : specs)
        if (s.width != specs.front().width || s.height != specs.front().height)
            throw Error(s.path + ": " + std::to_string(s.width) + "x" + std::to_string(s.height) +
                        " pixels, but " + specs.front().path + " is " +
                        std::to_string(specs.front().width) + "x" +
                        std::to_string(specs.front().height) +
                        ": every stimulus of a study has the same size (give --width)");
    const fs::path out(r.outDir);
    for (const char* file : {"index.html", "study.json"})
        if (fs::exists(out / file))
            throw Error("--out '" + r.outDir + "' already holds a study (" + file +
                        "): give a new folder");
    if (fs::exists(out / "stimuli"))
        throw Error("--out '" + r.outDir + "' already has a stimuli folder: give a new folder");
    // Everything written from here is this run's (the checks above found none of it): a failure
    // removes it again, so no half-made study is left.
    const bool newFolder = !fs::exists(out);
    createOutputFolder(r.outDir);
    size_t conditionCount = 0, trialCount = 0;
    try {
        RenderBatchRequest batch;
        batch.scenes = r.scenes;
        batch.outDir = (out / "stimuli").string();
        batch.overrides = r.overrides;
        batch.orbit = r.orbit;
        batch.quiet = r.quiet;
        if (markers) batch.aov = "objects";  // each object's specular pass, for the marker
        const std::vector<RenderedImage> images = renderBatch(batch);

        json conditions = json::array();
        json trials = json::array();
        Rng rng(mixBits(r.seed), 0x57d1);
        const auto draw = [&](size_t n) {
            return std::min(n - 1, size_t(rng.uniform() * double(n)));
        };
        std::vector<std::vector<std::string>> objectNames;
        for (size_t c = 0; c < specs.size(); ++c) {
            json frames = json::array();
            std::string first;
            for (const RenderedImage& image : images)
                if (fs::path(image.scene) == fs::path(specs[c].path)) {
                    frames.push_back("stimuli/" + fs::path(image.base).filename().string() +
                                     ".png");
                    if (first.empty()) first = image.base;
                }
            if (frames.empty()) throw Error(specs[c].path + ": no image was rendered");
            std::vector<std::string> names;
            for (const ObjectSpec& o : specs[c].objects) names.push_back(o.name);
            objectNames.push_back(names);
            conditions.push_back({{"name", fs::path(specs[c].path).stem().string()},
                                  {"title", specs[c].title},
                                  {"frames", frames},
                                  {"objects", names}});
            if (!markers) continue;
            // The marker task on the (first) frame: one trial per object whose highlight dominates
            // somewhere (analysis/study.h, highlightMarker).
            const auto layers = specularLuminance(first + ".exr", names.size());
            int placed = 0;
            for (size_t o = 0; o < names.size(); ++o) {
                const MarkerSpot spot =
                    highlightMarker(layers, specs[c].width, specs[c].height, int(o));
                if (!spot.found) {
                    if (!r.quiet)
                        std::fprintf(stderr,
                                     "lobe: note: %s: the highlight of '%s' dominates nowhere: "
                                     "no marker trial for it\n",
                                     specs[c].path.c_str(), names[o].c_str());
                    continue;
                }
                ++placed;
                trials.push_back({{"kind", "marker"},
                                  {"condition", c},
                                  {"object", names[o]},
                                  {"x", (spot.x + 0.5) / specs[c].width},
                                  {"y", (spot.y + 0.5) / specs[c].height},
                                  {"options", names}});
            }
            if (placed == 0)
                throw Error(specs[c].path +
                            ": no object's highlight dominates anywhere in the image, "
                            "so the marker task has no trial for it");
        }
        if (pairs)
            for (int k = 0; k < r.repeats; ++k)
                for (size_t i = 0; i < specs.size(); ++i)
                    for (size_t j = i + 1; j < specs.size(); ++j)
                        trials.push_back({{"kind", "pair"}, {"a", i}, {"b", j}});
        // Attention checks (instructed-response items: the prompt names the answer to give;
        // D. M. Oppenheimer, T. Meyvis & N. Davidenko, "Instructional manipulation checks", J. Exp.
        // Social Psychology 45(4), 2009): in a pair study over two random conditions, naming a
        // side; in a marker study over a random condition, naming one of its objects.
        for (int k = 0; k < r.checks; ++k) {
            if (pairs) {
                const size_t a = draw(specs.size());
                size_t b = draw(specs.size() - 1);
                if (b >= a) ++b;
                trials.push_back({{"kind", "attention"},
                                  {"a", a},
                                  {"b", b},
                                  {"instructed", rng.uniform() < 0.5 ? "left" : "right"}});
            }
            if (markers) {
                const size_t c = draw(specs.size());
                const std::vector<std::string>& names = objectNames[c];
                trials.push_back({{"kind", "attention"},
                                  {"condition", c},
                                  {"instructed", names[draw(names.size())]},
                                  {"options", names}});
            }
        }
        json study;
        study["format"] = "lobe-study-1";
        study["task"] = r.task;
        study["seed"] = uint32_t(r.seed & 0xffffffffu);
        study["width"] = specs.front().width;
        study["height"] = specs.front().height;
        study["orbit"] = r.orbit;
        study["question"] = r.question;
        study["markerQuestion"] = "Which structure does the highlight at the marker belong to?";
        study["instructions"] = instructions(r.task);
        study["conditions"] = conditions;
        study["trials"] = trials;
        study["study"] = fingerprint(study.dump());
        // The EXRs served the marker only; the folder keeps the page, the PNGs and study.json.
        for (const RenderedImage& image : images) {
            std::error_code ec;
            fs::remove(image.base + ".exr", ec);
        }
        const std::string text = study.dump(1);
        writeTextFileAtomic((out / "study.json").string(), text);
        writeTextFileAtomic((out / "index.html").string(), studyPage(study.dump()));
        conditionCount = specs.size();
        trialCount = trials.size();
    } catch (...) {
        std::error_code ec;
        fs::remove_all(out / "stimuli", ec);
        fs::remove(out / "study.json", ec);
        if (newFolder) fs::remove(out, ec);  // only when empty
        throw;
    }
    if (!r.quiet)
        std::fprintf(stderr, "study: %zu conditions, %zu trials -> %s\n", conditionCount,
                     trialCount, (out / "index.html").c_str());
}

}  // namespace lobe
