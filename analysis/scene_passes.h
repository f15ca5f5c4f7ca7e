// From a render's per-object passes (render/aov.h) to the luminance layers the separation score
// (analysis/separation.h) and the assignment search (analysis/assign.h) work on; and the BRDF
// candidates `lobe assign` offers (the nine models at their defaults, and with --tune the
// documented parameter sweep of analysis/properties.h).
#pragma once

#include "analysis/assign.h"
#include "analysis/separation.h"
#include "core/film.h"
#include "render/aov.h"
#include "render/scene_description.h"

#include <optional>
#include <string>
#include <vector>

namespace lobe {

// Per-object passes in display-linear sRGB (× the scene's exposure) with the scene's tone curve;
// needs a render with AovRequest objects and backdrop.
SeparationLayers separationLayers(const SceneSpec& spec, const AovImage& aovs);

struct BrdfCandidate {
    std::string model;
    std::vector<std::string> settings;  // key=value over the defaults
    std::optional<Brdf> brdf;           // when set: this exact BRDF (an object's own, kept)
    std::string tag;                    // appended to the label, e.g. "(as in the scene)"
    double albedo = 0.0;                // > 0: the lobe scaled to this albedo at normal incidence
    double scale = 1.0;                 // the factor on f_s (Material::specularScale)
    std::string label() const;          // "ward", "ward alpha_x=0.1 alpha_y=0.1", "ward albedo=0.1"
};

// The nine specular models at their defaults; with `tune`, also each documented sweep setting.
std::vector<BrdfCandidate> brdfCandidates(bool tune);

// Scales every candidate (not those with an exact `brdf`) to albedo `albedo` at normal incidence
// (materials/albedo.h); throws lobe::Error for a lobe that reflects nothing there.
void equalizeAlbedo(std::vector<BrdfCandidate>& candidates, double albedo);

// Adds the candidates' BRDFs to a pass request (AovRequest::models / modelBrdfs).
void requestCandidateLayers(const std::vector<BrdfCandidate>& candidates, AovRequest& request);

// Layers of a render made with requestCandidateLayers (objects' own passes give the base).
AssignmentLayers assignmentLayers(const SceneSpec& spec, const AovImage& aovs,
                                  const std::vector<BrdfCandidate>& candidates);

}  // namespace lobe
