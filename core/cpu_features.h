#pragma once
// What the CPU can run, asked once per process: the code that keeps a copy of a hot loop
// compiled for a wider instruction set (gnu::target) picks it at run time with these. Each copy
// does the same IEEE operations as its baseline (no fused multiply-add), so the choice never
// changes a result (volume/volume_marcher.h, surface/brick_walk.h).

namespace lobe {

// AVX2 (the coarse DVR path's copy, volume/volume_marcher.cpp).
inline bool cpuHasAvx2() {
    static const bool has = [] {
        __builtin_cpu_init();
        return bool(__builtin_cpu_supports("avx2"));
    }();
    return has;
}

// AVX-512 F, VL, DQ, BW and CD (the brick walk's copy, surface/iso_exact.cpp).
inline bool cpuHasAvx512() {
    static const bool has = [] {
        __builtin_cpu_init();
        return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
               __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512bw") &&
               __builtin_cpu_supports("avx512cd");
    }();
    return has;
}

}  // namespace lobe
