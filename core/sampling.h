// Jittered (stratified) sample positions inside a pixel.
#pragma once

#include "core/math.h"
#include "core/rng.h"

namespace lobe {

// The strata grid for n samples: rows × cols = n with the two as close to square as possible
// (16 → 4×4, 8 → 2×4, 7 → 1×7), so every count the CLI accepts is stratified exactly.
struct StrataGrid {
    int rows = 1;
    int cols = 1;
};
StrataGrid strataFor(int sampleCount);

// Sample `index` of `grid` in stratum units: (col + jx, row + jy), the stratum's column and row
// plus a uniform jitter each (jx drawn first). jitteredSample divides it by the grid's size.
inline Vec2 jitteredStratumPoint(const StrataGrid& grid, int index, Rng& rng) {
    const int row = index / grid.cols;
    const int col = index % grid.cols;
    const double jx = rng.uniform();
    const double jy = rng.uniform();
    return Vec2(col + jx, row + jy);
}

// Position in [0,1)² of sample `index` of `grid`: the stratum's corner plus a uniform jitter.
// Inline: the pixel loop calls it once per sample.
inline Vec2 jitteredSample(const StrataGrid& grid, int index, Rng& rng) {
    const Vec2 p = jitteredStratumPoint(grid, index, rng);
    return Vec2(p.x / grid.cols, p.y / grid.rows);
}

}  // namespace lobe
