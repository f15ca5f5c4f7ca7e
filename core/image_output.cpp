#include "core/image_output.h"

#include "core/error.h"
#include "core/interrupt.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>
#include <vector>

namespace lobe {
namespace {

namespace fs = std::filesystem;

std::string lowerExtension(const std::string& path) {
    std::string ext = fs::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    return ext;
}

bool isFloatFormat(const std::string& ext) { return ext == ".exr"; }

// Temporary sibling of `path` that keeps the extension, since OpenImageIO picks the format by it.
std::string temporarySibling(const std::string& path) {
    const fs::path p(path);
    std::random_device rd;
    const std::string tag = std::to_string(rd() % 1000000);
    return (p.parent_path() / ("." + p.stem().string() + ".partial-" + tag + p.extension().string()))
        .string();
}

PendingImage writePixels(const std::string& path, int width, int height,
                         const std::vector<std::string>& channelNames, const std::vector<float>& data,
                         const ImageAttributes& attributes = {}) {
    const std::string ext = lowerExtension(path);
    if (!isSupportedImageExtension(path))
        throw Error("cannot write '" + path + "': unsupported image extension '" + ext +
                    "' (use .exr, .png, .tif or .jpg)");
    const fs::path parent = fs::path(path).parent_path();
    if (!parent.empty() && !fs::is_directory(parent))
        throw Error("cannot write '" + path + "': folder '" + parent.string() + "' does not exist");

    const int channels = static_cast<int>(channelNames.size());
    OIIO::ImageSpec spec;
    std::vector<unsigned char> bytes;
    const void* pixels = data.data();
    if (isFloatFormat(ext)) {
        spec = OIIO::ImageSpec(width, height, channels, OIIO::TypeDesc::FLOAT);
        spec.channelnames = channelNames;
        spec.attribute("compression", "zip");
        for (const auto& [key, value] : attributes) spec.attribute(key, value);
    } else {
        // 8-bit formats get the display encoding and only the colour channels.
        spec = OIIO::ImageSpec(width, height, 3, OIIO::TypeDesc::UINT8);
        bytes.resize(size_t(width) * height * 3);
        for (size_t i = 0, n = size_t(width) * height; i < n; ++i)
            for (int c = 0; c < 3; ++c) {
                const double v = data[i * channels + c];
                bytes[i * 3 + c] = static_cast<unsigned char>(
                    std::lround(srgbEncode(std::isfinite(v) ? v : 0.0) * 255.0));
            }
        pixels = bytes.data();
        spec.attribute("oiio:ColorSpace", "sRGB");
        if (ext == ".jpg" || ext == ".jpeg") spec.attribute("Compression", "jpeg:85");
    }

    const std::string tmp = temporarySibling(path);
    PendingImage pending(tmp, path);  // removes tmp unless committed
    auto out = OIIO::ImageOutput::create(tmp);
    if (!out) throw Error("cannot write '" + path + "': " + OIIO::geterror());
    bool ok = out->open(tmp, spec);
    ok = ok && out->write_image(spec.format, pixels);
    ok = out->close() && ok;
    if (!ok) throw Error("cannot write '" + path + "': " + out->geterror());
    // OpenImageIO's PNG, JPEG and TIFF writers do not report a short write (a full disk left a
    // truncated PNG and exit 0); the file is read back instead, and a lossless one compared
    // byte for byte (a few ms for a 1024² PNG).
    if (!isFloatFormat(ext)) {
        std::vector<unsigned char> back(bytes.size());
        auto in = OIIO::ImageInput::open(tmp);
        const bool read = in && in->spec().width == width && in->spec().height == height &&
                          in->spec().nchannels == 3 &&
                          in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, back.data());
        if (in) in->close();
        const bool lossy = ext == ".jpg" || ext == ".jpeg";
        if (!read || (!lossy && back != bytes))
            throw Error("cannot write '" + path + "': the file written is incomplete (a full disk?)");
    }
    return pending;
}

}  // namespace

bool isSupportedImageExtension(const std::string& path) {
    const std::string ext = lowerExtension(path);
    return ext == ".exr" || ext == ".png" || ext == ".tif" || ext == ".tiff" || ext == ".jpg" ||
           ext == ".jpeg";
}

