#include "render/aov.h"

#include "core/error.h"
#include "core/image_output.h"
#include "materials/registry.h"
#include "render/shading.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <set>
#include <sstream>

namespace lobe {

AovRequest AovRequest::parse(const std::string& list) {
    AovRequest r;
    std::stringstream in(list);
    std::string item;
    bool empty = true;
    while (std::getline(in, item, ',')) {
        empty = false;
        if (item == "all")
            r.objects = r.backdrop = r.depth = r.normal = r.topObject = true;
        else if (item == "objects")
            r.objects = true;
        else if (item == "backdrop")
            r.backdrop = true;
        else if (item == "depth")
            r.depth = true;
        else if (item == "normal")
            r.normal = true;
        else if (item == "id")
            r.topObject = true;
        else
            throw Error("--aov: unknown pass '" + item +
                        "' (expected all or a comma list of objects, backdrop, depth, normal, id)");
    }
    if (empty)
        throw Error("--aov: expected all or a comma list of objects, backdrop, depth, normal, id");
    return r;
}

void AovRequest::setModels(const std::vector<std::string>& names) {
    models = names;
    modelBrdfs.clear();
    for (const std::string& name : names) modelBrdfs.push_back(makeBrdf(name));
}

double luminance(const Spectrum& bands) { return cieRgbToXyz(bands)[1]; }

Spectrum AovImage::lambertAt(size_t p, int o) const {
    const float* v = &lambert[(p * objectCount + size_t(o)) * 3];
    return Spectrum(v[0], v[1], v[2]);
}
Spectrum AovImage::specularAt(size_t p, int o) const {
    const float* v = &specular[(p * objectCount + size_t(o)) * 3];
    return Spectrum(v[0], v[1], v[2]);
}
Spectrum AovImage::backdropAt(size_t p) const {
    return Spectrum(backdrop[p * 3], backdrop[p * 3 + 1], backdrop[p * 3 + 2]);
}
Spectrum AovImage::modelSpecularAt(size_t p, int o, int m) const {
    const float* v = &modelSpecular[((p * objectCount + size_t(o)) * modelCount + size_t(m)) * 3];
    return Spectrum(v[0], v[1], v[2]);
}

AovImage makeAovImage(const AovRequest& request, int width, int height, int objectCount) {
    AovImage a;
    a.width = width;
    a.height = height;
    a.objectCount = objectCount;
    a.modelCount = int(request.models.size());
    const size_t n = a.pixelCount();
    // Object layers are also needed for the top object (it compares their sums).
    if (request.objects || request.topObject) {
        a.lambert.assign(n * size_t(objectCount) * 3, 0.0f);
        a.specular.assign(n * size_t(objectCount) * 3, 0.0f);
    }
    if (request.objects || !request.models.empty())
        a.objectDepth.assign(n * size_t(objectCount), 0.0f);
    if (request.backdrop || request.topObject || !request.models.empty())
        a.backdrop.assign(n * 3, 0.0f);
    if (request.depth) a.depth.assign(n, 0.0f);
    if (request.normal) a.normal.assign(n * 3, 0.0f);
    if (request.topObject) a.topObject.assign(n, -1.0f);
    if (request.alpha) a.alpha.assign(n, 0.0f);
    if (a.modelCount > 0) {
        a.modelSpecular.assign(n * size_t(objectCount) * size_t(a.modelCount) * 3, 0.0f);
        // The beauty minus the specular parts is needed to rebuild any assignment's image.
        a.lambert.assign(n * size_t(objectCount) * 3, 0.0f);
        a.specular.assign(n * size_t(objectCount) * 3, 0.0f);
    }
    return a;
}

AovAccumulator::AovAccumulator(const AovRequest& request, int objectCount,
                               const std::vector<PointLight>& lights)
    : request_(request), objects_(objectCount), lights_(lights) {
    lambert_.resize(size_t(objectCount));
    specular_.resize(size_t(objectCount));
    modelSpecular_.resize(size_t(objectCount) * request.modelBrdfs.size() * 3);
    perModel_.resize(request.modelBrdfs.size());
    objectDepthSum_.resize(size_t(objectCount));
    objectDepthCount_.resize(size_t(objectCount));
    objectSeen_.resize(size_t(objectCount));
}

void AovAccumulator::beginPixel() {
    std::fill(lambert_.begin(), lambert_.end(), Spectrum(0.0));
    std::fill(specular_.begin(), specular_.end(), Spectrum(0.0));
    std::fill(modelSpecular_.begin(), modelSpecular_.end(), 0.0);
    std::fill(objectDepthSum_.begin(), objectDepthSum_.end(), 0.0);
    std::fill(objectDepthCount_.begin(), objectDepthCount_.end(), 0);
    backdrop_ = Spectrum(0.0);
    depthSum_ = 0.0;
    depthCount_ = 0;
    normalSum_ = Vec3(0.0);
    coverageSum_ = 0.0;
    inSample_ = false;
}

void AovAccumulator::beginSample(const Vec3& toViewer) {
    toViewer_ = toViewer;
    depthFound_ = false;
    if (inSample_) coverageSum_ += 1.0 - sampleTransmittance_;
    sampleTransmittance_ = 1.0;
    inSample_ = true;
    std::fill(objectSeen_.begin(), objectSeen_.end(), 0);
}

void AovAccumulator::onEvent(const ShadingEvent& e) {
    if (!depthFound_ && 1.0 - e.transmittanceBefore * (1.0 - e.alpha) >= request_.depthOpacity) {
        depthFound_ = true;
        depthSum_ += e.t;
        ++depthCount_;
        if (e.point && e.point->hasFrame)
            normalSum_ += facingViewer(e.point->frame, toViewer_).n;
        else
            normalSum_ += toViewer_;  // backdrop, or a sample without a normal: faces the viewer
    }
    if (e.object == ShadingEvent::kBackdrop) {
        backdrop_ += e.radiance * e.weight;
        return;
    }
    // Exactly the compositor's T after this event (render/compositor.h).
    sampleTransmittance_ = e.transmittanceBefore * (1.0 - e.alpha);
    if (e.alpha > 0.0 && !objectSeen_[size_t(e.object)]) {  // the object's first event, this sample
        objectSeen_[size_t(e.object)] = 1;
        objectDepthSum_[size_t(e.object)] += e.t;
        ++objectDepthCount_[size_t(e.object)];
    }
    if (!e.point || e.weight == 0.0) return;
    if (!lambert_.empty()) {
        const ShadingTerms terms = shadeTerms(*e.point, toViewer_, lights_);
        lambert_[size_t(e.object)] += terms.lambert * e.weight;
        specular_[size_t(e.object)] += terms.specular * e.weight;
    }
    const size_t m = request_.modelBrdfs.size();
    if (m > 0) {
        shadeSpecularPerModel(*e.point, toViewer_, lights_, request_.modelBrdfs, perModel_.data(),
                              request_.modelScales.empty() ? nullptr : request_.modelScales.data());
        for (size_t k = 0; k < m; ++k)
            for (int b = 0; b < 3; ++b)
                modelSpecular_[(size_t(e.object) * m + k) * 3 + size_t(b)] +=
                    perModel_[k][b] * e.weight;
    }
}

void AovAccumulator::finishPixel(int samples, size_t p, AovImage& out) const {
    const double inv = 1.0 / samples;
    auto put = [](float* dst, const Spectrum& s, double scale) {
        for (int b = 0; b < 3; ++b) {
            const double v = s[b] * scale;
            dst[b] = imageFloat(v);
        }
    };
    if (!out.lambert.empty())
        for (int o = 0; o < objects_; ++o) {
            put(&out.lambert[(p * objects_ + size_t(o)) * 3], lambert_[size_t(o)], inv);
            put(&out.specular[(p * objects_ + size_t(o)) * 3], specular_[size_t(o)], inv);
        }
    if (!out.backdrop.empty()) put(&out.backdrop[p * 3], backdrop_, inv);
    if (!out.alpha.empty()) {
        const double coverage =
            (coverageSum_ + (inSample_ ? 1.0 - sampleTransmittance_ : 0.0)) * inv;
        out.alpha[p] = std::isfinite(coverage) ? float(std::clamp(coverage, 0.0, 1.0)) : 0.0f;
    }
    if (!out.depth.empty()) out.depth[p] = depthCount_ > 0 ? float(depthSum_ / depthCount_) : 0.0f;
    if (!out.normal.empty() && depthCount_ > 0) {
        const double len = normalSum_.length();
        if (len > 0.0)
            for (int a = 0; a < 3; ++a) out.normal[p * 3 + size_t(a)] = float(normalSum_[a] / len);
    }
    if (!out.topObject.empty()) {
        double best = luminance(backdrop_);
        int top = -1;
        for (int o = 0; o < objects_; ++o) {
            const double y = luminance(lambert_[size_t(o)] + specular_[size_t(o)]);
            if (y > best) best = y, top = o;
        }
        out.topObject[p] = float(top);
    }
    const size_t m = request_.modelBrdfs.size();
    for (size_t i = 0; i < size_t(objects_) * m * 3; ++i) {
        const double v = modelSpecular_[i] * inv;
        out.modelSpecular[p * size_t(objects_) * m * 3 + i] = imageFloat(v);
    }
    if (!out.objectDepth.empty())
        for (int o = 0; o < objects_; ++o) {
            const int c = objectDepthCount_[size_t(o)];
            const double d = c > 0 ? objectDepthSum_[size_t(o)] / c : 0.0;
            out.objectDepth[p * size_t(objects_) + size_t(o)] = imageFloat(d);
        }
}

namespace {

std::vector<std::string> channelSafeNames(const std::vector<std::string>& names) {
    std::vector<std::string> out;
    std::set<std::string> used = {"backdrop", "depth", "N", "object", "band"};
    for (const std::string& name : names) {
        std::string s;
        for (char c : name)
            s += (std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-') ? c : '_';
        if (s.empty()) s = "object";
        std::string unique = s;
        for (int k = 2; used.count(unique); ++k) unique = s + "_" + std::to_string(k);
        used.insert(unique);
        out.push_back(unique);
    }
    return out;
}

}  // namespace

void appendAovChannels(const AovRequest& request, const AovImage& a,
                       const std::vector<std::string>& objectNames, double exposure,
                       ImageChannels& out) {
    const size_t n = a.pixelCount();
    std::vector<std::pair<std::string, std::function<float(size_t)>>> channels;
    auto colour = [&](const std::string& layer, std::function<Spectrum(size_t)> get) {
        static const char* rgb[3] = {"R", "G", "B"};
        for (int c = 0; c < 3; ++c)
            channels.push_back({layer + "." + rgb[c], [get, c, exposure](size_t p) {
                                    return imageFloat(bandsToLinearSrgb(get(p))[size_t(c)] *
                                                      exposure);
                                }});
    };
    if (request.objects) {
        const std::vector<std::string> safe = channelSafeNames(objectNames);
        for (int o = 0; o < a.objectCount; ++o) {
            colour(safe[size_t(o)] + ".lambert", [&a, o](size_t p) { return a.lambertAt(p, o); });
            colour(safe[size_t(o)] + ".specular", [&a, o](size_t p) { return a.specularAt(p, o); });
        }
    }
    if (request.backdrop) colour("backdrop", [&a](size_t p) { return a.backdropAt(p); });
    if (request.depth) channels.push_back({"depth.Z", [&a](size_t p) { return a.depth[p]; }});
    if (request.normal) {
        static const char* xyz[3] = {"X", "Y", "Z"};
        for (int c = 0; c < 3; ++c)
            channels.push_back({std::string("N.") + xyz[c],
                                [&a, c](size_t p) { return a.normal[p * 3 + size_t(c)]; }});
    }
    if (request.topObject)
        channels.push_back({"object.id", [&a](size_t p) { return a.topObject[p]; }});
    const size_t k0 = out.names.size(), k = k0 + channels.size();
    std::vector<float> data(n * k);
    for (size_t p = 0; p < n; ++p) {
        for (size_t c = 0; c < k0; ++c) data[p * k + c] = out.data[p * k0 + c];
        for (size_t c = 0; c < channels.size(); ++c) data[p * k + k0 + c] = channels[c].second(p);
    }
    for (const auto& ch : channels) out.names.push_back(ch.first);
    out.data = std::move(data);
}

}  // namespace lobe
