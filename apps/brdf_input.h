// The input lines of `lobe brdf eval`: six comma-separated numbers, wi then wo.
#pragma once

#include "core/math.h"

#include <string>

namespace lobe {

// Parses "a,b,c,d,e,f" (spaces allowed around numbers); returns false on any malformation or a
// non-finite number.
bool parseSixNumbers(const std::string& line, double out[6]);

// unitDirection (the directions' normalisation): core/math.h.

}  // namespace lobe
