// Point lights, and the scene's lights in the form the SIMD light loops read (core/light.h,
// render/shading_simd.h): positions as structure of arrays and intensities padded to four bands.
// Built once per thread while the lights stay the same, instead of being copied lane by lane at
// every shaded point — a vector load of values just written one by one waits for the stores
// (no store-to-load forwarding), which was a visible part of the light loop (docs/performance.md,
// round 4).
#pragma once

#include "core/math.h"
#include "core/spectrum.h"

#include <cstdint>
#include <cstring>
#include <vector>

namespace lobe {

// Point ("omni") light of intensity I (W/sr per band): irradiance at distance d is I/d² · cos θ.
struct PointLight {
    Vec3 position{0.0};
    Spectrum intensity{1.0};
};

struct LightTable {
    int count = 0;
    // Each array padded with zeros to a multiple of kPad lights, so whole vectors can be read.
    static constexpr int kPad = 8;
    const double* px = nullptr;
    const double* py = nullptr;
    const double* pz = nullptr;
    const double* intensity = nullptr;  // 4 per light: the bands, then 0

    LightTable() = default;
    LightTable(const LightTable&) = delete;
    LightTable& operator=(const LightTable&) = delete;
    void assign(const std::vector<PointLight>& lights);
    // The same lights, bit for bit (PointLight is six doubles), without a call to memcmp.
    bool holds(const std::vector<PointLight>& lights) const {
        if (source_.size() != lights.size()) return false;
        static_assert(sizeof(PointLight) == 6 * sizeof(double));
        const auto* a = reinterpret_cast<const unsigned char*>(source_.data());
        const auto* b = reinterpret_cast<const unsigned char*>(lights.data());
        std::uint64_t differ = 0;
        for (size_t i = 0; i < lights.size() * 6; ++i) {
            std::uint64_t u, v;
            std::memcpy(&u, a + 8 * i, 8);
            std::memcpy(&v, b + 8 * i, 8);
            differ |= u ^ v;
        }
        return differ == 0;
    }

private:
    std::vector<PointLight> source_;
    std::vector<double> storage_;
};

// The table of `lights`, kept per thread: rebuilt when the lights differ (compared bit for bit)
// from those of the last call on this thread. Valid until the next call on the same thread.
// Inline: it runs at every shaded point.
inline const LightTable& lightTable(const std::vector<PointLight>& lights) {
    thread_local LightTable table;
    if (!table.holds(lights)) table.assign(lights);
    return table;
}

}  // namespace lobe
