// Poulin–Fournier cylinder BRDF; the model and its sources are described in poulin_fournier.h.
//
// Geometry of one period, in the cross-section plane with coordinates (y along b, z along n):
// cylinder 0 centred at (0, 0), cylinder 1 at (D, 0), floor z = −d (d = floor_depth). A point of
// cylinder 0 is p(φ) = (sin φ, cos φ) with normal N = (0, sin φ, cos φ) in the local frame, and
// ds = dφ. A direction w above the horizon projects to the 2-D direction u = (w.y, w.z)/L with
// L = |(w.y, w.z)|, at angle ψ from n (|ψ| < π/2) and elevation β = π/2 − |ψ| above the
// cross-section's horizon.
//
// Why the lit/seen sets have closed forms:
//  * Cylinder points. A ray leaving a cylinder point rises (u_z > 0) from a height ≥ −d, so it
//    can meet neither the floor nor a buried arc; if it clears the neighbour on its side it passes
//    above it, and the signed distance of the ray's line from a centre (c, 0) is affine in c, so it
//    clears every cylinder further on. For ψ ≥ 0 the neighbour is at c = D and the line's signed
//    distance from its centre is D cos ψ − sin(φ − ψ) (mirrored for ψ < 0), so the lit
//    part of the facing half-circle (|φ − ψ| < π/2) is, for ψ ≥ 0, φ ∈ (−β, −β + W) and, for
//    ψ < 0, φ ∈ (β − W, β), with W = acos(1 − D sin β) = 2 asin(sqrt(D sin β / 2)) (W = π: no
//    shadow when D sin β ≥ 2). Each direction gives one interval inside (−π, π), the arc itself
//    is (−arcLimit, arcLimit), so the visible-and-lit arc is a single interval.
//  * Floor points (y, −d). The line along u hits cylinder (c, 0) iff |(c − y) u_z − d u_y| < 1,
//    i.e. c in a window of width 2/u_z around y + d u_y/u_z, and the hit is ahead iff
//    (c − y) u_y + d u_z > 0 (a point outside a circle sees both intersections on one side). So
//    a floor point is shadowed iff a multiple of D lies in the window with the hit ahead; the
//    window edges move with y, giving breakpoints y = kD − (d u_y ± 1)/u_z, and at grazing angles
//    the window (and the occluder) is many periods away. The floor's integrand is constant
//    (N = n: fl(n)·cos θi·cos θo), so its integral is that constant times the lit-and-seen length.
#include "materials/poulin_fournier.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace lobe {
namespace {

// Relative accuracy of f asked by brdf-models.md (model 6); the Richardson-corrected adaptive
// Simpson error estimate is used with half of it as a margin.
constexpr double kRelativeAccuracy = 1e-6;
constexpr int kMaxDepth = 30;

// A direction's projection onto the cross-section plane.
struct Projected {
    double y = 0.0, z = 0.0;  // w.y, w.z
    double length = 0.0;      // L = |(w.y, w.z)| > 0 since w.z > 0
    double psi = 0.0;         // angle from n towards b, in (−π/2, π/2)
    double sinBeta = 0.0;     // sin β = cos ψ = w.z / L
};

Projected project(const Vec3& w) {
    Projected p;
    p.y = w.y;
    p.z = w.z;
    p.length = std::hypot(w.y, w.z);
    p.psi = std::atan2(w.y, w.z);
    p.sinBeta = w.z / p.length;
    return p;
}

// The lit (or seen) part of cylinder 0 for direction `w`, an interval of φ (see the file head).
void litArc(const Projected& w, double period, double& lo, double& hi) {
    const double beta = std::atan2(w.z, std::abs(w.y));  // π/2 − |ψ|, accurate at grazing
    const double width = 2.0 * std::asin(std::sqrt(std::min(1.0, period * w.sinBeta / 2.0)));
    if (w.y >= 0.0) {
        lo = -beta;
        hi = -beta + width;
    } else {
        lo = beta - width;
        hi = beta;
    }
}

// Whether the floor point (y, −d) is lit by (or seen from) `w`: no cylinder kD in the hit window
// with the hit ahead of the point (file head). Multiplied through by L to avoid dividing by it.
bool floorLit(double y, const Projected& w, double period, double depth) {
    const double lowC = y + (depth * w.y - w.length) / w.z;
    const double highC = y + (depth * w.y + w.length) / w.z;
    const double kMin = std::ceil(lowC / period), kMax = std::floor(highC / period);
    if (kMin > kMax) return true;
    // The "ahead" condition is affine in c, so it holds for some k in [kMin, kMax] iff it holds at
    // one end.
    const auto ahead = [&](double c) { return (c - y) * w.y + depth * w.z > 0.0; };
    return !(ahead(kMin * period) || ahead(kMax * period));
}

// Appends the floor shadow-window edges y = kD − (d u_y ± 1)/u_z inside (start, end).
void addFloorBreaks(const Projected& w, double period, double depth, double start, double end,
                    std::vector<double>& breaks) {
    for (const double sign : {-1.0, 1.0}) {
        const double offset = -(depth * w.y + sign * w.length) / w.z;
        const double first = std::ceil((start - offset) / period);
        for (int i = 0; i < 4; ++i) {  // a window edge repeats once per period: ≤ 2 in the piece
            const double y = offset + (first + i) * period;
            if (y >= end) break;
            if (y > start) breaks.push_back(y);
        }
    }
}

// Lit-and-seen length of the floor piece of one period.
double floorLitLength(const Projected& wi, const Projected& wo, const PoulinFournier::Profile& pr) {
    const double start = pr.floorStart, end = pr.floorEnd;
    if (!(end > start)) return 0.0;
    std::vector<double> breaks;
    breaks.reserve(10);
    breaks.push_back(start);
    breaks.push_back(end);
    addFloorBreaks(wi, pr.period, pr.depth, start, end, breaks);
    addFloorBreaks(wo, pr.period, pr.depth, start, end, breaks);
    std::sort(breaks.begin(), breaks.end());
    double length = 0.0;
    for (size_t j = 0; j + 1 < breaks.size(); ++j) {
        const double a = breaks[j], b = breaks[j + 1];
        if (!(b > a)) continue;
        const double mid = 0.5 * (a + b);
        if (floorLit(mid, wi, pr.period, pr.depth) && floorLit(mid, wo, pr.period, pr.depth))
            length += b - a;
    }
    return length;
}

// The arc integrand fl(N)/ks · (N·wi)(N·wo) at angle φ (brdf-models.md model 6, Phong's term with
// normal N: rN(wi)·wo = 2(N·wi)(N·wo) − wi·wo).
// x^n by repeated squaring: the same value as std::pow up to a few ulps, several times faster
// for the whole exponents the model is used with (100 by default).
double powWhole(double x, unsigned n) {
    double result = 1.0;
    while (n) {
        if (n & 1u) result *= x;
        x *= x;
        n >>= 1u;
    }
    return result;
}

struct ArcIntegrand {
    Vec3 wi, wo;
    double wiDotWo = 0.0;
    double exponent = 0.0;
    bool wholeExponent = false;  // exponent is a whole number ≤ 2³¹: use powWhole
    ArcIntegrand(const Vec3& i, const Vec3& o, double dot, double n)
        : wi(i), wo(o), wiDotWo(dot), exponent(n),
          wholeExponent(n == std::floor(n) && n >= 0.0 && n <= 2147483647.0) {}

