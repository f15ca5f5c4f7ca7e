#include "materials/registry.h"

#include "core/error.h"

#include <set>

namespace lobe {
namespace {

template <class Model>
BrdfModelInfo infoFor() {
    return {Model::kName,
            Model::kTitle,
            Model::kCitation,
            &Model::paramTable(),
            Model::kFlags,
            [](const ParamValues& values) -> Brdf { return Model::fromParams(values); }};
}

std::string knownNames() {
    std::string names;
    for (const BrdfModelInfo& m : brdfModels()) names += (names.empty() ? "" : ", ") + m.name;
    return names;
}

}  // namespace

const std::vector<BrdfModelInfo>& brdfModels() {
    static const std::vector<BrdfModelInfo> models = {
        infoFor<Phong>(),      infoFor<Strauss>(),      infoFor<SchlickLewis>(),
        infoFor<Ward>(),       infoFor<CookTorrance>(), infoFor<PoulinFournier>(),
        infoFor<HeTorrance>(), infoFor<Lafortune>(),    infoFor<AshikhminShirley>(),
        infoFor<Lambert>(),
    };
    return models;
}

std::vector<std::string> specularModelNames() {
    std::vector<std::string> names;
    for (const BrdfModelInfo& m : brdfModels())
        if (m.name != Lambert::kName) names.push_back(m.name);
    return names;
}

const BrdfModelInfo& findBrdfModel(const std::string& name) {
    for (const BrdfModelInfo& m : brdfModels())
        if (m.name == name) return m;
    throw Error("unknown BRDF model '" + name + "' (known: " + knownNames() + ")");
}

void setBrdfParam(const BrdfModelInfo& model, ParamValues& values, const std::string& key,
                  const Spectrum& value, const std::string& context) {
    for (const ParamSpec& spec : *model.params) {
        if (spec.name != key) continue;
        validateParam(spec, value, context + "." + key);
        values.set(key, value);
        return;
    }
    std::string names;
    for (const ParamSpec& spec : *model.params) names += (names.empty() ? "" : ", ") + spec.name;
    throw Error(context + ": unknown parameter '" + key + "' for " + model.name +
                " (parameters: " + names + ")");
}

ParamValues parseBrdfSettings(const BrdfModelInfo& model, const std::vector<std::string>& settings,
                              const std::string& context) {
    ParamValues values(*model.params);
    std::set<std::string> seen;
    for (const std::string& setting : settings) {
        const auto eq = setting.find('=');
        if (eq == std::string::npos || eq == 0)
            throw Error(context + ": expected key=value, got '" + setting + "'");
        const std::string key = setting.substr(0, eq);
        if (!seen.insert(key).second)
            throw Error(context + ": parameter '" + key + "' given twice");
        setBrdfParam(model, values, key,
                     parseBandValue(setting.substr(eq + 1), context + "." + key), context);
    }
    return values;
}

Brdf makeBrdf(const std::string& name, const std::vector<std::string>& settings) {
    const BrdfModelInfo& model = findBrdfModel(name);
    return model.create(parseBrdfSettings(model, settings, name));
}

}  // namespace lobe
