#include "volume/transfer_function.h"

#include "core/error.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace lobe {

double correctOpacity(double alphaVoxel, double stepInVoxels) {
    // Equation (1) of the header. alphaVoxel < 1 is guaranteed by the constructor; log1p keeps
    // precision for the tiny opacities (0.001 per voxel at 0.05-voxel steps).
    if (!(alphaVoxel > 0.0)) return 0.0;
    return -std::expm1(stepInVoxels * std::log1p(-alphaVoxel));
}

OpacityCorrection::OpacityCorrection(double stepInVoxels, double alphaMax) {
    if (!(stepInVoxels > 0.0) || !std::isfinite(stepInVoxels))
        throw Error("opacity correction: the step must be > 0 and finite, got " +
                    std::to_string(stepInVoxels));
    r_ = stepInVoxels;
    top_ = std::min(alphaMax, kTopLimit);
    if (!(top_ > 0.0)) {
        top_ = -1.0;  // nothing visible: no table
        return;
    }
    const int n = int(std::ceil(top_ * kIntervalsPerUnit));
    const double h = 1.0 / kIntervalsPerUnit;
    invH_ = kIntervalsPerUnit;
    last_ = n - 1;
    coef_.assign(size_t(n) * kCoefs, 0.0);
    // Chebyshev nodes y_j = cos((2j + 1)π / 12) on [−1, 1], u = y / 2 (Trefethen 2013, ch. 2).
    constexpr int m = kCoefs;
    long double y[m], q[m];
    for (int j = 0; j < m; ++j)
        y[j] = std::cos((2.0L * j + 1.0L) * 3.14159265358979323846L / (2 * m));
    for (int i = 0; i < n; ++i) {
        for (int j = 0; j < m; ++j) {
            const double a = (double(i) + 0.5 + 0.5 * double(y[j])) * h;
            q[j] = (long double)correctOpacity(a, r_) / a;
        }
        // Chebyshev coefficients of the interpolant: c_k = (2/m) Σ_j q_j T_k(y_j), c_0 halved
        // (the discrete orthogonality of T_k at the Chebyshev points).
        long double cheb[m];
        for (int k = 0; k < m; ++k) {
            long double s = 0.0L;
            for (int j = 0; j < m; ++j)
                s += q[j] * std::cos(k * (2.0L * j + 1.0L) * 3.14159265358979323846L / (2 * m));
            cheb[k] = s * 2.0L / m * (k == 0 ? 0.5L : 1.0L);
        }
        // To powers of y (T_{k+1} = 2y T_k − T_{k−1}), then of u = y / 2: y^p = 2^p u^p.
        long double t0[m] = {1.0L}, t1[m] = {0.0L, 1.0L}, mono[m] = {};
        for (int k = 0; k < m; ++k) {
            const long double* t = k == 0 ? t0 : t1;
            for (int p = 0; p < m; ++p) mono[p] += cheb[k] * t[p];
            if (k >= 1 && k + 1 < m) {
                long double t2[m];
                for (int p = 0; p < m; ++p) t2[p] = (p > 0 ? 2.0L * t1[p - 1] : 0.0L) - t0[p];
                for (int p = 0; p < m; ++p) {
                    t0[p] = t1[p];
                    t1[p] = t2[p];
                }
            }
        }
        long double scale = 1.0L;
        for (int p = 0; p < m; ++p, scale *= 2.0L)
            coef_[size_t(i) * m + size_t(p)] = double(mono[p] * scale);
    }
}

TransferFunction::TransferFunction(std::vector<TfPoint> points, const std::string& name)
    : points_(std::move(points)) {
    for (size_t i = 0; i < points_.size(); ++i) {
        const TfPoint& p = points_[i];
        const std::string where = name + ", control point " + std::to_string(i);
        if (!std::isfinite(p.value)) throw Error(where + ": value is not finite");
        if (i > 0 && p.value < points_[i - 1].value)
            throw Error(where + ": values must be sorted ascending (" + std::to_string(p.value) +
                        " < " + std::to_string(points_[i - 1].value) + ")");
        if (!(p.opacity >= 0.0 && p.opacity < 1.0))
            throw Error(where + ": opacity per voxel must be in [0, 1), got " +
                        std::to_string(p.opacity));
        if (!p.colour.isFinite() || p.colour[0] < 0.0 || p.colour[1] < 0.0 || p.colour[2] < 0.0)
            throw Error(where + ": colour bands must be finite and >= 0");
    }
}

void TransferFunction::evaluate(double value, double& opacity, Spectrum& colour) const {
    if (points_.empty()) {
        opacity = 0.0;
        colour = Spectrum(0.0);
        return;
    }
    // First point strictly above `value`: at a step (two equal values) the right limit wins.
    const auto it = std::upper_bound(points_.begin(), points_.end(), value,
                                     [](double v, const TfPoint& p) { return v < p.value; });
    if (it == points_.begin()) {
        opacity = it->opacity;
        colour = it->colour;
        return;
    }
    if (it == points_.end()) {
        opacity = points_.back().opacity;
        colour = points_.back().colour;
        return;
    }
    const TfPoint& a = *(it - 1);
    const TfPoint& b = *it;
    const double s = (value - a.value) / (b.value - a.value);  // b.value > a.value here
    opacity = a.opacity + s * (b.opacity - a.opacity);
    colour = a.colour * (1.0 - s) + b.colour * s;
}

double TransferFunction::opacity(double value) const {
    double a;
    Spectrum c;
    evaluate(value, a, c);
    return a;
}