    double operator()(double phi) const { return at(std::sin(phi), std::cos(phi)); }
    // The integrand at the angle whose sine and cosine are s and c.
    double at(double s, double c) const {
        const double ni = std::max(0.0, wi.y * s + wi.z * c);
        const double no = std::max(0.0, wo.y * s + wo.z * c);
        const double cosAlphaN = std::max(0.0, 2.0 * ni * no - wiDotWo);
        const double power = wholeExponent ? powWhole(cosAlphaN, unsigned(exponent))
                                           : std::pow(cosAlphaN, exponent);
        return power * ni * no;
    }
};

double simpson(double a, double b, double fa, double fm, double fb) {
    return (b - a) / 6.0 * (fa + 4.0 * fm + fb);
}

// Adaptive Simpson (Lyness' criterion |S₂ − S₁| ≤ 15·tol, Richardson-corrected result).
double adaptiveSimpson(const ArcIntegrand& g, double a, double b, double fa, double fm, double fb,
                       double whole, double tol, int depth) {
    const double m = 0.5 * (a + b);
    const double lm = 0.5 * (a + m), rm = 0.5 * (m + b);
    const double flm = g(lm), frm = g(rm);
    const double left = simpson(a, m, fa, flm, fm), right = simpson(m, b, fm, frm, fb);
    const double delta = left + right - whole;
    if (depth <= 0 || std::abs(delta) <= 15.0 * tol) return left + right + delta / 15.0;
    return adaptiveSimpson(g, a, m, fa, flm, fm, left, 0.5 * tol, depth - 1) +
           adaptiveSimpson(g, m, b, fm, frm, fb, right, 0.5 * tol, depth - 1);
}

PoulinFournier::Profile makeProfile(double exponent, double gap, double depth) {
    PoulinFournier::Profile pr;
    pr.exponent = exponent;
    pr.period = 2.0 + gap;
    pr.depth = depth;
    // Buried cylinders: the arc exists where cos φ > −d; the floor starts where it leaves the
    // cylinder, at |y| = sqrt(1 − d²).
    pr.arcLimit = depth >= 1.0 ? kPi : std::acos(-depth);
    const double buried = depth >= 1.0 ? 0.0 : std::sqrt(1.0 - depth * depth);
    pr.floorStart = buried;
    pr.floorEnd = pr.period - buried;
    return pr;
}

// f/ks for one profile: [arc integral / (cos θi cos θo) + fl(n)/ks · floor length] / D.
double evalProfile(const PoulinFournier::Profile& pr, int intervals, const Vec3& wi, const Vec3& wo,
                   bool adaptive) {
    const Projected pi = project(wi), po = project(wo);
    const double wiDotWo = wi.dot(wo);

    // Floor: N = n, fl = cos^n α with cos α = max(0, r(wi)·wo).
    const double floorLength = floorLitLength(pi, po, pr);
    const double floorValue =
        floorLength > 0.0 ? std::pow(cosAlpha(wi, wo), pr.exponent) * floorLength : 0.0;

    // Arc: the visible-and-lit interval.
    double loI, hiI, loO, hiO;
    litArc(pi, pr.period, loI, hiI);
    litArc(po, pr.period, loO, hiO);
    const double lo = std::max({-pr.arcLimit, loI, loO});
    const double hi = std::min({pr.arcLimit, hiI, hiO});
    double arc = 0.0;
    if (hi > lo) {
        const ArcIntegrand g(wi, wo, wiDotWo, pr.exponent);
        std::vector<double> nodes;
        nodes.reserve(intervals + 8);
        const double halfStep = 0.5 * (hi - lo) / intervals;
        for (int j = 0; j <= intervals; ++j) nodes.push_back(lo + (2 * j) * halfStep);
        nodes.back() = hi;
        // Sines and cosines of the uniform half-grid lo + k·h/2 (the starting nodes and their
        // midpoints) by the rotation recurrence instead of 2·intervals + 1 calls of sin/cos; the
        // recurrence's rounding (≈ k ulps) is far below the rule's 1e-6 accuracy.
        const int halfCount = 2 * intervals + 1;
        std::vector<double> gridValue(halfCount);
        {
            const double sh = std::sin(halfStep), ch = std::cos(halfStep);
            double s = std::sin(lo), c = std::cos(lo);
            for (int k = 0; k < halfCount; ++k) {
                gridValue[k] = g.at(s, c);
                const double s2 = s * ch + c * sh;
                c = c * ch - s * sh;
                s = s2;
            }
        }
        if (adaptive) {
            // Extra nodes where the integrand is least smooth, so no refinement can miss them: the
            // lobe's peak (rN(wi)·wo = LiLo[cos(2φ − ψi − ψo) + cos(ψi − ψo)] − wi·wo is largest
            // at φ = (ψi + ψo)/2) and the zeros of rN(wi)·wo, where max(0, ·)^n has its kink.
            const double sum = pi.psi + po.psi;
            std::vector<double> extra = {0.5 * sum};
            const double p = pi.length * po.length;
            if (p > 0.0) {
                const double w = wiDotWo / p - std::cos(pi.psi - po.psi);
                if (std::abs(w) < 1.0) {
                    const double a = std::acos(w);
                    for (int k = -1; k <= 1; ++k)
                        for (const double sgn : {-1.0, 1.0})
                            extra.push_back(0.5 * (sum + sgn * a) + k * kPi);
                }
            }
            for (const double x : extra)
                if (x > lo && x < hi) nodes.push_back(x);
            std::sort(nodes.begin(), nodes.end());
        }
        const size_t n = nodes.size();
        std::vector<double> values(n), mids(n - 1), pieces(n - 1);
        // A node is on the half-grid when it is one of the uniform starting nodes (the extra
        // nodes are not): look its value up, else evaluate.
        auto gridIndex = [&](double x) {
            const double k = (x - lo) / halfStep;
            const long r = std::lround(k);
            return (r >= 0 && r < halfCount && lo + r * halfStep == x) ? int(r) : -1;
        };
        std::vector<int> nodeGrid(n);
        for (size_t j = 0; j < n; ++j) {
            nodeGrid[j] = j + 1 == n ? (nodes[j] == hi ? halfCount - 1 : gridIndex(nodes[j]))
                                     : gridIndex(nodes[j]);
            values[j] = nodeGrid[j] >= 0 ? gridValue[nodeGrid[j]] : g(nodes[j]);
        }
        double estimate = 0.0;
        for (size_t j = 0; j + 1 < n; ++j) {
            const bool uniformPair = nodeGrid[j] >= 0 && nodeGrid[j + 1] == nodeGrid[j] + 2;
            mids[j] = uniformPair ? gridValue[nodeGrid[j] + 1] : g(0.5 * (nodes[j] + nodes[j + 1]));
            pieces[j] = simpson(nodes[j], nodes[j + 1], values[j], mids[j], values[j + 1]);
            estimate += pieces[j];
        }
        if (!adaptive) {
            arc = estimate;
        } else {
            // Tolerance relative to the whole numerator (arc and floor, in the same units), shared
            // among the sub-intervals in proportion to their width.
            const double total = estimate + floorValue * wi.z * wo.z;
            const double tol = 0.5 * kRelativeAccuracy * std::abs(total) / (hi - lo);
            for (size_t j = 0; j + 1 < n; ++j) {
                const double a = nodes[j], b = nodes[j + 1];
                if (!(b > a)) continue;
                arc += adaptiveSimpson(g, a, b, values[j], mids[j], values[j + 1], pieces[j],
                                       tol * (b - a), kMaxDepth);
            }
        }
        arc = std::max(0.0, arc);
    }
    // Dividing the arc integral by cos θi cos θo stays finite at grazing angles: the lit arc and
    // N·w on it shrink with cos θ (file head).
    const double value = (arc / (wi.z * wo.z) + floorValue) / pr.period;
    return std::isfinite(value) ? value : 0.0;
}

}  // namespace

