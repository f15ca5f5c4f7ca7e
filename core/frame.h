// Orthonormal shading frame: x = tangent t (anisotropy direction), y = bitangent b = n × t,
// z = normal n, as fixed in docs/models.md ("Conventions").
#pragma once

#include "core/math.h"

namespace lobe {

struct Frame {
    Vec3 t{1, 0, 0};
    Vec3 b{0, 1, 0};
    Vec3 n{0, 0, 1};

    Vec3 toLocal(const Vec3& w) const { return Vec3(w.dot(t), w.dot(b), w.dot(n)); }
    Vec3 toWorld(const Vec3& w) const { return t * w.x + b * w.y + n * w.z; }

    // Frame around unit normal n whose tangent is the projection of `axis` onto the tangent plane.
    // Where that projection degenerates (|axis × n| < minSine) `fallbackAxis` is projected instead;
    // this is the tangent field of docs/flux-overlap.md and of the renderer's anisotropic
    // objects.
    static Frame fromNormalAndAxis(const Vec3& n, const Vec3& axis, const Vec3& fallbackAxis,
                                   double minSine = 1e-3);

    // Any frame around n (for isotropic shading only): Duff et al. 2017, "Building an
    // orthonormal basis, revisited", JCGT 6(1).
    static Frame fromNormal(const Vec3& n);
};

// Inline: every shaded surface hit and volume sample builds one (render/integrator.cpp).
inline Frame Frame::fromNormalAndAxis(const Vec3& n, const Vec3& axis, const Vec3& fallbackAxis,
                                      double minSine) {
    // |axis × n| ≥ minSine, without the square root where |axis × n|² > 4·minSine² (the root is
    // then above 2·minSine whatever its rounding): the same choice as comparing length().
    const Vec3 c = axis.cross(n);
    const double c2 = c.length2();
    const bool useAxis = c2 > 4.0 * minSine * minSine || c.length() >= minSine;
    const Vec3& a = useAxis ? axis : fallbackAxis;
    Vec3 t = a - n * a.dot(n);
    const double len = t.length();
    if (!(len > 1e-12)) return fromNormal(n);  // both axes parallel to n: any tangent will do
    Frame f;
    f.n = n;
    f.t = t / len;
    f.b = n.cross(f.t);
    return f;
}

}  // namespace lobe
