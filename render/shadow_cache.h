// A per-light transmittance cache for shadowed volume samples (SceneSpec::shadows = "cached";
// render/integrator.h, "Shadows"): the transmittance from the nodes of a regular world grid to
// each light, each node computed once by an exact shadow ray (Integrator::lightTransmittance,
// with a fixed lattice offset) and interpolated trilinearly between the 8 nodes around a sample
// — the "light volume" / deep-shadow idea of volume rendering (Behrens & Ratering 1998, "Adding
// shadows to a texture-based volume renderer"; Kniss et al. 2003 compute it per light slice).
// Nodes are computed lazily, the first time a sample needs them; a node's value depends only on
// its position and the light, whoever computes it, so images are the same for any thread count.
#pragma once

#include "core/math.h"

#include <algorithm>
#include <atomic>
#include <memory>
#include <vector>

namespace lobe {

class ShadowCache {
public:
    // Nodes over [lo, hi] spaced `spacing` (grown so that each light holds at most maxNodes).
    ShadowCache(const Vec3& lo, const Vec3& hi, double spacing, int lights,
                long long maxNodes = 1LL << 22);

    // The interpolated transmittance towards light `light` at world point p (clamped to the
    // box); compute(nodePosition) gives a node's value when it is not yet known.
    template <class Compute>
    double lookup(int light, const Vec3& p, Compute&& compute) const {
        double u[3];
        int i0[3];
        for (int a = 0; a < 3; ++a) {
            const double x = std::clamp((p[a] - lo_[a]) / spacing_, 0.0, double(n_[a] - 1));
            i0[a] = std::min(int(x), std::max(0, n_[a] - 2));
            u[a] = x - i0[a];
        }
        std::atomic<float>* values = values_[size_t(light)].get();
        double sum = 0.0;
        for (int c = 0; c < 8; ++c) {
            const int ix = i0[0] + (c & 1), iy = i0[1] + ((c >> 1) & 1), iz = i0[2] + ((c >> 2) & 1);
            const double w = ((c & 1) ? u[0] : 1 - u[0]) * ((c & 2) ? u[1] : 1 - u[1]) *
                             ((c & 4) ? u[2] : 1 - u[2]);
            if (w == 0.0) continue;
            std::atomic<float>& node = values[(size_t(iz) * n_[1] + iy) * n_[0] + ix];
            float v = node.load(std::memory_order_relaxed);
            if (v < 0.0f) {
                v = float(compute(lo_ + Vec3(ix, iy, iz) * spacing_));
                node.store(v, std::memory_order_relaxed);
            }
            sum += w * v;
        }
        return sum;
    }

    double spacing() const { return spacing_; }
    long long nodesPerLight() const { return (long long)n_[0] * n_[1] * n_[2]; }
    // Nodes computed so far, over all lights (for reports and tests).
    long long computedNodes() const;

private:
    Vec3 lo_;
    double spacing_ = 1.0;
    int n_[3] = {2, 2, 2};
    std::vector<std::unique_ptr<std::atomic<float>[]>> values_;  // per light; < 0: not computed
};

}  // namespace lobe
