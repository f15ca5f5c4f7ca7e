// `lobe brdf list | eval | props`: the reflection models as a tool. `eval` is the stable interface
// other tools check the models through: one input line of six numbers (wi then wo, local frame,
// normalised here) gives one output line of three band values with 10 significant digits.
#include "analysis/properties.h"
#include "apps/brdf_input.h"
#include "apps/commands.h"
#include "core/error.h"
#include "core/tile_scheduler.h"
#include "materials/registry.h"

#include <CLI/CLI.hpp>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
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

void evalModel(const std::string& name, const std::vector<std::string>& settings) {
    const Brdf brdf = makeBrdf(name, settings);
    std::string line;
    long lineNumber = 0;
    while (std::getline(std::cin, line)) {
        ++lineNumber;
        if (line.find_first_not_of(" \t\r") == std::string::npos) continue;  // blank line
        double v[6];
        if (!parseSixNumbers(line, v)) {
            std::string shown;  // control characters (a NUL) shown as \xNN: the message is one line
            for (unsigned char c : line) {
                char hex[8];
                std::snprintf(hex, sizeof hex, "\\x%02x", c);
                shown += c < 32 || c == 127 ? std::string(hex) : std::string(1, char(c));
            }
            throw Error("standard input line " + std::to_string(lineNumber) +
                        ": expected six comma-separated numbers wi_x,wi_y,wi_z,wo_x,wo_y,wo_z, "
                        "got '" +
                        shown + "'");
        }
        Vec3 wi, wo;
        if (!unitDirection(v[0], v[1], v[2], wi) || !unitDirection(v[3], v[4], v[5], wo))
            throw Error("standard input line " + std::to_string(lineNumber) +
                        ": a direction is the zero vector");
        const Spectrum f = evalBrdf(brdf, wi, wo);
        std::printf("%.10g,%.10g,%.10g\n", f[0], f[1], f[2]);
    }
}

// ---- `lobe brdf props`: the paper's Table 1 regenerated from measurements ----------------------

struct PropsOptions {
    bool csv = false;
    bool perSetting = false;
    int64_t samples = 8192;
    int threads = 0;
    uint64_t seed = 20030101;
};

const char* yesNo(bool b) { return b ? "yes" : "no"; }

// "yes (3/4)": the value at the defaults, then in how many of the model's measured settings
// (defaults and sweep) the property holds.
template <class Pred>
std::string summaryCell(const std::vector<PropertyReport>& reports, const std::string& model,
                        Pred pred) {
    int holds = 0, total = 0;
    bool atDefaults = false;
    for (const PropertyReport& r : reports) {
        if (r.setting.model != model) continue;
        ++total;
        holds += pred(r) ? 1 : 0;
        if (r.setting.label == "defaults") atDefaults = pred(r);
    }
    return std::string(yesNo(atDefaults)) + " (" + std::to_string(holds) + "/" +
           std::to_string(total) + ")";
}

const PropertyReport& defaultsReport(const std::vector<PropertyReport>& reports,
                                     const std::string& model) {
    for (const PropertyReport& r : reports)
        if (r.setting.model == model && r.setting.label == "defaults") return r;
    throw Error("internal: no defaults measurement for " + model);
}

std::string claimsText(bool plausible, bool fresnel, bool anisotropic, bool popular) {
    std::string s;
    const auto add = [&](bool on, const char* name) {
        if (on) s += (s.empty() ? "" : ", ") + std::string(name);
    };
    add(plausible, "Physically plausible");
    add(fresnel, "Fresnel behavior");
    add(anisotropic, "anisotropic");
    add(popular, "Popular");
    return s.empty() ? "None" : s;
}

std::string csvField(const std::string& s) {
    return s.find_first_of(",\"") == std::string::npos ? s : "\"" + s + "\"";
}

