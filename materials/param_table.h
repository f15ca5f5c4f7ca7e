// Parameter tables: every model declares its parameters once, as {name, default, min, max, doc},
// and the registry, the CLI (`lobe brdf list`), scene files and the tests all read that table.
// Any parameter may be given per band ("eta=0.16,0.37,1.59"); a single value applies to all three
// bands (docs/models.md, "Conventions").
#pragma once

#include "core/spectrum.h"

#include <map>
#include <string>
#include <vector>

namespace lobe {

struct ParamSpec {
    std::string name;
    double defaultValue = 0.0;
    double minValue = 0.0;
    double maxValue = 0.0;
    std::string doc;
    bool integer = false;  // must be a whole number (and the same in every band)
};

using ParamTable = std::vector<ParamSpec>;

// Facts about a model that follow from its definition (docs/models.md), declared on
// the model itself as `static constexpr BrdfFlags kFlags` (as pbrt-v4's BxDF::Flags()), so the
// registry, analysis/ and the tests read them from one place instead of tables keyed by name.
// Each fact is named where it is declared, e.g. `kFlags = {Reciprocal::yes, Costly::no}`: the
// arguments cannot be swapped or left out.
enum class Reciprocal : bool { no = false, yes = true };
enum class Costly : bool { no = false, yes = true };
struct BrdfFlags {
    // f(wi, wo) = f(wo, wi) by construction (the derivation sits beside kFlags in each header).
    bool reciprocal = true;
    // An evaluation integrates or sums a series (µs, not ns): sampling code takes fewer samples
    // (analysis/properties.h, sampleScale).
    bool costly = false;

    constexpr BrdfFlags() = default;
    constexpr BrdfFlags(Reciprocal r, Costly c)
        : reciprocal(r == Reciprocal::yes), costly(c == Costly::yes) {}
};

// Validated values of one model's parameters: every parameter of its table, defaults filled in.
class ParamValues {
public:
    ParamValues() = default;
    // Defaults of `table`.
    explicit ParamValues(const ParamTable& table);

    // Value of a declared parameter; throws lobe::Error for an undeclared name (a bug).
    const Spectrum& get(const std::string& name) const;
    double scalar(const std::string& name) const { return get(name)[0]; }
    void set(const std::string& name, const Spectrum& value) { values_[name] = value; }
    const std::map<std::string, Spectrum>& all() const { return values_; }

private:
    std::map<std::string, Spectrum> values_;
};

// Parses "0.5" or "0.16,0.37,1.59" into a per-band value. `what` names the setting in errors.
Spectrum parseBandValue(const std::string& text, const std::string& what);

// Checks `value` against `spec` (range, integrality); throws lobe::Error naming `context`
// (e.g. "ward: alpha_x" or "objects[2].brdf.alpha_x") and the allowed range.
void validateParam(const ParamSpec& spec, const Spectrum& value, const std::string& context);

// Formats a per-band value the way it is parsed: "0.8" when the bands agree, else "a,b,c".
std::string formatBandValue(const Spectrum& value);

}  // namespace lobe
