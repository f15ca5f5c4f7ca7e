#include "render/shading.h"

#include <algorithm>
#include <cmath>

namespace lobe {

namespace {

// The lights of one point as forEachLightInFrame (core/light.h) walks them, bit for bit: the
// lights not at the point and above its surface, with wi the unit direction to the light in the
// local frame and g = cos θi / d² (× the shadow transmittance, lights it leaves at 0 dropped).
// They are worked out for a chunk of lights before any BRDF is evaluated, so that the square
// roots and divisions of different lights overlap; fn(light index, wi, g) is then called in the
// lights' order. Nothing when the viewer is below the surface (wo.z ≤ 0).
template <class Fn>
inline void forEachLitLight(const std::vector<PointLight>& lights, const Frame& frame,
                            const Vec3& position, const Vec3& wo, const double* shadow, Fn&& fn) {
    if (!(wo.z > 0.0)) return;
    constexpr size_t kChunk = 8;
    const size_t n = lights.size();
    for (size_t start = 0; start < n; start += kChunk) {
        const size_t end = std::min(n, start + kChunk);
        size_t index[kChunk];
        Vec3 wi[kChunk];
        double g[kChunk];
        size_t count = 0;
        for (size_t i = start; i < end; ++i) {
            const Vec3 toLight = lights[i].position - position;
            const double d2 = toLight.dot(toLight);
            if (!(d2 > 0.0)) continue;
            const double s = std::sqrt(d2);
            const Vec3 l(toLight.x / s, toLight.y / s, toLight.z / s);
            const Vec3 w(l.dot(frame.t), l.dot(frame.b), l.dot(frame.n));
            if (!(w.z > 0.0)) continue;
            double gi = w.z / d2;
            if (shadow) {
                gi *= shadow[i];
                if (!(gi > 0.0)) continue;
            }
            index[count] = i;
            wi[count] = w;
            g[count] = gi;
            ++count;
        }
        for (size_t k = 0; k < count; ++k) fn(index[k], wi[k], g[k]);
    }
}

// The light loops of directLighting and shadeTerms, the material's model chosen once per point
// (materials/brdf.h, visitAtView); onEvaluation() is called once per BRDF evaluation (a no-op
// except for `lobe cost`'s counting).
template <class OnEvaluation>
Spectrum directLightingImpl(const Material& material, const Frame& frameIn, const Vec3& position,
                            const Vec3& toViewer, const std::vector<PointLight>& lights,
                            bool twoSided, OnEvaluation&& onEvaluation,
                            const double* shadow = nullptr) {
    const Frame frame = twoSided ? facingViewer(frameIn, toViewer) : frameIn;
    const Vec3 wo = frame.toLocal(toViewer);
    const Spectrum diffuse = material.kd * kInvPi;
    return visitAtView(material.specular, wo, [&](auto& specular) {
        Spectrum radiance;
        forEachLitLight(lights, frame, position, wo, shadow,
                        [&](size_t light, const Vec3& wi, double g) {
                            onEvaluation();
                            Spectrum f = diffuse;
                            if (material.specularOn)
                                f += specular.eval(wi) * material.specularScale;
                            radiance += f * lights[light].intensity * g;
                        });
        return radiance;
    });
}

template <class OnEvaluation>
ShadingTerms shadeTermsImpl(const ShadingPoint& point, const Vec3& toViewer,
                            const std::vector<PointLight>& lights, OnEvaluation&& onEvaluation);

template <class OnEvaluation>
Spectrum shadeImpl(const ShadingPoint& point, const Vec3& toViewer,
                   const std::vector<PointLight>& lights, OnEvaluation&& onEvaluation) {
    if (point.hasFrame) {
        if (point.highlight == point.colour)
            return point.colour * directLightingImpl(*point.material, point.frame, point.position,
                                                     toViewer, lights, true, onEvaluation,
                                                     point.shadow);
        const ShadingTerms terms = shadeTermsImpl(point, toViewer, lights, onEvaluation);
        return terms.lambert + terms.specular;
    }
    Spectrum radiance;
    forEachLight(lights, point.position, [&](const PointLight& light, const Vec3&, double d2) {
        const double v = point.shadow ? point.shadow[&light - lights.data()] : 1.0;
        radiance += point.material->kd * kInvPi * light.intensity * (v / d2);
    });
    return point.colour * radiance;
}

template <class OnEvaluation>
ShadingTerms shadeTermsImpl(const ShadingPoint& point, const Vec3& toViewer,
                            const std::vector<PointLight>& lights, OnEvaluation&& onEvaluation) {
    const Material& m = *point.material;
    ShadingTerms terms;
    if (!point.hasFrame) {
        terms.lambert = shadeImpl(point, toViewer, lights, onEvaluation);
        return terms;
    }
    const Frame frame = facingViewer(point.frame, toViewer);
    const Vec3 wo = frame.toLocal(toViewer);
    const Spectrum diffuse = m.kd * kInvPi;
    visitAtView(m.specular, wo, [&](auto& specular) {
        forEachLitLight(lights, frame, point.position, wo, point.shadow,
                        [&](size_t light, const Vec3& wi, double g) {
                            onEvaluation();
                            const Spectrum& intensity = lights[light].intensity;
                            terms.lambert += diffuse * intensity * g;
                            if (m.specularOn)
                                terms.specular +=
                                    specular.eval(wi) * m.specularScale * intensity * g;
                        });
    });
    terms.lambert = point.colour * terms.lambert;
    terms.specular = point.highlight * terms.specular;
    return terms;
}

struct NoCount {
    void operator()() const {}
};

}  // namespace

Spectrum directLighting(const Material& material, const Frame& frameIn, const Vec3& position,
                        const Vec3& toViewer, const std::vector<PointLight>& lights,
                        bool twoSided) {
    return directLightingImpl(material, frameIn, position, toViewer, lights, twoSided, NoCount{});
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
    return shadeImpl(point, toViewer, lights, NoCount{});
}

Spectrum shade(const ShadingPoint& point, const Vec3& toViewer,
               const std::vector<PointLight>& lights, long long& brdfEvaluations) {
    return shadeImpl(point, toViewer, lights, [&] { ++brdfEvaluations; });
}

ShadingTerms shadeTerms(const ShadingPoint& point, const Vec3& toViewer,
                        const std::vector<PointLight>& lights) {
    return shadeTermsImpl(point, toViewer, lights, NoCount{});
}

void shadeSpecularPerModel(const ShadingPoint& point, const Vec3& toViewer,
                           const std::vector<PointLight>& lights, const std::vector<Brdf>& models,
                           Spectrum* out, const double* scales) {
    for (size_t m = 0; m < models.size(); ++m) out[m] = Spectrum(0.0);
    if (!point.hasFrame) return;
    const Frame frame = facingViewer(point.frame, toViewer);
    forEachLightInFrame(lights, frame, point.position, toViewer,
                        [&](const PointLight& light, const Vec3& wi, const Vec3& wo, double g) {
                            if (point.shadow) g *= point.shadow[&light - lights.data()];
                            const Spectrum irradiance = light.intensity * g;
                            for (size_t m = 0; m < models.size(); ++m)
                                out[m] += evalBrdf(models[m], wi, wo) *
                                          (scales ? irradiance * scales[m] : irradiance);
                        });
    for (size_t m = 0; m < models.size(); ++m) out[m] = point.highlight * out[m];
}

}  // namespace lobe
