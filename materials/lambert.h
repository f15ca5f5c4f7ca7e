// Lambert: the diffuse part every object carries, f = kd/π (Lambert 1760, "Photometria").
// Parameter: kd ∈ [0, 1], the diffuse albedo (0.2 in the paper).
#pragma once

#include "materials/brdf_common.h"
#include "materials/param_table.h"

namespace lobe {

struct Lambert {
    static constexpr const char* kName = "lambert";
    static constexpr const char* kTitle = "Lambert";
    static constexpr const char* kCitation = "J. H. Lambert, Photometria, 1760";
    // Reciprocity: a constant.
    static constexpr BrdfFlags kFlags = {Reciprocal::yes, Costly::no};
    static const ParamTable& paramTable();
    static Lambert fromParams(const ParamValues& p);
    Spectrum eval(const Vec3& wi, const Vec3& wo) const;

    Spectrum kd{0.2};
};

}  // namespace lobe
