// The closed set of reflection models as one std::variant: dispatch without virtual calls, and a
// model added in one place (its file pair, one line here, one in registry.cpp, one in CMake;
// docs/architecture.md, "Where to add").
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

#include <algorithm>
#include <cmath>
#include <variant>

namespace lobe {

using Brdf = std::variant<Lambert, Phong, Strauss, SchlickLewis, Ward, CookTorrance, PoulinFournier,
                          HeTorrance, Lafortune, AshikhminShirley>;

// The largest BRDF value Lobe passes on, in sr⁻¹. Parameters in range can take a model past any
// float — Lafortune's (C·u)^n with cz = 2 and n = 1100 is 10^321 at normal incidence — and such a
// value means "white" in any image; clamped here it stays finite through the light loop, the
// compositing and the EXR.
constexpr double kMaxBrdfValue = 1e30;

// f(wi, wo) per band in sr⁻¹, without the cosine; wi and wo unit vectors in the local frame.
// Always finite and non-negative: NaN (0/0 exactly at the horizon) is 0, a value rounded below 0
// is 0, values are at most kMaxBrdfValue.
inline Spectrum evalBrdf(const Brdf& brdf, const Vec3& wi, const Vec3& wo) {
    Spectrum f = std::visit([&](const auto& model) { return model.eval(wi, wo); }, brdf);
    for (double& v : f.v) v = std::isnan(v) ? 0.0 : std::clamp(v, 0.0, kMaxBrdfValue);
    return f;
}

// f(·, wo) for one viewer direction and any number of light directions: eval(wi) is
// evalBrdf(brdf, wi, wo) bit for bit. What depends on wo alone is computed once, on the first
// eval — He–Torrance's K(θo) and S(θo) (an erfc and an exp per distinct band); every other model
// has nothing to share and is evaluated as evalBrdf does. render/shading.cpp lights a point with
// one of these across its lights. wo must be above the horizon.
class BrdfAtView {
public:
    BrdfAtView(const Brdf& brdf, const Vec3& wo)
        : brdf_(brdf), wo_(wo), heTorrance_(std::get_if<HeTorrance>(&brdf)) {}
    Spectrum eval(const Vec3& wi) {
        if (!heTorrance_) return evalBrdf(brdf_, wi, wo_);
        if (!haveView_) {
            view_ = heTorrance_->viewTerms(wo_);
            haveView_ = true;
        }
        Spectrum f = heTorrance_->eval(wi, wo_, view_);
        for (double& v : f.v) v = std::isnan(v) ? 0.0 : std::clamp(v, 0.0, kMaxBrdfValue);
        return f;
    }

private:
    const Brdf& brdf_;
    Vec3 wo_;
    const HeTorrance* heTorrance_;
    bool haveView_ = false;
    HeTorrance::ViewTerms view_;
};

inline const char* brdfName(const Brdf& brdf) {
    return std::visit([](const auto& model) { return std::decay_t<decltype(model)>::kName; }, brdf);
}

}  // namespace lobe
