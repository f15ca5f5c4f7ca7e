// A per-light transmittance cache for shadows (SceneSpec::shadows = "cached"; render/integrator.h,
// "Shadows"): the transmittance through the casting objects from the nodes of a regular world
// grid over their boxes to each light, each node computed once by a shadow ray
// (Integrator::lightTransmittance, a fixed lattice offset) and interpolated trilinearly between
// the 8 nodes around a point — the "light volume" / deep-shadow idea of volume rendering
// (Behrens & Ratering 1998, "Adding shadows to a texture-based volume renderer"; Kniss et al.
// 2003 compute it per light slice). Surface points interpolate only the nodes on the light's side
// of their tangent plane (lookupAbove).
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
        return interpolate(light, p, nullptr, compute);
    }

    // The same from the nodes of p's cell that lie strictly on the side of the plane through p
    // with normal n that n points to (their trilinear weights renormalised): a surface point
    // interpolates only nodes on the light's side of its tangent plane, whose shadow rays do not
    // cross the surface itself (render/integrator.h, "Shadows"). A negative value when no node
    // of the cell lies on that side (p on a cell face with n along it).
    template <class Compute>
    double lookupAbove(int light, const Vec3& p, const Vec3& n, Compute&& compute) const {
        return interpolate(light, p, &n, compute);
    }

    // The point where the segment from p to `to` enters the cache's box (p itself when inside);
    // false when the segment misses the box. Transmittance through what lies only inside the
    // box is the same from p as from that point.
    bool entry(const Vec3& p, const Vec3& to, Vec3& q) const {
        const Vec3 hi = lo_ + Vec3(n_[0] - 1, n_[1] - 1, n_[2] - 1) * spacing_;
        if (p.x >= lo_.x && p.y >= lo_.y && p.z >= lo_.z && p.x <= hi.x && p.y <= hi.y &&
            p.z <= hi.z) {
            q = p;
            return true;
        }
        const Vec3 d = to - p;
        double t0 = 0.0, t1 = 1.0;  // the slab method (Kay & Kajiya 1986) on the segment
        for (int a = 0; a < 3; ++a) {
            if (d[a] == 0.0) {
                if (p[a] < lo_[a] || p[a] > hi[a]) return false;
                continue;
            }
            double ta = (lo_[a] - p[a]) / d[a], tb = (hi[a] - p[a]) / d[a];
            if (ta > tb) std::swap(ta, tb);
            t0 = std::max(t0, ta);
            t1 = std::min(t1, tb);
        }
        if (!(t0 <= t1)) return false;
        q = p + d * t0;
        return true;
    }

    double spacing() const { return spacing_; }
    long long nodesPerLight() const { return (long long)n_[0] * n_[1] * n_[2]; }
    // Nodes computed so far, over all lights (for reports and tests).
    long long computedNodes() const;

private:
    template <class Compute>
    double interpolate(int light, const Vec3& p, const Vec3* n, Compute&& compute) const {
        double u[3];
        int i0[3];
        for (int a = 0; a < 3; ++a) {
            const double x = std::clamp((p[a] - lo_[a]) / spacing_, 0.0, double(n_[a] - 1));
            i0[a] = std::min(int(x), std::max(0, n_[a] - 2));
            u[a] = x - i0[a];
        }
        std::atomic<float>* values = values_[size_t(light)].get();
        double sum = 0.0, weights = 0.0;
        for (int c = 0; c < 8; ++c) {
            const int ix = i0[0] + (c & 1), iy = i0[1] + ((c >> 1) & 1),
                      iz = i0[2] + ((c >> 2) & 1);
            const double w = ((c & 1) ? u[0] : 1 - u[0]) * ((c & 2) ? u[1] : 1 - u[1]) *
                             ((c & 4) ? u[2] : 1 - u[2]);
            const Vec3 node = lo_ + Vec3(ix, iy, iz) * spacing_;
            if (w == 0.0 || (n && !((node - p).dot(*n) > 0.0))) continue;
            std::atomic<float>& value = values[(size_t(iz) * n_[1] + iy) * n_[0] + ix];
            float v = value.load(std::memory_order_relaxed);
            if (v < 0.0f) {
                v = float(compute(node));
                value.store(v, std::memory_order_relaxed);
            }
            sum += w * v;
            weights += w;
        }
        if (!n) return sum;
        return weights > 0.0 ? sum / weights : -1.0;
    }

    Vec3 lo_;
    double spacing_ = 1.0;
    int n_[3] = {2, 2, 2};
    std::vector<std::unique_ptr<std::atomic<float>[]>> values_;  // per light; < 0: not computed
};

}  // namespace lobe
