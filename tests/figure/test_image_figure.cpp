// Figure output at the image level (issue 12): UTF-8 captions drawn glyph for glyph (checked
// against FreeType's own bitmaps of the same characters, drawn here directly), a box for a
// missing glyph, 16-bit PNG, alpha in PNG and EXR with hand-computed samples, and string
// attributes (provenance) read back from PNG text chunks and EXR headers.
#include "core/error.h"
#include "core/image_output.h"
#include "core/utf8.h"
#include "figure/image_text.h"

#include <OpenImageIO/imageio.h>
#include <ft2build.h>
#include FT_FREETYPE_H
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using lobe::RgbImage;

fs::path testDir() {
    const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
    const fs::path d = fs::path(LOBE_BINARY_DIR) / "test-output" / "image_figure" /
                       (std::string(info->test_suite_name()) + "." + info->name());
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}

// ---- UTF-8 -----------------------------------------------------------------------------------

TEST(Utf8, DecodesTwoThreeAndFourByteCharacters) {
    // é = C3 A9 (U+00E9), μ = CE BC (U+03BC), € = E2 82 AC (U+20AC), 😀 = F0 9F 98 80 (U+1F600).
    const std::vector<char32_t> cps =
        lobe::decodeUtf8("a\xC3\xA9\xCE\xBC\xE2\x82\xAC\xF0\x9F\x98\x80");
    EXPECT_EQ(cps, (std::vector<char32_t>{U'a', 0xE9, 0x3BC, 0x20AC, 0x1F600}));
}

TEST(Utf8, InvalidBytesBecomeReplacementCharacters) {
    const char32_t r = lobe::kReplacementCharacter;
    // A lone continuation byte, a truncated sequence at the end, an overlong '/' (C0 AF), a
    // surrogate (ED A0 80), and a Latin-1 'é' (E9 followed by ASCII).
    EXPECT_EQ(lobe::decodeUtf8("\x80"), std::vector<char32_t>{r});
    EXPECT_EQ(lobe::decodeUtf8("x\xC3"), (std::vector<char32_t>{U'x', r}));
    EXPECT_EQ(lobe::decodeUtf8("\xC0\xAF"), (std::vector<char32_t>{r, r}));
    EXPECT_EQ(lobe::decodeUtf8("\xED\xA0\x80"), (std::vector<char32_t>{r, r, r}));
    EXPECT_EQ(lobe::decodeUtf8("caf\xE9!"), (std::vector<char32_t>{U'c', U'a', U'f', r, U'!'}));
}

TEST(Utf8, AsciiEscapesAreJsonEscapes) {
    EXPECT_EQ(lobe::asciiEscaped("{\"t\": \"\xC3\xA9 \xCE\xBC\"}"), "{\"t\": \"\\u00e9 \\u03bc\"}");
    EXPECT_EQ(lobe::asciiEscaped("\xF0\x9F\x98\x80"),
              "\\ud83d\\ude00");  // surrogate pair of U+1F600
    EXPECT_EQ(lobe::asciiEscaped("a\\b\n"), "a\\b\n");
}

// ---- captions --------------------------------------------------------------------------------

constexpr const char* kFont = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";

// The glyph of `cp` at `size` as FreeType renders it, placed with its pen at x and baseline at y
// on a black image, white coverage: what drawText must produce for that one character.
RgbImage directGlyph(char32_t cp, int w, int h, int x, int y, int size) {
    FT_Library lib;
    FT_Face face;
    EXPECT_EQ(FT_Init_FreeType(&lib), 0);
    EXPECT_EQ(FT_New_Face(lib, kFont, 0, &face), 0);
    FT_Set_Pixel_Sizes(face, 0, FT_UInt(size));
    EXPECT_NE(FT_Get_Char_Index(face, FT_ULong(cp)), 0u)
        << "DejaVu Sans lacks U+" << std::hex << cp;
    EXPECT_EQ(FT_Load_Char(face, FT_ULong(cp), FT_LOAD_RENDER), 0);
    RgbImage img(w, h);
    const FT_Bitmap& bm = face->glyph->bitmap;
    for (unsigned r = 0; r < bm.rows; ++r)
        for (unsigned c = 0; c < bm.width; ++c) {
            const int px = x + face->glyph->bitmap_left + int(c),
                      py = y - face->glyph->bitmap_top + int(r);
            if (px < 0 || py < 0 || px >= w || py >= h) continue;
            const float v = bm.buffer[int(r) * bm.pitch + int(c)] / 255.0f;
            for (int k = 0; k < 3; ++k) img.pixel(px, py)[k] = v;
        }
    FT_Done_Face(face);
    FT_Done_FreeType(lib);
    return img;
}

