#include "materials/material.h"

namespace lobe {

Spectrum directLighting(const Material& material, const Frame& frameIn, const Vec3& position,
                        const Vec3& toViewer, const std::vector<PointLight>& lights,
                        bool twoSided) {
    Frame frame = frameIn;
    if (twoSided && frame.n.dot(toViewer) < 0.0) {
        // Mirror the frame to the viewer's side; flipping n and b keeps it right-handed and the
        // tangent (anisotropy direction) unchanged.
        frame.n = -frame.n;
        frame.b = -frame.b;
    }
    const Vec3 wo = frame.toLocal(toViewer);
    Spectrum radiance;
    if (!(wo.z > 0.0)) return radiance;
    for (const PointLight& light : lights) {
        const Vec3 toLight = light.position - position;
        const double d2 = toLight.length2();
        if (!(d2 > 0.0)) continue;
        const Vec3 wi = frame.toLocal(toLight / std::sqrt(d2));
        if (!(wi.z > 0.0)) continue;
        Spectrum f = material.kd * kInvPi;
        if (material.specularOn) f += evalBrdf(material.specular, wi, wo);
        radiance += f * light.intensity * (wi.z / d2);
    }
    return radiance;
}

}  // namespace lobe
