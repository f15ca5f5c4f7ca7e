// Deterministic random numbers. Every pixel sample gets its own generator, seeded from
// (scene seed, pixel, sample index), so an image does not depend on how tiles are scheduled or on
// the thread count. Generator: PCG32 (O'Neill 2014, "PCG: A Family of Simple Fast Space-Efficient
// Statistically Good Algorithms for Random Number Generation", pcg32 XSH-RR); seeding hash:
// SplitMix64 finaliser (Steele et al. 2014).
#pragma once

#include <cstdint>

namespace lobe {

inline uint64_t mixBits(uint64_t v) {
    v ^= v >> 30;
    v *= 0xbf58476d1ce4e5b9ULL;
    v ^= v >> 27;
    v *= 0x94d049bb133111ebULL;
    v ^= v >> 31;
    return v;
}

class Rng {
public:
    explicit Rng(uint64_t seed = 0, uint64_t stream = 0) { reseed(seed, stream); }

    void reseed(uint64_t seed, uint64_t stream) {
        state_ = 0;
        inc_ = (stream << 1u) | 1u;
        nextUint();
        state_ += seed;
        nextUint();
    }

    uint32_t nextUint() {
        const uint64_t old = state_;
        state_ = old * 6364136223846793005ULL + inc_;
        const auto xorshifted = static_cast<uint32_t>(((old >> 18u) ^ old) >> 27u);
        const auto rot = static_cast<uint32_t>(old >> 59u);
        return (xorshifted >> rot) | (xorshifted << ((32u - rot) & 31u));
    }

    // Uniform in [0, 1): 32 random bits scaled, so 1.0 itself is never returned.
    double uniform() { return nextUint() * (1.0 / 4294967296.0); }

private:
    uint64_t state_ = 0;
    uint64_t inc_ = 1;
};

// Generator for one pixel sample: the same arguments give the same sequence, always.
inline Rng pixelSampleRng(uint64_t seed, uint32_t x, uint32_t y, uint32_t sample) {
    const uint64_t pixel = (uint64_t(y) << 32) | x;
    return Rng(mixBits(seed ^ mixBits(pixel)), mixBits(uint64_t(sample) + 0x9e3779b97f4a7c15ULL));
}

}  // namespace lobe