double maxDifference(const RgbImage& a, const RgbImage& b) {
    double m = 0.0;
    for (size_t i = 0; i < a.rgb.size(); ++i)
        m = std::max(m, double(std::abs(a.rgb[i] - b.rgb[i])));
    return m;
}

double sum(const RgbImage& a) {
    double s = 0.0;
    for (float v : a.rgb) s += v;
    return s;
}

TEST(Caption, NonAsciiCharactersAreTheirOwnGlyphs) {
    // é (U+00E9), μ (U+03BC), Ω (U+03A9), ° (U+00B0): each drawn alone equals FreeType's glyph.
    for (const auto& [text, cp] : std::vector<std::pair<std::string, char32_t>>{
             {"\xC3\xA9", 0xE9}, {"\xCE\xBC", 0x3BC}, {"\xCE\xA9", 0x3A9}, {"\xC2\xB0", 0xB0}}) {
        RgbImage drawn(40, 40);
        ASSERT_TRUE(lobe::drawText(drawn, 8, 30, text, 24));
        const RgbImage expected = directGlyph(cp, 40, 40, 8, 30, 24);
        EXPECT_GT(sum(expected), 10.0) << text;  // the glyph has ink
        EXPECT_LT(maxDifference(drawn, expected), 1e-6) << text;
    }
    // And é is not e: the accent is there.
    RgbImage e(40, 40), eAcute(40, 40);
    lobe::drawText(e, 8, 30, "e", 24);
    lobe::drawText(eAcute, 8, 30, "\xC3\xA9", 24);
    EXPECT_GT(maxDifference(e, eAcute), 0.5);
}

TEST(Caption, SecondCharacterFollowsTheFirstsAdvance) {
    // "aμ": μ's glyph sits at the pen after 'a' (no kerning pair between them in DejaVu Sans).
    FT_Library lib;
    FT_Face face;
    ASSERT_EQ(FT_Init_FreeType(&lib), 0);
    ASSERT_EQ(FT_New_Face(lib, kFont, 0, &face), 0);
    FT_Set_Pixel_Sizes(face, 0, 24);
    FT_Load_Char(face, 'a', FT_LOAD_DEFAULT);
    const int advance = int(face->glyph->advance.x >> 6);
    FT_Vector kern{0, 0};
    FT_Get_Kerning(face, FT_Get_Char_Index(face, 'a'), FT_Get_Char_Index(face, 0x3BC),
                   FT_KERNING_DEFAULT, &kern);
    FT_Done_Face(face);
    FT_Done_FreeType(lib);
    ASSERT_EQ(kern.x, 0);
    RgbImage both(60, 40), a(60, 40);
    lobe::drawText(both, 4, 30, "a\xCE\xBC", 24);
    lobe::drawText(a, 4, 30, "a", 24);
    const RgbImage mu = directGlyph(0x3BC, 60, 40, 4 + advance, 30, 24);
    // "aμ" is 'a' with μ's coverage blended over it: a · (1 − c) + c.
    RgbImage composed = a;
    for (size_t i = 0; i < composed.rgb.size(); ++i)
        composed.rgb[i] = float(a.rgb[i] * (1.0 - mu.rgb[i]) + mu.rgb[i]);
    EXPECT_LT(maxDifference(both, composed), 1e-6);
    EXPECT_EQ(lobe::textWidth("a\xCE\xBC", 24),
              lobe::textWidth("a", 24) + lobe::textWidth("\xCE\xBC", 24));
}

