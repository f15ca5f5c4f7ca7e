// The closed set of reflection models as one std::variant: dispatch without virtual calls, and a
// model added in one place (its file pair, one line here, one in registry.cpp, one in CMake;
// docs/architecture.md, "Where to add").
#pragma once

#include "materials/ashikhmin_shirley.h"
#include "materials/cook_torrance.h"
#include "materials/he_torrance.h"
#include "materials/he_torrance_table.h"
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

// A BRDF value as Lobe passes it on: NaN (0/0 exactly at the horizon) is 0, a value rounded
// below 0 is 0, values are at most kMaxBrdfValue.
inline Spectrum clampBrdfValue(Spectrum f) {
    for (double& v : f.v) v = std::isnan(v) ? 0.0 : std::clamp(v, 0.0, kMaxBrdfValue);
    return f;
}

// f(wi, wo) per band in sr⁻¹, without the cosine; wi and wo unit vectors in the local frame.
// Always finite and non-negative (clampBrdfValue).
inline Spectrum evalBrdf(const Brdf& brdf, const Vec3& wi, const Vec3& wo) {
    return clampBrdfValue(std::visit([&](const auto& model) { return model.eval(wi, wo); }, brdf));
}

// f(·, wo) of one model for one viewer direction and any number of light directions: eval(wi) is
// evalBrdf(brdf, wi, wo) bit for bit. render/shading.cpp lights a point with one of these across
// its lights (visitAtView below), so that the model is chosen once per point, not per light, and
// what depends on wo or on the parameters alone is worked out once. wo must be above the horizon.
// Most models have nothing to share: eval is the model's own.
template <class Model>
class ModelAtView {
public:
    ModelAtView(const Model& model, const Vec3& wo) : model_(model), wo_(wo) {}
    Spectrum eval(const Vec3& wi) const { return clampBrdfValue(model_.eval(wi, wo_)); }

private:
    const Model& model_;
    Vec3 wo_;
};

// Phong with one exponent for all bands (the usual case): the exponent's form (whole, for
// repeated squaring, or not) is decided once, and one power serves the three bands — the
// operations of Phong::eval and powerOf in the same order.
template <>
class ModelAtView<Phong> {
public:
    ModelAtView(const Phong& model, const Vec3& wo)
        : model_(model),
          wo_(wo),
          shared_(model.exponent[0] == model.exponent[1] && model.exponent[1] == model.exponent[2]),
          whole_(isWholeExponent(model.exponent[0])),
          n_(whole_ ? static_cast<unsigned>(model.exponent[0]) : 0u) {}
    Spectrum eval(const Vec3& wi) const {
        if (!shared_) return clampBrdfValue(model_.eval(wi, wo_));
        if (!aboveHorizon(wi, wo_)) return Spectrum(0.0);
        const double c = cosAlpha(wi, wo_);
        const double power = whole_ ? powerOfWhole(c, n_) : std::pow(c, model_.exponent[0]);
        return clampBrdfValue(model_.ks * power);
    }

private:
    const Phong& model_;
    Vec3 wo_;
    bool shared_, whole_;
    unsigned n_;
};

// Ashikhmin–Shirley: the normalisation per band once per point (a square root and a division
// the model's eval makes per evaluation).
template <>
class ModelAtView<AshikhminShirley> {
public:
    ModelAtView(const AshikhminShirley& model, const Vec3& wo)
        : model_(model), wo_(wo), norm_(model.norms()) {}
    Spectrum eval(const Vec3& wi) const { return clampBrdfValue(model_.eval(wi, wo_, norm_)); }

private:
    const AshikhminShirley& model_;
    Vec3 wo_;
    Spectrum norm_;
};

// He–Torrance: the table's lookup when the model has one (he_torrance_table.h); otherwise the
// series with K(θo) and S(θo) (an erfc and an exp per distinct band) computed once, on the first
// eval.
template <>
class ModelAtView<HeTorrance> {
public:
    ModelAtView(const HeTorrance& model, const Vec3& wo) : model_(model), wo_(wo) {}
    Spectrum eval(const Vec3& wi) {
        if (model_.table) return clampBrdfValue(model_.table->eval(wi, wo_));
        if (!haveView_) {
            view_ = model_.viewTerms(wo_);
            haveView_ = true;
        }
        return clampBrdfValue(model_.eval(wi, wo_, view_));
    }

private:
    const HeTorrance& model_;
    Vec3 wo_;
    bool haveView_ = false;
    HeTorrance::ViewTerms view_;
};

// fn(view) with view the ModelAtView of `brdf`'s model at `wo`: one dispatch on the model for
// any number of evaluations.
template <class Fn>
decltype(auto) visitAtView(const Brdf& brdf, const Vec3& wo, Fn&& fn) {
    return std::visit(
        [&](const auto& model) -> decltype(auto) {
            ModelAtView<std::decay_t<decltype(model)>> view(model, wo);
            return fn(view);
        },
        brdf);
}

inline const char* brdfName(const Brdf& brdf) {
    return std::visit([](const auto& model) { return std::decay_t<decltype(model)>::kName; }, brdf);
}

}  // namespace lobe
