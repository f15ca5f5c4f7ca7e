// Rays of one DvrVolume marched side by side (issue 31: "several rays of a tile marched together
// through the coarse path"). A RayPacketSampler holds kLanes lanes, each one ray with its own
// lattice, jitter and empty-space jumps; next() advances every lane it is asked for to that
// lane's next sample with non-zero opacity before the lane's tEnd — the same sample, bit for bit,
// that VolumeRaySampler::next(tEnd, sample, false) gives for that ray alone, and the same
// counters — so an integrator may trace several rays at once and composite each as trace() does.
// Lanes are independent: a lane that finished may be started on a new ray while the others go on
// (the integrator refills lanes from a tile row, render/integrator.h).
//
// Paths. Without DvrSettings::simd (or with LOBE_SIMD=off) every lane is a VolumeRaySampler of
// its own, the reference. With it, lanes on the coarse path (VolumeRaySampler::coarsePath(): the
// octant tables, trilinear values, steps ≥ 0.3 voxel, no clip gaps or pre-integration) are
// marched together with SIMD; any other lane keeps its VolumeRaySampler.
#pragma once

#include "volume/volume_marcher.h"

#include <cstdint>
#include <vector>

namespace lobe {

class RayPacketSampler {
public:
    static constexpr int kLanes = 8;

    // Throws nothing; the volume must outlive the sampler (per thread, as VolumeRaySampler).
    explicit RayPacketSampler(const DvrVolume& volume);

    // Starts `lane` on a ray with jitter ξ ∈ [0, 1) (VolumeRaySampler::begin). Returns false
    // when the ray misses the volume's domain (the lane then has no samples).
    bool begin(int lane, const Ray& ray, double jitter);

    // For every lane whose bit is set in `lanes`: the lane's next sample with non-zero opacity
    // and t < tEnd[lane] into samples[lane] (without its normal: addNormal). Returns the mask of
    // the lanes that have one; a lane asked for but not in the result has none before its tEnd
    // (and, like VolumeRaySampler, moves on with a larger tEnd). tEnd and samples have kLanes
    // entries; lanes not asked for are not read or written.
    uint32_t next(uint32_t lanes, const double* tEnd, VolumeSample* samples);

    // Fills gradient, normal and hasNormal of the sample `lane` last returned
    // (VolumeRaySampler::addNormal).
    void addNormal(int lane, VolumeSample& sample);

    // Counters over the sampler's life, summed over the lanes (VolumeRaySampler's).
    long long samplesEvaluated() const;
    long long samplesSkipped() const;

private:
    std::vector<VolumeRaySampler> lanes_;  // kLanes
};

}  // namespace lobe
