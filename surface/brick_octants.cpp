// The octant clip of the brick walk (brick_walk.h, clipToStraddlingOctants): the slab test of a
// ray against the straddling boxes of a brick's eight 4³ octants (Kay & Kajiya 1986, "Ray
// tracing complex scenes", the slab method), one AVX-512 vector of eight doubles per plane.
// Compiled for AVX-512F alone (the function's target attribute) and called only where the CPU
// has it (kOctantClip); the walk's hits do not depend on it (brick_walk.h), so the images are
// the same with and without it. Round 4 measured eight scalar box tests at 63 ns a call, more
// than they save (docs/performance.md); as vectors they cost a few nanoseconds.
#include "surface/brick_walk.h"

#include <immintrin.h>

namespace lobe {
namespace {

bool cpuHasAvx512f() {
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx512f");
}

}  // namespace

const bool kOctantClip = cpuHasAvx512f();

[[gnu::target("avx512f")]] bool clipToStraddlingOctants(const openvdb::Coord& origin,
                                                        const BrickCells& cells, const WalkRay& ray,
                                                        double& t0, double& t1) {
    using brick_walk_detail::kStraddleBoxMarginVoxels;
    __m512d enter = _mm512_set1_pd(t0), leave = _mm512_set1_pd(t1);
    for (int a = 0; a < 3; ++a) {
        // The planes origin + lo − margin and origin + hi + margin of the eight octants (the
        // integers are exact in double), then (plane − o)/d as the walk's clip computes it.
        const __m512d lo = _mm512_cvtepi32_pd(
            _mm256_cvtepu8_epi32(_mm_cvtsi64_si128(static_cast<long long>(cells.octantPlanes[a]))));
        const __m512d hi = _mm512_cvtepi32_pd(_mm256_cvtepu8_epi32(
            _mm_cvtsi64_si128(static_cast<long long>(cells.octantPlanes[a + 3]))));
        const __m512d org = _mm512_set1_pd(origin[a]);
        const __m512d margin = _mm512_set1_pd(kStraddleBoxMarginVoxels);
        const __m512d o = _mm512_set1_pd(ray.o[a]);
        const __m512d invD = _mm512_set1_pd(ray.invD[a]);
        const __m512d tLo =
            _mm512_mul_pd(_mm512_sub_pd(_mm512_sub_pd(_mm512_add_pd(org, lo), margin), o), invD);
        const __m512d tHi =
            _mm512_mul_pd(_mm512_sub_pd(_mm512_add_pd(_mm512_add_pd(org, hi), margin), o), invD);
        // A regular ray's d[a] is non-zero: it enters the low plane first going up, the high one
        // going down. An octant without straddling cells (lo 8, hi 0) is entered after it is
        // left, so it drops out below.
        const bool up = ray.d[a] > 0.0;
        enter = _mm512_max_pd(enter, up ? tLo : tHi);
        leave = _mm512_min_pd(leave, up ? tHi : tLo);
    }
    const __mmask8 met = _mm512_cmp_pd_mask(enter, leave, _CMP_LE_OQ);
    if (!met) return false;
    t0 = _mm512_mask_reduce_min_pd(met, enter);
    t1 = _mm512_mask_reduce_max_pd(met, leave);
    return true;
}

}  // namespace lobe
