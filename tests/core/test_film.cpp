// core/film.h: a film's pixels start at zero with the zeroed allocator (calloc, no per-pixel
// pass), whatever the heap held before, and copies keep their values.
#include "core/film.h"

#include <gtest/gtest.h>

#include <memory>

using namespace lobe;

TEST(Film, NewFilmsAreZeroEvenWhereTheHeapHeldOtherValues) {
    for (int round = 0; round < 4; ++round) {
        // Sizes below and above glibc's mmap threshold (heap chunks are reused, not fresh).
        for (const auto& [w, h] : {std::pair{7, 5}, std::pair{64, 64}, std::pair{700, 600}}) {
            {
                Film dirty(w, h);
                for (int y = 0; y < h; ++y)
                    for (int x = 0; x < w; ++x) dirty.at(x, y) = Spectrum(1.5, -2.0, 3.0);
            }
            const Film film(w, h);
            ASSERT_EQ(film.pixels().size(), size_t(w) * h);
            for (const Spectrum& s : film.pixels()) ASSERT_EQ(s, Spectrum(0.0));
        }
    }
    Film a(3, 2);
    a.at(2, 1) = Spectrum(1, 2, 3);
    const Film b = a;
    EXPECT_EQ(b.at(2, 1), Spectrum(1, 2, 3));
    EXPECT_EQ(b.at(0, 0), Spectrum(0.0));
    EXPECT_EQ(Film().pixels().size(), 0u);
}
