#include "core/memory.h"

#include "core/error.h"

#include <sys/resource.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <mutex>
#include <sstream>

namespace lobe {
namespace {

// A limit file's number; 0 for "max", unreadable, or v1's "unlimited" (2^63 rounded to pages).
double readLimit(const std::string& path) {
    std::ifstream in(path);
    std::string text;
    if (!in || !(in >> text) || text == "max") return 0.0;
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (*end != '\0' || !(v > 0.0) || v >= 1e18) return 0.0;
    return v;
}

}  // namespace

double physicalMemoryBytes() {
    const long pages = sysconf(_SC_PHYS_PAGES), size = sysconf(_SC_PAGE_SIZE);
    return pages > 0 && size > 0 ? double(pages) * double(size) : 0.0;
}

double cgroupMemoryLimit(const std::string& procSelfCgroup, const std::string& root,
                         std::string* file) {
    double least = 0.0;
    std::istringstream lines(procSelfCgroup);
    for (std::string line; std::getline(lines, line);) {
        // hierarchy-ID:controller-list:cgroup-path (cgroups(7), /proc/[pid]/cgroup)
        const size_t a = line.find(':'), b = a == std::string::npos ? a : line.find(':', a + 1);
        if (b == std::string::npos) continue;
        const std::string id = line.substr(0, a), controllers = line.substr(a + 1, b - a - 1);
        std::string path = line.substr(b + 1);
        std::string base, name;
        if (id == "0" && controllers.empty()) {
            base = root;
            name = "memory.max";
        } else if (("," + controllers + ",").find(",memory,") != std::string::npos) {
            base = root + "/memory";
            name = "memory.limit_in_bytes";
        } else {
            continue;
        }
        // The cgroup and each ancestor up to the root: the least limit binds.
        while (true) {
            const std::string f = base + (path == "/" ? "" : path) + "/" + name;
            const double v = readLimit(f);
            if (v > 0.0 && (least == 0.0 || v < least)) {
                least = v;
                if (file) *file = f;
            }
            if (path.empty() || path == "/") break;
            const size_t slash = path.rfind('/');
            path = slash == 0 || slash == std::string::npos ? "/" : path.substr(0, slash);
        }
    }
    return least;
}

namespace {
std::mutex g_budgetMutex;
MemoryBudget g_fixedBudget;  // bytes 0: none
}  // namespace

void setMemoryBudget(const MemoryBudget& budget) {
    std::lock_guard<std::mutex> lock(g_budgetMutex);
    g_fixedBudget = budget;
}

MemoryBudget memoryBudget() {
    {
        std::lock_guard<std::mutex> lock(g_budgetMutex);
        if (g_fixedBudget.bytes > 0.0) return g_fixedBudget;
    }
    MemoryBudget budget;
    const auto consider = [&](double bytes, const std::string& source) {
        if (bytes > 0.0 && (budget.bytes == 0.0 || bytes < budget.bytes)) {
            budget.bytes = bytes;
            budget.source = source;
        }
    };
    consider(physicalMemoryBytes(), "physical memory");
    struct rlimit limit;
    if (getrlimit(RLIMIT_AS, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY)
        consider(double(limit.rlim_cur), "the address-space limit, ulimit -v (RLIMIT_AS)");
    if (getrlimit(RLIMIT_DATA, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY)
        consider(double(limit.rlim_cur), "the data-segment limit, ulimit -d (RLIMIT_DATA)");
    std::ifstream in("/proc/self/cgroup");
    std::stringstream text;
    text << in.rdbuf();
    std::string file;
    consider(cgroupMemoryLimit(text.str(), "/sys/fs/cgroup", &file),
             "the memory cgroup's limit, " + file);
    return budget;
}

void checkFits(double bytes, const std::string& what) {
    const MemoryBudget budget = memoryBudget();
    const double limit = budget.bytes > 0.0 ? budget.bytes / 2.0 : 1e12;
    if (!(bytes <= limit)) {
        char text[160];
        std::snprintf(text, sizeof text,
                      " needs %.3g GB, more than half of the %.3g GB this process may use (",
                      bytes / 1e9, (budget.bytes > 0.0 ? budget.bytes : 2e12) / 1e9);
        throw Error(what + text + (budget.source.empty() ? "unknown" : budget.source) + ")");
    }
}

std::string outOfMemoryText() {
    const MemoryBudget budget = memoryBudget();
    if (budget.bytes <= 0.0) return "out of memory";
    char text[64];
    std::snprintf(text, sizeof text, "%.3g GB", budget.bytes / 1e9);
    return "out of memory (this process may use " + std::string(text) + ": " + budget.source + ")";
}

}  // namespace lobe
