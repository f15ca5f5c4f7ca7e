#include "volume/pre_integration.h"

#include <algorithm>
#include <cmath>

namespace lobe {

namespace {

// Extinction per reference voxel length and its product with the colour at value v.
void extinction(const TransferFunction& tf, double v, double& tau, Spectrum& tauC) {
    double alpha;
    Spectrum c;
    tf.evaluate(v, alpha, c);
    tau = -std::log1p(-alpha);
    tauC = c * tau;
}

// 4-point Gauss–Legendre rule on [−1, 1] (Abramowitz & Stegun 1964, table 25.4).
constexpr double kGaussX[4] = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563,
                               0.8611363115940526};
constexpr double kGaussW[4] = {0.3478548451374538, 0.6521451548625461, 0.6521451548625461,
                               0.3478548451374538};

}  // namespace

PreIntegratedTf::PreIntegratedTf(const TransferFunction& tf) : tf_(tf) {
    const std::vector<TfPoint>& p = tf.points();
    if (!p.empty()) {
        v0_ = p.front().value;
        v1_ = p.back().value;
        if (!(v1_ > v0_)) {
            v0_ -= 0.5;
            v1_ += 0.5;
        }
    }
    h_ = (v1_ - v0_) / kIntervals;
    // End values (transfer_function.h: below the first point and above the last, they hold).
    extinction(tf_, v0_ - 1.0, tauLo_, tauCLo_);
    extinction(tf_, v1_ + 1.0, tauHi_, tauCHi_);
    t_.assign(kIntervals + 1, 0.0);
    k_.assign(kIntervals + 1, Spectrum(0.0));
    m_.assign(kIntervals + 1, 0.0);
    for (int i = 0; i < kIntervals; ++i) {
        const double a = v0_ + i * h_, mid = a + 0.5 * h_;
        double sumT = 0.0, sumM = 0.0;
        Spectrum sumK(0.0);
        for (int g = 0; g < 4; ++g) {
            double tau;
            Spectrum tauC;
            const double u = mid + 0.5 * h_ * kGaussX[g];
            extinction(tf_, u, tau, tauC);
            sumT += kGaussW[g] * tau;
            sumM += kGaussW[g] * tau * u;
            sumK += tauC * kGaussW[g];
        }
        t_[i + 1] = t_[i] + 0.5 * h_ * sumT;
        m_[i + 1] = m_[i] + 0.5 * h_ * sumM;
        k_[i + 1] = k_[i] + sumK * (0.5 * h_);
    }
}

void PreIntegratedTf::locate(double v, int& i, double& frac, double& beyond) const {
    beyond = 0.0;
    frac = 0.0;
    if (!(v > v0_)) {  // also NaN: the start (the marcher never passes NaN; values are finite)
        i = 0;
        beyond = std::isfinite(v) ? v - v0_ : 0.0;
        return;
    }
    if (v >= v1_) {
        i = kIntervals;
        beyond = std::isfinite(v) ? v - v1_ : 0.0;
        return;
    }
    const double x = (v - v0_) / h_;
    i = std::min(int(x), kIntervals - 1);
    frac = x - i;
}

double PreIntegratedTf::interpolate(const std::vector<double>& nodes, double v, double& beyond,
                                    double& end) const {
    int i;
    double frac;
    locate(v, i, frac, beyond);
    end = beyond < 0.0 ? v0_ : v1_;
    return i < kIntervals ? nodes[i] + frac * (nodes[i + 1] - nodes[i]) : nodes[i];
}

double PreIntegratedTf::extinctionIntegral(double v) const {
    double beyond, end;
    const double t = interpolate(t_, v, beyond, end);
    return t + (beyond < 0.0 ? tauLo_ : tauHi_) * beyond;
}

double PreIntegratedTf::momentIntegral(double v) const {
    // Beyond the span τ is constant: ∫ τ u du from the end to v.
    double beyond, end;
    const double m = interpolate(m_, v, beyond, end);
    return m + (beyond < 0.0 ? tauLo_ : tauHi_) * beyond * (end + 0.5 * beyond);
}

Spectrum PreIntegratedTf::colourIntegral(double v) const {
    int i;
    double frac, beyond;
    locate(v, i, frac, beyond);
    Spectrum k = k_[i];
    const Spectrum& slope = beyond < 0.0 ? tauCLo_ : tauCHi_;
    for (int b = 0; b < kBandCount; ++b) {
        if (i < kIntervals) k[b] += frac * (k_[i + 1][b] - k_[i][b]);
        k[b] += slope[b] * beyond;
    }
    return k;
}

void PreIntegratedTf::segment(double sFront, double sBack, double lengthRef, double& alpha,
                              Spectrum& colour, double& where) const {
    const double ds = sBack - sFront;
    double tau;
    where = 0.5;
    if (std::abs(ds) <= 1e-6 * (v1_ - v0_)) {
        // The limit of both quotients as s_b → s_f: the point values (at the midpoint).
        Spectrum tauC;
        extinction(tf_, 0.5 * (sFront + sBack), tau, tauC);
        colour = tau > 0.0 ? tauC * (1.0 / tau) : Spectrum(0.0);
    } else {
        const double dT = extinctionIntegral(sBack) - extinctionIntegral(sFront);
        tau = dT / ds;
        if (!(tau > 0.0) || !(std::abs(dT) > 0.0)) {
            alpha = 0.0;
            colour = Spectrum(0.0);
            return;
        }
        const Spectrum kb = colourIntegral(sBack), kf = colourIntegral(sFront);
        for (int b = 0; b < kBandCount; ++b) colour[b] = (kb[b] - kf[b]) / dT;
        const double mean = (momentIntegral(sBack) - momentIntegral(sFront)) / dT;
        where = std::min(1.0, std::max(0.0, (mean - sFront) / ds));
    }
    alpha = tau > 0.0 ? -std::expm1(-tau * lengthRef) : 0.0;
}

}  // namespace lobe
