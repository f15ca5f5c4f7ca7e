#include "materials/phong.h"

namespace lobe {

const ParamTable& Phong::paramTable() {
    static const ParamTable table = {
        {"ks", 0.8, 0.0, 1.0, "specular coefficient", false},
        {"exponent", 10.0, 0.0, 1e6, "shininess: power of cos α", false},
    };
    return table;
}

Phong Phong::fromParams(const ParamValues& p) { return Phong{p.get("ks"), p.get("exponent")}; }

}  // namespace lobe
