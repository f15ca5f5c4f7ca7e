#include "core/image_output.h"

#include "core/error.h"
#include "core/interrupt.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
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

// A 64-bit hash of a sequence of samples, eight bytes at a time: what an integer file read back
// is compared with, so the check needs no copy of the whole image.
class SampleHash {
public:
    void add(const void* data, size_t bytes) {
        const unsigned char* p = static_cast<const unsigned char*>(data);
        for (; bytes > 0; ) {
            uint64_t word = 0;
            const size_t n = std::min<size_t>(8, bytes);
            std::memcpy(&word, p, n);
            h_ = (h_ ^ word) * 1099511628211ull;
            h_ ^= h_ >> 29;
            p += n;
            bytes -= n;
        }
    }
    uint64_t value() const { return h_; }

private:
    uint64_t h_ = 1469598103934665603ull;
};

}  // namespace

struct ImageBandWriter::Impl {
    std::string path, ext;
    int width = 0, height = 0;
    int channels = 0;       // floats a pixel in write()
    bool withAlpha = false;
    int bits = 8;
    bool isFloat = false, jpeg = false;
    OIIO::ImageSpec spec;
    std::unique_ptr<PendingImage> pending;  // removes the temporary file unless finished
    std::unique_ptr<OIIO::ImageOutput> output;
    std::string temporary;
    int nextRow = 0;
    SampleHash written;
    std::vector<float> floats;            // EXR with alpha: A inserted after B
    std::vector<unsigned char> bytes;     // 8-bit samples
    std::vector<unsigned short> words;    // 16-bit samples

    [[noreturn]] void fail(const std::string& why) const {
        throw Error("cannot write '" + path + "': " + why);
    }
};

ImageBandWriter::ImageBandWriter(const std::string& path, int width, int height,
                                 const std::vector<std::string>& channelNames, bool withAlpha,
                                 const ImageWriteOptions& options)
    : impl_(std::make_unique<Impl>()) {
    Impl& m = *impl_;
    m.path = path;
    m.ext = lowerExtension(path);
    m.width = width;
    m.height = height;
    m.channels = int(channelNames.size());
    m.withAlpha = withAlpha;
    m.bits = options.bits;
    m.isFloat = isFloatFormat(m.ext);
    m.jpeg = m.ext == ".jpg" || m.ext == ".jpeg";
    const bool png = m.ext == ".png";
    if (!isSupportedImageExtension(path))
        throw Error("cannot write '" + path + "': unsupported image extension '" + m.ext +
                    "' (use .exr, .png, .tif or .jpg)");
    const fs::path parent = fs::path(path).parent_path();
    if (!parent.empty() && !fs::is_directory(parent))
        m.fail("folder '" + parent.string() + "' does not exist");
    if (withAlpha && m.jpeg)
        m.fail("JPEG has no alpha channel (write .png, .tif or .exr, or give the image a "
               "background colour)");
    if (options.bits != 8 && !(options.bits == 16 && (png || m.ext == ".tif" || m.ext == ".tiff")))
        m.fail(std::to_string(options.bits) + "-bit output is for .png and .tif only (8 or 16 bits)");
    if (m.channels < 3 || width < 1 || height < 1) m.fail("an image needs R, G, B and a size");

    if (m.isFloat) {
        std::vector<std::string> names = channelNames;
        if (withAlpha) names.insert(names.begin() + 3, "A");
        m.spec = OIIO::ImageSpec(width, height, int(names.size()), OIIO::TypeDesc::FLOAT);
        m.spec.channelnames = names;
        if (withAlpha) m.spec.alpha_channel = 3;
        m.spec.attribute("compression", "zip");
    } else {
        m.spec = OIIO::ImageSpec(width, height, withAlpha ? 4 : 3,
                                 options.bits == 16 ? OIIO::TypeDesc::UINT16 : OIIO::TypeDesc::UINT8);
        if (withAlpha) {
            m.spec.alpha_channel = 3;
            m.spec.attribute("oiio:UnassociatedAlpha", 1);  // already divided: not again
        }
        m.spec.attribute("oiio:ColorSpace", "sRGB");
        if (m.jpeg) m.spec.attribute("Compression", "jpeg:85");
    }
    if (m.isFloat || png)
        for (const auto& [key, value] : options.attributes) m.spec.attribute(key, value);

    m.temporary = temporarySibling(path);
    m.pending = std::make_unique<PendingImage>(m.temporary, path);
    m.output = OIIO::ImageOutput::create(m.temporary);
    if (!m.output) m.fail(OIIO::geterror());
    if (!m.output->open(m.temporary, m.spec)) m.fail(m.output->geterror());
}

