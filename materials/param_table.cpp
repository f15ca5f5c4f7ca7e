#include "materials/param_table.h"

#include "core/error.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

namespace lobe {

ParamValues::ParamValues(const ParamTable& table) {
    for (const ParamSpec& spec : table) values_[spec.name] = Spectrum(spec.defaultValue);
}

const Spectrum& ParamValues::get(const std::string& name) const {
    auto it = values_.find(name);
    if (it == values_.end()) throw Error("internal: parameter '" + name + "' is not declared");
    return it->second;
}

namespace {

double parseNumber(const std::string& text, const std::string& what) {
    const char* begin = text.c_str();
    char* end = nullptr;
    const double v = std::strtod(begin, &end);
    if (text.empty() || end == begin || *end != '\0')
        throw Error(what + ": '" + text + "' is not a number");
    if (!std::isfinite(v)) throw Error(what + ": '" + text + "' is not a finite number");
    return v;
}

std::string formatNumber(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.10g", v);
    return buf;
}

}  // namespace

Spectrum parseBandValue(const std::string& text, const std::string& what) {
    std::vector<std::string> parts;
    std::stringstream ss(text);
    std::string item;
    while (std::getline(ss, item, ',')) parts.push_back(item);
    if (!text.empty() && text.back() == ',') parts.push_back("");
    if (parts.size() == 1) return Spectrum(parseNumber(parts[0], what));
    if (parts.size() == kBandCount)
        return Spectrum(parseNumber(parts[0], what), parseNumber(parts[1], what),
                        parseNumber(parts[2], what));
    throw Error(what +
                ": expected one value or three comma-separated values (700, 546.1, "
                "435.8 nm), got '" +
                text + "'");
}

void validateParam(const ParamSpec& spec, const Spectrum& value, const std::string& context) {
    for (int band = 0; band < kBandCount; ++band) {
        const double v = value[band];
        if (!std::isfinite(v) || v < spec.minValue || v > spec.maxValue)
            throw Error(context + " = " + formatNumber(v) + " is outside its range [" +
                        formatNumber(spec.minValue) + ", " + formatNumber(spec.maxValue) + "]");
        if (spec.integer && (v != std::floor(v) || v != value[0]))
            throw Error(context + " must be one whole number for all bands, got " +
                        formatBandValue(value));
    }
}

std::string formatBandValue(const Spectrum& value) {
    if (value[0] == value[1] && value[1] == value[2]) return formatNumber(value[0]);
    return formatNumber(value[0]) + "," + formatNumber(value[1]) + "," + formatNumber(value[2]);
}

}  // namespace lobe
