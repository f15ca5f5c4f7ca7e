#include "analysis/cost_report.h"

#include <cstdarg>
#include <cstdio>
#include <filesystem>

namespace lobe {
namespace {

std::string format(const char* fmt, ...) __attribute__((format(printf, 1, 2)));
std::string format(const char* fmt, ...) {
    char buf[512];
    va_list args;
    va_start(args, fmt);
    std::vsnprintf(buf, sizeof buf, fmt, args);
    va_end(args);
    return buf;
}

double share(double part, double total) { return total > 0.0 ? 100.0 * part / total : 0.0; }

std::string nsPerEvaluation(const ObjectCost& o) {
    if (o.brdfEvaluations == 0) return "-";
    return format("%.1f", 1e9 * o.shadingSeconds / double(o.brdfEvaluations));
}

struct Part {
    const char* key;
    const char* title;
    double seconds;
};

std::vector<Part> partsOf(const RenderCost& c) {
    return {{"surfaces", "surfaces (Embree traversal + hit)", c.surfaces},
            {"volumes", "volume sampling (reconstruction + transfer function)", c.volumes},
            {"shading", "shading (BRDF + light loop)", c.shading},
            {"other", "other (camera rays, compositing, backdrop)", c.other}};
}

std::string csvField(const std::string& s) {
    if (s.find_first_of(",\"\n") == std::string::npos) return s;
    std::string q = "\"";
    for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
    return q + "\"";
}

}  // namespace

std::string costMarkdown(const std::vector<CostRun>& runs, int target, int threads, int repeat) {
    if (runs.empty()) return "";
    const CostRun& base = runs.front();
    const SceneSpec& spec = base.spec;
    const RenderCost& c = base.cost;
    std::string md =
        format("## Cost of %s\n\n", std::filesystem::path(spec.path).filename().c_str());
    md += format(
        "%dx%d, %d spp, %s threads%s: wall %.3f s, CPU %.3f s.\n\n", spec.width, spec.height,
        spec.samplesPerPixel, threads > 0 ? std::to_string(threads).c_str() : "all",
        repeat > 1 ? format(", fastest of %d", repeat).c_str() : "", c.wallSeconds, c.cpuSeconds);
    md += "| part | CPU s | share |\n|---|---:|---:|\n";
    for (const Part& p : partsOf(c))
        md +=
            format("| %s | %.3f | %.1f %% |\n", p.title, p.seconds, share(p.seconds, c.cpuSeconds));
    md += format("| total | %.3f | 100 %% |\n\n", c.cpuSeconds);
    md +=
        "| object | model | shaded points | BRDF evaluations | shading CPU s | ns / evaluation |\n"
        "|---|---|---:|---:|---:|---:|\n";
    for (size_t i = 0; i < spec.objects.size() && i < c.objects.size(); ++i) {
        const ObjectCost& o = c.objects[i];
        md += format("| %s | %s | %lld | %lld | %.3f | %s |\n", spec.objects[i].name.c_str(),
                     spec.objects[i].brdfModel.c_str(), o.shadedPoints, o.brdfEvaluations,
                     o.shadingSeconds, nsPerEvaluation(o).c_str());
    }
    if (runs.size() > 1 && target >= 0) {
        const std::string& name = spec.objects[size_t(target)].name;
        md += format("\n### Models on '%s'\n\n", name.c_str());
        md += format(
            "| model | BRDF evaluations | shading CPU s (%s) | ns / evaluation | shading CPU "
            "s (all) | render CPU s | render CPU vs. scene | wall s |\n"
            "|---|---:|---:|---:|---:|---:|---:|---:|\n",
            name.c_str());
        for (const CostRun& run : runs) {
            const ObjectCost& o = run.cost.objects[size_t(target)];
            const std::string label = run.label == "scene"
                                          ? run.spec.objects[size_t(target)].brdfModel + " (scene)"
                                          : run.label;
            md += format("| %s | %lld | %.3f | %s | %.3f | %.3f | %.2f | %.3f |\n", label.c_str(),
                         o.brdfEvaluations, o.shadingSeconds, nsPerEvaluation(o).c_str(),
                         run.cost.shading, run.cost.cpuSeconds,
                         c.cpuSeconds > 0 ? run.cost.cpuSeconds / c.cpuSeconds : 0.0,
                         run.cost.wallSeconds);
        }
    }
    return md;
}

std::string costCsv(const std::vector<CostRun>& runs) {
    std::string csv =
        "run,row,name,model,shaded_points,brdf_evaluations,cpu_seconds,ns_per_evaluation\n";
    for (const CostRun& run : runs) {
        const RenderCost& c = run.cost;
        const std::string r = csvField(run.label);
        for (const Part& p : partsOf(c))
            csv += format("%s,part,%s,,,,%.9g,\n", r.c_str(), p.key, p.seconds);
        csv += format("%s,total,cpu,,,%lld,%.9g,\n", r.c_str(), c.brdfEvaluations(), c.cpuSeconds);
        csv += format("%s,total,wall,,,,%.9g,\n", r.c_str(), c.wallSeconds);
        for (size_t i = 0; i < run.spec.objects.size() && i < c.objects.size(); ++i) {
            const ObjectCost& o = c.objects[i];
            const std::string ns = o.brdfEvaluations ? nsPerEvaluation(o) : "";
            csv += r + ",object," + csvField(run.spec.objects[i].name) + "," +
                   csvField(run.spec.objects[i].brdfModel) +
                   format(",%lld,%lld,%.9g,", o.shadedPoints, o.brdfEvaluations, o.shadingSeconds) +
                   ns + "\n";
        }
    }
    return csv;
}

std::string costSummary(const SceneSpec& spec, const RenderCost& c) {
    std::string s = format("CPU %.3f s (wall %.3f s):", c.cpuSeconds, c.wallSeconds);
    for (const Part& p : partsOf(c))
        s += format(" %s %.3f s (%.1f %%),", p.key, p.seconds, share(p.seconds, c.cpuSeconds));
    s.back() = '\n';
    for (size_t i = 0; i < spec.objects.size() && i < c.objects.size(); ++i) {
        const ObjectCost& o = c.objects[i];
        s += format("  %s (%s): %lld BRDF evaluations, %.3f s shading, %s ns/evaluation\n",
                    spec.objects[i].name.c_str(), spec.objects[i].brdfModel.c_str(),
                    o.brdfEvaluations, o.shadingSeconds, nsPerEvaluation(o).c_str());
    }
    return s;
}

}  // namespace lobe
