#include "render/shading.h"

namespace lobe {

Spectrum directLighting(const Material& material, const Frame& frameIn, const Vec3& position,
                        const Vec3& toViewer, const std::vector<PointLight>& lights,
                        bool twoSided) {
    const Frame frame = twoSided ? facingViewer(frameIn, toViewer) : frameIn;
    Spectrum radiance;
    forEachLightInFrame(lights, frame, position, toViewer,
                        [&](const PointLight& light, const Vec3& wi, const Vec3& wo, double g) {
                            Spectrum f = material.kd * kInvPi;
                            if (material.specularOn) f += evalBrdf(material.specular, wi, wo);
                            radiance += f * light.intensity * g;
                        });
    return radiance;
}

Spectrum shadeVolumeSample(const Material& material, const VolumeSample& sample,
                           const Vec3& toViewer, const std::vector<PointLight>& lights,
                           const Vec3& tangentAxis, const Vec3& fallbackAxis) {
    if (sample.hasNormal) {
        const Frame frame = Frame::fromNormalAndAxis(sample.normal, tangentAxis, fallbackAxis);
        return sample.colour *
               directLighting(material, frame, sample.position, toViewer, lights, true);
    }
    Spectrum radiance;
    forEachLight(lights, sample.position, [&](const PointLight& light, const Vec3&, double d2) {
        radiance += material.kd * kInvPi * light.intensity * (1.0 / d2);
    });
    return sample.colour * radiance;
}

}  // namespace lobe
