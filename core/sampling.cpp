#include "core/sampling.h"

#include <cmath>

namespace lobe {

StrataGrid strataFor(int sampleCount) {
    const int n = std::max(1, sampleCount);
    int rows = static_cast<int>(std::floor(std::sqrt(double(n))));
    while (n % rows != 0) --rows;
    return {rows, n / rows};
}

Vec2 jitteredSample(const StrataGrid& grid, int index, Rng& rng) {
    const int row = index / grid.cols;
    const int col = index % grid.cols;
    const double jx = rng.uniform();
    const double jy = rng.uniform();
    return Vec2((col + jx) / grid.cols, (row + jy) / grid.rows);
}

}  // namespace lobe
