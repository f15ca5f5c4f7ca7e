// The preview table of a He–Torrance material; see he_torrance_table.h.
#include "materials/he_torrance_table.h"

#include "materials/brdf_common.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <utility>

namespace lobe {
namespace {

constexpr double kHalfPi = 0.5 * kPi;
constexpr double kHorizonZ = 1e-6;
// A table whose validation error exceeds this fraction of kErrorBound is refused: the margin for
// directions between the validation points.
constexpr double kRefuseAbove = 0.75;

// w with its z raised to the horizon's kHorizonZ if below, renormalised (he_torrance_table.h,
// "Nodes below the horizon").
Vec3 ontoHorizon(Vec3 w) {
    if (w.z >= kHorizonZ) return w;
    const double s = std::sqrt(std::max(0.0, 1.0 - kHorizonZ * kHorizonZ));
    const double r = std::sqrt(w.x * w.x + w.y * w.y);
    if (!(r > 0.0)) return Vec3(1.0, 0.0, kHorizonZ);
    return Vec3(w.x / r * s, w.y / r * s, kHorizonZ);
}

// The series' value as evalBrdf (materials/brdf.h) passes it on: finite, ≥ 0, at most 1e30.
Spectrum seriesValue(const HeTorrance& model, const Vec3& wi, const Vec3& wo) {
    Spectrum f = model.eval(wi, wo);
    for (double& v : f.v) v = std::isnan(v) ? 0.0 : std::clamp(v, 0.0, 1e30);
    return f;
}

// The θd axis: v ∈ [0, 1] ↦ θd = (π/2)(1 − (1 − v)²), nodes crowding towards grazing θd, where
// the Fresnel factor and the geometry term make f rise and fall within a few degrees.
double thetaDOf(double v) { return kHalfPi * (1.0 - (1.0 - v) * (1.0 - v)); }
double diffAxisOf(double thetaD) { return 1.0 - std::sqrt(std::max(0.0, 1.0 - thetaD / kHalfPi)); }

// The radical inverse of i in base b (Halton 1960): the validation directions.
double radicalInverse(int i, int base) {
    double inv = 1.0 / base, f = inv, r = 0.0;
    for (; i > 0; i /= base, f *= inv) r += f * (i % base);
    return r;
}

}  // namespace

void HeTorranceTable::coordinates(const Vec3& wi, const Vec3& wo, double& u, double& thetaD,
                                  double& phiD) {
    const Vec3 sum = wi + wo;
    const double len = sum.length();
    const Vec3 h = len > 0.0 ? sum / len : Vec3(0, 0, 1);
    const double cosH = std::clamp(h.z, -1.0, 1.0), cosD = std::clamp(wi.dot(h), -1.0, 1.0);
    u = std::sqrt(std::acos(cosH) / kHalfPi);
    thetaD = std::acos(cosD);
    // cos φd = (wi − cos θd·h)·b̂ / sin θd with b̂ the unit direction of n − (n·h)h within the
    // plane ⊥ h (length sin θh); (wi − cos θd·h)·b = wi.z − cos θd·h.z since wi − cos θd·h ⊥ h.
    const double sinH = std::sqrt(std::max(0.0, 1.0 - cosH * cosH));
    const double sinD = std::sqrt(std::max(0.0, 1.0 - cosD * cosD));
    const double denom = sinH * sinD;
    phiD = denom > 1e-12 ? std::acos(std::min(1.0, std::abs(wi.z - cosD * h.z) / denom)) : 0.0;
}

void HeTorranceTable::directions(double u, double thetaD, double phiD, Vec3& wi, Vec3& wo) {
    const double thetaH = u * u * kHalfPi;
    const double ch = std::cos(thetaH), sh = std::sin(thetaH);
    const double cd = std::cos(thetaD), sd = std::sin(thetaD);
    const Vec3 d(sd * std::cos(phiD), sd * std::sin(phiD), cd);
    // Rotation by θh about y: the pole to h = (sin θh, 0, cos θh).
    wi = Vec3(ch * d.x + sh * d.z, d.y, -sh * d.x + ch * d.z);
    const Vec3 h(sh, 0.0, ch);
    wo = h * (2.0 * wi.dot(h)) - wi;
}

std::shared_ptr<const HeTorranceTable> HeTorranceTable::build(const HeTorrance& modelIn,
                                                              const Resolution& res) {
    HeTorrance model = modelIn;
    model.table = nullptr;  // the series itself
    auto table = std::make_shared<HeTorranceTable>();
    table->res_ = res;
    const int nHalf = res.half, nDiff = res.diff, nPhi = res.phi;
    table->values_.assign(std::size_t(nHalf) * nDiff * nPhi * kBandCount, 0.0f);
    std::vector<Spectrum> peaks(nHalf, Spectrum(0.0));  // per u slice: no shared reduction
    tbb::parallel_for(0, nHalf, [&](int iu) {
        const double u = double(iu) / (nHalf - 1);
        for (int id = 0; id < nDiff; ++id)
            for (int ip = 0; ip < nPhi; ++ip) {
                Vec3 wi, wo;
                directions(u, thetaDOf(double(id) / (nDiff - 1)), kHalfPi * ip / (nPhi - 1), wi,
                           wo);
                const bool above = wi.z > 0.0 && wo.z > 0.0;
                const Vec3 i = ontoHorizon(wi), o = ontoHorizon(wo);
                const Spectrum f = seriesValue(model, i, o);
                float* v =
                    &table->values_[((std::size_t(iu) * nDiff + id) * nPhi + ip) * kBandCount];
                for (int b = 0; b < kBandCount; ++b) {
                    v[b] = static_cast<float>(f[b]);
                    if (above) peaks[size_t(iu)][b] = std::max(peaks[size_t(iu)][b], f[b] * wi.z);
                }
            }
    });
    for (const Spectrum& p : peaks)
        for (int b = 0; b < kBandCount; ++b) table->peak_[b] = std::max(table->peak_[b], p[b]);

    // Validation (he_torrance_table.h, "Error bound"): a regular grid of direction pairs —
    // θi, θo at the midpoints of 24 steps of 3.75° (down to 1.9° from the horizon), the azimuth
    // between them in 16 steps of 11.25° from 5.625° — and kValidationPoints quasi-random points
    // in the table's coordinates (they crowd at the highlight as the nodes do). M is taken over
    // the nodes and these points.
    constexpr int kGrid = 24, kAzimuths = 16, kGridPoints = kGrid * kGrid * kAzimuths;
    const int total = kGridPoints + kValidationPoints;
    std::vector<std::pair<Vec3, Vec3>> pairs(static_cast<size_t>(total));
    for (int i = 0; i < total; ++i) {
        Vec3 wi, wo;
        if (i < kGridPoints) {
            const double ti = kHalfPi * ((i / (kGrid * kAzimuths)) + 0.5) / kGrid;
            const double to = kHalfPi * (((i / kAzimuths) % kGrid) + 0.5) / kGrid;
            const double phi = 2.0 * kPi * ((i % kAzimuths) + 0.5) / kAzimuths;
            wi = Vec3(std::sin(ti), 0.0, std::cos(ti));
            wo = Vec3(std::sin(to) * std::cos(phi), std::sin(to) * std::sin(phi), std::cos(to));
        } else {
            const int k = i - kGridPoints + 1;
            directions(radicalInverse(k, 2), thetaDOf(radicalInverse(k, 3)),
                       kHalfPi * radicalInverse(k, 5), wi, wo);
        }
        pairs[size_t(i)] = {wi, wo};
    }
    std::vector<Spectrum> exact(static_cast<size_t>(total), Spectrum(0.0));
    tbb::parallel_for(0, total, [&](int i) {
        const auto& [wi, wo] = pairs[size_t(i)];
        if (wi.z > 0.0 && wo.z > 0.0) exact[size_t(i)] = seriesValue(model, wi, wo);
    });
    for (int i = 0; i < total; ++i)
        for (int b = 0; b < kBandCount; ++b)
            table->peak_[b] =
                std::max(table->peak_[b], exact[size_t(i)][b] * pairs[size_t(i)].first.z);
    std::vector<double> errors(static_cast<size_t>(total), 0.0);
    tbb::parallel_for(0, total, [&](int i) {
        const auto& [wi, wo] = pairs[size_t(i)];
        if (!(wi.z > 0.0 && wo.z > 0.0)) return;
        const Spectrum approx = table->eval(wi, wo);
        for (int b = 0; b < kBandCount; ++b)
            if (table->peak_[b] > 0.0)
                errors[size_t(i)] =
                    std::max(errors[size_t(i)],
                             std::abs(approx[b] - exact[size_t(i)][b]) * wi.z / table->peak_[b]);
    });
    table->measuredError_ = *std::max_element(errors.begin(), errors.end());
    if (!(table->measuredError_ <= kRefuseAbove * res.errorBound)) return nullptr;
    return table;
}

double HeTorranceTable::relativeError(const HeTorrance& series, const Vec3& wi,
                                      const Vec3& wo) const {
    const Spectrum exact = seriesValue(series, wi, wo), approx = eval(wi, wo);
    double e = 0.0;
    for (int b = 0; b < kBandCount; ++b)
        if (peak_[b] > 0.0) e = std::max(e, std::abs(approx[b] - exact[b]) * wi.z / peak_[b]);
    return e;
}

Spectrum HeTorranceTable::eval(const Vec3& wi, const Vec3& wo) const {
    if (!aboveHorizon(wi, wo)) return Spectrum(0.0);
    const int nHalf = res_.half, nDiff = res_.diff, nPhi = res_.phi;
    double u, thetaD, phiD;
    coordinates(wi, wo, u, thetaD, phiD);
    const double x = std::clamp(u, 0.0, 1.0) * (nHalf - 1);
    const double y = std::clamp(diffAxisOf(thetaD), 0.0, 1.0) * (nDiff - 1);
    const double z = std::clamp(phiD / kHalfPi, 0.0, 1.0) * (nPhi - 1);
    const int cell[3] = {std::min(int(x), nHalf - 2), std::min(int(y), nDiff - 2),
                         std::min(int(z), nPhi - 2)};
    const double frac[3] = {x - cell[0], y - cell[1], z - cell[2]};
    return interpolate(cell, frac);
}

Spectrum HeTorranceTable::interpolate(const int* cell, const double* frac) const {
    const int nDiff = res_.diff, nPhi = res_.phi;
    const int ix = cell[0], iy = cell[1], iz = cell[2];
    const double fx = frac[0], fy = frac[1], fz = frac[2];
    const float* v = &values_[((std::size_t(ix) * nDiff + iy) * nPhi + iz) * kBandCount];
    const std::size_t sz = kBandCount, sy = std::size_t(nPhi) * kBandCount,
                      sx = std::size_t(nDiff) * nPhi * kBandCount;
    Spectrum f;
    for (int b = 0; b < kBandCount; ++b) {
        const float* p = v + b;
        const double c00 = p[0] + (p[sz] - p[0]) * fz;
        const double c01 = p[sy] + (p[sy + sz] - p[sy]) * fz;
        const double c10 = p[sx] + (p[sx + sz] - p[sx]) * fz;
        const double c11 = p[sx + sy] + (p[sx + sy + sz] - p[sx + sy]) * fz;
        const double c0 = c00 + (c01 - c00) * fy, c1 = c10 + (c11 - c10) * fy;
        f[b] = std::max(0.0, c0 + (c1 - c0) * fx);
    }
    return f;
}

}  // namespace lobe
