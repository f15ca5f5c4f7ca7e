// The image being rendered: one band triple per pixel (linear, unbounded), row-major, row 0 at
// the top. Writing it to disk is core/image_output.h's job.
#pragma once

#include "core/spectrum.h"

#include <cstdlib>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

namespace lobe {

// The film's allocator: zeroed memory from calloc, and no per-element pass for the value-
// initialised elements of the film's constructor, since all-zero bits are Spectrum() exactly
// (three doubles +0.0). A large film thus comes straight from fresh zero pages of the kernel,
// first touched by the render threads that write its tiles, in parallel, instead of by one
// thread zeroing it before the render starts (a 1024² film is 24 MB: about 14 ms of one core,
// 6 % of the T1 skull's render time on 2 cores; docs/performance.md). Only Film's constructor
// creates elements without a value, and only in memory just allocated.
template <class T>
struct ZeroedAllocator {
    static_assert(std::is_trivially_copyable_v<T> && std::is_trivially_destructible_v<T>,
                  "all-zero bits must be a valid value");
    using value_type = T;
    ZeroedAllocator() = default;
    template <class U>
    ZeroedAllocator(const ZeroedAllocator<U>&) {}
    T* allocate(std::size_t n) {
        void* p = std::calloc(n, sizeof(T));
        if (!p && n > 0) throw std::bad_alloc();
        return static_cast<T*>(p);
    }
    void deallocate(T* p, std::size_t) { std::free(p); }
    template <class U>
    void construct(U*) noexcept {}  // already zero: calloc
    template <class U, class... Args>
    void construct(U* p, Args&&... args) {
        ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }
    template <class U>
    bool operator==(const ZeroedAllocator<U>&) const {
        return true;
    }
    template <class U>
    bool operator!=(const ZeroedAllocator<U>&) const {
        return false;
    }
};

using FilmPixels = std::vector<Spectrum, ZeroedAllocator<Spectrum>>;

class Film {
public:
    Film() = default;
    Film(int width, int height) : width_(width), height_(height), pixels_(size_t(width) * height) {}

    int width() const { return width_; }
    int height() const { return height_; }
    Spectrum& at(int x, int y) { return pixels_[size_t(y) * width_ + x]; }
    const Spectrum& at(int x, int y) const { return pixels_[size_t(y) * width_ + x]; }
    const FilmPixels& pixels() const { return pixels_; }
    Spectrum* data() { return pixels_.data(); }

private:
    int width_ = 0;
    int height_ = 0;
    FilmPixels pixels_;
};

}  // namespace lobe
