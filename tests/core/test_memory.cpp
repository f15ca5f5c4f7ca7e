// The memory budget (core/memory.h): the cgroup limit read from a /proc/self/cgroup text and a
// cgroup tree written here (v2 memory.max, v1 memory.limit_in_bytes, the least over the cgroup
// and its ancestors, "max" and v1's "unlimited" as none), and the resource limit taken in: a
// child process under RLIMIT_AS sees it as its budget and checkFits names it.
#include "core/error.h"
#include "core/memory.h"

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace lobe {
namespace {

namespace fs = std::filesystem;

fs::path freshDir(const std::string& name) {
    const fs::path d = fs::path(LOBE_BINARY_DIR) / "test-output" / "memory" / name;
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}

void write(const fs::path& p, const std::string& text) {
    fs::create_directories(p.parent_path());
    std::ofstream(p) << text;
}

TEST(Memory, CgroupV2LimitIsTheLeastOverTheCgroupAndItsAncestors) {
    const fs::path root = freshDir("v2");
    write(root / "memory.max", "max\n");                             // the root: no limit
    write(root / "slurm" / "memory.max", "8589934592\n");            // 8 GiB
    write(root / "slurm" / "job_7" / "memory.max", "2147483648\n");  // 2 GiB: binds
    write(root / "slurm" / "job_7" / "step_0" / "memory.max", "max\n");
    std::string file;
    EXPECT_EQ(cgroupMemoryLimit("0::/slurm/job_7/step_0\n", root.string(), &file), 2147483648.0);
    EXPECT_EQ(file, (root / "slurm" / "job_7" / "memory.max").string());
    // A parent tighter than the child binds.
    write(root / "slurm" / "memory.max", "1073741824\n");
    EXPECT_EQ(cgroupMemoryLimit("0::/slurm/job_7/step_0\n", root.string()), 1073741824.0);
    // No limit anywhere: 0.
    EXPECT_EQ(cgroupMemoryLimit("0::/\n", root.string()), 0.0);
}

TEST(Memory, CgroupV1LimitAndItsUnlimitedValue) {
    const fs::path root = freshDir("v1");
    write(root / "memory" / "memory.limit_in_bytes", "9223372036854771712\n");  // unlimited
    write(root / "memory" / "docker" / "abc" / "memory.limit_in_bytes", "536870912\n");
    const std::string cgroup = "12:pids:/docker/abc\n4:memory:/docker/abc\n1:cpu,cpuacct:/\n";
    EXPECT_EQ(cgroupMemoryLimit(cgroup, root.string()), 536870912.0);
    EXPECT_EQ(cgroupMemoryLimit("4:memory:/\n", root.string()), 0.0);
    EXPECT_EQ(cgroupMemoryLimit("", root.string()), 0.0);
}

#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define LOBE_HAS_ASAN 1
#endif
#endif
#ifndef LOBE_HAS_ASAN
#define LOBE_HAS_ASAN 0
#endif

// In a child under RLIMIT_AS = 1 GiB: the budget is that limit (unless the machine has less
// memory), and checkFits refuses 0.6 GB naming ulimit -v — the physical memory alone was the
// budget before, and the allocation failed with std::bad_alloc.
TEST(Memory, AddressSpaceLimitIsTheBudget) {
#if defined(__SANITIZE_ADDRESS__) || LOBE_HAS_ASAN
    // AddressSanitizer maps its shadow memory far beyond any 1 GiB address-space limit, so the
    // child cannot allocate at all; the Release build's run of this test checks the limit.
    GTEST_SKIP() << "not under AddressSanitizer (its shadow memory exceeds RLIMIT_AS)";
#endif
    int pipeFds[2];
    ASSERT_EQ(::pipe(pipeFds), 0);
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        ::close(pipeFds[0]);
        struct rlimit limit;
        limit.rlim_cur = limit.rlim_max = rlim_t(1) << 30;
        std::string report;
        if (::setrlimit(RLIMIT_AS, &limit) != 0) report = "setrlimit failed";
        const MemoryBudget b = memoryBudget();
        report += std::to_string(static_cast<long long>(b.bytes)) + "|" + b.source + "|";
        try {
            checkFits(0.6e9, "the test buffer");
            report += "fits";
        } catch (const Error& e) {
            report += e.what();
        }
        const ssize_t n = ::write(pipeFds[1], report.data(), report.size());
        ::_exit(n == ssize_t(report.size()) ? 0 : 1);
    }
    ::close(pipeFds[1]);
    std::string report;
    char buffer[512];
    for (ssize_t n; (n = ::read(pipeFds[0], buffer, sizeof buffer)) > 0;)
        report.append(buffer, size_t(n));
    ::close(pipeFds[0]);
    int status = 0;
    ::waitpid(child, &status, 0);
    if (memoryBudget().bytes < double(1u << 30)) GTEST_SKIP() << "less than 1 GiB of memory here";
    EXPECT_EQ(report.rfind("1073741824|the address-space limit, ulimit -v (RLIMIT_AS)|", 0), 0u)
        << report;
    EXPECT_NE(
        report.find("the test buffer needs 0.6 GB, more than half of the 1.07 GB this process "
                    "may use (the address-space limit, ulimit -v (RLIMIT_AS))"),
        std::string::npos)
        << report;
}

// A fixed budget (what the fuzz harness sets, fuzz/fuzz_common.h) replaces the measured one for
// memoryBudget and checkFits, on any machine; bytes 0 measures again.
TEST(Memory, AFixedBudgetReplacesTheMeasuredOne) {
    const MemoryBudget measured = memoryBudget();
    setMemoryBudget({3e6, "the test's budget"});
    EXPECT_EQ(memoryBudget().bytes, 3e6);
    EXPECT_EQ(memoryBudget().source, "the test's budget");
    EXPECT_NO_THROW(checkFits(1.5e6, "half"));
    try {
        checkFits(1.6e6, "the test buffer");
        ADD_FAILURE() << "1.6 MB passed a 3 MB budget";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("the test's budget"), std::string::npos) << e.what();
    }
    setMemoryBudget({});
    EXPECT_EQ(memoryBudget().bytes, measured.bytes);
    EXPECT_EQ(memoryBudget().source, measured.source);
}

}  // namespace
}  // namespace lobe
