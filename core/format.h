#pragma once
// Numbers in text for people: one printf conversion of one number ("%.3g", "%.1f %%").

#include <cstdio>
#include <string>

namespace lobe {

inline std::string formatNumber(const char* printfFormat, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, printfFormat, v);
    return buf;
}

}  // namespace lobe
