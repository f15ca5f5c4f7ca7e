// Standard error caught while a library that prints its own messages runs — GDCM's trace and the
// libjpeg inside it, libpng inside OpenImageIO ("libpng error: IDAT: Read error", "PNG library
// error") — so that what it says is folded into Lobe's one error line, or dropped, instead of
// printed beside it. The process's file descriptor 2 goes to an unnamed temporary file while a
// capture lives; captures are serialised (one descriptor for the whole process), and nothing else
// of Lobe prints meanwhile. Without a temporary file (no writable /tmp) nothing is captured.
#pragma once

#include <cstdio>
#include <mutex>
#include <string>

namespace lobe {

class StderrCapture {
public:
    StderrCapture();
    ~StderrCapture();  // restores standard error; what was not taken is dropped
    StderrCapture(const StderrCapture&) = delete;
    StderrCapture& operator=(const StderrCapture&) = delete;

    // Everything written to standard error since the capture began or the last take().
    std::string take();

private:
    std::unique_lock<std::recursive_mutex> lock_;
    std::FILE* file_ = nullptr;
    int saved_ = -1;
};

}  // namespace lobe
