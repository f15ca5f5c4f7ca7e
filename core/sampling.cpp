#include "core/sampling.h"

#include <cmath>

namespace lobe {

StrataGrid strataFor(int sampleCount) {
    const int n = std::max(1, sampleCount);
    int rows = static_cast<int>(std::floor(std::sqrt(double(n))));
    while (n % rows != 0) --rows;
    return {rows, n / rows};
}

}  // namespace lobe