ImageBandWriter::~ImageBandWriter() {
    // A PNG closed short of its rows makes libpng print "No IDATs written into file" to stderr
    // beside the real error; the file is removed either way, so its remaining rows are written
    // as zeros (deflated at once) to close it quietly. The other formats close quietly.
    Impl& m = *impl_;
    if (!m.output || m.ext != ".png") return;
    const int band = std::max(1, int((size_t(1) << 20) / size_t(m.width)));
    const std::vector<unsigned char> zeros(size_t(m.width) * size_t(band) *
                                           size_t(m.spec.nchannels) * m.spec.format.size());
    for (bool ok = true; ok && m.nextRow < m.height; m.nextRow += band)
        ok = m.output->write_scanlines(m.nextRow, std::min(m.height, m.nextRow + band), 0,
                                       m.spec.format, zeros.data());
}

int ImageBandWriter::rowsWritten() const { return impl_->nextRow; }

void ImageBandWriter::write(int rows, const float* data, const float* alpha) {
    Impl& m = *impl_;
    if (!m.output) m.fail("internal: rows written after the file was finished");
    if (rows < 0 || m.nextRow + rows > m.height)
        m.fail("internal: rows " + std::to_string(m.nextRow) + " + " + std::to_string(rows) +
               " beyond the image's " + std::to_string(m.height));
    if (m.withAlpha != (alpha != nullptr)) m.fail("internal: alpha given to an image without it");
    const size_t n = size_t(m.width) * size_t(rows);
    const size_t channels = size_t(m.channels);
    const void* pixels = data;
    if (m.isFloat) {
        if (alpha) {
            m.floats.resize(n * (channels + 1));
            for (size_t i = 0; i < n; ++i) {
                const float* src = &data[i * channels];
                float* dst = &m.floats[i * (channels + 1)];
                std::copy(src, src + 3, dst);
                dst[3] = std::isfinite(alpha[i]) ? std::clamp(alpha[i], 0.0f, 1.0f) : 0.0f;
                std::copy(src + 3, src + channels, dst + 4);
            }
            pixels = m.floats.data();
        }
    } else {
        // Integer formats get the display encoding and only the colour channels (and alpha);
        // with alpha the colour is divided by it (straight alpha), 0 where nothing covers.
        const int out = alpha ? 4 : 3;
        const double scale = m.bits == 16 ? 65535.0 : 255.0;
        if (m.bits == 16) m.words.resize(n * size_t(out));
        else m.bytes.resize(n * size_t(out));
        for (size_t i = 0; i < n; ++i) {
            double a = 1.0;
            if (alpha) a = std::isfinite(alpha[i]) ? std::clamp(double(alpha[i]), 0.0, 1.0) : 0.0;
            for (int c = 0; c < out; ++c) {
                double v;
                if (c == 3) {
                    v = a;
                } else {
                    const double premultiplied = data[i * channels + size_t(c)];
                    const double straight = !alpha ? premultiplied : a > 0.0 ? premultiplied / a : 0.0;
                    v = srgbEncode(std::isfinite(straight) ? straight : 0.0);
                }
                const long q = std::lround(v * scale);
                if (m.bits == 16) m.words[i * size_t(out) + size_t(c)] = static_cast<unsigned short>(q);
                else m.bytes[i * size_t(out) + size_t(c)] = static_cast<unsigned char>(q);
            }
        }
        if (m.bits == 16) {
            m.written.add(m.words.data(), m.words.size() * sizeof(unsigned short));
            pixels = m.words.data();
        } else {
            m.written.add(m.bytes.data(), m.bytes.size());
            pixels = m.bytes.data();
        }
    }
    if (rows > 0 && !m.output->write_scanlines(m.nextRow, m.nextRow + rows, 0, m.spec.format, pixels))
        m.fail(m.output->geterror());
    m.nextRow += rows;
}