const ParamTable& PoulinFournier::paramTable() {
    static const ParamTable table = {
        {"ks", 0.8, 0.0, 1.0, "Phong coefficient of the cylinder and floor material", false},
        {"exponent", 100.0, 0.0, 1e5, "Phong exponent of the local reflection", false},
        {"gap", 2.0, 0.0, 100.0, "distance between neighbouring cylinders, in radii", false},
        {"floor_depth", 4.0, 0.0, 100.0, "depth of the floor below the cylinder axes, in radii",
         false},
        {"intervals", 64.0, 2.0, 4096.0, "Simpson sub-intervals the arc integration starts from",
         true},
    };
    return table;
}

PoulinFournier PoulinFournier::fromParams(const ParamValues& p) {
    PoulinFournier m;
    m.ks = p.get("ks");
    m.exponent = p.get("exponent");
    m.gap = p.get("gap");
    m.floorDepth = p.get("floor_depth");
    m.intervals = int(std::lround(p.scalar("intervals")));
    // One profile per distinct (exponent, gap, floor_depth): with the defaults all three bands
    // share one integration.
    for (int b = 0; b < kBandCount; ++b) {
        int found = -1;
        for (int q = 0; q < m.profileCount; ++q)
            if (m.profiles[q].exponent == m.exponent[b] && m.profiles[q].period == 2.0 + m.gap[b] &&
                m.profiles[q].depth == m.floorDepth[b])
                found = q;
        if (found < 0) {
            found = m.profileCount++;
            m.profiles[found] = makeProfile(m.exponent[b], m.gap[b], m.floorDepth[b]);
        }
        m.profileOfBand[b] = found;
    }
    return m;
}

Spectrum PoulinFournier::evaluate(const Vec3& wi, const Vec3& wo, bool adaptive) const {
    if (!aboveHorizon(wi, wo)) return Spectrum(0.0);
    const int intervalCount = std::max(2, intervals);
    Spectrum f;
    if (profileCount == 0) {  // a value built without fromParams: derive the profiles here
        for (int b = 0; b < kBandCount; ++b)
            f[b] = ks[b] * evalProfile(makeProfile(exponent[b], gap[b], floorDepth[b]),
                                       intervalCount, wi, wo, adaptive);
        return f;
    }
    std::array<double, kBandCount> perProfile{};
    for (int q = 0; q < profileCount; ++q)
        perProfile[q] = evalProfile(profiles[q], intervalCount, wi, wo, adaptive);
    for (int b = 0; b < kBandCount; ++b) f[b] = ks[b] * perProfile[profileOfBand[b]];
    return f;
}

Spectrum PoulinFournier::eval(const Vec3& wi, const Vec3& wo) const {
    return evaluate(wi, wo, true);
}

Spectrum PoulinFournier::evalFixedRule(const Vec3& wi, const Vec3& wo) const {
    return evaluate(wi, wo, false);
}

}  // namespace lobe
