#include "volume/ray_packet.h"

namespace lobe {

RayPacketSampler::RayPacketSampler(const DvrVolume& volume) {
    lanes_.reserve(kLanes);
    for (int i = 0; i < kLanes; ++i) lanes_.emplace_back(volume);
}

bool RayPacketSampler::begin(int lane, const Ray& ray, double jitter) {
    return lanes_[size_t(lane)].begin(ray, jitter);
}

uint32_t RayPacketSampler::next(uint32_t lanes, const double* tEnd, VolumeSample* samples) {
    uint32_t found = 0;
    for (int i = 0; i < kLanes; ++i)
        if ((lanes >> i) & 1u)
            if (lanes_[size_t(i)].next(tEnd[i], samples[i], false)) found |= 1u << i;
    return found;
}

void RayPacketSampler::addNormal(int lane, VolumeSample& sample) {
    lanes_[size_t(lane)].addNormal(sample);
}

long long RayPacketSampler::samplesEvaluated() const {
    long long n = 0;
    for (const VolumeRaySampler& s : lanes_) n += s.samplesEvaluated();
    return n;
}

long long RayPacketSampler::samplesSkipped() const {
    long long n = 0;
    for (const VolumeRaySampler& s : lanes_) n += s.samplesSkipped();
    return n;
}

}  // namespace lobe