void printPerSetting(const std::vector<PropertyReport>& reports, bool csv) {
    if (csv) {
        std::printf(
            "model,setting,reciprocity_error,max_albedo,max_albedo_stderr,theta_at_max_deg,"
            "anisotropy,albedo_80_over_0,albedo_80_over_0_stderr,reciprocal,"
            "energy_conserving,plausible,fresnel,anisotropic\n");
        for (const PropertyReport& r : reports)
            std::printf("%s,%s,%.3g,%.5g,%.2g,%g,%.3g,%.5g,%.2g,%s,%s,%s,%s,%s\n",
                        r.setting.model.c_str(), csvField(r.setting.label).c_str(),
                        r.reciprocityError, r.maxAlbedo.value, r.maxAlbedo.stdError,
                        r.thetaAtMaxDeg, r.anisotropy, r.albedoRatio80To0.value,
                        r.albedoRatio80To0.stdError, yesNo(r.reciprocal), yesNo(r.energyConserving),
                        yesNo(r.plausible), yesNo(r.fresnel), yesNo(r.anisotropic));
        return;
    }
    std::printf(
        "| model | setting | reciprocity error | max a(θi) ± σ | at θi | anisotropy | "
        "a(80°)/a(0°) | reciprocal | a ≤ 1 | plausible | Fresnel | anisotropic |\n");
    std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    for (const PropertyReport& r : reports)
        std::printf(
            "| %s | %s | %.2g | %.4g ± %.1g | %g° | %.2g | %.3g ± %.1g | %s | %s | %s | %s "
            "| %s |\n",
            r.setting.model.c_str(), r.setting.label.c_str(), r.reciprocityError, r.maxAlbedo.value,
            r.maxAlbedo.stdError, r.thetaAtMaxDeg, r.anisotropy, r.albedoRatio80To0.value,
            r.albedoRatio80To0.stdError, yesNo(r.reciprocal), yesNo(r.energyConserving),
            yesNo(r.plausible), yesNo(r.fresnel), yesNo(r.anisotropic));
}

// Table 1 of the paper (Koldenhof 2003), one row per model in the paper's order, measured
// columns beside the paper's claims. Popular cannot be measured: the paper's value is carried.
void printTable1(const std::vector<PropertyReport>& reports, bool csv) {
    struct Row {
        std::string model;
        PaperClaims claims;
    };
    std::vector<Row> rows;
    for (const BrdfModelInfo& m : brdfModels()) rows.push_back({m.name, paperClaims(m.name)});
    // In the paper's printed order (sorted by score; PaperClaims::tableRow); models it does not
    // list (lambert) go last.
    const auto rank = [](const Row& r) { return r.claims.found ? r.claims.tableRow : 1 << 20; };
    std::stable_sort(rows.begin(), rows.end(),
                     [&](const Row& a, const Row& b) { return rank(a) < rank(b); });

    if (csv)
        std::printf(
            "number,model,plausible,fresnel,anisotropic,popular_paper,score_measured,"
            "paper_properties,paper_score,disagreements\n");
    else {
        std::printf(
            "| # | BRDF | Physically plausible | Fresnel behavior | Anisotropic | "
            "Popular (paper) | Score (measured) | Paper: properties | Paper: score | "
            "Disagreements |\n");
        std::printf("|---|---|---|---|---|---|---|---|---|---|\n");
    }
    for (const Row& row : rows) {
        const PropertyReport& d = defaultsReport(reports, row.model);
        const PaperClaims& c = row.claims;
        const int score =
            int(d.plausible) + int(d.fresnel) + int(d.anisotropic) + int(c.found && c.popular);
        std::string disagree;
        const auto check = [&](bool measured, bool claimed, const char* what) {
            if (!c.found || measured == claimed) return;
            disagree += (disagree.empty() ? "" : "; ") + std::string(what) + ": paper " +
                        yesNo(claimed) + ", measured " + yesNo(measured);
        };
        check(d.plausible, c.plausible, "plausible");
        check(d.fresnel, c.fresnel, "Fresnel");
        check(d.anisotropic, c.anisotropic, "anisotropic");
        const std::string plausible =
            summaryCell(reports, row.model, [](const PropertyReport& r) { return r.plausible; });
        const std::string fresnel =
            summaryCell(reports, row.model, [](const PropertyReport& r) { return r.fresnel; });
        const std::string aniso =
            summaryCell(reports, row.model, [](const PropertyReport& r) { return r.anisotropic; });
        const std::string number = c.found ? std::to_string(c.number) : "-";
        const std::string popular = c.found ? yesNo(c.popular) : "n/a";
        const std::string paperProps =
            c.found ? claimsText(c.plausible, c.fresnel, c.anisotropic, c.popular)
                    : "not in the paper";
        const std::string paperScore = c.found ? std::to_string(c.score) : "-";
        if (csv)
            std::printf("%s,%s,%s,%s,%s,%s,%d,%s,%s,%s\n", number.c_str(), row.model.c_str(),
                        plausible.c_str(), fresnel.c_str(), aniso.c_str(), popular.c_str(), score,
                        csvField(paperProps).c_str(), paperScore.c_str(),
                        csvField(disagree).c_str());
        else
            std::printf("| %s | %s | %s | %s | %s | %s | %d | %s | %s | %s |\n", number.c_str(),
                        row.model.c_str(), plausible.c_str(), fresnel.c_str(), aniso.c_str(),
                        popular.c_str(), score, paperProps.c_str(), paperScore.c_str(),
                        disagree.empty() ? "-" : disagree.c_str());
    }
}