TEST(Caption, MissingGlyphAndInvalidBytesAreBoxes) {
    // 漢 (E6 BC A2, U+6F22) is not in DejaVu Sans: a box outline, exactly where missingGlyphBox
    // says, nothing else. A control character draws the same box.
    for (const std::string text : {"\xE6\xBC\xA2", "\x01"}) {
        RgbImage drawn(40, 40);
        ASSERT_TRUE(lobe::drawText(drawn, 5, 30, text, 24));
        const lobe::MissingGlyphBox b = lobe::missingGlyphBox(5, 30, 24);
        ASSERT_LT(b.x0 + 2, b.x1);
        ASSERT_LT(b.y0 + 2, b.y1);
        for (int y = 0; y < 40; ++y)
            for (int x = 0; x < 40; ++x) {
                const bool onEdge = (x >= b.x0 && x <= b.x1 && (y == b.y0 || y == b.y1)) ||
                                    (y >= b.y0 && y <= b.y1 && (x == b.x0 || x == b.x1));
                const bool inside = x > b.x0 + 1 && x < b.x1 - 1 && y > b.y0 + 1 && y < b.y1 - 1;
                if (onEdge) {
                    EXPECT_EQ(drawn.pixel(x, y)[0], 1.0f) << x << "," << y;
                }
                if (inside || x < b.x0 || x > b.x1 || y < b.y0 || y > b.y1) {
                    EXPECT_EQ(drawn.pixel(x, y)[0], 0.0f) << x << "," << y;
                }
            }
    }
}

// ---- integer formats, alpha, attributes --------------------------------------------------------

double srgb(double v) {
    return v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
}

TEST(ImageOutput, SixteenBitPngKeepsWhatEightBitsRound) {
    const fs::path d = testDir();
    RgbImage img(2, 1);
    img.rgb = {0.2f, 0.5f, 0.01f, 1.0f, 0.0f, 0.731f};
    lobe::ImageWriteOptions o16;
    o16.bits = 16;
    lobe::writeImagePending((d / "a16.png").string(), img, o16).commit();
    lobe::writeImage((d / "a8.png").string(), img);
    auto in = OIIO::ImageInput::open((d / "a16.png").string());
    ASSERT_TRUE(in);
    EXPECT_EQ(in->spec().format, OIIO::TypeDesc::UINT16);
    std::vector<unsigned short> raw(6);
    ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT16, raw.data()));
    for (size_t i = 0; i < 6; ++i) EXPECT_EQ(raw[i], std::lround(srgb(img.rgb[i]) * 65535.0)) << i;
    const RgbImage back16 = lobe::readImage((d / "a16.png").string());
    const RgbImage back8 = lobe::readImage((d / "a8.png").string());
    double err16 = 0, err8 = 0;
    for (size_t i = 0; i < 6; ++i) {
        err16 = std::max(err16, double(std::abs(back16.rgb[i] - img.rgb[i])));
        err8 = std::max(err8, double(std::abs(back8.rgb[i] - img.rgb[i])));
    }
    EXPECT_LT(err16, 2e-5);
    EXPECT_GT(err8, 2e-4);  // 8 bits cannot hold these values: the test can tell the two apart
    lobe::ImageWriteOptions jpeg16 = o16;
    EXPECT_THROW(lobe::writeImagePending((d / "a.jpg").string(), img, jpeg16), lobe::Error);
}

TEST(ImageOutput, AlphaIsStraightInPngAndAssociatedInExr) {
    const fs::path d = testDir();
    // Three pixels: fully covered (alpha 1), half covered with premultiplied colour 0.25 (straight
    // 0.5), empty (alpha 0, colour 0).
    RgbImage img(3, 1);
    img.rgb = {0.8f, 0.6f, 0.4f, 0.25f, 0.25f, 0.25f, 0.0f, 0.0f, 0.0f};
    const std::vector<float> alpha = {1.0f, 0.5f, 0.0f};
    lobe::ImageWriteOptions o;
    o.alpha = &alpha;
    lobe::writeImagePending((d / "a.png").string(), img, o).commit();
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    auto in = OIIO::ImageInput::open((d / "a.png").string(), &config);
    ASSERT_TRUE(in);
    ASSERT_EQ(in->spec().nchannels, 4);
    EXPECT_EQ(in->spec().alpha_channel, 3);
    std::vector<unsigned char> px(12);
    ASSERT_TRUE(in->read_image(0, 0, 0, 4, OIIO::TypeDesc::UINT8, px.data()));
    EXPECT_EQ(px[3], 255);
    EXPECT_EQ(px[0], std::lround(srgb(0.8) * 255));
    EXPECT_EQ(px[4], std::lround(srgb(0.5) * 255));  // 0.25 / 0.5
    EXPECT_EQ(px[7], 128);                           // 0.5 · 255 = 127.5, rounded half up
    EXPECT_EQ(px[8], 0);
    EXPECT_EQ(px[11], 0);

    lobe::Film film(3, 1);
    film.at(0, 0) = lobe::Spectrum(1.0);
    lobe::writeFilmPending((d / "a.exr").string(), film, 1.0, {}, o).commit();
    const lobe::FloatImage exr = lobe::readFloatImage((d / "a.exr").string());
    // OpenEXR keeps channels sorted by name (R, G, B, A first in OpenImageIO's reading).
    const auto& names = exr.channels.names;
    ASSERT_EQ(names.size(), 7u);
    EXPECT_EQ(names[3], "A");
    const auto channel = [&](const std::string& name, int pixel) {
        const size_t c = size_t(std::find(names.begin(), names.end(), name) - names.begin());
        EXPECT_LT(c, names.size()) << name;
        return exr.channels.data[size_t(pixel) * names.size() + c];
    };
    EXPECT_EQ(channel("A", 0), 1.0f);
    EXPECT_EQ(channel("A", 1), 0.5f);
    EXPECT_EQ(channel("A", 2), 0.0f);
    EXPECT_EQ(channel("band.700", 0), 1.0f);  // premultiplied as given, not divided
    EXPECT_EQ(channel("band.700", 1), 0.0f);
    EXPECT_THROW(lobe::writeImagePending((d / "a.jpg").string(), img, o), lobe::Error);
    EXPECT_FALSE(fs::exists(d / "a.jpg"));
}

