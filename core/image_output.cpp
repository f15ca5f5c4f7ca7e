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
                         const ImageWriteOptions& options = {}) {
    const std::string ext = lowerExtension(path);
    if (!isSupportedImageExtension(path))
        throw Error("cannot write '" + path + "': unsupported image extension '" + ext +
                    "' (use .exr, .png, .tif or .jpg)");
    const fs::path parent = fs::path(path).parent_path();
    if (!parent.empty() && !fs::is_directory(parent))
        throw Error("cannot write '" + path + "': folder '" + parent.string() + "' does not exist");
    const bool jpeg = ext == ".jpg" || ext == ".jpeg";
    const bool png = ext == ".png";
    const std::vector<float>* alpha = options.alpha;
    const size_t n = size_t(width) * height;
    if (alpha && alpha->size() != n)
        throw Error("cannot write '" + path + "': the alpha channel does not match the image size");
    if (alpha && jpeg)
        throw Error("cannot write '" + path + "': JPEG has no alpha channel (write .png, .tif or "
                    ".exr, or give the image a background colour)");
    if (options.bits != 8 && !(options.bits == 16 && (png || ext == ".tif" || ext == ".tiff")))
        throw Error("cannot write '" + path + "': " + std::to_string(options.bits) +
                    "-bit output is for .png and .tif only (8 or 16 bits)");

    const int channels = static_cast<int>(channelNames.size());
    OIIO::ImageSpec spec;
    std::vector<unsigned char> bytes;      // 8-bit samples
    std::vector<unsigned short> words;     // 16-bit samples
    std::vector<float> floats;             // EXR with alpha: A inserted after B
    const void* pixels = data.data();
    if (isFloatFormat(ext)) {
        std::vector<std::string> names = channelNames;
        if (alpha) {
            names.insert(names.begin() + 3, "A");
            floats.resize(n * size_t(channels + 1));
            for (size_t i = 0; i < n; ++i) {
                const float* src = &data[i * size_t(channels)];
                float* dst = &floats[i * size_t(channels + 1)];
                std::copy(src, src + 3, dst);
                dst[3] = std::isfinite((*alpha)[i]) ? std::clamp((*alpha)[i], 0.0f, 1.0f) : 0.0f;
                std::copy(src + 3, src + channels, dst + 4);
            }
            pixels = floats.data();
        }
        spec = OIIO::ImageSpec(width, height, int(names.size()), OIIO::TypeDesc::FLOAT);
        spec.channelnames = names;
        if (alpha) spec.alpha_channel = 3;
        spec.attribute("compression", "zip");
    } else {
        // Integer formats get the display encoding and only the colour channels (and alpha);
        // with alpha the colour is divided by it (straight alpha), 0 where nothing covers.
        const int out = alpha ? 4 : 3;
        const double scale = options.bits == 16 ? 65535.0 : 255.0;
        if (options.bits == 16) words.resize(n * size_t(out));
        else bytes.resize(n * size_t(out));
        for (size_t i = 0; i < n; ++i) {
            double a = 1.0;
            if (alpha) a = std::isfinite((*alpha)[i]) ? std::clamp(double((*alpha)[i]), 0.0, 1.0) : 0.0;
            for (int c = 0; c < out; ++c) {
                double v;
                if (c == 3) {
                    v = a;
                } else {
                    const double premultiplied = data[i * size_t(channels) + size_t(c)];
                    const double straight = !alpha ? premultiplied : a > 0.0 ? premultiplied / a : 0.0;
                    v = srgbEncode(std::isfinite(straight) ? straight : 0.0);
                }
                const long q = std::lround(v * scale);
                if (options.bits == 16) words[i * size_t(out) + size_t(c)] = static_cast<unsigned short>(q);
                else bytes[i * size_t(out) + size_t(c)] = static_cast<unsigned char>(q);
            }
        }
        spec = OIIO::ImageSpec(width, height, out,
                               options.bits == 16 ? OIIO::TypeDesc::UINT16 : OIIO::TypeDesc::UINT8);
        if (alpha) {
            spec.alpha_channel = 3;
            spec.attribute("oiio:UnassociatedAlpha", 1);  // already divided: not again
        }
        pixels = options.bits == 16 ? static_cast<const void*>(words.data()) : bytes.data();
        spec.attribute("oiio:ColorSpace", "sRGB");
        if (jpeg) spec.attribute("Compression", "jpeg:85");
    }
    if (isFloatFormat(ext) || png)
        for (const auto& [key, value] : options.attributes) spec.attribute(key, value);

    const std::string tmp = temporarySibling(path);
    PendingImage pending(tmp, path);  // removes tmp unless committed
    auto output = OIIO::ImageOutput::create(tmp);
    if (!output) throw Error("cannot write '" + path + "': " + OIIO::geterror());
    bool ok = output->open(tmp, spec);
    ok = ok && output->write_image(spec.format, pixels);
    ok = output->close() && ok;
    if (!ok) throw Error("cannot write '" + path + "': " + output->geterror());
    // OpenImageIO's PNG, JPEG and TIFF writers do not report a short write (a full disk left a
    // truncated PNG and exit 0); the file is read back instead, and a lossless one compared
    // sample for sample (a few ms for a 1024² PNG).
    if (!isFloatFormat(ext)) {
        OIIO::ImageSpec config;
        config.attribute("oiio:UnassociatedAlpha", 1);  // as written, not premultiplied again
        auto in = OIIO::ImageInput::open(tmp, &config);
        const int out = spec.nchannels;
        bool read = in && in->spec().width == width && in->spec().height == height &&
                    in->spec().nchannels == out;
        bool same = true;
        if (read && options.bits == 16) {
            std::vector<unsigned short> back(words.size());
            read = in->read_image(0, 0, 0, out, OIIO::TypeDesc::UINT16, back.data());
            same = back == words;
        } else if (read) {
            std::vector<unsigned char> back(bytes.size());
            read = in->read_image(0, 0, 0, out, OIIO::TypeDesc::UINT8, back.data());
            same = back == bytes;
        }
        if (in) in->close();
        if (!read || (!jpeg && !same))
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

PendingImage writeImagePending(const std::string& path, const RgbImage& image,
                               const ImageWriteOptions& options) {
    return writePixels(path, image.width, image.height, {"R", "G", "B"}, image.rgb, options);
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
    ImageWriteOptions options;
    options.attributes = attributes;
    return writeFilmPending(path, film, exposure, extra, options);
}

PendingImage writeFilmPending(const std::string& path, const Film& film, double exposure,
                              const ImageChannels& extra, const ImageWriteOptions& options) {
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
    return writePixels(path, film.width(), film.height(), names, data, options);
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
    ImageWriteOptions options;
    options.attributes = image.attributes;
    writePixels(path, image.width, image.height, image.channels.names, image.channels.data, options)
        .commit();
}

ImageAttributes readImageAttributes(const std::string& path) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) throw Error("cannot read image '" + path + "': " + OIIO::geterror());
    ImageAttributes attributes;
    for (const OIIO::ParamValue& p : in->spec().extra_attribs)
        if (p.type() == OIIO::TypeDesc::STRING) attributes[p.name().string()] = p.get_string();
    return attributes;
}

RgbImage readImage(const std::string& path) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) throw Error("cannot read image '" + path + "': " + OIIO::geterror());
    const OIIO::ImageSpec& spec = in->spec();
    std::vector<float> data(size_t(spec.width) * spec.height * spec.nchannels);
    if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, data.data()))
        throw Error("cannot read image '" + path + "': " + in->geterror());
    const bool encoded = spec.format == OIIO::TypeDesc::UINT8 || spec.format == OIIO::TypeDesc::UINT16;
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

std::string lowerExtension(const std::string& path) {
    std::string ext = fs::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    return ext;
}

}  // namespace lobe
