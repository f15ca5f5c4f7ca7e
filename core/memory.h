// Limits that follow from the machine: a buffer is refused before it is allocated when it could
// not fit — more than half of the memory this process may use — with one error that says how
// much it needed, how much there is and which limit that is, instead of std::bad_alloc or the
// out-of-memory killer.
#pragma once

#include <string>

namespace lobe {

// Physical memory of this machine in bytes (sysconf), or 0 when unknown.
double physicalMemoryBytes();

// The memory this process may use: the least of physical memory, the resource limits RLIMIT_AS
// and RLIMIT_DATA (`ulimit -v`, `ulimit -d`) and the memory cgroup's limit (cgroup v2
// memory.max, v1 memory.limit_in_bytes: what Slurm's --mem and a container's limit set), with
// the name of the one that binds. bytes is 0 when none is known.
struct MemoryBudget {
    double bytes = 0.0;
    std::string
        source;  // "physical memory", "ulimit -v (RLIMIT_AS)", "the cgroup's memory.max", ...
};
MemoryBudget memoryBudget();
// Makes memoryBudget() return `budget` from now on, whatever the machine (bytes 0: measure
// again). For the fuzz targets (fuzz/fuzz_common.h): what an input may allocate, and the code
// that finds the limit, must not depend on the machine's memory, its cgroup or the process's
// environment, or a fixed-count run explores other inputs elsewhere.
void setMemoryBudget(const MemoryBudget& budget);

// The cgroup memory limit found from a /proc/self/cgroup text and the cgroup file-system root
// (normally "/sys/fs/cgroup"): the least limit on the process's cgroup and its ancestors, v2
// ("0::/path", memory.max) or v1 ("N:memory:/path", memory/…/memory.limit_in_bytes); 0 when
// there is none ("max", or v1's huge "unlimited"). `file` names the limiting file.
double cgroupMemoryLimit(const std::string& procSelfCgroup, const std::string& root,
                         std::string* file = nullptr);

// Throws lobe::Error "WHAT needs N GB, more than half of the M GB this process may use (SOURCE)"
// when `bytes` exceeds half the budget (when that is unknown: 1 TB).
void checkFits(double bytes, const std::string& what);

// "out of memory (this process may use M GB: SOURCE)": what an allocation failure says.
std::string outOfMemoryText();

}  // namespace lobe
