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

namespace lobe {
namespace {

// Relative accuracy of f asked by docs/models.md (model 6); the arc integration is asked for half
// of it as a margin.
constexpr double kRelativeAccuracy = 1e-6;

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

// The floor's breakpoints: the piece's ends and, per direction, ≤ 4 repeats of each of its 2
// window edges.
struct FloorBreaks {
    std::array<double, 18> y;
    int count = 0;
    void push(double v) { y[count++] = v; }
};

// Appends the floor shadow-window edges y = kD − (d u_y ± 1)/u_z inside (start, end).
void addFloorBreaks(const Projected& w, double period, double depth, double start, double end,
                    FloorBreaks& breaks) {
    for (const double sign : {-1.0, 1.0}) {
        const double offset = -(depth * w.y + sign * w.length) / w.z;
        const double first = std::ceil((start - offset) / period);
        for (int i = 0; i < 4; ++i) {  // a window edge repeats once per period: ≤ 2 in the piece
            const double y = offset + (first + i) * period;
            if (y >= end) break;
            if (y > start) breaks.push(y);
        }
    }
}

// Lit-and-seen length of the floor piece of one period.
double floorLitLength(const Projected& wi, const Projected& wo, const PoulinFournier::Profile& pr) {
    const double start = pr.floorStart, end = pr.floorEnd;
    if (!(end > start)) return 0.0;
    FloorBreaks breaks;
    breaks.push(start);
    breaks.push(end);
    addFloorBreaks(wi, pr.period, pr.depth, start, end, breaks);
    addFloorBreaks(wo, pr.period, pr.depth, start, end, breaks);
    std::sort(breaks.y.begin(), breaks.y.begin() + breaks.count);
    double length = 0.0;
    for (int j = 0; j + 1 < breaks.count; ++j) {
        const double a = breaks.y[j], b = breaks.y[j + 1];
        if (!(b > a)) continue;
        const double mid = 0.5 * (a + b);
        if (floorLit(mid, wi, pr.period, pr.depth) && floorLit(mid, wo, pr.period, pr.depth))
            length += b - a;
    }
    return length;
}

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

// The arc integrand in θ = 2φ − (ψi + ψo). With N = (0, sin φ, cos φ), wi.y = Li sin ψi and
// wi.z = Li cos ψi (likewise wo), N·wi = Li cos(φ − ψi), and the product-to-sum identity gives
//   (N·wi)(N·wo) = ½[P cos θ + q],   P = Li·Lo,  q = wi.y·wo.y + wi.z·wo.z = P cos(ψi − ψo),
//   rN(wi)·wo = 2(N·wi)(N·wo) − wi·wo = P cos θ − m,   m = wi.x·wo.x
// (docs/models.md model 6: Phong's term with normal N). So the integrand is
//   g(θ) = max(0, P cos θ − m)^n · ½ max(0, P cos θ + q),   ∫ (…) dφ = ½ ∫ g dθ,
// one cosine per evaluation, a lobe peaked at θ = 0 (mod 2π) with value (P − m)^n, and — all of
// P, q, m, θ being symmetric in wi and wo — exactly reciprocal. On the lit-and-seen interval
// N·wi, N·wo ≥ 0, so the second max() only removes rounding.
struct ArcLobe {
    double p = 0.0, q = 0.0, m = 0.0;
    double exponent = 0.0;
    bool wholeExponent = false;  // exponent is a whole number ≤ 2³¹: use powWhole
    unsigned whole = 0;
    ArcLobe(const Vec3& wi, const Vec3& wo, double li, double lo, double n)
        : p(li * lo),
          q(wi.y * wo.y + wi.z * wo.z),
          m(wi.x * wo.x),
          exponent(n),
          wholeExponent(n == std::floor(n) && n >= 0.0 && n <= 2147483647.0),
          whole(wholeExponent ? unsigned(n) : 0u) {}
    double power(double u) const {
        return wholeExponent ? powWhole(u, whole) : std::pow(u, exponent);
    }
    // g at the angle whose cosine is c.
    double atCos(double c) const {
        const double x = p * c;
        const double u = x - m;
        if (!(u > 0.0)) return exponent == 0.0 ? 0.5 * std::max(0.0, x + q) : 0.0;
        return power(u) * 0.5 * std::max(0.0, x + q);
    }
    double operator()(double theta) const { return atCos(std::cos(theta)); }
};

// Gauss–Kronrod 7/15-point rule (QUADPACK dqk15: R. Piessens et al., QUADPACK, Springer 1983):
// abscissae ±kXgk[j] on [−1, 1]; kXgk[1], [3], [5] and 0 are the 7-point Gauss nodes.
constexpr double kXgk[8] = {
    0.991455371120812639206854697526329, 0.949107912342758524526189684047851,
    0.864864423359769072789712788640926, 0.741531185599394439863864773280788,
    0.586087235467691130294144845693013, 0.405845151377397166906606412076961,
    0.207784955007898467600689403773245, 0.0};
constexpr double kWgk[8] = {
    0.022935322010529224963732008058970, 0.063092092629978553290700663189204,
    0.104790010322250183839876322541518, 0.140653259715525918745189590510238,
    0.169004726639267902826583426598550, 0.190350578064785409913256402421014,
    0.204432940075298892414161999234649, 0.209482141084727828012999174891714};
constexpr double kWg[4] = {0.129484966168869693270611432679082, 0.279705391489276667901467771423780,
                           0.381830050505118944950369775488975,
                           0.417959183673469387755102040816327};

struct Segment {
    double a = 0.0, b = 0.0;
    double value = 0.0;  // the 15-point Kronrod value
    double error = 0.0;  // |Kronrod − Gauss|, the error of the 7-point Gauss value: a safe bound
};

// Sines and cosines of the 7 node offsets half·kXgk[j] of a segment of half-width `half`: the
// nodes' cosines then follow by angle addition, cos(c ± x) = cos c cos x ∓ sin c sin x — 8
// sine-cosine pairs per segment instead of 15 cosines, and the pieces either side of a lobe peak
// and the two halves of a split segment have the same width, so the offsets are reused.
struct NodeOffsets {
    double half = -1.0;
    std::array<double, 7> sinX{}, cosX{};
    void prepare(double h) {
        if (h == half) return;
        half = h;
        for (int j = 0; j < 7; ++j) {
            sinX[j] = std::sin(h * kXgk[j]);
            cosX[j] = std::cos(h * kXgk[j]);
        }
    }
};

Segment gaussKronrod(const ArcLobe& g, double a, double b, NodeOffsets& offsets) {
    Segment s;
    s.a = a;
    s.b = b;
    const double centre = 0.5 * (a + b), half = 0.5 * (b - a);
    offsets.prepare(half);
    const double sc = std::sin(centre), cc = std::cos(centre);
    const double fc = g.atCos(cc);
    double kronrod = fc * kWgk[7], gauss = fc * kWg[3];
    for (int j = 0; j < 7; ++j) {
        const double even = cc * offsets.cosX[j], odd = sc * offsets.sinX[j];
        const double pair = g.atCos(even + odd) + g.atCos(even - odd);
        kronrod += kWgk[j] * pair;
        if (j & 1) gauss += kWg[j / 2] * pair;
    }
    s.value = kronrod * half;
    s.error = std::abs(kronrod - gauss) * half;
    return s;
}

// ∫ g dθ over [ta, tb] (width ≤ 2π) to `relative` accuracy of (that integral + floorTheta), the
// floor's share of the numerator in the same units (≥ 0).
//  1. Breakpoints: the lobe peaks θ = 2πk; the edges ±θ0 of the support cos θ > m/P (where u^n has
//     its kink) or, when u > 0 everywhere, the troughs π + 2πk; and ±3s, ±6.5s from each peak, s =
//     sqrt((P − m)/(nP)) the lobe's width (u^n ≈ (P − m)^n exp(−θ²/2s²) near the peak). On every
//     piece the integrand is smooth and cos θ monotone.
//  2. A piece whose exact bound max(u)^n · max(½(P cos θ + q)) · width (u and cos θ monotone:
//     the maxima are at an end) is below a tenth of the tolerance is not integrated — checked in
//     order of decreasing bound against the running total, which can only grow (g ≥ 0); the other
//     pieces get the 15-point Kronrod rule with |K15 − G7| as error bound.
//  3. While the summed bounds exceed the tolerance, the piece with the largest one is halved.
double integrateArc(const ArcLobe& g, double ta, double tb, double floorTheta, double relative) {
    if (!(tb > ta)) return 0.0;
    const double p = g.p, m = g.m, n = g.exponent;
    // At exponent 0, g = ½(P cos θ + q) everywhere (x⁰ = 1, also at x ≤ 0): no lobe, no support
    // edge. (Its closed form ½[P(sin tb − sin ta) + q(tb − ta)] is not used: at grazing angles the
    // two terms cancel to a part in 10⁴.)
    const double peak = p - m;
    if (n > 0.0 && !(peak > 0.0)) return 0.0;  // rN(wi)·wo ≤ 0 on the whole circle
    constexpr double kTwoPi = 2.0 * kPi;
    const double ratio = m / p;  // support: cos θ > ratio
    const bool wholeCircle = n == 0.0 || ratio < -1.0;
    const double edge = wholeCircle ? 0.0 : std::acos(std::min(1.0, ratio));
    const double width = n > 0.0 ? std::sqrt(peak / (n * p)) : kTwoPi;

    // Breakpoints with their cosines, known exactly but at the interval's ends and ±3s, ±6.5s.
    struct Break {
        double x, cosX;
    };
    std::array<Break, 48> breaks;
    int count = 0;
    breaks[count++] = {ta, std::cos(ta)};
    breaks[count++] = {tb, std::cos(tb)};
    const auto add = [&](double x, double cosX) {
        if (x > ta && x < tb && count < int(breaks.size())) breaks[count++] = {x, cosX};
    };
    const double limit = wholeCircle ? kPi : edge;
    const double lobeOffsets[2] = {3.0 * width, 6.5 * width};
    const double cosOffsets[2] = {lobeOffsets[0] < limit ? std::cos(lobeOffsets[0]) : 0.0,
                                  lobeOffsets[1] < limit ? std::cos(lobeOffsets[1]) : 0.0};
    const int kMin = int(std::floor(ta / kTwoPi)) - 1, kMax = int(std::ceil(tb / kTwoPi)) + 1;
    for (int k = kMin; k <= kMax; ++k) {
        const double c = k * kTwoPi;
        add(c, 1.0);
        if (wholeCircle) {
            add(c + kPi, -1.0);
        } else {
            add(c - edge, ratio);
            add(c + edge, ratio);
        }
        for (int j = 0; j < 2; ++j) {
            if (lobeOffsets[j] >= limit) break;
            add(c - lobeOffsets[j], cosOffsets[j]);
            add(c + lobeOffsets[j], cosOffsets[j]);
        }
    }
    std::sort(breaks.begin(), breaks.begin() + count,
              [](const Break& x, const Break& y) { return x.x < y.x; });

    // Pieces inside the support (the midpoint nearer to a peak than the support's edge), with
    // their bounds.
    struct Piece {
        double a, b, bound;
    };
    std::array<Piece, 48> pieces;
    int pieceCount = 0;
    for (int j = 0; j + 1 < count; ++j) {
        const double a = breaks[j].x, b = breaks[j + 1].x;
        if (!(b > a)) continue;
        const double mid = 0.5 * (a + b);
        if (!wholeCircle && !(std::abs(mid - kTwoPi * std::nearbyint(mid / kTwoPi)) < edge))
            continue;
        const double cmax = std::max(breaks[j].cosX, breaks[j + 1].cosX);
        const double u = std::max(0.0, p * cmax - m);
        const double w = std::max(0.0, 0.5 * (p * cmax + g.q));
        pieces[pieceCount++] = {a, b, g.power(u) * w * (b - a)};
    }
    std::sort(pieces.begin(), pieces.begin() + pieceCount,
              [](const Piece& x, const Piece& y) { return x.bound > y.bound; });

    constexpr int kMaxSegments = 256;
    std::array<Segment, kMaxSegments> segments;
    int segmentCount = 0;
    NodeOffsets offsets;
    double running = floorTheta, skipped = 0.0;
    for (int j = 0; j < pieceCount; ++j) {
        const Piece& piece = pieces[j];
        if (skipped + piece.bound <= 0.1 * relative * running) {
            skipped += piece.bound;
            continue;
        }
        segments[segmentCount] = gaussKronrod(g, piece.a, piece.b, offsets);
        running += segments[segmentCount].value;
        ++segmentCount;
    }
    for (;;) {
        double total = floorTheta, error = skipped;
        int worst = -1;
        for (int j = 0; j < segmentCount; ++j) {
            total += segments[j].value;
            error += segments[j].error;
            if (worst < 0 || segments[j].error > segments[worst].error) worst = j;
        }
        if (error <= relative * total || worst < 0 || segmentCount + 1 >= kMaxSegments) break;
        const Segment s = segments[worst];
        const double mid = 0.5 * (s.a + s.b);
        if (!(mid > s.a && mid < s.b)) {  // no longer divisible: keep its value
            segments[worst].error = 0.0;
            continue;
        }
        segments[worst] = gaussKronrod(g, s.a, mid, offsets);
        segments[segmentCount++] = gaussKronrod(g, mid, s.b, offsets);
    }
    double arc = 0.0;
    for (int j = 0; j < segmentCount; ++j) arc += segments[j].value;
    return arc;
}

// The fixed composite Simpson rule of `intervals` equal sub-intervals of [lo, hi] in φ (the 1990
// paper's rule), for evalFixedRule.
double fixedSimpsonArc(const ArcLobe& g, double sigma, double lo, double hi, int intervals) {
    const double h = (hi - lo) / intervals;
    const auto at = [&](double phi) { return g(2.0 * phi - sigma); };
    double sum = at(lo) + at(hi);
    for (int j = 1; j < intervals; ++j) sum += 2.0 * at(lo + j * h);
    for (int j = 0; j < intervals; ++j) sum += 4.0 * at(lo + (j + 0.5) * h);
    return sum * h / 6.0;  // in φ: ∫ g(2φ − σ) dφ
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

    const ArcLobe g(wi, wo, pi.length, po.length, pr.exponent);

    // Floor: N = n, fl = cos^n α with cos α = max(0, r(wi)·wo).
    const double floorLength = floorLitLength(pi, po, pr);
    const double floorValue = floorLength > 0.0 ? g.power(cosAlpha(wi, wo)) * floorLength : 0.0;

    // Arc: the visible-and-lit interval.
    double loI, hiI, loO, hiO;
    litArc(pi, pr.period, loI, hiI);
    litArc(po, pr.period, loO, hiO);
    const double lo = std::max({-pr.arcLimit, loI, loO});
    const double hi = std::min({pr.arcLimit, hiI, hiO});
    double arc = 0.0;
    if (hi > lo) {
        const double sigma = pi.psi + po.psi;
        if (adaptive) {
            // In θ = 2φ − σ (dφ = dθ/2); the floor's share of the numerator in the same units.
            const double floorTheta = 2.0 * floorValue * wi.z * wo.z;
            arc = 0.5 * integrateArc(g, 2.0 * lo - sigma, 2.0 * hi - sigma, floorTheta,
                                     0.5 * kRelativeAccuracy);
        } else {
            arc = fixedSimpsonArc(g, sigma, lo, hi, intervals);
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
    };
    return table;
}

PoulinFournier PoulinFournier::fromParams(const ParamValues& p) {
    PoulinFournier m;
    m.ks = p.get("ks");
    m.exponent = p.get("exponent");
    m.gap = p.get("gap");
    m.floorDepth = p.get("floor_depth");
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

Spectrum PoulinFournier::evaluate(const Vec3& wi, const Vec3& wo, bool adaptive,
                                  int intervals) const {
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
    return evaluate(wi, wo, true, kPaperIntervals);
}

Spectrum PoulinFournier::evalFixedRule(const Vec3& wi, const Vec3& wo, int intervals) const {
    return evaluate(wi, wo, false, intervals);
}

}  // namespace lobe
