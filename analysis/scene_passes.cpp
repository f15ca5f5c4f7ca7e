#include "analysis/scene_passes.h"

#include "analysis/properties.h"
#include "core/error.h"
#include "core/math.h"
#include "materials/albedo.h"
#include "materials/registry.h"

#include <array>
#include <cstdio>

namespace lobe {

namespace {

void putRgb(std::vector<float>& out, size_t p, const Spectrum& bands, double exposure) {
    const std::array<double, 3> rgb = bandsToLinearSrgb(bands * exposure);
    for (int c = 0; c < 3; ++c) out[3 * p + size_t(c)] = imageFloat(rgb[size_t(c)]);
}

// Everything but the specular layers: objects, Lambert, depth, backdrop, display.
SeparationLayers fixedLayers(const SceneSpec& spec, const AovImage& a) {
    SeparationLayers l;
    l.width = a.width;
    l.height = a.height;
    l.tone = spec.tone;
    const size_t n = a.pixelCount();
    l.backdrop.assign(3 * n, 0.0f);
    if (!a.backdrop.empty())
        for (size_t p = 0; p < n; ++p) putRgb(l.backdrop, p, a.backdropAt(p), spec.exposure);
    for (int o = 0; o < a.objectCount; ++o) {
        l.objects.push_back(spec.objects[size_t(o)].name);
        std::vector<float> lambert(3 * n), depth(n, 0.0f);
        for (size_t p = 0; p < n; ++p) {
            putRgb(lambert, p, a.lambertAt(p, o), spec.exposure);
            if (!a.objectDepth.empty())
                depth[p] = a.objectDepth[p * size_t(a.objectCount) + size_t(o)];
        }
        l.lambert.push_back(std::move(lambert));
        if (!a.objectDepth.empty()) l.depth.push_back(std::move(depth));
    }
    return l;
}

}  // namespace

SeparationLayers separationLayers(const SceneSpec& spec, const AovImage& a) {
    if (a.lambert.empty() || a.backdrop.empty())
        throw Error("internal: separation layers need the objects and backdrop passes");
    SeparationLayers l = fixedLayers(spec, a);
    const size_t n = a.pixelCount();
    for (int o = 0; o < a.objectCount; ++o) {
        std::vector<float> s(3 * n);
        for (size_t p = 0; p < n; ++p) putRgb(s, p, a.specularAt(p, o), spec.exposure);
        l.specular.push_back(std::move(s));
    }
    return l;
}

std::string BrdfCandidate::label() const {
    std::string s = model;
    for (const std::string& x : settings) s += " " + x;
    if (albedo > 0.0) {
        char buf[48];
        std::snprintf(buf, sizeof buf, " albedo=%g", albedo);
        s += buf;
    }
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

void equalizeAlbedo(std::vector<BrdfCandidate>& candidates, double albedo) {
    for (BrdfCandidate& c : candidates) {
        if (c.brdf) continue;
        c.albedo = albedo;
        c.scale = albedoScale(makeBrdf(c.model, c.settings), albedo);
    }
}

void requestCandidateLayers(const std::vector<BrdfCandidate>& candidates, AovRequest& request) {
    request.models.clear();
    request.modelBrdfs.clear();
    request.modelScales.clear();
    for (const BrdfCandidate& c : candidates) {
        request.models.push_back(c.label());
        request.modelBrdfs.push_back(c.brdf ? *c.brdf : makeBrdf(c.model, c.settings));
        request.modelScales.push_back(c.scale);
    }
}

AssignmentLayers assignmentLayers(const SceneSpec& spec, const AovImage& a,
                                  const std::vector<BrdfCandidate>& candidates) {
    if (a.modelCount != int(candidates.size()))
        throw Error("internal: the passes hold " + std::to_string(a.modelCount) + " models, not " +
                    std::to_string(candidates.size()));
    AssignmentLayers l;
    l.scene = fixedLayers(spec, a);
    const size_t n = a.pixelCount(), m = candidates.size();
    for (const BrdfCandidate& c : candidates) {
        l.candidates.push_back(c.label());
        l.candidateModels.push_back(c.brdf ? brdfName(*c.brdf) : c.model);
    }
    for (int o = 0; o < a.objectCount; ++o)
        for (size_t c = 0; c < m; ++c) {
            std::vector<float> layer(3 * n);
            for (size_t p = 0; p < n; ++p)
                putRgb(layer, p, a.modelSpecularAt(p, o, int(c)), spec.exposure);
            l.specular.push_back(std::move(layer));
        }
    return l;
}

}  // namespace lobe