// ---- band by band (posters)
// ----------------------------------------------------------------------

// Reads every sample of an image file as stored (integers as 0…255/65535, floats as they are).
std::vector<float> samplesOf(const fs::path& p, int* channels = nullptr) {
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    auto in = OIIO::ImageInput::open(p.string(), &config);
    if (!in) return {};
    const OIIO::ImageSpec& spec = in->spec();
    std::vector<float> data(size_t(spec.width) * spec.height * spec.nchannels);
    const bool integer = spec.format != OIIO::TypeDesc::FLOAT;
    if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, data.data())) return {};
    if (integer)  // back to the stored integers: exact in a float
        for (float& v : data)
            v = std::round(v * (spec.format == OIIO::TypeDesc::UINT16 ? 65535.0f : 255.0f));
    if (channels) *channels = spec.nchannels;
    return data;
}

// A 7 × 5 image whose every sample differs, with coverage from 0 to 1.
struct Sample7x5 {
    RgbImage rgb{7, 5};
    lobe::Film film{7, 5};
    std::vector<float> alpha = std::vector<float>(35);
    Sample7x5() {
        for (int i = 0; i < 35; ++i) {
            alpha[size_t(i)] = float(i % 6) / 5.0f;
            for (int c = 0; c < 3; ++c)
                rgb.rgb[size_t(i) * 3 + size_t(c)] = alpha[size_t(i)] * float(i + c) / 40.0f;
            film.at(i % 7, i / 7) = lobe::Spectrum(0.01 * i, 0.02 * i, 0.5 - 0.01 * i);
        }
    }
};

TEST(ImageBandWriter, BandsGiveTheSamePixelsAsOneWrite) {
    const fs::path d = testDir();
    const Sample7x5 s;
    for (const std::string ext : {".png", ".tif", ".exr"}) {
        for (const int bits : {8, 16}) {
            if (ext == ".exr" && bits == 16) continue;
            lobe::ImageWriteOptions o;
            o.alpha = &s.alpha;
            o.bits = bits;
            const std::string whole = (d / ("whole" + std::to_string(bits) + ext)).string();
            const std::string banded = (d / ("banded" + std::to_string(bits) + ext)).string();
            std::vector<std::string> names{"R", "G", "B"};
            std::vector<float> data = s.rgb.rgb;
            if (ext == ".exr") {
                lobe::writeFilmPending(whole, s.film, 1.0, {}, o).commit();
                names = lobe::filmChannelNames({});
                data = lobe::filmChannels(s.film, 1.0, {});
            } else {
                lobe::writeImagePending(whole, s.rgb, o).commit();
            }
            // Rows 0-1, 2-3, then 4: bands of 2 and a last band of 1.
            lobe::ImageBandWriter w(banded, 7, 5, names, true, o);
            for (int y0 = 0; y0 < 5; y0 += 2) {
                const int rows = std::min(2, 5 - y0);
                w.write(rows, &data[size_t(y0) * 7 * names.size()], &s.alpha[size_t(y0) * 7]);
            }
            EXPECT_EQ(w.rowsWritten(), 5);
            EXPECT_FALSE(fs::exists(banded));  // not in place before finish() and commit()
            w.finish().commit();
            int channels = 0;
            const std::vector<float> a = samplesOf(whole, &channels), b = samplesOf(banded);
            ASSERT_FALSE(a.empty()) << whole;
            EXPECT_EQ(channels, ext == ".exr" ? 7 : 4);
            EXPECT_EQ(a, b) << banded;
        }
    }
    // Hand-computed: pixel 5 of the 8-bit PNG has alpha 1 and colour 1·(5 + c)/40 → sRGB;
    // pixel 6 has alpha 0 → all 0; pixel 3 alpha 0.6 (153) and straight colour (3 + c)/40.
    const std::vector<float> png = samplesOf(d / "banded8.png");
    for (int c = 0; c < 3; ++c) {
        EXPECT_EQ(png[5 * 4 + size_t(c)], std::lround(srgb((5.0 + c) / 40.0) * 255)) << c;
        EXPECT_EQ(png[6 * 4 + size_t(c)], 0.0f) << c;
        const double straight = double(0.6f * float(3 + c) / 40.0f) / double(0.6f);
        EXPECT_EQ(png[3 * 4 + size_t(c)], std::lround(srgb(straight) * 255)) << c;
    }
    EXPECT_EQ(png[5 * 4 + 3], 255.0f);
    EXPECT_EQ(png[3 * 4 + 3], 153.0f);
}