PendingImage::PendingImage(std::string temporary, std::string path)
    : temporary_(std::move(temporary)), path_(std::move(path)),
      guard_(std::make_unique<RemovedOnInterrupt>(temporary_)) {}

PendingImage::PendingImage(PendingImage&& other) noexcept
    : temporary_(std::move(other.temporary_)), path_(std::move(other.path_)),
      guard_(std::move(other.guard_)) {
    other.temporary_.clear();
}

PendingImage::~PendingImage() {
    if (!temporary_.empty()) std::remove(temporary_.c_str());
}

void PendingImage::commit() {
    std::error_code ec;
    fs::rename(temporary_, path_, ec);
    if (ec) throw Error("cannot write '" + path_ + "': " + ec.message());  // the destructor removes it
    temporary_.clear();
}

PendingImage writeImagePending(const std::string& path, const RgbImage& image) {
    return writePixels(path, image.width, image.height, {"R", "G", "B"}, image.rgb);
}

void writeImage(const std::string& path, const RgbImage& image) {
    writeImagePending(path, image).commit();
}

void writeFilm(const std::string& path, const Film& film, double exposure,
               const ImageChannels& extra, const ImageAttributes& attributes) {
    writeFilmPending(path, film, exposure, extra, attributes).commit();
}

PendingImage writeFilmPending(const std::string& path, const Film& film, double exposure,
                              const ImageChannels& extra, const ImageAttributes& attributes) {
    const RgbImage rgb = filmToRgb(film, exposure);
    const size_t n = size_t(film.width()) * film.height();
    const size_t k = extra.names.size();
    if (extra.data.size() != n * k)
        throw Error("cannot write '" + path + "': extra channels do not match the image size");
    const size_t stride = 6 + k;
    std::vector<float> data(n * stride);
    for (size_t i = 0; i < n; ++i) {
        const Spectrum& s = film.pixels()[i];
        for (int c = 0; c < 3; ++c) {
            data[i * stride + c] = rgb.rgb[i * 3 + c];
            const double band = s[c] * exposure;
            data[i * stride + 3 + c] = imageFloat(band);
        }
        for (size_t c = 0; c < k; ++c) {
            const float v = extra.data[i * k + c];
            data[i * stride + 6 + c] = imageFloat(v);
        }
    }
    std::vector<std::string> names = {"R", "G", "B", "band.700", "band.546_1", "band.435_8"};
    names.insert(names.end(), extra.names.begin(), extra.names.end());
    return writePixels(path, film.width(), film.height(), names, data, attributes);
}

FloatImage readFloatImage(const std::string& path) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) throw Error("cannot read image '" + path + "': " + OIIO::geterror());
    const OIIO::ImageSpec& spec = in->spec();
    FloatImage image;
    image.width = spec.width;
    image.height = spec.height;
    image.channels.names = spec.channelnames;
    image.channels.data.resize(size_t(spec.width) * spec.height * spec.nchannels);
    if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, image.channels.data.data()))
        throw Error("cannot read image '" + path + "': " + in->geterror());
    for (const OIIO::ParamValue& p : spec.extra_attribs) {
        const std::string name = p.name().string();
        if (name.rfind("lobe:", 0) == 0 && p.type() == OIIO::TypeDesc::STRING)
            image.attributes[name] = p.get_string();
    }
    return image;
}

void writeFloatImage(const std::string& path, const FloatImage& image) {
    writePixels(path, image.width, image.height, image.channels.names, image.channels.data,
                image.attributes)
        .commit();
}

RgbImage readImage(const std::string& path) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) throw Error("cannot read image '" + path + "': " + OIIO::geterror());
    const OIIO::ImageSpec& spec = in->spec();
    std::vector<float> data(size_t(spec.width) * spec.height * spec.nchannels);
    if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, data.data()))
        throw Error("cannot read image '" + path + "': " + in->geterror());
    const bool encoded = spec.format == OIIO::TypeDesc::UINT8;
    RgbImage image(spec.width, spec.height);
    for (size_t i = 0, n = size_t(spec.width) * spec.height; i < n; ++i)
        for (int c = 0; c < 3; ++c) {
            float v = data[i * spec.nchannels + std::min(c, spec.nchannels - 1)];
            if (encoded)  // inverse sRGB transfer function
                v = v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
            image.rgb[i * 3 + c] = v;
        }
    return image;
}

}  // namespace lobe
