// The input lines of `lobe brdf eval`: six comma-separated numbers, wi then wo.
#pragma once

#include "core/math.h"

#include <string>

namespace lobe {

// Parses "a,b,c,d,e,f" (spaces allowed around numbers); returns false on any malformation or a
// non-finite number.
bool parseSixNumbers(const std::string& line, double out[6]);

// (x, y, z) as a unit vector, divided by its largest component first so that neither 1e308 nor
// 1e-300 components overflow or vanish in the length; false for the zero vector.
bool unitDirection(double x, double y, double z, Vec3& out);

}  // namespace lobe
