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
    ShadingPoint point;
    point.material = &material;
    point.colour = point.highlight = sample.colour;
    point.position = sample.position;
    point.hasFrame = sample.hasNormal;
    if (sample.hasNormal)
        point.frame = Frame::fromNormalAndAxis(sample.normal, tangentAxis, fallbackAxis);
    return shade(point, toViewer, lights);
}

Spectrum shade(const ShadingPoint& point, const Vec3& toViewer,
               const std::vector<PointLight>& lights) {
    if (point.hasFrame) {
        if (point.highlight == point.colour)
            return point.colour * directLighting(*point.material, point.frame, point.position,
                                                 toViewer, lights, true);
        const ShadingTerms terms = shadeTerms(point, toViewer, lights);
        return terms.lambert + terms.specular;
    }
    Spectrum radiance;
    forEachLight(lights, point.position, [&](const PointLight& light, const Vec3&, double d2) {
        radiance += point.material->kd * kInvPi * light.intensity * (1.0 / d2);
    });
    return point.colour * radiance;
}

ShadingTerms shadeTerms(const ShadingPoint& point, const Vec3& toViewer,
                        const std::vector<PointLight>& lights) {
    const Material& m = *point.material;
    ShadingTerms terms;
    if (!point.hasFrame) {
        terms.lambert = shade(point, toViewer, lights);
        return terms;
    }
    const Frame frame = facingViewer(point.frame, toViewer);
    forEachLightInFrame(lights, frame, point.position, toViewer,
                        [&](const PointLight& light, const Vec3& wi, const Vec3& wo, double g) {
                            terms.lambert += m.kd * kInvPi * light.intensity * g;
                            if (m.specularOn)
                                terms.specular += evalBrdf(m.specular, wi, wo) * light.intensity * g;
                        });
    terms.lambert = point.colour * terms.lambert;
    terms.specular = point.highlight * terms.specular;
    return terms;
}

void shadeSpecularPerModel(const ShadingPoint& point, const Vec3& toViewer,
                           const std::vector<PointLight>& lights, const std::vector<Brdf>& models,
                           Spectrum* out) {
    for (size_t m = 0; m < models.size(); ++m) out[m] = Spectrum(0.0);
    if (!point.hasFrame) return;
    const Frame frame = facingViewer(point.frame, toViewer);
    forEachLightInFrame(lights, frame, point.position, toViewer,
                        [&](const PointLight& light, const Vec3& wi, const Vec3& wo, double g) {
                            const Spectrum irradiance = light.intensity * g;
                            for (size_t m = 0; m < models.size(); ++m)
                                out[m] += evalBrdf(models[m], wi, wo) * irradiance;
                        });
    for (size_t m = 0; m < models.size(); ++m) out[m] = point.highlight * out[m];
}

}  // namespace lobe
