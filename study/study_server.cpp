#include "study/study_server.h"

#include "analysis/study.h"
#include "core/error.h"
#include "core/temporary_file.h"
#include "study/study_page.h"

#include <arpa/inet.h>
#include <httplib.h>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>

namespace lobe {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr size_t kMaxAnswersBytes = 4u << 20;  // a study's answers are a few hundred kB at most

std::string readFile(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error("cannot read '" + path.string() + "'");
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

// A participant id as a file name: letters, digits, '-' and '_' kept, others '_', at most 64.
std::string safeName(const std::string& id) {
    std::string s;
    for (char c : id) {
        if (s.size() >= 64) break;
        s += (std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_') ? c : '_';
    }
    return s.empty() ? "participant" : s;
}

// The name in a Host header ("127.0.0.1:8080" → "127.0.0.1", "[::1]:8080" → "::1").
std::string hostName(const std::string& header) {
    if (!header.empty() && header[0] == '[') {
        const size_t close = header.find(']');
        return close == std::string::npos ? header : header.substr(1, close - 1);
    }
    return header.substr(0, header.rfind(':'));
}

void refuse(httplib::Response& res, int status, const std::string& message) {
    res.status = status;
    res.set_content(message + "\n", "text/plain");
}

}  // namespace

bool isLoopbackHost(const std::string& host) {
    if (host == "localhost") return true;
    unsigned char v4[4];
    if (inet_pton(AF_INET, host.c_str(), v4) == 1) return v4[0] == 127;
    unsigned char v6[16];
    if (inet_pton(AF_INET6, host.c_str(), v6) == 1) {
        for (int i = 0; i < 15; ++i)
            if (v6[i] != 0) return false;
        return v6[15] == 1;
    }
    return false;
}

void serveStudy(const StudyServerOptions& options) {
    if (!options.allowRemote && !isLoopbackHost(options.host))
        throw Error("--host " + options.host +
                    " is not a loopback address: the server binds to 127.0.0.1, ::1 or localhost "
                    "unless --allow-remote is given (anyone who can reach the port can then load "
                    "the page and post answers)");
    if (options.port < 0 || options.port > 65535) throw Error("--port must be in [0, 65535]");
    const fs::path dir(options.dir);
    const fs::path studyPath = dir / "study.json";
    if (!fs::is_regular_file(studyPath) || !fs::is_regular_file(dir / "index.html"))
        throw Error("'" + options.dir +
                    "' holds no study (index.html and study.json, written by "
                    "`lobe study SCENES… --out DIR`)");
    json study;
    try {
        study = json::parse(readFile(studyPath));
    } catch (const json::exception& e) {
        throw Error(studyPath.string() + ": not JSON (" + e.what() + ")");
    }
    const std::string fingerprint = study.value("study", "");
    const size_t trialCount = study.contains("trials") ? study["trials"].size() : 0;
    // The only files served: the page and the stimuli the study lists (read when asked for).
    std::map<std::string, std::pair<fs::path, std::string>> files{
        {"/", {dir / "index.html", "text/html; charset=utf-8"}},
        {"/index.html", {dir / "index.html", "text/html; charset=utf-8"}}};
    for (const json& c : study.value("conditions", json::array()))
        for (const json& f : c.value("frames", json::array())) {
            const std::string rel = f.get<std::string>();
            if (rel.find("..") != std::string::npos || rel.empty() || rel[0] == '/')
                throw Error(studyPath.string() + ": stimulus path '" + rel + "' leaves the folder");
            files["/" + rel] = {dir / rel, "image/png"};
        }
    const fs::path answersDir = dir / "answers";
    std::error_code ec;
    fs::create_directories(answersDir, ec);
    if (ec) throw Error("cannot create '" + answersDir.string() + "': " + ec.message());

    httplib::Server server;
    server.set_payload_max_length(kMaxAnswersBytes);
    std::mutex saving;
    server.set_pre_routing_handler([&](const httplib::Request& req, httplib::Response& res) {
        using Handled = httplib::Server::HandlerResponse;
        if (req.target.find("..") != std::string::npos ||
            req.path.find("..") != std::string::npos) {
            refuse(res, 403, "paths with '..' are refused");
            return Handled::Handled;
        }
        // On loopback, the browser must have asked for a loopback name: a page of another site
        // whose name was re-pointed at 127.0.0.1 (DNS rebinding) sends its own name as Host.
        const std::string hostHeader = req.get_header_value("Host");
        if (!options.allowRemote && !isLoopbackHost(hostName(hostHeader))) {
            refuse(res, 403, "requests for host '" + hostHeader + "' are refused");
            return Handled::Handled;
        }
        if (req.method == "GET" || req.method == "HEAD") {
            const auto it = files.find(req.path);
            if (it == files.end()) {
                refuse(res, 404, "not part of this study");
                return Handled::Handled;
            }
            try {
                res.set_content(readFile(it->second.first), it->second.second.c_str());
                res.set_header("Cache-Control", "no-store");
            } catch (const Error& e) {
                refuse(res, 404, e.what());
            }
            return Handled::Handled;
        }
        if (req.method != "POST" || req.path != "/answers") {
            refuse(res, 405, "only GET of the page's files and POST /answers");
            return Handled::Handled;
        }
        // Same origin only: the page that posts was loaded from this server (by the name the
        // browser used for it, e.g. localhost or 127.0.0.1).
        if (req.has_header("Origin") && req.get_header_value("Origin") != "http://" + hostHeader) {
            refuse(res, 403, "answers are accepted from the study's own page only");
            return Handled::Handled;
        }
        return Handled::Unhandled;  // the body is read for the route below
    });
    server.Post("/answers", [&](const httplib::Request& req, httplib::Response& res) {
        StudyAnswers answers;
        try {
            answers = parseStudyAnswers(req.body, "posted answers");
        } catch (const Error& e) {
            refuse(res, 400, e.what());
            return;
        }
        if (answers.study != fingerprint) {
            refuse(res, 400, "answers of another study (" + answers.study + ")");
            return;
        }
        if (size_t(answers.trials()) != trialCount) {
            refuse(res, 400,
                   "answers to " + std::to_string(answers.trials()) + " of " +
                       std::to_string(trialCount) + " trials");
            return;
        }
        std::lock_guard<std::mutex> lock(saving);
        const std::string base = safeName(answers.participant);
        for (int k = 1; k < 100000; ++k) {
            const std::string name = base + (k == 1 ? "" : "-" + std::to_string(k)) + ".json";
            try {
                if (writeTextFileAtomic((answersDir / name).string(), req.body, true)) {
                    if (!options.quiet) std::fprintf(stderr, "saved answers/%s\n", name.c_str());
                    res.set_content(json{{"saved", "answers/" + name}}.dump(), "application/json");
                    return;
                }
            } catch (const Error& e) {
                refuse(res, 500, e.what());
                return;
            }
        }
        refuse(res, 500, "too many answers files for participant '" + base + "'");
    });
    int port = options.port;
    if (port == 0) {
        port = server.bind_to_any_port(options.host);
        if (port < 0) throw Error("cannot bind to " + options.host + " (any port)");
    } else if (!server.bind_to_port(options.host, port)) {
        throw Error("cannot bind to " + options.host + ":" + std::to_string(port) +
                    " (in use? try another --port)");
    }
    const std::string hostPart =
        options.host.find(':') != std::string::npos ? "[" + options.host + "]" : options.host;
    const std::string origin = "http://" + hostPart + ":" + std::to_string(port);
    std::printf("serving %s/ (answers into %s; Ctrl-C stops)\n", origin.c_str(),
                answersDir.string().c_str());
    std::fflush(stdout);
    if (!server.listen_after_bind()) throw Error("the server stopped: " + origin);
}

}  // namespace lobe
