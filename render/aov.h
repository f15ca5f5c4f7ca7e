// Per-object passes ("arbitrary output variables"): what each object contributes to each pixel,
// built from the integrator's composited events (render/integrator.h, ShadingEvent). For every
// object: its Lambertian and its specular part, Σ over its hits and samples of
// T·α·(roulette weight)·colour·lighting, so that per pixel
//     Σ_objects (lambert + specular) + backdrop = beauty      (to float rounding);
// the backdrop's contribution; depth — the ray distance at which the accumulated opacity 1 − T
// first reaches `depthOpacity`; the shading normal there (turned to the viewer); the object
// contributing most (by luminance; −1: the backdrop). With `models`, also per object the
// specular part (band triple) it would contribute with each of those BRDFs instead of its own,
// from the same render: transmittance never depends on a BRDF, so these layers are exact
// (`lobe assign`). With `objects`, also per object the distance along the ray of its first event
// (mean over the samples that reach it): which object lies in front of which in each pixel, for
// the veiling term of the separation score (analysis/separation.h).
// Everything is averaged over the pixel's samples as the beauty image is.
#pragma once

#include "core/light.h"
#include "materials/brdf.h"
#include "render/integrator.h"

#include <string>
#include <vector>

namespace lobe {

struct AovRequest {
    bool objects = false;  // per-object lambert and specular layers
    bool backdrop = false;
    bool depth = false;
    bool normal = false;
    bool topObject = false;
    // Coverage of the objects (alpha, render/background.h): 1 − the transmittance through every
    // object along the ray, averaged over the pixel's samples. Not an EXR pass of its own: the
    // figure output writes it as channel A.
    bool alpha = false;
    double depthOpacity = 0.5;
    std::vector<std::string> models;  // specular luminance per object per model
    std::vector<Brdf> modelBrdfs;     // filled from `models` at their defaults
    std::vector<double> modelScales;  // per model: factor on f_s (empty: 1 for all)

    bool any() const {
        return objects || backdrop || depth || normal || topObject || alpha || !models.empty();
    }
    // Sets `models` and builds their BRDFs at their defaults; throws for an unknown name.
    void setModels(const std::vector<std::string>& names);
    // "all" or a comma list of objects, backdrop, depth, normal, id; throws lobe::Error naming a
    // bad item.
    static AovRequest parse(const std::string& list);
};

struct AovImage {
    int width = 0, height = 0;
    int objectCount = 0, modelCount = 0;
    std::vector<float> lambert, specular;  // bands: [(pixel · objectCount + object) · 3 + band]
    std::vector<float> backdrop;           // bands: [pixel · 3 + band]
    std::vector<float> depth;              // 0 where no sample reached the opacity
    std::vector<float> normal;             // [pixel · 3 + axis], world space; 0 where no depth
    std::vector<float> topObject;          // object index, −1 for the backdrop
    // bands: [((pixel · objectCount + object) · modelCount + model) · 3 + band]
    std::vector<float> modelSpecular;
    // per object: its first event's ray distance, mean over the samples that reach it; 0: none
    std::vector<float> objectDepth;  // [pixel · objectCount + object]
    std::vector<float> alpha;        // coverage in [0, 1] (AovRequest::alpha)

    size_t pixelCount() const { return size_t(width) * height; }
    Spectrum lambertAt(size_t pixel, int object) const;
    Spectrum specularAt(size_t pixel, int object) const;
    Spectrum backdropAt(size_t pixel) const;
    Spectrum modelSpecularAt(size_t pixel, int object, int model) const;
};

// Luminance Y of a band triple (CIE 1931: Y row of core/spectrum.h's cieRgbToXyz); linear, so
// it adds up over objects as the bands do.
double luminance(const Spectrum& bands);

// Accumulates one pixel's passes from the events of its samples (one per thread, reused).
class AovAccumulator : public EventSink {
public:
    AovAccumulator(const AovRequest& request, int objectCount,
                   const std::vector<PointLight>& lights);
    void beginPixel();
    void beginSample(const Vec3& toViewer);
    void onEvent(const ShadingEvent& event) override;
    // Writes the mean over `samples` samples into pixel `pixel` of `out`.
    void finishPixel(int samples, size_t pixel, AovImage& out) const;

private:
    const AovRequest& request_;
    int objects_;
    const std::vector<PointLight>& lights_;
    Vec3 toViewer_{0, 0, 1};
    bool depthFound_ = false;
    std::vector<Spectrum> lambert_, specular_;
    std::vector<double> modelSpecular_;
    std::vector<Spectrum> perModel_;  // scratch
    std::vector<double> objectDepthSum_;
    std::vector<int> objectDepthCount_;
    std::vector<char> objectSeen_;  // this sample
    Spectrum backdrop_;
    double depthSum_ = 0.0;
    int depthCount_ = 0;
    Vec3 normalSum_{0.0};
    double sampleTransmittance_ = 1.0;  // through the objects so far, this sample
    double coverageSum_ = 0.0;          // Σ (1 − T) over the finished samples
    bool inSample_ = false;
};

// An AovImage of the right size with the requested layers allocated.
AovImage makeAovImage(const AovRequest& request, int width, int height, int objectCount);

// The EXR channels of the requested layers: colour layers in linear sRGB × exposure, as the
// beauty's R, G, B (so they add up to it), named <object>.lambert.R …, <object>.specular.R …,
// backdrop.R …, depth.Z, N.X N.Y N.Z, object.id. Object names are made channel-safe (letters,
// digits, '_' and '-'; others become '_'; a repeated name gets a suffix).
struct ImageChannels;
void appendAovChannels(const AovRequest& request, const AovImage& aovs,
                       const std::vector<std::string>& objectNames, double exposure,
                       ImageChannels& out);

}  // namespace lobe
