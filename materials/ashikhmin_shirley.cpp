#include "materials/ashikhmin_shirley.h"

namespace lobe {

const ParamTable& AshikhminShirley::paramTable() {
    static const ParamTable table = {
        {"rs", 0.05, 0.0, 1.0, "specular reflectance at normal incidence (Schlick F0)", false},
        {"nu", 10.0, 0.0, 1e6, "Phong exponent along the tangent", false},
        {"nv", 1000.0, 0.0, 1e6, "Phong exponent along the bitangent", false},
    };
    return table;
}

AshikhminShirley AshikhminShirley::fromParams(const ParamValues& p) {
    return AshikhminShirley{p.get("rs"), p.get("nu"), p.get("nv")};
}

}  // namespace lobe
