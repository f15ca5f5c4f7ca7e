// Files being written when the process is interrupted (SIGINT, SIGTERM — Ctrl-C, a scheduler's
// kill, MPI_Abort stopping the other ranks) are removed before the process ends, so an
// interrupted render leaves no partial file behind. The process then ends by the signal, as it
// would have without the handler.
#pragma once

#include <string>

namespace lobe {

// Installs the SIGINT and SIGTERM handlers. Call once, early in main.
void installInterruptCleanup();

// While alive, `path` is removed if SIGINT or SIGTERM arrives (up to 16 at a time; more are not
// guarded). For temporary files that are renamed when complete.
class RemovedOnInterrupt {
public:
    explicit RemovedOnInterrupt(const std::string& path);
    ~RemovedOnInterrupt();
    RemovedOnInterrupt(const RemovedOnInterrupt&) = delete;
    RemovedOnInterrupt& operator=(const RemovedOnInterrupt&) = delete;

private:
    int slot_ = -1;
};

}  // namespace lobe