PendingImage ImageBandWriter::finish() {
    Impl& m = *impl_;
    if (!m.output) m.fail("internal: finished twice");
    if (m.nextRow != m.height)
        m.fail("internal: " + std::to_string(m.nextRow) + " of " + std::to_string(m.height) +
               " rows written");
    const bool closed = m.output->close();
    const std::string error = closed ? "" : m.output->geterror();
    m.output.reset();
    if (!closed) m.fail(error);
    // OpenImageIO's PNG, JPEG and TIFF writers do not report a short write (a full disk left a
    // truncated PNG and exit 0); the file is read back instead, band by band, and a lossless one
    // compared sample for sample through a hash of the samples written (a few ms for a 1024² PNG).
    if (!m.isFloat) {
        OIIO::ImageSpec config;
        config.attribute("oiio:UnassociatedAlpha", 1);  // as written, not premultiplied again
        auto in = OIIO::ImageInput::open(m.temporary, &config);
        const int out = m.spec.nchannels;
        bool read = in && in->spec().width == m.width && in->spec().height == m.height &&
                    in->spec().nchannels == out;
        SampleHash back;
        const size_t sampleBytes = m.bits == 16 ? 2 : 1;
        const int band = std::max(1, int((size_t(1) << 22) / size_t(m.width)));
        std::vector<unsigned char> buffer;
        for (int y0 = 0; read && y0 < m.height; y0 += band) {
            const int y1 = std::min(m.height, y0 + band);
            buffer.resize(size_t(m.width) * size_t(y1 - y0) * size_t(out) * sampleBytes);
            read = in->read_scanlines(0, 0, y0, y1, 0, 0, out, m.spec.format, buffer.data());
            back.add(buffer.data(), buffer.size());
        }
        if (in) in->close();
        if (!read || (!m.jpeg && back.value() != m.written.value()))
            m.fail("the file written is incomplete (a full disk?)");
    }
    PendingImage done = std::move(*m.pending);
    m.pending.reset();
    return done;
}

namespace {

PendingImage writePixels(const std::string& path, int width, int height,
                         const std::vector<std::string>& channelNames, const std::vector<float>& data,
                         const ImageWriteOptions& options = {}) {
    const std::vector<float>* alpha = options.alpha;
    if (alpha && alpha->size() != size_t(width) * size_t(height))
        throw Error("cannot write '" + path + "': the alpha channel does not match the image size");
    ImageBandWriter writer(path, width, height, channelNames, alpha != nullptr, options);
    writer.write(height, data.data(), alpha ? alpha->data() : nullptr);
    return writer.finish();
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

std::vector<std::string> filmChannelNames(const ImageChannels& extra) {
    std::vector<std::string> names = {"R", "G", "B", "band.700", "band.546_1", "band.435_8"};
    names.insert(names.end(), extra.names.begin(), extra.names.end());
    return names;
}

std::vector<float> filmChannels(const Film& film, double exposure, const ImageChannels& extra) {
    const RgbImage rgb = filmToRgb(film, exposure);
    const size_t n = size_t(film.width()) * film.height();
    const size_t k = extra.names.size();
    if (extra.data.size() != n * k) throw Error("internal: extra channels do not match the image size");
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
    return data;
}

PendingImage writeFilmPending(const std::string& path, const Film& film, double exposure,
                              const ImageChannels& extra, const ImageWriteOptions& options) {
    if (extra.data.size() != size_t(film.width()) * film.height() * extra.names.size())
        throw Error("cannot write '" + path + "': extra channels do not match the image size");
    return writePixels(path, film.width(), film.height(), filmChannelNames(extra),
                       filmChannels(film, exposure, extra), options);
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

void forEachRgbBand(const std::string& path, long long bandPixels,
                    const std::function<void(RgbImage&, int)>& fn) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) throw Error("cannot read image '" + path + "': " + OIIO::geterror());
    const OIIO::ImageSpec& spec = in->spec();
    int channel[3];
    for (int c = 0; c < 3; ++c) {
        const auto& names = spec.channelnames;
        const auto it = std::find(names.begin(), names.end(), std::string(1, "RGB"[c]));
        if (it == names.end()) throw Error(path + ": no channel " + std::string(1, "RGB"[c]));
        channel[c] = int(it - names.begin());
    }
    // The channels from the first to the last of R, G, B, and R, G, B picked from them.
    const int first = std::min({channel[0], channel[1], channel[2]});
    const int count = std::max({channel[0], channel[1], channel[2]}) - first + 1;
    const int bandRows = int(std::clamp<long long>(bandPixels / std::max(1, spec.width), 1,
                                                   std::max(1, spec.height)));
    std::vector<float> rows;
    for (int y0 = 0; y0 < spec.height; y0 += bandRows) {
        const int y1 = std::min(spec.height, y0 + bandRows);
        rows.resize(size_t(spec.width) * size_t(y1 - y0) * size_t(count));
        if (!in->read_scanlines(0, 0, y0, y1, 0, first, first + count, OIIO::TypeDesc::FLOAT,
                                rows.data()))
            throw Error("cannot read image '" + path + "': " + in->geterror());
        RgbImage band(spec.width, y1 - y0);
        for (size_t p = 0; p < size_t(spec.width) * size_t(y1 - y0); ++p)
            for (int c = 0; c < 3; ++c)
                band.rgb[p * 3 + size_t(c)] = rows[p * size_t(count) + size_t(channel[c] - first)];
        fn(band, spec.height);
    }
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
