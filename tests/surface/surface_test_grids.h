// Analytic test grids and an independent reference for the first iso-crossing along a ray, shared
// by the surface tests. The reference uses OpenVDB's own trilinear sampler (tools::BoxSampler),
// not our trilinear_cell.h, sampled densely between every cell-face crossing and bisected.
#pragma once

#include "core/math.h"

#include <openvdb/openvdb.h>
#include <openvdb/tools/Interpolation.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <optional>
#include <vector>

namespace lobe::test {

// A dense grid dims[0]×dims[1]×dims[2] whose voxel (i,j,k) holds f(world position of (i,j,k)),
// with the index → world map x = diag(spacing)·R·u + origin, R a rotation/flip given as rows.
inline openvdb::FloatGrid::Ptr makeGrid(const int dims[3], const double linear[3][3],
                                        const Vec3& origin, float background,
                                        const std::function<double(const Vec3&)>& f) {
    openvdb::Mat4d m = openvdb::Mat4d::identity();
    // OpenVDB matrices act on row vectors: world = index · M, so M holds the transpose of our
    // column-vector linear part, with the translation in the last row.
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) m[c][r] = linear[r][c];
    m[3][0] = origin.x;
    m[3][1] = origin.y;
    m[3][2] = origin.z;
    auto grid = openvdb::FloatGrid::create(background);
    grid->setTransform(openvdb::math::Transform::createLinearTransform(m));
    auto acc = grid->getAccessor();
    for (int k = 0; k < dims[2]; ++k)
        for (int j = 0; j < dims[1]; ++j)
            for (int i = 0; i < dims[0]; ++i) {
                const openvdb::Vec3d w = grid->transform().indexToWorld(openvdb::Vec3d(i, j, k));
                acc.setValue(openvdb::Coord(i, j, k),
                             static_cast<float>(f(Vec3(w[0], w[1], w[2]))));
            }
    return grid;
}

// Concentric shells: sin(π r / kShellSpacing) on a 48³ unit grid shifted by `offset`, with r the
// distance from kShellCentre + offset, up to r = 20.25, where it is −1, and −1 beyond (shells at
// r = k·1.5, k = 1 … 13): several roots per brick along a ray (the hit-list and packet tests).
inline const Vec3 kShellCentre(24.3, 23.7, 24.1);
inline constexpr double kShellSpacing = 1.5;  // voxels between neighbouring shells
inline openvdb::FloatGrid::Ptr shellGrid(const Vec3& offset) {
    const int dims[3] = {48, 48, 48};
    const double identity[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    return makeGrid(dims, identity, offset, -1.0f, [&](const Vec3& x) {
        const double r = (x - kShellCentre - offset).length();
        return r < 20.25 ? std::sin(kPi * r / kShellSpacing) : -1.0;
    });
}

// First t ∈ [tMin, tMax] where the grid's trilinear interpolant (BoxSampler, index space) along
// o + t·d (index space) crosses iso: samples at every cell-face crossing and `perSegment` points
// between, then 200 bisection steps on the first bracket.
inline std::optional<double> referenceRoot(const openvdb::FloatGrid& grid, double iso,
                                           const Vec3& o, const Vec3& d, double tMin, double tMax,
                                           int perSegment = 24) {
    std::vector<double> ts{tMin, tMax};
    for (int a = 0; a < 3; ++a) {
        if (d[a] == 0.0) continue;
        double p0 = o[a] + tMin * d[a], p1 = o[a] + tMax * d[a];
        if (p0 > p1) std::swap(p0, p1);
        for (double k = std::ceil(p0); k <= p1; k += 1.0) ts.push_back((k - o[a]) / d[a]);
    }
    std::sort(ts.begin(), ts.end());
    const openvdb::FloatTree& tree = grid.tree();
    auto g = [&](double t) {
        const Vec3 p = o + d * t;
        return double(openvdb::tools::BoxSampler::sample(tree, openvdb::Vec3R(p.x, p.y, p.z))) -
               iso;
    };
    double tPrev = tMin, gPrev = g(tMin);
    if (gPrev == 0.0) return tMin;
    for (std::size_t s = 0; s + 1 < ts.size(); ++s) {
        if (ts[s + 1] <= ts[s]) continue;
        for (int i = 1; i <= perSegment; ++i) {
            const double t = ts[s] + (ts[s + 1] - ts[s]) * i / perSegment;
            const double gt = g(t);
            if (gt == 0.0) return t;
            if ((gt < 0.0) != (gPrev < 0.0)) {
                double lo = tPrev, hi = t, gLo = gPrev;
                for (int it = 0; it < 200 && hi - lo > 0.0; ++it) {
                    const double mid = 0.5 * (lo + hi);
                    if (mid <= lo || mid >= hi) break;
                    const double gm = g(mid);
                    if ((gm < 0.0) == (gLo < 0.0)) {
                        lo = mid;
                        gLo = gm;
                    } else {
                        hi = mid;
                    }
                }
                return 0.5 * (lo + hi);
            }
            tPrev = t;
            gPrev = gt;
        }
    }
    return std::nullopt;
}

// BoxSampler value at an index-space point, in double.
inline double sampleIndex(const openvdb::FloatGrid& grid, const Vec3& u) {
    return openvdb::tools::BoxSampler::sample(grid.tree(), openvdb::Vec3R(u.x, u.y, u.z));
}

}  // namespace lobe::test
