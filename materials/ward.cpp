#include "materials/ward.h"

namespace lobe {

const ParamTable& Ward::paramTable() {
    static const ParamTable table = {
        {"rho_s", 0.05, 0.0, 1.0, "specular reflectance", false},
        {"alpha_x", 0.05, 1e-3, 1.0, "RMS slope along the tangent", false},
        {"alpha_y", 0.3, 1e-3, 1.0, "RMS slope along the bitangent", false},
    };
    return table;
}

Ward Ward::fromParams(const ParamValues& p) {
    return Ward{p.get("rho_s"), p.get("alpha_x"), p.get("alpha_y")};
}

}  // namespace lobe
