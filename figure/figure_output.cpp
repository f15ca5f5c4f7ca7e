#include "figure/figure_output.h"

#include "core/error.h"
#include "core/image_output.h"
#include "core/utf8.h"
#include "figure/contact_sheet.h"
#include "render/gallery.h"
#include "render/render_scene.h"
#include "volume/transfer_function.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#ifndef LOBE_VERSION
#define LOBE_VERSION "unknown"
#endif

namespace lobe {
namespace {

namespace fs = std::filesystem;

bool isExr(const std::string& path) { return lowerExtension(path) == ".exr"; }

std::string fileText(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

std::string shellQuoted(const std::string& arg) {
    if (!arg.empty() && arg.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                              "0123456789_-+=/.,:%@") == std::string::npos)
        return arg;
    std::string out = "'";
    for (char c : arg) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return out + "'";
}

}  // namespace

void FigureOptions::validate(size_t sceneCount, bool sharded) const {
    if (pngBits != 8 && pngBits != 16) throw Error("--png-bits must be 8 or 16");
    if (!background.empty()) parseBackground(background, "--background");
    if (withExr && output.empty())
        throw Error("--exr goes with -o FILE (without -o both are written)");
    if (bandRows < 0) throw Error("--band-rows must be >= 0");
    if (bandRows > 0 && sharded)
        throw Error("--band-rows: not with --shard (a part is a band of rows already)");
    if (output.empty()) return;
    if (sceneCount != 1)
        throw Error("-o " + output + ": names one image, but " + std::to_string(sceneCount) +
                    " scenes were given (use --out DIR for a batch)");
    if (sharded)
        throw Error("-o " + output + ": not with --shard (parts are joined by `lobe merge`)");
    if (!isSupportedImageExtension(output))
        throw Error("-o " + output + ": unsupported image extension '" + lowerExtension(output) +
                    "' (use .png, .jpg, .tif or .exr)");
    if (withExr && isExr(output)) throw Error("-o " + output + ": is an EXR already; drop --exr");
    if (pngBits == 16 && !(lowerExtension(output) == ".png" || lowerExtension(output) == ".tif" ||
                           lowerExtension(output) == ".tiff"))
        throw Error("-o " + output + ": --png-bits 16 needs a .png or .tif file");
    const fs::path parent = fs::path(output).parent_path();
    if (!parent.empty() && !fs::is_directory(parent))
        throw Error("-o " + output + ": folder '" + parent.string() + "' does not exist");
    if (fs::is_directory(output)) throw Error("-o " + output + ": is a folder (use --out DIR)");
}

void FigureOptions::apply(SceneSpec& spec) const {
    if (!background.empty()) spec.background = parseBackground(background, "--background");
    const std::string ext = lowerExtension(output);
    if (spec.background.mode == Background::Mode::None && (ext == ".jpg" || ext == ".jpeg"))
        throw Error(spec.path + ": background none needs an alpha channel, which JPEG (-o " +
                    output + ") has not: write .png, .tif or .exr, or give a background colour");
}

std::vector<std::string> FigureOptions::outputPaths(const std::string& base) const {
    if (output.empty()) return {base + ".png", base + ".exr"};
    std::vector<std::string> paths{output};
    if (withExr) paths.push_back((fs::path(output).replace_extension(".exr")).string());
    return paths;
}

std::string commandLine() {
    std::ifstream in("/proc/self/cmdline", std::ios::binary);
    std::string all((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::string out;
    size_t start = 0;
    while (start < all.size()) {
        size_t end = all.find('\0', start);
        if (end == std::string::npos) end = all.size();
        out += (out.empty() ? "" : " ") + shellQuoted(all.substr(start, end - start));
        start = end + 1;
    }
    return out;
}

ImageAttributes provenance(const SceneSpec& spec) {
    char settings[512];
    std::snprintf(settings, sizeof settings,
                  "%dx%d spp %d seed %llu step_voxels %.17g%s roulette %.17g exposure %.17g "
                  "tone %s background %s",
                  spec.width, spec.height, spec.samplesPerPixel, (unsigned long long)spec.seed,
                  spec.volumeStepVoxels, spec.volumePreIntegrated ? " pre_integrated" : "",
                  spec.shadingRoulette, spec.exposure, spec.tone.c_str(),
                  spec.background.text.c_str());
    return toolProvenance({{"lobe:scene_file", spec.path},
                           {"lobe:scene_json", fileText(spec.path)},
                           {"lobe:seed", std::to_string(spec.seed)},
                           {"lobe:render_settings", settings}});
}

ImageAttributes toolProvenance(const ImageAttributes& more) {
    ImageAttributes out = {{"Software", std::string("Lobe ") + LOBE_VERSION},
                           {"lobe:version", LOBE_VERSION},
                           {"lobe:command_line", asciiEscaped(commandLine())}};
    for (const auto& [key, value] : more) out[key] = asciiEscaped(value);
    return out;
}

ImageAttributes galleryProvenance(const GalleryOptions& options) {
    char settings[256];
    std::snprintf(settings, sizeof settings, "cell %d spp %d seed %llu light %.17g",
                  options.cellSize, options.samplesPerPixel, (unsigned long long)options.seed,
                  options.lightIntensity);
    std::string text = settings;
    for (const std::string& set : options.settings) text += " set " + set;
    return toolProvenance(
        {{"lobe:seed", std::to_string(options.seed)}, {"lobe:render_settings", text}});
}

void writeGalleryFiles(const std::string& base, const Gallery& gallery,
                       const GalleryOptions& options) {
    ImageWriteOptions write;
    write.attributes = galleryProvenance(options);
    std::vector<PendingImage> files;
    files.push_back(writeImagePending(base + ".png", labelledGalleryImage(gallery), write));
    files.push_back(writeFilmPending(base + ".exr", gallery.film, 1.0, {}, write));
    PendingImage::commitAll(files);
}

ImageAttributes sheetProvenance(const std::vector<std::string>& captions) {
    std::string text;
    for (const std::string& c : captions) text += (text.empty() ? "" : "\n") + c;
    return toolProvenance({{"lobe:sheet_captions", text}});
}

void writeContactSheet(const std::string& path, const std::vector<ContactSheetEntry>& entries,
                       int columns, int thumbSize) {
    std::vector<std::string> captions;
    for (const ContactSheetEntry& e : entries) captions.push_back(e.caption);
    ImageWriteOptions options;
    options.attributes = sheetProvenance(captions);
    writeImagePending(path, makeContactSheet(entries, columns, thumbSize), options).commit();
}

RgbImage displayImage(const Film& film, const std::vector<float>* alpha, const std::string& tone,
                      double exposure) {
    RgbImage rgb = filmToRgb(film, exposure);
    applyDisplayTone(rgb, alpha, tone);
    return rgb;
}

void applyDisplayTone(RgbImage& rgb, const std::vector<float>* alpha, const std::string& tone) {
    if (!alpha || tone == "clip") {  // clipping commutes with the division by alpha
        applyTone(rgb, tone);
        return;
    }
    RgbImage none;
    applyTone(none, tone);  // refuses an unknown curve by name
    for (size_t i = 0; i < alpha->size(); ++i) {
        const double a = (*alpha)[i];
        for (int c = 0; c < 3; ++c) {
            float& v = rgb.rgb[i * 3 + size_t(c)];
            v = a > 0.0 ? float(shoulderTone(v / a) * a) : 0.0f;
        }
    }
}

int bandRowsFor(const SceneSpec& spec, int requested) {
    if (requested > 0) return std::min(requested, spec.height);
    if (int64_t(spec.width) * spec.height <= kBandThresholdPixels) return spec.height;
    const int64_t rows = kBandPixels / std::max(1, spec.width) / 16 * 16;  // whole tiles
    return int(std::clamp<int64_t>(rows, 16, spec.height));
}

struct FigureWriter::Impl {
    FigureOptions options;
    SceneSpec spec;
    std::string base;
    std::vector<std::string> paths;
    bool transparent = false;
    std::vector<std::unique_ptr<ImageBandWriter>> files;  // opened with the first band
    std::unique_ptr<BoxResizer> thumb;  // the contact-sheet thumbnail, when asked for
    bool covered = false;
};

FigureWriter::FigureWriter(const FigureOptions& options, const SceneSpec& spec,
                           const std::string& base, int thumbWidth)
    : impl_(std::make_unique<Impl>()) {
    Impl& m = *impl_;
    m.options = options;
    m.spec = spec;
    m.base = base;
    m.paths = options.outputPaths(base);
    m.transparent = spec.background.mode == Background::Mode::None;
    if (thumbWidth > 0) {
        const int h = int(std::lround(double(thumbWidth) * spec.height / std::max(1, spec.width)));
        m.thumb = std::make_unique<BoxResizer>(spec.width, spec.height, thumbWidth, std::max(1, h));
    }
}

FigureWriter::~FigureWriter() = default;

void FigureWriter::write(Film& band, const std::vector<float>& alpha, const ImageChannels& extra) {
    Impl& m = *impl_;
    const SceneSpec& spec = m.spec;
    compositeBackground(band, alpha, spec.background, spec.exposure);
    for (float a : alpha)
        if (a > 0.0f) {
            m.covered = true;
            break;
        }
    if (m.files.empty()) {
        ImageWriteOptions write;
        write.attributes = provenance(spec);
        for (const std::string& path : m.paths) {
            if (isExr(path)) {
                m.files.push_back(std::make_unique<ImageBandWriter>(
                    path, spec.width, spec.height, filmChannelNames(extra), m.transparent, write));
            } else {
                ImageWriteOptions integer = write;
                integer.bits = m.options.pngBits;
                m.files.push_back(std::make_unique<ImageBandWriter>(
                    path, spec.width, spec.height, std::vector<std::string>{"R", "G", "B"},
                    m.transparent, integer));
            }
        }
    }
    const float* coverage = m.transparent ? alpha.data() : nullptr;
    if (m.transparent && alpha.size() != size_t(band.width()) * size_t(band.height()))
        throw Error("internal: no coverage for a transparent background");
    const RgbImage display =
        displayImage(band, m.transparent ? &alpha : nullptr, spec.tone, spec.exposure);
    for (size_t i = 0; i < m.paths.size(); ++i) {
        if (isExr(m.paths[i])) {
            const std::vector<float> data = filmChannels(band, spec.exposure, extra);
            m.files[i]->write(band.height(), data.data(), coverage);
        } else {
            m.files[i]->write(band.height(), display.rgb.data(), coverage);
        }
    }
    if (m.thumb) m.thumb->addRows(display);
}

FigureResult FigureWriter::finish() {
    Impl& m = *impl_;
    // Every file written before any is put in place: a failed EXR after a good PNG (a full disk)
    // leaves neither. The EXR last: a resumed batch (--skip-existing) takes a scene as done only
    // when all exist.
    std::vector<PendingImage> pending;
    for (const auto& file : m.files) pending.push_back(file->finish());
    PendingImage::commitAll(pending);
    FigureResult result;
    if (m.thumb) result.display = m.thumb->result();
    result.covered = m.covered;
    result.written = m.options.output.empty() ? m.base + ".png/.exr" : m.paths.front();
    if (m.paths.size() > 1) result.written += " and " + m.paths.back();
    return result;
}

int warnInvisibleObjects(const RenderScene& scene) {
    int count = 0;
    const SceneSpec& spec = scene.spec();
    for (const SceneVolume& vo : scene.scene().volumeObjects()) {
        if (!vo.volume->empty() && vo.volume->transparentBrickFraction() < 1.0) {
            // The transfer function visible only outside the active voxels' values (a brain
            // given in 0..255 to a preset made for 0..1: a forgotten divide_by). The empty-space
            // table above still counts the bricks where the reconstruction blends the data
            // with the background through the visible values, so it does not see this.
            const std::vector<TfPoint>& points = vo.volume->transferFunction().points();
            double lo = std::numeric_limits<double>::infinity(), hi = -lo;
            for (size_t i = 0; i < points.size(); ++i) {
                if (!(points[i].opacity > 0.0)) continue;
                lo = std::min(
                    lo, i == 0 ? -std::numeric_limits<double>::infinity() : points[i - 1].value);
                hi = std::max(hi, i + 1 == points.size() ? std::numeric_limits<double>::infinity()
                                                         : points[i + 1].value);
            }
            float vmin = 0.0f, vmax = 0.0f;
            bool any = false;
            for (auto it = vo.volume->grid().cbeginValueOn(); it; ++it) {
                const float v = *it;
                vmin = any ? std::min(vmin, v) : v;
                vmax = any ? std::max(vmax, v) : v;
                any = true;
            }
            if (!any || !(lo <= hi) || (hi >= double(vmin) && lo <= double(vmax))) continue;
            std::fprintf(stderr,
                         "lobe: warning: %s: objects[%d] (%s): its transfer function is visible "
                         "only for values %g to %g, but the volume's active voxels hold %g to %g, "
                         "so it cannot be seen (a divide_by missing?)\n",
                         spec.path.c_str(), vo.objectIndex, vo.spec->name.c_str(), lo, hi,
                         double(vmin), double(vmax));
            ++count;
            continue;
        }
        std::fprintf(
            stderr,
            "lobe: warning: %s: objects[%d] (%s): its transfer function gives opacity 0 to "
            "every voxel of its volume, so it cannot be seen (check the transfer "
            "function's values against `lobe info` of the source)\n",
            spec.path.c_str(), vo.objectIndex, vo.spec->name.c_str());
        ++count;
    }
    return count;
}

bool warnIfEmpty(const SceneSpec& spec, bool covered) {
    if (covered) return false;
    std::fprintf(
        stderr,
        "lobe: warning: %s: the image is empty: no object covers any pixel (every pixel is "
        "background; check the camera and the objects)\n",
        spec.path.c_str());
    return true;
}

}  // namespace lobe