TEST(ImageBandWriter, RgbBandsReadBackAsWritten) {
    // An EXR with A between B and the bands: R, G, B read back band by band (bands of 14 pixels:
    // 2 rows of 7, the last of 1) are the floats written, pixel for pixel.
    const fs::path d = testDir();
    const Sample7x5 s;
    lobe::ImageWriteOptions o;
    o.alpha = &s.alpha;
    lobe::writeFilmPending((d / "a.exr").string(), s.film, 1.0, {}, o).commit();
    const std::vector<float> written = lobe::filmChannels(s.film, 1.0, {});  // 6 a pixel
    std::vector<int> heights;
    std::vector<float> rgb;
    lobe::forEachRgbBand((d / "a.exr").string(), 14, [&](lobe::RgbImage& band, int height) {
        EXPECT_EQ(height, 5);
        EXPECT_EQ(band.width, 7);
        heights.push_back(band.height);
        rgb.insert(rgb.end(), band.rgb.begin(), band.rgb.end());
    });
    EXPECT_EQ(heights, (std::vector<int>{2, 2, 1}));
    ASSERT_EQ(rgb.size(), 35u * 3);
    for (size_t p = 0; p < 35; ++p)
        for (size_t c = 0; c < 3; ++c) EXPECT_EQ(rgb[p * 3 + c], written[p * 6 + c]) << p << c;
    EXPECT_GT(rgb[34 * 3 + 2], 0.0f);  // not all zero
    // A file without R, G, B channels: one error naming it.
    lobe::FloatImage bands;
    bands.width = 2;
    bands.height = 1;
    bands.channels.names = {"X", "Y", "Z"};
    bands.channels.data.assign(6, 0.5f);
    lobe::writeFloatImage((d / "xyz.exr").string(), bands);
    try {
        lobe::forEachRgbBand((d / "xyz.exr").string(), 14, [](lobe::RgbImage&, int) {});
        ADD_FAILURE() << "no error for an image without R";
    } catch (const lobe::Error& e) {
        EXPECT_NE(std::string(e.what()).find("xyz.exr: no channel R"), std::string::npos)
            << e.what();
    }
}

