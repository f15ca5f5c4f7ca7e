// The closed set of reflection models as one std::variant: dispatch without virtual calls, and a
// model added in one place (its file pair, one line here, one in registry.cpp, one in CMake).
#pragma once

#include "materials/ashikhmin_shirley.h"
#include "materials/cook_torrance.h"
#include "materials/he_torrance.h"
#include "materials/lafortune.h"
#include "materials/lambert.h"
#include "materials/phong.h"
#include "materials/poulin_fournier.h"
#include "materials/schlick_lewis.h"
#include "materials/strauss.h"
#include "materials/ward.h"

#include <variant>

namespace lobe {

using Brdf = std::variant<Lambert, Phong, Strauss, SchlickLewis, Ward, CookTorrance, PoulinFournier,
                          HeTorrance, Lafortune, AshikhminShirley>;

// f(wi, wo) per band in sr⁻¹, without the cosine; wi and wo unit vectors in the local frame.
inline Spectrum evalBrdf(const Brdf& brdf, const Vec3& wi, const Vec3& wo) {
    return std::visit([&](const auto& model) { return model.eval(wi, wo); }, brdf);
}

inline const char* brdfName(const Brdf& brdf) {
    return std::visit([](const auto& model) { return std::decay_t<decltype(model)>::kName; }, brdf);
}

}  // namespace lobe
