// Clipping: planes and boxes in world space that cut objects away (docs/scene-format.md, "Clip").
//
// A clip shape keeps a region: a plane {x : n·(x − p) ≥ 0} (the side the normal points to), a
// box lo ≤ x ≤ hi (its inside), or, inverted, the complement (the other side; the outside of the
// box). A list of shapes keeps the intersection of their regions, so every shape cuts something
// away. Along a ray o + t d the kept region is a union of disjoint intervals, computed exactly
// (the slab method for boxes, Kay & Kajiya 1986; one division for a plane): surfaces report only
// hits inside them (surface/surface_scene.h), volumes march only inside them
// (volume/volume_marcher.h), so clipping is exact, not a test per sample.
//
// Each interval end knows whether a clip boundary made it, and the outward normal of the kept
// region there (pointing into the cut-away side): where that end lies inside a solid, the cut
// face of the solid (its "cap") passes through it with that normal.
#pragma once

#include "core/math.h"
#include "core/ray.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace lobe {

struct ClipShape {
    enum class Kind { Plane, Box };
    Kind kind = Kind::Plane;
    Vec3 point{0.0}, normal{0, 0, 1};  // plane (normal unit length)
    Vec3 lo{0.0}, hi{0.0};             // box
    bool invert = false;               // keep the other side / the outside of the box
    bool cap = false;                  // draw the cut faces of iso-surfaces (render/integrator.h)
};

// At most this many shapes in one list (scene or object): bounds the intervals per ray.
constexpr int kMaxClipShapes = 8;

struct ClipBound {
    double t = 0.0;
    bool clipped = false;  // made by a clip boundary (not the ray's own tMin / tMax)
    bool cap = false;      // that boundary's shape asks for caps
    Vec3 normal{0.0};      // outward normal of the kept region (into the cut-away side)
};

struct ClipInterval {
    ClipBound lo, hi;
};

// The kept intervals of a ray, in increasing t, disjoint. At most 1 + (inverted boxes) of them.
struct ClipIntervals {
    static constexpr int kMax = 2 * kMaxClipShapes + 2;
    int count = 0;
    ClipInterval v[kMax];

    bool empty() const { return count == 0; }
    bool contains(double t) const {
        for (int i = 0; i < count; ++i)
            if (t >= v[i].lo.t && t <= v[i].hi.t) return true;
        return false;
    }
};

namespace clip_detail {

inline void add(ClipIntervals& out, const ClipBound& lo, const ClipBound& hi) {
    if (lo.t < hi.t && out.count < ClipIntervals::kMax) out.v[out.count++] = {lo, hi};
}

// The kept intervals of one shape within [a, b] (a, b: unclipped bounds of the ray).
inline ClipIntervals shapeIntervals(const ClipShape& s, const Ray& ray, const ClipBound& a,
                                    const ClipBound& b) {
    ClipIntervals out;
    if (s.kind == ClipShape::Kind::Plane) {
        const Vec3 n = s.invert ? -s.normal : s.normal;
        const double s0 = n.dot(ray.o - s.point), dn = n.dot(ray.d);
        if (dn == 0.0) {
            if (s0 >= 0.0) add(out, a, b);
            return out;
        }
        const double t = -s0 / dn;
        // The kept half-space's outward normal is −n.
        ClipBound c{t, true, s.cap, -n};
        if (dn > 0.0)
            add(out, t > a.t ? c : a, b);  // kept for t ≥ t*
        else
            add(out, a, t < b.t ? c : b);  // kept for t ≤ t*
        return out;
    }
    // Box: the slab method. Entry and exit t and the box's outward normals there.
    double t0 = -std::numeric_limits<double>::infinity(), t1 = -t0;
    Vec3 n0(0.0), n1(0.0);
    for (int k = 0; k < 3; ++k) {
        if (ray.d[k] == 0.0) {
            if (ray.o[k] < s.lo[k] || ray.o[k] > s.hi[k]) {
                t0 = 1.0;  // misses
                t1 = 0.0;
                break;
            }
            continue;
        }
        double ta = (s.lo[k] - ray.o[k]) / ray.d[k], tb = (s.hi[k] - ray.o[k]) / ray.d[k];
        Vec3 na(0.0), nb(0.0);
        na[k] = -1.0;
        nb[k] = 1.0;
        if (ta > tb) {
            std::swap(ta, tb);
            std::swap(na, nb);
        }
        if (ta > t0) {
            t0 = ta;
            n0 = na;
        }
        if (tb < t1) {
            t1 = tb;
            n1 = nb;
        }
    }
    const bool hits = t0 <= t1;
    if (!s.invert) {
        if (hits)
            add(out, t0 > a.t ? ClipBound{t0, true, s.cap, n0} : a,
                t1 < b.t ? ClipBound{t1, true, s.cap, n1} : b);
        return out;
    }
    if (!hits) {
        add(out, a, b);
        return out;
    }
    // Outside the box: before its entry and after its exit; the kept region's outward normal
    // points into the box.
    add(out, a, t0 < b.t ? ClipBound{t0, true, s.cap, -n0} : b);
    add(out, t1 > a.t ? ClipBound{t1, true, s.cap, -n1} : a, b);
    return out;
}

inline ClipIntervals intersect(const ClipIntervals& x, const ClipIntervals& y) {
    ClipIntervals out;
    for (int i = 0; i < x.count; ++i)
        for (int j = 0; j < y.count; ++j) {
            const ClipBound& lo = x.v[i].lo.t >= y.v[j].lo.t ? x.v[i].lo : y.v[j].lo;
            const ClipBound& hi = x.v[i].hi.t <= y.v[j].hi.t ? x.v[i].hi : y.v[j].hi;
            add(out, lo, hi);
        }
    std::sort(out.v, out.v + out.count,
              [](const ClipInterval& p, const ClipInterval& q) { return p.lo.t < q.lo.t; });
    return out;
}

}  // namespace clip_detail

