// One explicit list of every reflection model by name, with its parameter table and a factory.
// The CLI, scene files, the flux-overlap test and the generic tests all go through it.
#pragma once

#include "materials/brdf.h"
#include "materials/param_table.h"

#include <string>
#include <vector>

namespace lobe {

struct BrdfModelInfo {
    std::string name;   // registry / CLI name, e.g. "ashikhmin_shirley"
    std::string title;  // for people, e.g. "Ashikhmin-Shirley"
    std::string citation;
    const ParamTable* params = nullptr;
    BrdfFlags flags;
    Brdf (*create)(const ParamValues&) = nullptr;
};

// Every model: the nine specular models in the paper's order, then lambert.
const std::vector<BrdfModelInfo>& brdfModels();

// The names of the nine specular models, in the paper's order (phong … ashikhmin_shirley).
std::vector<std::string> specularModelNames();

// Throws lobe::Error "unknown BRDF model 'x' (known: …)".
const BrdfModelInfo& findBrdfModel(const std::string& name);

// Applies "key=value" settings (value: one number or three per-band numbers) over the defaults,
// validating names and ranges. `context` prefixes errors (e.g. "ward" or "objects[2].brdf").
ParamValues parseBrdfSettings(const BrdfModelInfo& model, const std::vector<std::string>& settings,
                              const std::string& context);

// Validates one named value against the model's table and stores it in `values`.
void setBrdfParam(const BrdfModelInfo& model, ParamValues& values, const std::string& key,
                  const Spectrum& value, const std::string& context);

// findBrdfModel + parseBrdfSettings + create.
Brdf makeBrdf(const std::string& name, const std::vector<std::string>& settings = {});

}  // namespace lobe