Spectrum TransferFunction::colour(double value) const {
    double a;
    Spectrum c;
    evaluate(value, a, c);
    return c;
}

double TransferFunction::maxOpacity(double lo, double hi) const {
    if (points_.empty()) return 0.0;
    if (hi < lo) std::swap(lo, hi);
    double m = std::max(opacity(lo), opacity(hi));
    // Control points inside the interval, including both limits of a step at an interior value.
    for (const TfPoint& p : points_)
        if (p.value >= lo && p.value <= hi) m = std::max(m, p.opacity);
    return m;
}

std::vector<std::pair<double, double>> TransferFunction::transparentRanges() const {
    constexpr double kInf = std::numeric_limits<double>::infinity();
    std::vector<std::pair<double, double>> ranges;
    if (points_.empty()) return {{-kInf, kInf}};
    // Walk the segments (−inf, p0], [p0, p1], …, [pn, +inf) and merge those with zero opacity at
    // both ends (a linear piece that is zero at both ends is zero throughout).
    auto add = [&](double a, double b) {
        if (!ranges.empty() && ranges.back().second >= a)
            ranges.back().second = std::max(ranges.back().second, b);
        else
            ranges.emplace_back(a, b);
    };
    if (points_.front().opacity == 0.0) add(-kInf, points_.front().value);
    for (size_t i = 0; i + 1 < points_.size(); ++i)
        if (points_[i].opacity == 0.0 && points_[i + 1].opacity == 0.0)
            add(points_[i].value, points_[i + 1].value);
    if (points_.back().opacity == 0.0) add(points_.back().value, kInf);
    return ranges;
}

namespace {

constexpr double kDensityIso[4] = {0.70, 0.75, 0.80, 0.85};
constexpr double kDensityOpacity[4] = {0.3, 0.4, 0.5, 0.6};

Spectrum densityColour(int i) {
    // Blue, green, yellow, red as linear sRGB primaries (Figure 10 of the paper names only the
    // colours).
    static const Spectrum kColours[4] = {linearSrgbToBands(0, 0, 1), linearSrgbToBands(0, 1, 0),
                                         linearSrgbToBands(1, 1, 0), linearSrgbToBands(1, 0, 0)};
    return kColours[i];
}

void checkRampWidth(double w) {
    if (!(w > 0.0 && w < 0.05))
        throw Error("density map transfer function: ramp width must be in (0, 0.05), got " +
                    std::to_string(w));
}

}  // namespace

TransferFunction TransferFunction::densityMap(int index, double rampWidth) {
    if (index < 0 || index > 3)
        throw Error("density map transfer function: index must be 0..3, got " +
                    std::to_string(index));
    checkRampWidth(rampWidth);
    const double h = 0.5 * rampWidth;
    const Spectrum c = densityColour(index);
    const double a = kDensityOpacity[index];
    std::vector<TfPoint> p = {{kDensityIso[index] - h, 0.0, c}, {kDensityIso[index] + h, a, c}};
    if (index < 3) {
        p.push_back({kDensityIso[index + 1] - h, a, c});
        p.push_back({kDensityIso[index + 1] + h, 0.0, c});
    }
    return TransferFunction(std::move(p), "density map " + std::to_string(index));
}

TransferFunction TransferFunction::densityMaps(double rampWidth) {
    checkRampWidth(rampWidth);
    const double h = 0.5 * rampWidth;
    std::vector<TfPoint> p = {{kDensityIso[0] - h, 0.0, densityColour(0)}};
    for (int i = 0; i < 4; ++i) {
        p.push_back({kDensityIso[i] + h, kDensityOpacity[i], densityColour(i)});
        if (i < 3) p.push_back({kDensityIso[i + 1] - h, kDensityOpacity[i], densityColour(i)});
    }
    return TransferFunction(std::move(p), "density maps");
}

TransferFunction TransferFunction::cortex(double boundary, double width, const Spectrum& colour) {
    if (!(width > 0.0) || !std::isfinite(boundary) || !std::isfinite(width))
        throw Error("cortex transfer function: width must be > 0 and boundary finite");
    const double lo = boundary - 0.5 * width;
    const double hi = boundary + 0.5 * width;
    // A step from 0 to 0.001 at `lo` (two points at one value): below it the ramp is exactly
    // transparent, so empty-space skipping can drop the low-valued tissue.
    return TransferFunction({{lo, 0.0, colour}, {lo, 0.001, colour}, {hi, 0.2, colour}}, "cortex");
}

TransferFunction TransferFunction::cortexShell(double boundary, double width, double opacity,
                                               const Spectrum& colour) {
    if (!(width > 0.0) || !std::isfinite(boundary) || !std::isfinite(width))
        throw Error("cortex shell transfer function: width must be > 0 and boundary finite");
    constexpr double kEdge = 0.001;  // the paper's lowest cortex opacity
    if (!(opacity >= kEdge && opacity < 1.0))
        throw Error("cortex shell transfer function: opacity must be in [0.001, 1), got " +
                    std::to_string(opacity));
    const double lo = boundary - 0.5 * width;
    const double hi = boundary + 0.5 * width;
    // Steps at both ends (two points at one value) keep everything outside the tent exactly
    // transparent, so empty-space skipping drops it.
    return TransferFunction({{lo, 0.0, colour},
                             {lo, kEdge, colour},
                             {boundary, opacity, colour},
                             {hi, kEdge, colour},
                             {hi, 0.0, colour}},
                            "cortex shell");
}

}  // namespace lobe
