// Limits that follow from the machine: a buffer is refused before it is allocated when it could
// not fit — more than half of this machine's physical memory — with one error that says how much
// it needed and how much there is, instead of std::bad_alloc or the out-of-memory killer.
#pragma once

#include <string>

namespace lobe {

// Physical memory of this machine in bytes (sysconf), or 0 when unknown.
double physicalMemoryBytes();

// Throws lobe::Error "WHAT needs N GB, more than half of this machine's M GB" when `bytes`
// exceeds half the physical memory (when that is unknown: 1 TB).
void checkFits(double bytes, const std::string& what);

}  // namespace lobe
