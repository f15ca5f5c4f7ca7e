// UTF-8 decoding (RFC 3629) for text drawn into images and written into file headers. Bytes
// that do not form a valid sequence (a stray continuation byte, a truncated or overlong
// sequence, a surrogate, a value above U+10FFFF) decode to U+FFFD, one per bad byte, so broken
// text shows up as replacement characters instead of turning into other characters.
#pragma once

#include <cstdio>
#include <string>
#include <vector>

namespace lobe {

constexpr char32_t kReplacementCharacter = 0xFFFD;

inline std::vector<char32_t> decodeUtf8(const std::string& text) {
    std::vector<char32_t> out;
    const auto* s = reinterpret_cast<const unsigned char*>(text.data());
    const size_t n = text.size();
    for (size_t i = 0; i < n;) {
        const unsigned char b = s[i];
        int length = 0;
        char32_t cp = 0, min = 0;
        if (b < 0x80)
            length = 1, cp = b;
        else if ((b & 0xE0) == 0xC0)
            length = 2, cp = b & 0x1F, min = 0x80;
        else if ((b & 0xF0) == 0xE0)
            length = 3, cp = b & 0x0F, min = 0x800;
        else if ((b & 0xF8) == 0xF0)
            length = 4, cp = b & 0x07, min = 0x10000;
        bool ok = length > 0 && i + size_t(length) <= n;
        for (int k = 1; ok && k < length; ++k) {
            if ((s[i + size_t(k)] & 0xC0) != 0x80)
                ok = false;
            else
                cp = (cp << 6) | (s[i + size_t(k)] & 0x3F);
        }
        if (ok && (cp < min || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF))) ok = false;
        if (!ok) {
            out.push_back(kReplacementCharacter);
            ++i;
            continue;
        }
        out.push_back(cp);
        i += size_t(length);
    }
    return out;
}

// The text with every character outside printable ASCII written as a JSON escape \uXXXX (a
// surrogate pair above U+FFFF), backslashes left as they are: JSON text stays the same JSON,
// and the result is plain ASCII, as PNG's tEXt chunks expect.
inline std::string asciiEscaped(const std::string& text) {
    std::string out;
    char buf[16];
    auto escape = [&](unsigned v) {
        std::snprintf(buf, sizeof buf, "\\u%04x", v);
        out += buf;
    };
    for (char32_t cp : decodeUtf8(text)) {
        if ((cp >= 0x20 && cp < 0x7F) || cp == '\n' || cp == '\t' || cp == '\r') {
            out += char(cp);
        } else if (cp < 0x10000) {
            escape(unsigned(cp));
        } else {
            const unsigned v = unsigned(cp) - 0x10000;
            escape(0xD800 + (v >> 10));
            escape(0xDC00 + (v & 0x3FF));
        }
    }
    return out;
}

}  // namespace lobe
