// An interrupted process removes the files it was writing (core/interrupt.h): a child process
// guards two files, is sent SIGTERM or SIGINT, and must end by that signal with both removed,
// while a file whose guard ended stays.
#include "core/interrupt.h"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <fstream>

namespace lobe {
namespace {

namespace fs = std::filesystem;

fs::path touch(const fs::path& p) {
    std::ofstream(p) << "partial";
    return p;
}

void interruptWhileWriting(int signal) {
    const fs::path dir =
        fs::path(LOBE_BINARY_DIR) / "test-output" / "interrupt" / std::to_string(signal);
    fs::remove_all(dir);
    fs::create_directories(dir);
    const pid_t child = fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        installInterruptCleanup();
        const fs::path done = touch(dir / "done.exr");
        { const RemovedOnInterrupt finished(done.string()); }
        const fs::path a = touch(dir / ".a.partial-1.exr");
        const fs::path b = touch(dir / ".b.partial-2.png");
        const RemovedOnInterrupt guardA(a.string());
        const RemovedOnInterrupt guardB(b.string());
        std::raise(signal);
        _exit(0);  // not reached: the signal ends the process
    }
    int status = 0;
    ASSERT_EQ(waitpid(child, &status, 0), child);
    ASSERT_TRUE(WIFSIGNALED(status)) << "the child exited instead of ending by the signal";
    EXPECT_EQ(WTERMSIG(status), signal);
    EXPECT_FALSE(fs::exists(dir / ".a.partial-1.exr"));
    EXPECT_FALSE(fs::exists(dir / ".b.partial-2.png"));
    EXPECT_TRUE(fs::exists(dir / "done.exr"));
}

TEST(Interrupt, SigtermRemovesTheFilesBeingWritten) { interruptWhileWriting(SIGTERM); }
TEST(Interrupt, SigintRemovesTheFilesBeingWritten) { interruptWhileWriting(SIGINT); }

}  // namespace
}  // namespace lobe
