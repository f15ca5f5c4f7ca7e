#include "core/memory.h"

#include "core/error.h"

#include <unistd.h>

#include <cstdio>

namespace lobe {

double physicalMemoryBytes() {
    const long pages = sysconf(_SC_PHYS_PAGES), size = sysconf(_SC_PAGE_SIZE);
    return pages > 0 && size > 0 ? double(pages) * double(size) : 0.0;
}

void checkFits(double bytes, const std::string& what) {
    const double physical = physicalMemoryBytes();
    const double limit = physical > 0.0 ? physical / 2.0 : 1e12;
    if (!(bytes <= limit)) {
        char text[160];
        std::snprintf(text, sizeof text, " needs %.3g GB, more than half of this machine's %.3g GB",
                      bytes / 1e9, (physical > 0.0 ? physical : 2e12) / 1e9);
        throw Error(what + text);
    }
}

}  // namespace lobe