std::string readText(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

// Only the temporary file (dot-named) may exist before finish(); nothing at all after an abandon.
std::vector<std::string> filesIn(const fs::path& d) {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(d)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

TEST(ImageBandWriter, AnUnfinishedImageLeavesNoFile) {
    const fs::path d = testDir();
    const Sample7x5 s;
    std::ofstream(d / "old.png") << "an earlier file, kept";
    ::testing::internal::CaptureStderr();  // a PNG closed short of its rows: libpng stays quiet
    {
        lobe::ImageBandWriter w((d / "old.png").string(), 7, 5, {"R", "G", "B"}, false);
        w.write(2, s.rgb.rgb.data());
        const std::vector<std::string> during = filesIn(d);
        ASSERT_EQ(during.size(), 2u);  // old.png and the temporary file beside it
        EXPECT_EQ(during[0].rfind(".old.partial-", 0), 0u) << during[0];
        // finish() with rows missing: an error naming the file; the old file stays as it was.
        try {
            (void)w.finish();
            ADD_FAILURE() << "finish() accepted 2 of 5 rows";
        } catch (const lobe::Error& e) {
            EXPECT_NE(std::string(e.what()).find("old.png"), std::string::npos) << e.what();
        }
        // More rows than the image has: refused.
        EXPECT_THROW(w.write(4, s.rgb.rgb.data()), lobe::Error);
    }
    EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
    EXPECT_EQ(filesIn(d), std::vector<std::string>{"old.png"});
    EXPECT_EQ(readText(d / "old.png"), "an earlier file, kept");
    {  // abandoned without an error (a render that threw): the same
        lobe::ImageBandWriter w((d / "new.exr").string(), 7, 5, lobe::filmChannelNames({}), true);
        const std::vector<float> data = lobe::filmChannels(s.film, 1.0, {});
        w.write(3, data.data(), s.alpha.data());
    }
    EXPECT_EQ(filesIn(d), std::vector<std::string>{"old.png"});
}

TEST(ImageOutput, AttributesReadBackFromPngAndExr) {
    const fs::path d = testDir();
    RgbImage img(2, 2);
    lobe::ImageWriteOptions o;
    const std::string json = "{\n \"title\": \"\\u00e9 \\u03bc\",\n \"image\": {\"seed\": 3}\n}\n";
    o.attributes = {{"lobe:scene_json", json},
                    {"lobe:seed", "3"},
                    {"lobe:command_line", "lobe render 'a b.json'"}};
    lobe::writeImagePending((d / "a.png").string(), img, o).commit();
    lobe::Film film(2, 2);
    lobe::writeFilmPending((d / "a.exr").string(), film, 1.0, {}, o).commit();
    for (const char* name : {"a.png", "a.exr"}) {
        const lobe::ImageAttributes back = lobe::readImageAttributes((d / name).string());
        for (const auto& [key, value] : o.attributes) {
            ASSERT_TRUE(back.count(key)) << name << " " << key;
            EXPECT_EQ(back.at(key), value) << name << " " << key;
        }
    }
}

}  // namespace

namespace {

// A set of files put in place together (PendingImage::commitAll): when a later rename fails (its
// folder gone: the rename finds no temporary), the earlier file is undone — the file it replaced
// is back as it was, and a file that was new is removed; the error names the failing path. With a
// final path that is a folder, nothing is renamed at all.
TEST(ImageOutput, CommitAllUndoesEarlierRenamesWhenALaterFails) {
    const fs::path d = testDir();
    fs::create_directories(d / "a");
    fs::create_directories(d / "b");
    std::ofstream(d / "a" / "x.png") << "an earlier figure";
    lobe::RgbImage img(2, 2);
    {
        std::vector<lobe::PendingImage> files;
        files.push_back(lobe::writeImagePending((d / "a" / "x.png").string(), img));
        files.push_back(lobe::writeImagePending((d / "a" / "new.png").string(), img));
        files.push_back(lobe::writeImagePending((d / "b" / "x.png").string(), img));
        fs::remove_all(d / "b");  // the third rename fails
        try {
            lobe::PendingImage::commitAll(files);
            ADD_FAILURE() << "commitAll succeeded without its third file";
        } catch (const lobe::Error& e) {
            EXPECT_NE(std::string(e.what()).find((d / "b" / "x.png").string()), std::string::npos)
                << e.what();
            EXPECT_NE(std::string(e.what()).find("restored"), std::string::npos) << e.what();
        }
    }
    std::ifstream in(d / "a" / "x.png");
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_EQ(text, "an earlier figure");
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(d / "a"))
        names.push_back(e.path().filename().string());
    EXPECT_EQ(names, std::vector<std::string>{"x.png"});  // no new.png, no temporary, no backup
    // A folder where a file goes: refused before any rename.
    fs::create_directories(d / "c" / "y.exr");
    {
        std::vector<lobe::PendingImage> files;
        files.push_back(lobe::writeImagePending((d / "c" / "y.png").string(), img));
        files.push_back(lobe::writeImagePending((d / "c" / "y.exr").string(), img));
        EXPECT_THROW(lobe::PendingImage::commitAll(files), lobe::Error);
    }
    names.clear();
    for (const auto& e : fs::directory_iterator(d / "c"))
        names.push_back(e.path().filename().string());
    EXPECT_EQ(names, std::vector<std::string>{"y.exr"});
}

}  // namespace
