// `lobe study serve DIR [--port P]` (docs/study.md): an HTTP server (cpp-httplib, Debian
// libcpp-httplib-dev) for a study folder written by `lobe study`. It answers the page's own
// requests only — GET of the page and of the stimuli study.json lists, POST of a participant's
// answers — and nothing else: any other path is 404, a path with ".." 403, a POST from another
// origin than the page's 403, and (on loopback) a request naming a non-loopback host 403 (a
// page of another site whose name was re-pointed at 127.0.0.1, "DNS rebinding"). Each participant's
// answers (checked: this study's fingerprint and every trial answered) are stored as
// DIR/answers/<participant>.json, written completely under a temporary name and linked into place,
// never over an existing file (a second file of the same participant becomes <participant>-2.json,
// …). It binds to a loopback address unless --allow-remote is given.
#pragma once

#include <string>

namespace lobe {

struct StudyServerOptions {
    std::string dir;
    std::string host = "127.0.0.1";
    int port = 8080;  // 0: any free port (printed)
    bool allowRemote = false;
    bool quiet = false;
};

// Whether `host` is a numeric loopback address (127.0.0.0/8 or ::1) or "localhost".
bool isLoopbackHost(const std::string& host);

// Serves until the process is stopped (SIGINT/SIGTERM). Prints "serving http://HOST:PORT/" on
// stdout once listening. Throws lobe::Error for a folder without a study, a non-loopback host
// without allowRemote, or a port that cannot be bound.
void serveStudy(const StudyServerOptions& options);

}  // namespace lobe
