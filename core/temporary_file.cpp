#include "core/temporary_file.h"

#include "core/error.h"
#include "core/interrupt.h"

#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <random>
#include <set>
#include <vector>

namespace lobe {
namespace {

namespace fs = std::filesystem;

std::string hostName() {
    char name[256] = {0};
    if (::gethostname(name, sizeof name - 1) != 0 || !name[0]) return "host";
    std::string h = name;
    for (char& c : h)
        if (c == '~' || c == '/') c = '_';
    return h;
}

// Whether process `pid` on this host is alive and is a lobe (a PID reused by another program
// after the owner died counts as dead).
bool lobeAlive(long pid) {
    if (pid <= 0) return false;
    if (::kill(pid_t(pid), 0) != 0 && errno == ESRCH) return false;
    std::ifstream comm("/proc/" + std::to_string(pid) + "/comm");
    std::string name;
    if (!comm || !std::getline(comm, name)) return true;  // cannot tell: keep its files
    return name.rfind("lobe", 0) == 0;
}

std::mutex g_mutex;
std::set<std::string> g_reclaimed;  // folders already looked at by this process

}  // namespace

std::string temporarySibling(const std::string& path, bool keepExtension) {
    const fs::path p(path);
    const fs::path folder = p.parent_path().empty() ? fs::path(".") : p.parent_path();
    bool first = false;
    {
        std::lock_guard<std::mutex> lock(g_mutex);
        first = g_reclaimed.insert(fs::absolute(folder).lexically_normal().string()).second;
    }
    if (first) reclaimDeadTemporaries(folder.string());
    std::random_device rd;
    const std::string owner =
        hostName() + "~" + std::to_string(::getpid()) + "~" + std::to_string(rd() % 1000000);
    const std::string name =
        keepExtension ? "." + p.stem().string() + ".partial-" + owner + p.extension().string()
                      : "." + p.filename().string() + ".partial-" + owner;
    return (p.parent_path() / name).string();
}

int reclaimDeadTemporaries(const std::string& folder) {
    std::error_code ec;
    const std::string host = hostName();
    std::vector<fs::path> dead;
    std::set<std::string> owners, foreign;
    std::vector<std::string> foreignNames;
    for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string name = it->path().filename().string();
        const size_t at = name.find(".partial-");
        if (name.empty() || name[0] != '.' || at == std::string::npos) continue;
        // HOST~PID~TAG after ".partial-", up to the extension's dot (a host may hold dots).
        const std::string rest = name.substr(at + 9);
        const size_t a = rest.find('~'), b = a == std::string::npos ? a : rest.find('~', a + 1);
        if (b == std::string::npos) continue;
        const std::string ownerHost = rest.substr(0, a);
        const std::string pidText = rest.substr(a + 1, b - a - 1);
        if (pidText.empty() || pidText.find_first_not_of("0123456789") != std::string::npos ||
            pidText.size() > 9)
            continue;
        const long pid = std::stol(pidText);
        if (ownerHost != host) {
            foreign.insert(ownerHost + " PID " + pidText);
            foreignNames.push_back(name);
            continue;
        }
        if (pid == long(::getpid()) || lobeAlive(pid)) continue;
        dead.push_back(it->path());
        owners.insert(pidText);
    }
    int removed = 0;
    std::uintmax_t bytes = 0;
    for (const fs::path& p : dead) {
        std::error_code e;
        const std::uintmax_t size = fs::file_size(p, e);
        if (fs::remove(p, e)) {
            ++removed;
            if (size != std::uintmax_t(-1)) bytes += size;
        }
    }
    if (removed > 0) {
        std::string pids;
        for (const std::string& o : owners) pids += (pids.empty() ? "" : ", ") + o;
        std::fprintf(stderr,
                     "lobe: removed %d temporary file%s (%.3g MB) that %s run%s killed before "
                     "finishing left in %s (PID %s)\n",
                     removed, removed == 1 ? "" : "s", double(bytes) / 1e6,
                     owners.size() == 1 ? "a" : "", owners.size() == 1 ? "" : "s", folder.c_str(),
                     pids.c_str());
    }
    if (!foreign.empty()) {
        std::string who;
        for (const std::string& o : foreign) who += (who.empty() ? "" : ", ") + o;
        std::fprintf(stderr,
                     "lobe: note: %s holds %zu temporary file%s of runs on other machines (%s), "
                     "e.g. %s; remove them if those runs are over\n",
                     folder.c_str(), foreignNames.size(), foreignNames.size() == 1 ? "" : "s",
                     who.c_str(), foreignNames.front().c_str());
    }
    return removed;
}

bool writeTextFileAtomic(const std::string& path, const std::string& text, bool noReplace) {
    const std::string temporary = temporarySibling(path, false);
    RemovedOnInterrupt guard(temporary);
    {
        std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
        if (!out) throw Error("cannot write '" + path + "': cannot create a file in its folder");
        out << text;
        out.flush();
        if (!out) {
            std::error_code ec;
            fs::remove(temporary, ec);
            throw Error("cannot write '" + path + "': write failed");
        }
    }
    if (noReplace) {
        // link(2) fails with EEXIST rather than replace a file: no answers are overwritten.
        const int linked = ::link(temporary.c_str(), path.c_str());
        const int error = errno;
        std::error_code ec;
        fs::remove(temporary, ec);
        if (linked == 0) return true;
        if (error == EEXIST) return false;
        throw Error("cannot write '" + path + "': " + std::strerror(error));
    }
    std::error_code ec;
    fs::rename(temporary, path, ec);
    if (ec) {
        fs::remove(temporary, ec);
        throw Error("cannot write '" + path + "': " + ec.message());
    }
    return true;
}

}  // namespace lobe
