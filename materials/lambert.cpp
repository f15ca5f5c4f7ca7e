#include "materials/lambert.h"

namespace lobe {

const ParamTable& Lambert::paramTable() {
    static const ParamTable table = {
        {"kd", 0.2, 0.0, 1.0, "diffuse albedo", false},
    };
    return table;
}

Lambert Lambert::fromParams(const ParamValues& p) { return Lambert{p.get("kd")}; }

Spectrum Lambert::eval(const Vec3& wi, const Vec3& wo) const {
    if (!aboveHorizon(wi, wo)) return Spectrum(0.0);
    return kd * kInvPi;
}

}  // namespace lobe
