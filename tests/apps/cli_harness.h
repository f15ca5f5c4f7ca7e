// Running the built `lobe` from a test: a shell command with its standard streams in files, and
// a folder of the test's own, so that parallel ctest processes never share files. Shared by
// tests/apps/test_cli.cpp and test_cli_figure.cpp.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace lobe::test {

namespace fs = std::filesystem;

struct CliRun {
    int exitCode = -1;
    std::string out, err;
    int errLines() const {
        int n = 0;
        for (char c : err) n += c == '\n';
        return n;
    }
};

inline std::string readFile(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

// Single-quoted for the shell.
inline std::string quote(const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

// A fresh folder of the test's own: LOBE_BINARY_DIR/test-output/GROUP/SUITE.NAME.
inline fs::path testDir(const std::string& group) {
    const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
    const fs::path d = fs::path(LOBE_BINARY_DIR) / "test-output" / group /
                       (std::string(info->test_suite_name()) + "." + info->name());
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}

// Runs `command` in a shell with `input` on standard input; the streams pass through files in
// `ioDir` named by this process, removed afterwards.
inline CliRun runShell(const std::string& command, const fs::path& ioDir,
                       const std::string& input = "") {
    fs::create_directories(ioDir);
    const std::string pid = std::to_string(::getpid());
    const fs::path in = ioDir / ("in" + pid), out = ioDir / ("out" + pid),
                   err = ioDir / ("err" + pid);
    std::ofstream(in) << input;
    const std::string cmd = command + " <" + quote(in.string()) + " >" + quote(out.string()) +
                            " 2>" + quote(err.string());
    const int status = std::system(cmd.c_str());
    CliRun r;
    r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = readFile(out);
    r.err = readFile(err);
    fs::remove(in);
    fs::remove(out);
    fs::remove(err);
    return r;
}

}  // namespace lobe::test
