// `lobe brdf list | eval | props`: the reflection models as a tool. `eval` is the stable interface
// other tools check the models through: one input line of six numbers (wi then wo, local frame,
// normalised here) gives one output line of three band values with 10 significant digits.
#include "apps/commands.h"
#include "core/error.h"
#include "materials/registry.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace lobe {
namespace {

void listModels() {
    for (const BrdfModelInfo& model : brdfModels()) {
        std::printf("%s  (%s)\n    %s\n", model.name.c_str(), model.title.c_str(),
                    model.citation.c_str());
        for (const ParamSpec& p : *model.params)
            std::printf("    %-20s default %-8g range [%g, %g]%s  %s\n", p.name.c_str(),
                        p.defaultValue, p.minValue, p.maxValue, p.integer ? " integer" : "",
                        p.doc.c_str());
    }
}

// Parses "a,b,c,d,e,f" (spaces allowed around numbers); returns false on any malformation.
bool parseSixNumbers(const std::string& line, double out[6]) {
    std::stringstream ss(line);
    std::string field;
    int count = 0;
    while (std::getline(ss, field, ',')) {
        if (count == 6) return false;
        const char* begin = field.c_str();
        char* end = nullptr;
        out[count] = std::strtod(begin, &end);
        if (end == begin) return false;
        while (*end == ' ' || *end == '\t' || *end == '\r') ++end;
        if (*end != '\0' || !std::isfinite(out[count])) return false;
        ++count;
    }
    return count == 6 && (line.empty() || line.back() != ',');
}

void evalModel(const std::string& name, const std::vector<std::string>& settings) {
    const Brdf brdf = makeBrdf(name, settings);
    std::string line;
    long lineNumber = 0;
    while (std::getline(std::cin, line)) {
        ++lineNumber;
        if (line.find_first_not_of(" \t\r") == std::string::npos) continue;  // blank line
        double v[6];
        if (!parseSixNumbers(line, v))
            throw Error("standard input line " + std::to_string(lineNumber) +
                        ": expected six comma-separated numbers wi_x,wi_y,wi_z,wo_x,wo_y,wo_z, "
                        "got '" + line + "'");
        const Vec3 wi(v[0], v[1], v[2]), wo(v[3], v[4], v[5]);
        if (!(wi.length() > 0.0) || !(wo.length() > 0.0))
            throw Error("standard input line " + std::to_string(lineNumber) +
                        ": a direction is the zero vector");
        const Spectrum f = evalBrdf(brdf, wi.normalized(), wo.normalized());
        std::printf("%.10g,%.10g,%.10g\n", f[0], f[1], f[2]);
    }
}

}  // namespace

void registerBrdfCommand(CLI::App& app) {
    CLI::App* brdf = app.add_subcommand("brdf", "List, evaluate and measure the reflection models");
    brdf->require_subcommand(1);

    brdf->add_subcommand("list", "List the models with their parameters, defaults and ranges")
        ->callback(listModels);

    CLI::App* eval = brdf->add_subcommand(
        "eval",
        "Evaluate a model: reads lines wi_x,wi_y,wi_z,wo_x,wo_y,wo_z (local frame: x tangent, y "
        "bitangent, z normal) from standard input and writes f_700,f_546.1,f_435.8 per line");
    // CLI11 binds options to variables that must outlive parsing: one static set per command.
    static std::string model;
    static std::vector<std::string> settings;
    eval->add_option("MODEL", model, "model name (see 'lobe brdf list')")->required();
    eval->add_option("settings", settings, "parameter overrides key=value; per band key=a,b,c");
    eval->callback([] { evalModel(model, settings); });
}

}  // namespace lobe
