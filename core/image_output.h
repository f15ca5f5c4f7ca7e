// Writing images with OpenImageIO. The format follows the extension: .exr keeps linear floats
// (R, G, B in linear sRGB and, for a Film, the three bands as channels band.700, band.546_1,
// band.435_8); .png, .tif, .jpg get 8-bit sRGB-encoded values (.png also 16-bit, see
// ImageWriteOptions). With an alpha (coverage) channel the colour given is premultiplied by it
// (associated alpha, as an EXR stores it: channel A after R, G, B); PNG and TIFF store colour
// divided by alpha (straight alpha, as those formats expect), JPEG has no alpha and refuses it.
// String attributes go into an EXR's header and a PNG's text chunks (iTXt/tEXt). Files are written
// under a temporary name in the same folder and renamed, so a failed write never leaves a partial
// file. This lives in its own library (lobe_image_io) because OpenImageIO costs every process that
// links it ~0.3 s of start-up (docs/dependencies.md, pitfall 3).
#pragma once

#include "core/film.h"
#include "core/rgb_image.h"

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace lobe {

// Extra float channels for an EXR beside a film's own: names.size() floats per pixel.
struct ImageChannels {
    std::vector<std::string> names;
    std::vector<float> data;  // [pixel · names.size() + channel]
};

// String attributes stored in an EXR's header (e.g. "lobe:shard") and as PNG text chunks; JPEG
// and TIFF ignore them.
using ImageAttributes = std::map<std::string, std::string>;

struct ImageWriteOptions {
    ImageAttributes attributes;
    int bits = 8;  // integer formats: 8, or 16 for .png and .tif
    // Coverage per pixel in [0, 1] (width · height values), the colour premultiplied by it; null:
    // opaque. Written as channel A.
    const std::vector<float>* alpha = nullptr;
};

// An image written completely under a temporary name beside its path, not yet in place:
// commit() renames it there; destroyed uncommitted (an error in a later file of the same set),
// or on SIGINT/SIGTERM (core/interrupt.h), the temporary file is removed. So a command that
// writes several files (a render's PNG and EXR) puts them in place only when all were written.
class PendingImage {
public:
    PendingImage(std::string temporary, std::string path);
    PendingImage(PendingImage&& other) noexcept;
    PendingImage& operator=(PendingImage&&) = delete;
    ~PendingImage();
    void commit();  // throws lobe::Error naming the path if the rename fails
    // Puts a set of files in place together (a render's PNG and EXR): every final path checked
    // before the first rename (a folder of that name refuses the set), then renamed in order;
    // when a later rename fails, the earlier ones are undone — a file that replaced another is
    // put back (the old one kept as a hard link until all are in place), a new one removed.
    // Throws lobe::Error naming the path; every temporary is removed either way.
    static void commitAll(std::vector<PendingImage>& images);
    const std::string& path() const { return path_; }

private:
    std::string temporary_, path_;
    std::unique_ptr<class RemovedOnInterrupt> guard_;
};

// An image file written band by band — rows in order, top first — under a temporary name beside
// its path: a poster's rows are written as they are rendered and never held at once. The
// whole-image writers below are one band of it, so both give the same file.
//  - channelNames: the floats of each pixel given to write(). An EXR stores them all; PNG, TIFF
//    and JPEG take the first three as linear sRGB and encode them (options.bits).
//  - withAlpha: write() also takes the coverage, stored as channel A (the colour given is
//    premultiplied by it); options.alpha is ignored here.
// The constructor opens the temporary file; it throws lobe::Error naming the path for an
// unsupported extension, a missing folder, alpha in a JPEG or a bit depth the format lacks.
// Destroyed before finish() (an error, a failed render), the temporary file is removed, and on
// SIGINT/SIGTERM too (core/interrupt.h): no partial file is left under any name.
class ImageBandWriter {
public:
    ImageBandWriter(const std::string& path, int width, int height,
                    const std::vector<std::string>& channelNames, bool withAlpha,
                    const ImageWriteOptions& options = {});
    ~ImageBandWriter();
    ImageBandWriter(const ImageBandWriter&) = delete;
    ImageBandWriter& operator=(const ImageBandWriter&) = delete;

    // The next `rows` rows: rows · width · channelNames.size() floats, and rows · width
    // coverages when the image has alpha (null otherwise).
    void write(int rows, const float* data, const float* alpha = nullptr);
    int rowsWritten() const;
    // After the last row: closes the file and checks it — PNG, TIFF and JPEG are read back band
    // by band, a lossless one compared with what was written (a full disk shows there) — and
    // returns it pending (not yet in place).
    [[nodiscard]] PendingImage finish();

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// A film's EXR channels: R, G, B (linear sRGB × exposure), the three bands × exposure, then
// `extra`'s; the floats interleaved per pixel, as the writers take them.
std::vector<std::string> filmChannelNames(const ImageChannels& extra);
std::vector<float> filmChannels(const Film& film, double exposure, const ImageChannels& extra);

// Throws lobe::Error naming the path when the extension is unsupported or writing fails.
void writeImage(const std::string& path, const RgbImage& image);
// `extra` channels (an EXR only; ignored by 8-bit formats) follow R, G, B and the bands.
void writeFilm(const std::string& path, const Film& film, double exposure = 1.0,
               const ImageChannels& extra = {}, const ImageAttributes& attributes = {});
// The same, left pending (see PendingImage).
[[nodiscard]] PendingImage writeImagePending(const std::string& path, const RgbImage& image,
                                             const ImageWriteOptions& options = {});
[[nodiscard]] PendingImage writeFilmPending(const std::string& path, const Film& film,
                                            double exposure = 1.0, const ImageChannels& extra = {},
                                            const ImageAttributes& attributes = {});
[[nodiscard]] PendingImage writeFilmPending(const std::string& path, const Film& film,
                                            double exposure, const ImageChannels& extra,
                                            const ImageWriteOptions& options);

// Every string attribute of an image file (EXR header, PNG text chunks), by name.
ImageAttributes readImageAttributes(const std::string& path);

// Every channel of a float image as stored, and its "lobe:" attributes: what `lobe merge`
// assembles shard parts from, so the merged file holds exactly the floats a single render writes.
struct FloatImage {
    int width = 0, height = 0;
    ImageChannels channels;  // names in the file's order, data interleaved
    ImageAttributes attributes;
};
FloatImage readFloatImage(const std::string& path);
// Writes a FloatImage (an .exr path) with its attributes.
void writeFloatImage(const std::string& path, const FloatImage& image);

// The R, G, B channels of an image file as stored, in bands of rows of about `bandPixels` pixels
// (at least one row), top first: fn(band, imageHeight), the band fn's to change. What builds a
// poster's contact-sheet thumbnail from its EXR without holding the image. Throws lobe::Error
// naming the path and a missing channel.
void forEachRgbBand(const std::string& path, long long bandPixels,
                    const std::function<void(RgbImage& band, int imageHeight)>& fn);

// Reads any image OpenImageIO understands into linear sRGB (8-bit files are decoded from sRGB).
RgbImage readImage(const std::string& path);

// True for the extensions writeImage accepts.
bool isSupportedImageExtension(const std::string& path);

// The file name's extension in lower case, with its dot (".png"); empty when there is none.
std::string lowerExtension(const std::string& path);

}  // namespace lobe
