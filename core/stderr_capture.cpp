#include "core/stderr_capture.h"

#include <unistd.h>

namespace lobe {
namespace {

std::recursive_mutex& captureMutex() {
    static std::recursive_mutex m;
    return m;
}

}  // namespace

StderrCapture::StderrCapture() : lock_(captureMutex()) {
    std::fflush(stderr);
    file_ = std::tmpfile();
    saved_ = file_ ? ::dup(2) : -1;
    if (saved_ >= 0 && ::dup2(::fileno(file_), 2) < 0) {
        ::close(saved_);
        saved_ = -1;
    }
}

StderrCapture::~StderrCapture() {
    if (saved_ >= 0) {
        std::fflush(stderr);
        ::dup2(saved_, 2);
        ::close(saved_);
    }
    if (file_) std::fclose(file_);
}

std::string StderrCapture::take() {
    std::fflush(stderr);
    if (!file_) return "";
    std::fflush(file_);
    const long end = std::ftell(file_);
    std::string text;
    if (end > 0) {
        text.resize(size_t(end));
        std::rewind(file_);
        text.resize(std::fread(text.data(), 1, text.size(), file_));
        std::rewind(file_);
        if (::ftruncate(::fileno(file_), 0) != 0) text += "";
    }
    return text;
}

}  // namespace lobe
