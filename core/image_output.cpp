#include "core/image_output.h"

#include "core/error.h"
#include "core/interrupt.h"
#include "core/stderr_capture.h"
#include "core/temporary_file.h"

#include <OpenImageIO/imageio.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <csetjmp>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <random>
#include <vector>

extern "C" {
#include <jpeglib.h>
}

namespace lobe {
namespace {

namespace fs = std::filesystem;

bool isFloatFormat(const std::string& ext) { return ext == ".exr"; }

// OpenImageIO's error text as one line: it holds one line per message (a damaged PNG: "Read
// error: hit end of file", "PNG read error: IDAT: ...", "PNG library error"), joined by "; ".
std::string oneLine(const std::string& text) {
    std::string out, line;
    for (size_t i = 0; i <= text.size(); ++i) {
        if (i == text.size() || text[i] == '\n') {
            if (!line.empty()) out += (out.empty() ? "" : "; ") + line;
            line.clear();
        } else {
            line += text[i];
        }
    }
    return out;
}

// A 64-bit hash of a sequence of samples, eight bytes at a time: what an integer file read back
// is compared with, so the check needs no copy of the whole image.
class SampleHash {
public:
    void add(const void* data, size_t bytes) {
        const unsigned char* p = static_cast<const unsigned char*>(data);
        for (; bytes > 0;) {
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

// A JPEG file written with libjpeg directly, not through OpenImageIO: OpenImageIO's JPEG writer
// keeps libjpeg's default error handler (jpeg_std_error), whose error_exit prints and calls
// exit() — a full disk ended the process inside libjpeg, leaving the temporary file and no
// Lobe message. Here error_exit jumps back (the libjpeg manual, libjpeg.txt, "Error handling";
// its example.c) and the failure is returned with libjpeg's words for it. Baseline JFIF, 8-bit
// sRGB, quality 85 (what the OpenImageIO path wrote). Each method that calls libjpeg sets the
// jump point itself and holds no object with a destructor, as longjmp requires.
class JpegFile {
public:
    JpegFile(const std::string& path, int width, int height, int quality) {
        cinfo_.err = jpeg_std_error(&errors_.pub);
        errors_.pub.error_exit = &JpegFile::onError;
        errors_.pub.output_message = &JpegFile::onMessage;  // warnings: kept, never printed
        errors_.message[0] = '\0';
        file_ = std::fopen(path.c_str(), "wb");
        if (!file_) {
            std::snprintf(errors_.message, sizeof errors_.message, "%s", std::strerror(errno));
            return;
        }
        if (setjmp(errors_.jump)) return;
        jpeg_create_compress(&cinfo_);
        created_ = true;
        jpeg_stdio_dest(&cinfo_, file_);
        cinfo_.image_width = JDIMENSION(width);
        cinfo_.image_height = JDIMENSION(height);
        cinfo_.input_components = 3;
        cinfo_.in_color_space = JCS_RGB;
        jpeg_set_defaults(&cinfo_);
        jpeg_set_quality(&cinfo_, quality, TRUE);
        jpeg_start_compress(&cinfo_, TRUE);
        ok_ = true;
    }
    ~JpegFile() {
        if (created_) jpeg_destroy_compress(&cinfo_);
        if (file_) std::fclose(file_);
    }
    JpegFile(const JpegFile&) = delete;
    JpegFile& operator=(const JpegFile&) = delete;

    bool ok() const { return ok_; }
    const char* error() const { return errors_.message; }

    // `rows` rows of width · 3 bytes.
    bool write(const unsigned char* rgb, int rows) {
        if (!ok_) return false;
        if (setjmp(errors_.jump)) return ok_ = false;
        const size_t stride = size_t(cinfo_.image_width) * 3;
        for (int y = 0; y < rows; ++y) {
            JSAMPROW row = const_cast<JSAMPROW>(rgb + size_t(y) * stride);
            jpeg_write_scanlines(&cinfo_, &row, 1);
        }
        return true;
    }
    // Flushes libjpeg's buffer (its destination checks every write: a short one is an error)
    // and closes the file, whose own flush can fail too.
    bool finish() {
        if (!ok_) return false;
        if (setjmp(errors_.jump)) return ok_ = false;
        jpeg_finish_compress(&cinfo_);
        std::FILE* f = file_;
        file_ = nullptr;
        if (std::fclose(f) != 0) {
            std::snprintf(errors_.message, sizeof errors_.message, "%s", std::strerror(errno));
            return ok_ = false;
        }
        return true;
    }

private:
    struct Errors {
        jpeg_error_mgr pub;
        std::jmp_buf jump;
        char message[JMSG_LENGTH_MAX];
    };
    static void onError(j_common_ptr cinfo) {
        Errors* e = reinterpret_cast<Errors*>(cinfo->err);
        (*cinfo->err->format_message)(cinfo, e->message);
        std::longjmp(e->jump, 1);
    }
    static void onMessage(j_common_ptr) {}

    jpeg_compress_struct cinfo_{};
    Errors errors_{};
    std::FILE* file_ = nullptr;
    bool created_ = false, ok_ = false;
};

}  // namespace

struct ImageBandWriter::Impl {
    std::string path, ext;
    int width = 0, height = 0;
    int channels = 0;  // floats a pixel in write()
    bool withAlpha = false;
    int bits = 8;
    bool isFloat = false, jpeg = false;
    OIIO::ImageSpec spec;
    std::unique_ptr<PendingImage> pending;      // removes the temporary file unless finished
    std::unique_ptr<OIIO::ImageOutput> output;  // every format but JPEG
    std::unique_ptr<JpegFile> jpegFile;         // JPEG
    bool open = false;                          // rows may still be written
    std::string temporary;
    int nextRow = 0;
    SampleHash written;
    std::vector<float> floats;          // EXR with alpha: A inserted after B
    std::vector<unsigned char> bytes;   // 8-bit samples
    std::vector<unsigned short> words;  // 16-bit samples

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
        m.fail(
            "JPEG has no alpha channel (write .png, .tif or .exr, or give the image a "
            "background colour)");
    if (options.bits != 8 && !(options.bits == 16 && (png || m.ext == ".tif" || m.ext == ".tiff")))
        m.fail(std::to_string(options.bits) +
               "-bit output is for .png and .tif only (8 or 16 bits)");
    if (m.channels < 3 || width < 1 || height < 1) m.fail("an image needs R, G, B and a size");

    if (m.isFloat) {
        std::vector<std::string> names = channelNames;
        if (withAlpha) names.insert(names.begin() + 3, "A");
        m.spec = OIIO::ImageSpec(width, height, int(names.size()), OIIO::TypeDesc::FLOAT);
        m.spec.channelnames = names;
        if (withAlpha) m.spec.alpha_channel = 3;
        m.spec.attribute("compression", "zip");
    } else {
        m.spec =
            OIIO::ImageSpec(width, height, withAlpha ? 4 : 3,
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
    if (m.jpeg) {
        m.jpegFile = std::make_unique<JpegFile>(m.temporary, width, height, 85);
        if (!m.jpegFile->ok()) m.fail(m.jpegFile->error());
    } else {
        m.output = OIIO::ImageOutput::create(m.temporary);
        if (!m.output) m.fail(oneLine(OIIO::geterror()));
        if (!m.output->open(m.temporary, m.spec)) m.fail(oneLine(m.output->geterror()));
    }
    m.open = true;
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
    if (!m.open) m.fail("internal: rows written after the file was finished");
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
        if (m.bits == 16)
            m.words.resize(n * size_t(out));
        else
            m.bytes.resize(n * size_t(out));
        for (size_t i = 0; i < n; ++i) {
            double a = 1.0;
            if (alpha) a = std::isfinite(alpha[i]) ? std::clamp(double(alpha[i]), 0.0, 1.0) : 0.0;
            for (int c = 0; c < out; ++c) {
                double v;
                if (c == 3) {
                    v = a;
                } else {
                    const double premultiplied = data[i * channels + size_t(c)];
                    const double straight = !alpha    ? premultiplied
                                            : a > 0.0 ? premultiplied / a
                                                      : 0.0;
                    v = srgbEncode(std::isfinite(straight) ? straight : 0.0);
                }
                const long q = std::lround(v * scale);
                if (m.bits == 16)
                    m.words[i * size_t(out) + size_t(c)] = static_cast<unsigned short>(q);
                else
                    m.bytes[i * size_t(out) + size_t(c)] = static_cast<unsigned char>(q);
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
    if (m.jpegFile) {
        if (rows > 0 && !m.jpegFile->write(m.bytes.data(), rows)) m.fail(m.jpegFile->error());
    } else if (rows > 0 &&
               !m.output->write_scanlines(m.nextRow, m.nextRow + rows, 0, m.spec.format, pixels)) {
        m.fail(oneLine(m.output->geterror()));
    }
    m.nextRow += rows;
}

PendingImage ImageBandWriter::finish() {
    Impl& m = *impl_;
    if (!m.open) m.fail("internal: finished twice");
    if (m.nextRow != m.height)
        m.fail("internal: " + std::to_string(m.nextRow) + " of " + std::to_string(m.height) +
               " rows written");
    m.open = false;
    const bool closed = m.jpegFile ? m.jpegFile->finish() : m.output->close();
    const std::string error = closed       ? ""
                              : m.jpegFile ? m.jpegFile->error()
                                           : oneLine(m.output->geterror());
    m.output.reset();
    m.jpegFile.reset();
    if (!closed) m.fail(error);
    // OpenImageIO's PNG, JPEG and TIFF writers do not report a short write (a full disk left a
    // truncated PNG and exit 0); the file is read back instead, band by band, and a lossless one
    // compared sample for sample through a hash of the samples written (a few ms for a 1024² PNG).
    if (!m.isFloat) {
        StderrCapture quiet;  // libpng's own lines on a short file: the error below says it
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
                         const std::vector<std::string>& channelNames,
                         const std::vector<float>& data, const ImageWriteOptions& options = {}) {
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
    : temporary_(std::move(temporary)),
      path_(std::move(path)),
      guard_(std::make_unique<RemovedOnInterrupt>(temporary_)) {}

PendingImage::PendingImage(PendingImage&& other) noexcept
    : temporary_(std::move(other.temporary_)),
      path_(std::move(other.path_)),
      guard_(std::move(other.guard_)) {
    other.temporary_.clear();
}

PendingImage::~PendingImage() {
    if (!temporary_.empty()) std::remove(temporary_.c_str());
}

void PendingImage::commit() {
    std::error_code ec;
    fs::rename(temporary_, path_, ec);
    if (ec)
        throw Error("cannot write '" + path_ + "': " + ec.message());  // the destructor removes it
    temporary_.clear();
}

void PendingImage::commitAll(std::vector<PendingImage>& images) {
    for (const PendingImage& p : images) {
        std::error_code ec;
        const fs::file_status st = fs::symlink_status(p.path_, ec);
        if (fs::is_directory(st))
            throw Error("cannot write '" + p.path_ +
                        "': a folder of that name exists (none of the " +
                        std::to_string(images.size()) + " files was put in place)");
        if (fs::exists(st) && !fs::is_regular_file(st) && !fs::is_symlink(st))
            throw Error("cannot write '" + p.path_ +
                        "': something other than a file has that name");
    }
    struct Done {
        std::string path, previous;  // previous: a hard link to the file it replaced, or ""
    };
    std::vector<Done> done;
    const auto undo = [&] {
        for (auto it = done.rbegin(); it != done.rend(); ++it) {
            if (!it->previous.empty())
                std::rename(it->previous.c_str(), it->path.c_str());
            else
                std::remove(it->path.c_str());
        }
    };
    for (PendingImage& p : images) {
        Done d{p.path_, ""};
        std::error_code ec;
        if (fs::is_regular_file(p.path_, ec)) {
            const std::string keep = temporarySibling(p.path_);
            if (::link(p.path_.c_str(), keep.c_str()) == 0) d.previous = keep;
        }
        fs::rename(p.temporary_, p.path_, ec);
        if (ec) {
            if (!d.previous.empty()) std::remove(d.previous.c_str());
            undo();
            throw Error("cannot write '" + p.path_ + "': " + ec.message() +
                        (done.empty() ? "" : " (the files put in place before it were restored)"));
        }
        p.temporary_.clear();
        done.push_back(d);
    }
    for (const Done& d : done)
        if (!d.previous.empty()) std::remove(d.previous.c_str());
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
    if (extra.data.size() != n * k)
        throw Error("internal: extra channels do not match the image size");
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
    // A damaged file's libpng lines ("libpng error: IDAT: Read error", "PNG library error") are
    // not printed beside Lobe's error, which names the file and says the same.
    StderrCapture quiet;
    auto in = OIIO::ImageInput::open(path);
    if (!in) throw Error("cannot read image '" + path + "': " + oneLine(OIIO::geterror()));
    const OIIO::ImageSpec& spec = in->spec();
    FloatImage image;
    image.width = spec.width;
    image.height = spec.height;
    image.channels.names = spec.channelnames;
    image.channels.data.resize(size_t(spec.width) * spec.height * spec.nchannels);
    if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, image.channels.data.data()))
        throw Error("cannot read image '" + path + "': " + oneLine(in->geterror()));
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
    // A damaged file's libpng lines ("libpng error: IDAT: Read error", "PNG library error") are
    // not printed beside Lobe's error, which names the file and says the same.
    StderrCapture quiet;
    auto in = OIIO::ImageInput::open(path);
    if (!in) throw Error("cannot read image '" + path + "': " + oneLine(OIIO::geterror()));
    ImageAttributes attributes;
    for (const OIIO::ParamValue& p : in->spec().extra_attribs)
        if (p.type() == OIIO::TypeDesc::STRING) attributes[p.name().string()] = p.get_string();
    return attributes;
}

void forEachRgbBand(const std::string& path, long long bandPixels,
                    const std::function<void(RgbImage&, int)>& fn) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) throw Error("cannot read image '" + path + "': " + oneLine(OIIO::geterror()));
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
    const int bandRows = int(
        std::clamp<long long>(bandPixels / std::max(1, spec.width), 1, std::max(1, spec.height)));
    std::vector<float> rows;
    for (int y0 = 0; y0 < spec.height; y0 += bandRows) {
        const int y1 = std::min(spec.height, y0 + bandRows);
        rows.resize(size_t(spec.width) * size_t(y1 - y0) * size_t(count));
        if (!in->read_scanlines(0, 0, y0, y1, 0, first, first + count, OIIO::TypeDesc::FLOAT,
                                rows.data()))
            throw Error("cannot read image '" + path + "': " + oneLine(in->geterror()));
        RgbImage band(spec.width, y1 - y0);
        for (size_t p = 0; p < size_t(spec.width) * size_t(y1 - y0); ++p)
            for (int c = 0; c < 3; ++c)
                band.rgb[p * 3 + size_t(c)] = rows[p * size_t(count) + size_t(channel[c] - first)];
        fn(band, spec.height);
    }
}

RgbImage readImage(const std::string& path) {
    // A damaged file's libpng lines ("libpng error: IDAT: Read error", "PNG library error") are
    // not printed beside Lobe's error, which names the file and says the same.
    StderrCapture quiet;
    auto in = OIIO::ImageInput::open(path);
    if (!in) throw Error("cannot read image '" + path + "': " + oneLine(OIIO::geterror()));
    const OIIO::ImageSpec& spec = in->spec();
    std::vector<float> data(size_t(spec.width) * spec.height * spec.nchannels);
    if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, data.data()))
        throw Error("cannot read image '" + path + "': " + oneLine(in->geterror()));
    const bool encoded =
        spec.format == OIIO::TypeDesc::UINT8 || spec.format == OIIO::TypeDesc::UINT16;
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
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return std::tolower(c); });
    return ext;
}

}  // namespace lobe
