#include "materials/strauss.h"

namespace lobe {
namespace {

constexpr double kF = 1.12;
constexpr double kG = 1.01;
constexpr double kJ = 0.1;

// Strauss' Fresnel-like and shadow-like shaping functions of x = θ/(π/2) ∈ [0, 1].
double strausF(double x) {
    return (1.0 / ((x - kF) * (x - kF)) - 1.0 / (kF * kF)) /
           (1.0 / ((1.0 - kF) * (1.0 - kF)) - 1.0 / (kF * kF));
}
double strausG(double x) {
    return (1.0 / ((1.0 - kG) * (1.0 - kG)) - 1.0 / ((x - kG) * (x - kG))) /
           (1.0 / ((1.0 - kG) * (1.0 - kG)) - 1.0 / (kG * kG));
}
double angleFraction(double cosTheta) {
    return std::acos(std::min(1.0, std::max(0.0, cosTheta))) / (0.5 * kPi);
}

}  // namespace

const ParamTable& Strauss::paramTable() {
    static const ParamTable table = {
        {"ks", 0.5, 0.0, 1.0, "specular coefficient", false},
        {"smoothness", 0.75, 0.0, 0.99, "smoothness s; highlight power h = 3/(1 - s)", false},
        {"metalness", 0.5, 0.0, 1.0, "metalness m: how much the highlight takes the colour", false},
        {"transparency", 0.0, 0.0, 1.0, "transparency t", false},
        {"color", 1.0, 0.0, 1.0, "surface colour (per band)", false},
    };
    return table;
}

Strauss Strauss::fromParams(const ParamValues& p) {
    return Strauss{p.get("ks"), p.get("smoothness"), p.get("metalness"), p.get("transparency"),
                   p.get("color")};
}

Spectrum Strauss::eval(const Vec3& wi, const Vec3& wo) const {
    if (!aboveHorizon(wi, wo)) return Spectrum(0.0);
    const double ca = cosAlpha(wi, wo);
    const double xi = angleFraction(wi.z), xo = angleFraction(wo.z);
    const double fi = strausF(xi);
    const double j = fi * strausG(xi) * strausG(xo);
    Spectrum f;
    for (int b = 0; b < kBandCount; ++b) {
        const double s = smoothness[b], t = transparency[b];
        const double rd = (1.0 - s * s * s) * (1.0 - t);
        const double rn = (1.0 - t) - rd;
        const double h = 3.0 / (1.0 - s);
        const double rj = std::min(1.0, rn + (rn + kJ) * j);
        const double cs = 1.0 + metalness[b] * (1.0 - fi) * (color[b] - 1.0);
        f[b] = ks[b] * cs * rj * std::pow(ca, h);
    }
    return f;
}

}  // namespace lobe
