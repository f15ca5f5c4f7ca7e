// `lobe study`: a perception study of BRDF assignments with people (docs/study.md).
//   lobe study SCENES… --out DIR [--task pair|which-object|both] [--orbit N]   stimuli + page
//   lobe study serve DIR [--port P]                                           collect answers
//   lobe study analyse ANSWERS… --out DIR                                      JOD, accuracy
//   lobe study simulate DIR --jod Q,… --observers N --out DIR                 simulated answers
#include "analysis/study.h"
#include "analysis/study_report.h"
#include "apps/commands.h"
#include "apps/options.h"
#include "core/error.h"
#include "core/image_output.h"
#include "core/output_folder.h"
#include "core/temporary_file.h"
#include "figure/figure_output.h"
#include "study/study_page.h"
#include "study/study_server.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace lobe {
namespace {

namespace fs = std::filesystem;

std::string readText(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error("cannot read '" + path + "'");
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

std::vector<double> parseList(const std::string& text, const std::string& option) {
    std::vector<double> values;
    std::stringstream in(text);
    std::string item;
    while (std::getline(in, item, ',')) {
        try {
            size_t used = 0;
            values.push_back(std::stod(item, &used));
            if (used != item.size()) throw std::invalid_argument(item);
        } catch (const std::exception&) {
            throw Error(option + ": expected a comma list of numbers, got '" + text + "'");
        }
    }
    if (values.empty()) throw Error(option + ": expected a comma list of numbers");
    return values;
}

// Answers files named by the inputs: files as given, folders' *.json in name order.
std::vector<std::string> answersFiles(const std::vector<std::string>& inputs) {
    std::vector<std::string> files;
    for (const std::string& input : inputs) {
        if (fs::is_directory(input)) {
            std::vector<std::string> found;
            for (const auto& e : fs::directory_iterator(input))
                if (e.path().extension() == ".json") found.push_back(e.path().string());
            std::sort(found.begin(), found.end());
            if (found.empty()) throw Error("folder '" + input + "' holds no .json answers files");
            files.insert(files.end(), found.begin(), found.end());
        } else {
            if (!fs::exists(input)) throw Error("answers file '" + input + "' does not exist");
            files.push_back(input);
        }
    }
    return files;
}

struct AnalyseCommand {
    std::vector<std::string> inputs;
    std::string outDir;
    StudyAnalysisOptions options;
    bool quiet = false;
};

void runAnalyse(const AnalyseCommand& cmd) {
    const std::vector<std::string> files = answersFiles(cmd.inputs);
    std::vector<StudyAnswers> answers;
    for (const std::string& f : files) answers.push_back(parseStudyAnswers(readText(f), f));
    const StudyAnalysis analysis = analyseStudy(answers, cmd.options);
    if (analysis.included.empty())
        throw Error("every participant failed the attention checks: nothing to analyse");
    const fs::path out(cmd.outDir);
    for (const char* name : {"study-results.md", "study-results.csv", "study-results.png"})
        if (fs::exists(out / name))
            throw Error("'" + (out / name).string() + "' exists: give a new --out folder");
    createOutputFolder(cmd.outDir);
    // The plot first (the step that can fail), then the two tables.
    ImageWriteOptions png;
    png.attributes = toolProvenance();
    PendingImage plot =
        writeImagePending((out / "study-results.png").string(), studyPlot(analysis), png);
    writeTextFileAtomic((out / "study-results.csv").string(), studyCsv(analysis));
    writeTextFileAtomic((out / "study-results.md").string(), studyMarkdown(analysis, files));
    plot.commit();
    if (!cmd.quiet) std::fputs(studyMarkdown(analysis, files).c_str(), stdout);
}

struct SimulateCommand {
    std::string studyDir, outDir, jod, accuracy, prefix = "sim-";
    double attentionPass = 1.0;
    int observers = 20;
    uint64_t seed = 1;
};

void runSimulate(const SimulateCommand& cmd) {
    const std::string studyJson = readText((fs::path(cmd.studyDir) / "study.json").string());
    SimulatedObserverModel model;
    model.jod = parseList(cmd.jod, "--jod");
    if (!cmd.accuracy.empty()) model.markerAccuracy = parseList(cmd.accuracy, "--accuracy");
    for (double p : model.markerAccuracy)
        if (p < 0.0 || p > 1.0) throw Error("--accuracy: probabilities in [0, 1]");
    model.attentionPass = cmd.attentionPass;
    if (cmd.observers < 1) throw Error("--observers must be at least 1");
    if (cmd.prefix.empty() ||
        cmd.prefix.find_first_not_of(
            "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789-_") !=
            std::string::npos)
        throw Error("--prefix: letters, digits, '-' and '_' only, got '" + cmd.prefix + "'");
    std::vector<std::string> texts;
    for (int o = 0; o < cmd.observers; ++o)
        texts.push_back(
            simulateStudyAnswers(studyJson, model, o, cmd.seed, cmd.prefix + std::to_string(o)));
    createOutputFolder(cmd.outDir);
    for (int o = 0; o < cmd.observers; ++o) {
        const std::string path =
            (fs::path(cmd.outDir) / (cmd.prefix + std::to_string(o) + ".json")).string();
        if (!writeTextFileAtomic(path, texts[size_t(o)], true))
            throw Error("'" + path + "' exists: give a new --out folder");
    }
    std::fprintf(stderr, "%d simulated participants -> %s\n", cmd.observers, cmd.outDir.c_str());
}

}  // namespace

void registerStudyCommand(CLI::App& app) {
    static StudyRequest study;
    CLI::App* sub = app.add_subcommand(
        "study",
        "A perception study of the scenes with people: renders the stimuli and writes a "
        "self-contained web page (2AFC pairs, marker task); `serve` collects answers, "
        "`analyse` scales them to JOD (docs/study.md)");
    sub->add_option("scenes", study.scenes, "scene files, one per condition");
    sub->add_option("--out", study.outDir, "the study folder to write (new)");
    sub->add_option("--task", study.task,
                    "pair: 2AFC \"which image separates the structures better\"; which-object: "
                    "\"which structure does the highlight at the marker belong to\"; both")
        ->capture_default_str();
    sub->add_option("--orbit", study.orbit,
                    "N: each condition as an N-frame turntable, played at 10 frames/s in the pairs "
                    "(the marker task shows frame 0)")
        ->check(CLI::Range(1, 360));
    sub->add_option("--repeats", study.repeats, "times each pair of conditions is shown")
        ->capture_default_str()
        ->check(CLI::Range(1, 100));
    sub->add_option("--checks", study.checks, "attention checks per task")
        ->capture_default_str()
        ->check(CLI::Range(0, 100));
    sub->add_option("--order-seed", study.seed,
                    "seed of the attention checks; the page mixes it with the participant ID for "
                    "each participant's order and sides")
        ->capture_default_str();
    sub->add_option("--question", study.question, "the question of the pair trials")
        ->capture_default_str();
    addOverrideOptions(*sub, study.overrides);
    sub->add_flag("--quiet", study.quiet, "no progress display");
    sub->footer(
        "Open DIR/index.html in a browser (answers are downloaded as a JSON file), or run "
        "`lobe study serve DIR` and open the address it prints (answers are stored in "
        "DIR/answers).");
    sub->callback([sub] {
        if (sub->get_subcommands().empty()) {
            if (study.scenes.empty()) throw Error("lobe study: no scene file given");
            if (study.outDir.empty()) throw Error("lobe study: --out DIR is required");
            buildStudy(study);
        }
    });

    static StudyServerOptions serve;
    CLI::App* serveSub = sub->add_subcommand(
        "serve",
        "Serve a study folder over HTTP on this machine and store each participant's "
        "answers in DIR/answers (the page's own requests only)");
    serveSub->add_option("dir", serve.dir, "the study folder (written by `lobe study`)")
        ->required();
    serveSub->add_option("--port", serve.port, "TCP port (0: any free port)")
        ->capture_default_str()
        ->check(CLI::Range(0, 65535));
    serveSub
        ->add_option("--host", serve.host,
                     "address to bind: a loopback address unless --allow-remote")
        ->capture_default_str();
    serveSub->add_flag("--allow-remote", serve.allowRemote,
                       "allow a non-loopback --host (anyone reaching the port can post answers)");
    serveSub->add_flag("--quiet", serve.quiet, "do not print each saved answers file");
    serveSub->callback([] { serveStudy(serve); });

    static AnalyseCommand analyse;
    CLI::App* analyseSub = sub->add_subcommand(
        "analyse",
        "Scale the pair answers to JOD (Thurstone case V, bootstrap intervals) and score "
        "the marker task (Wilson intervals); Markdown, CSV and a PNG plot");
    analyseSub->alias("analyze");
    analyseSub->add_option("answers", analyse.inputs, "answers files or folders of them")
        ->required();
    analyseSub->add_option("--out", analyse.outDir, "output folder")->required();
    analyseSub->add_option("--bootstrap", analyse.options.bootstrapSamples, "bootstrap resamples")
        ->capture_default_str()
        ->check(CLI::Range(0, 1000000));
    analyseSub->add_option("--seed", analyse.options.seed, "bootstrap seed")->capture_default_str();
    analyseSub->add_option("--level", analyse.options.level, "confidence level of the intervals")
        ->capture_default_str()
        ->check(CLI::Range(0.5, 0.999));
    analyseSub
        ->add_option("--max-failed-checks", analyse.options.maxFailedChecks,
                     "participants failing more attention checks are excluded")
        ->capture_default_str()
        ->check(CLI::Range(0, 1000));
    analyseSub->add_flag("--quiet", analyse.quiet, "do not print the table");
    analyseSub->callback([] { runAnalyse(analyse); });

    static SimulateCommand simulate;
    CLI::App* simSub = sub->add_subcommand(
        "simulate",
        "Answer a study's trials with simulated observers (Thurstone case V choices "
        "from given JOD values): for checking an analysis and for docs/study.md");
    simSub->add_option("dir", simulate.studyDir, "the study folder (its study.json)")->required();
    simSub->add_option("--jod", simulate.jod, "Q0,Q1,…: each condition's quality in JOD")
        ->required();
    simSub->add_option(
        "--accuracy", simulate.accuracy,
        "P0,P1,…: each condition's probability of naming the marked object (default 1)");
    simSub
        ->add_option("--attention-pass", simulate.attentionPass,
                     "probability of passing each attention check")
        ->capture_default_str()
        ->check(CLI::Range(0.0, 1.0));
    simSub->add_option("--observers", simulate.observers, "simulated participants")
        ->capture_default_str();
    simSub->add_option("--seed", simulate.seed, "seed of the simulated choices")
        ->capture_default_str();
    simSub
        ->add_option("--prefix", simulate.prefix,
                     "participant ids and file names: PREFIX0, PREFIX1, … (PREFIXK.json)")
        ->capture_default_str();
    simSub->add_option("--out", simulate.outDir, "folder for the answers files")->required();
    simSub->callback([] { runSimulate(simulate); });
}

}  // namespace lobe
