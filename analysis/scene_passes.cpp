#include "analysis/scene_passes.h"

#include "analysis/properties.h"
#include "materials/registry.h"

namespace lobe {

SeparationLayers separationLayers(const SceneSpec& spec, const Film& beauty, const AovImage& a) {
    SeparationLayers l;
    l.width = a.width;
    l.height = a.height;
    const size_t n = a.pixelCount();
    l.beauty.resize(n);
    for (size_t p = 0; p < n; ++p) l.beauty[p] = float(luminance(beauty.pixels()[p]));
    for (int o = 0; o < a.objectCount; ++o) {
        l.objects.push_back(spec.objects[size_t(o)].name);
        std::vector<float> s(n), t(n);
        for (size_t p = 0; p < n; ++p) {
            const Spectrum spec = a.specularAt(p, o);
            s[p] = float(luminance(spec));
            t[p] = float(luminance(spec + a.lambertAt(p, o)));
        }
        l.specular.push_back(std::move(s));
        l.total.push_back(std::move(t));
    }
    return l;
}

std::string BrdfCandidate::label() const {
    std::string s = model;
    for (const std::string& x : settings) s += " " + x;
    if (!tag.empty()) s += " " + tag;
    return s;
}

std::vector<BrdfCandidate> brdfCandidates(bool tune) {
    std::vector<BrdfCandidate> out;
    if (!tune) {
        for (const std::string& m : specularModelNames()) out.push_back({m, {}, std::nullopt, {}});
        return out;
    }
    for (const ModelSetting& s : propertySettings())
        if (s.model != "lambert") out.push_back({s.model, s.settings, std::nullopt, {}});
    return out;
}

void requestCandidateLayers(const std::vector<BrdfCandidate>& candidates, AovRequest& request) {
    request.models.clear();
    request.modelBrdfs.clear();
    for (const BrdfCandidate& c : candidates) {
        request.models.push_back(c.label());
        request.modelBrdfs.push_back(c.brdf ? *c.brdf : makeBrdf(c.model, c.settings));
    }
}

AssignmentLayers assignmentLayers(const SceneSpec& spec, const AovImage& a,
                                  const std::vector<BrdfCandidate>& candidates) {
    AssignmentLayers l;
    l.width = a.width;
    l.height = a.height;
    const size_t n = a.pixelCount(), m = candidates.size();
    for (const BrdfCandidate& c : candidates) l.candidates.push_back(c.label());
    for (const ObjectSpec& o : spec.objects) l.objects.push_back(o.name);
    l.base.assign(n, 0.0f);
    for (size_t p = 0; p < n; ++p) {
        Spectrum rest = a.backdropAt(p);
        for (int o = 0; o < a.objectCount; ++o) rest += a.lambertAt(p, o);
        l.base[p] = float(luminance(rest));
    }
    for (int o = 0; o < a.objectCount; ++o)
        for (size_t c = 0; c < m; ++c) {
            std::vector<float> layer(n);
            for (size_t p = 0; p < n; ++p)
                layer[p] = a.modelSpecular[(p * size_t(a.objectCount) + size_t(o)) * m + c];
            l.specular.push_back(std::move(layer));
        }
    return l;
}

}  // namespace lobe
