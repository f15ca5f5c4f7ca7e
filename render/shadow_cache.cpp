#include "render/shadow_cache.h"

#include <cmath>

namespace lobe {

ShadowCache::ShadowCache(const Vec3& lo, const Vec3& hi, double spacing, int lights,
                         long long maxNodes)
    : lo_(lo), spacing_(spacing > 0.0 && std::isfinite(spacing) ? spacing : 1.0) {
    const Vec3 extent(std::max(0.0, hi.x - lo.x), std::max(0.0, hi.y - lo.y),
                      std::max(0.0, hi.z - lo.z));
    for (;;) {
        long long count = 1;
        for (int a = 0; a < 3; ++a) {
            n_[a] = std::max(2, int(std::ceil(extent[a] / spacing_)) + 1);
            count *= n_[a];
        }
        if (count <= maxNodes) break;
        spacing_ *= 1.25;
    }
    for (int l = 0; l < lights; ++l) {
        values_.emplace_back(new std::atomic<float>[size_t(nodesPerLight())]);
        for (long long i = 0; i < nodesPerLight(); ++i)
            values_.back()[size_t(i)].store(-1.0f, std::memory_order_relaxed);
    }
}

long long ShadowCache::computedNodes() const {
    long long n = 0;
    for (const auto& v : values_)
        for (long long i = 0; i < nodesPerLight(); ++i)
            n += v[size_t(i)].load(std::memory_order_relaxed) >= 0.0f;
    return n;
}

}  // namespace lobe