void measureAndPrint(const PropsOptions& o) {
    // Bounded: 8 x samples pairs are drawn per setting, over 60 settings; 2^24 samples already
    // take hours (an int count overflowed at 300 000 000 and the run never ended).
    constexpr int64_t kMaxSamples = int64_t(1) << 24;
    if (o.samples < 64 || o.samples > kMaxSamples)
        throw Error("--samples " + std::to_string(o.samples) + ": expected 64 to " +
                    std::to_string(kMaxSamples));
    if (o.threads < 0) throw Error("--threads " + std::to_string(o.threads) + ": must be ≥ 0");
    PropertyOptions options;
    options.albedoSamples = o.samples;
    options.pairs = 8 * o.samples;
    options.seed = o.seed;
    const std::vector<ModelSetting> settings = propertySettings();
    std::vector<PropertyReport> reports(settings.size());
    const auto start = std::chrono::steady_clock::now();
    runWithThreads(o.threads, [&] {
        tbb::parallel_for(size_t(0), settings.size(),
                          [&](size_t i) { reports[i] = measureProperties(settings[i], options); });
    });
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (o.csv) {
        if (o.perSetting)
            printPerSetting(reports, true);
        else
            printTable1(reports, true);
    } else {
        std::printf("## Table 1, regenerated from measurements\n\n");
        std::printf(
            "Measured columns: the value at the model's defaults, then (k/N) the number of "
            "its N measured settings (defaults and sweep) where the property holds. "
            "Score = measured properties at the defaults + the paper's 'Popular' (not "
            "measurable, carried over).\n\n");
        printTable1(reports, false);
        std::printf("\n## Per setting\n\n");
        std::printf("Albedo: %lld samples per (θi, φi), θi ∈ {", static_cast<long long>(o.samples));
        for (size_t i = 0; i < albedoThetasDeg().size(); ++i)
            std::printf("%s%g", i ? ", " : "", albedoThetasDeg()[i]);
        std::printf(
            "}°, max over φi ∈ {0, 45, 90}° and the three bands; reciprocity and "
            "anisotropy over %lld pairs; thresholds: reciprocal if error ≤ %g, anisotropic "
            "if measure > %g, a ≤ 1 and Fresnel decided at %g σ.\n\n",
            static_cast<long long>(options.pairs), kReciprocityTolerance, kAnisotropyTolerance,
            kSigmaThreshold);
        printPerSetting(reports, false);
    }
    std::fprintf(stderr, "lobe brdf props: %zu settings measured in %.2f s\n", settings.size(),
                 seconds);
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

    CLI::App* props = brdf->add_subcommand(
        "props",
        "Measure every model (defaults and a documented parameter sweep): reciprocity error, "
        "directional albedo over θi, anisotropy, Fresnel behaviour; print the paper's Table 1 "
        "regenerated from the measurements beside the paper's claims (Markdown, or --csv)");
    static PropsOptions propsOptions;
    props->add_flag("--csv", propsOptions.csv, "CSV instead of Markdown (Table 1 only)");
    props->add_flag("--per-setting", propsOptions.perSetting,
                    "with --csv: one row per measured setting instead of Table 1");
    props
        ->add_option("--samples", propsOptions.samples,
                     "albedo samples per (θi, φi) estimate, 64 to 16777216 (pairs for "
                     "reciprocity/anisotropy: 8×)")
        ->capture_default_str();
    props->add_option("--threads", propsOptions.threads, "worker threads (0: all)")
        ->capture_default_str();
    props->add_option("--seed", propsOptions.seed, "random seed")->capture_default_str();
    props->callback([] { measureAndPrint(propsOptions); });
}

}  // namespace lobe
