#include "apps/brdf_input.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>

namespace lobe {

bool parseSixNumbers(const std::string& line, double out[6]) {
    std::stringstream ss(line);
    std::string field;
    int count = 0;
    while (std::getline(ss, field, ',')) {
        if (count == 6) return false;
        const char* begin = field.c_str();
        const char* stop = begin + field.size();  // the field's end: a NUL inside it is not
        char* end = nullptr;
        out[count] = std::strtod(begin, &end);
        if (end == begin) return false;
        while (end < stop && (*end == ' ' || *end == '\t' || *end == '\r')) ++end;
        if (end != stop || !std::isfinite(out[count])) return false;
        ++count;
    }
    return count == 6 && (line.empty() || line.back() != ',');
}

}  // namespace lobe