// The parts of [ray.tMin, ray.tMax] that every shape of every list keeps.
inline ClipIntervals clipRay(const Ray& ray,
                             const std::vector<const std::vector<ClipShape>*>& lists) {
    ClipIntervals out;
    const ClipBound a{ray.tMin, false, false, Vec3(0.0)}, b{ray.tMax, false, false, Vec3(0.0)};
    clip_detail::add(out, a, b);
    for (const std::vector<ClipShape>* list : lists)
        for (const ClipShape& s : *list) {
            out = clip_detail::intersect(out, clip_detail::shapeIntervals(s, ray, a, b));
            if (out.empty()) return out;
        }
    return out;
}

inline ClipIntervals clipRay(const Ray& ray, const std::vector<ClipShape>& shapes) {
    return clipRay(ray, std::vector<const std::vector<ClipShape>*>{&shapes});
}

// Whether a world point is kept by every shape.
inline bool clipKeeps(const std::vector<ClipShape>& shapes, const Vec3& x) {
    for (const ClipShape& s : shapes) {
        bool in;
        if (s.kind == ClipShape::Kind::Plane) {
            in = s.normal.dot(x - s.point) >= 0.0;
        } else {
            in = x.x >= s.lo.x && x.x <= s.hi.x && x.y >= s.lo.y && x.y <= s.hi.y &&
                 x.z >= s.lo.z && x.z <= s.hi.z;
        }
        if (in == s.invert) return false;
    }
    return true;
}

// The axis-aligned box around the part of [lo, hi] that the shapes keep: each box shape
// intersected, each plane cutting the box (the kept corners and the crossings of the box's
// edges), inverted shapes ignored (their kept part is not convex; the box stays conservative).
// An empty result has lo > hi.
inline void clipBox(const std::vector<ClipShape>& shapes, Vec3& lo, Vec3& hi) {
    for (const ClipShape& s : shapes) {
        if (!(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z) || s.invert) continue;
        if (s.kind == ClipShape::Kind::Box) {
            for (int k = 0; k < 3; ++k) {
                lo[k] = std::max(lo[k], s.lo[k]);
                hi[k] = std::min(hi[k], s.hi[k]);
            }
            continue;
        }
        Vec3 nlo(std::numeric_limits<double>::infinity()),
            nhi(-std::numeric_limits<double>::infinity());
        auto grow = [&](const Vec3& p) {
            for (int k = 0; k < 3; ++k) {
                nlo[k] = std::min(nlo[k], p[k]);
                nhi[k] = std::max(nhi[k], p[k]);
            }
        };
        auto corner = [&](int c) {
            return Vec3((c & 1) ? hi.x : lo.x, (c & 2) ? hi.y : lo.y, (c & 4) ? hi.z : lo.z);
        };
        for (int c = 0; c < 8; ++c) {
            const Vec3 p = corner(c);
            const double sp = s.normal.dot(p - s.point);
            if (sp >= 0.0) grow(p);
            for (int k = 0; k < 3; ++k) {  // the edge from corner c along axis k
                if (c & (1 << k)) continue;
                const Vec3 q = corner(c | (1 << k));
                const double sq = s.normal.dot(q - s.point);
                if ((sp < 0.0) != (sq < 0.0)) grow(p + (q - p) * (sp / (sp - sq)));
            }
        }
        lo = nlo;
        hi = nhi;
    }
}

}  // namespace lobe
