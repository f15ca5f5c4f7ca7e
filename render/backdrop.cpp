#include "render/backdrop.h"

#include "core/rng.h"

#include <cmath>
#include <limits>

namespace lobe {
namespace {

// Separable Gaussian blur with wrap-around, so the texture tiles without seams.
std::vector<Spectrum> blurWrapped(const std::vector<Spectrum>& in, int n, double sigma) {
    if (sigma <= 0.0) return in;
    const int radius = int(std::ceil(3.0 * sigma));
    std::vector<double> w(2 * radius + 1);
    double sum = 0.0;
    for (int i = -radius; i <= radius; ++i)
        sum += w[i + radius] = std::exp(-0.5 * i * i / (sigma * sigma));
    for (double& x : w) x /= sum;
    std::vector<Spectrum> tmp(in.size()), out(in.size());
    auto wrap = [n](int i) { return ((i % n) + n) % n; };
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            Spectrum s;
            for (int k = -radius; k <= radius; ++k) s += in[y * n + wrap(x + k)] * w[k + radius];
            tmp[y * n + x] = s;
        }
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            Spectrum s;
            for (int k = -radius; k <= radius; ++k) s += tmp[wrap(y + k) * n + x] * w[k + radius];
            out[y * n + x] = s;
        }
    return out;
}

}  // namespace

Backdrop::Backdrop(const BackdropSettings& settings, const Vec3& planePoint, const Vec3& forward,
                   const Vec3& right, const Vec3& up, double halfExtent)
    : settings_(settings),
      point_(planePoint),
      normal_(-forward),
      right_(right),
      up_(up),
      halfExtent_(halfExtent) {
    // 8 texels per cell so the blurred colours interpolate smoothly.
    const int perCell = 8;
    resolution_ = settings.cells * perCell;
    std::vector<Spectrum> cells(size_t(settings.cells) * settings.cells);
    Rng rng(settings.seed, 0xbac4d409);
    for (Spectrum& c : cells) {
        // Blue is drawn first: the order in which GCC evaluated the arguments of the former
        // Spectrum(rng.uniform(), rng.uniform(), rng.uniform()) (right to left; the order was
        // unspecified), so the backdrop of every existing scene stays the same.
        const double b = rng.uniform(), g = rng.uniform(), r = rng.uniform();
        // Grey: the first draw as the cell's lightness, uniform in [0, 1) as each colour channel
        // is — the same spread of light and dark (the Gelb-effect guard) without a hue to tint
        // what is seen through translucent objects.
        c = settings.grey ? Spectrum(b) : Spectrum(r, g, b);
    }
    std::vector<Spectrum> fine(size_t(resolution_) * resolution_);
    for (int y = 0; y < resolution_; ++y)
        for (int x = 0; x < resolution_; ++x)
            fine[y * resolution_ + x] = cells[(y / perCell) * settings.cells + x / perCell];
    texture_ = blurWrapped(fine, resolution_, settings.blur * perCell);
}

double Backdrop::intersect(const Ray& ray) const {
    const double denom = ray.d.dot(normal_);
    if (!(denom < 0.0)) return std::numeric_limits<double>::infinity();
    const double t = (point_ - ray.o).dot(normal_) / denom;
    return t > ray.tMin ? t : std::numeric_limits<double>::infinity();
}

Spectrum Backdrop::textureAt(double u, double v) const {
    // Bilinear lookup with wrap-around; u, v in texels.
    const double fu = u - std::floor(u / resolution_) * resolution_;
    const double fv = v - std::floor(v / resolution_) * resolution_;
    const int x0 = int(fu) % resolution_, y0 = int(fv) % resolution_;
    const int x1 = (x0 + 1) % resolution_, y1 = (y0 + 1) % resolution_;
    const double ax = fu - std::floor(fu), ay = fv - std::floor(fv);
    auto at = [&](int x, int y) { return texture_[size_t(y) * resolution_ + x]; };
    return at(x0, y0) * ((1 - ax) * (1 - ay)) + at(x1, y0) * (ax * (1 - ay)) +
           at(x0, y1) * ((1 - ax) * ay) + at(x1, y1) * (ax * ay);
}

Spectrum Backdrop::radiance(const Vec3& p, const std::vector<PointLight>& lights) const {
    const Vec3 d = p - point_;
    const double scale = resolution_ / (2.0 * halfExtent_);
    const Spectrum colour =
        textureAt((d.dot(right_) + halfExtent_) * scale, (halfExtent_ - d.dot(up_)) * scale);
    Spectrum light;
    forEachLight(lights, p, [&](const PointLight& l, const Vec3& toLight, double d2) {
        const double cosine = std::max(0.0, normal_.dot(toLight) / std::sqrt(d2));
        light += l.intensity * ((settings_.ambient + settings_.diffuse * cosine) / d2);
    });
    return colour * light * kInvPi;
}

}  // namespace lobe
