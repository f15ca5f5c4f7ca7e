#include "volume/gaussian_blur.h"

#include "core/error.h"
#include "volume/grid_world.h"

#include <openvdb/tools/Dense.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <vector>

namespace lobe {
namespace {

std::vector<double> gaussianKernel(double sigma) {
    const int radius = std::max(1, int(std::ceil(4.0 * sigma)));
    std::vector<double> k(2 * radius + 1);
    double sum = 0.0;
    for (int i = -radius; i <= radius; ++i)
        sum += k[i + radius] = std::exp(-0.5 * (i / sigma) * (i / sigma));
    for (double& w : k) w /= sum;
    return k;
}

// Convolves every line of `data` (dims nx×ny×nz, x fastest) along `axis` with `kernel`.
void convolveAxis(std::vector<float>& data, const std::array<int, 3>& n, int axis,
                  const std::vector<double>& kernel) {
    const int radius = int(kernel.size() / 2);
    const int len = n[axis];
    const size_t stride = axis == 0 ? 1 : axis == 1 ? size_t(n[0]) : size_t(n[0]) * n[1];
    const int a1 = axis == 0 ? 1 : 0, a2 = axis == 2 ? 1 : 2;  // the two other axes
    const size_t s1 = a1 == 0 ? 1 : size_t(n[0]);
    const size_t s2 = a2 == 1 ? size_t(n[0]) : size_t(n[0]) * n[1];
    tbb::parallel_for(0, n[a2], [&](int j2) {
        std::vector<double> line(len), out(len);
        for (int j1 = 0; j1 < n[a1]; ++j1) {
            const size_t base = j1 * s1 + j2 * s2;
            for (int i = 0; i < len; ++i) line[i] = data[base + i * stride];
            for (int i = 0; i < len; ++i) {
                double acc = 0.0;
                const int lo = std::max(-radius, -i), hi = std::min(radius, len - 1 - i);
                for (int k = lo; k <= hi; ++k) acc += kernel[k + radius] * line[i + k];
                out[i] = acc;
            }
            for (int i = 0; i < len; ++i) data[base + i * stride] = float(out[i]);
        }
    });
}

}  // namespace

void gaussianBlurDense(std::vector<float>& data, const std::array<int, 3>& dims,
                       const std::array<double, 3>& sigmaVoxels) {
    for (int a = 0; a < 3; ++a)
        if (sigmaVoxels[a] > 0.0) convolveAxis(data, dims, a, gaussianKernel(sigmaVoxels[a]));
}

void gaussianBlurFwhm(Volume& volume, double fwhm) {
    if (!(fwhm >= 0.0) || !std::isfinite(fwhm))
        throw Error(volume.sourcePath + ": blur FWHM must be a finite number >= 0");
    if (fwhm == 0.0) return;
    // The index axes' world directions must be orthogonal for a separable isotropic blur.
    const openvdb::math::Transform& xf = volume.grid->transform();
    openvdb::Vec3d axes[3];
    for (int a = 0; a < 3; ++a) {
        openvdb::Vec3d e(0.0);
        e[a] = 1.0;
        axes[a] =
            gridIndexToWorld(*volume.grid, e) - gridIndexToWorld(*volume.grid, openvdb::Vec3d(0.0));
    }
    for (int a = 0; a < 3; ++a)
        for (int b = a + 1; b < 3; ++b)
            if (std::abs(axes[a].dot(axes[b])) > 1e-6 * axes[a].length() * axes[b].length())
                throw Error(volume.sourcePath +
                            ": cannot blur a volume whose index axes are oblique in world space");

    const std::array<int, 3>& n = volume.dims;
    const openvdb::Coord lo(volume.indexOrigin[0], volume.indexOrigin[1], volume.indexOrigin[2]);
    const openvdb::CoordBBox box(lo, lo + openvdb::Coord(n[0] - 1, n[1] - 1, n[2] - 1));
    // Dense layout with x fastest (LayoutXYZ is z fastest; we index ourselves below).
    std::vector<float> data(size_t(n[0]) * n[1] * n[2], 0.0f);
    {
        auto acc = volume.grid->getConstAccessor();
        for (int k = 0; k < n[2]; ++k)
            for (int j = 0; j < n[1]; ++j)
                for (int i = 0; i < n[0]; ++i)
                    data[(size_t(k) * n[1] + j) * n[0] + i] =
                        acc.getValue(lo + openvdb::Coord(i, j, k));
    }
    const double sigma = fwhm / (2.0 * std::sqrt(2.0 * std::log(2.0)));
    for (int a = 0; a < 3; ++a) convolveAxis(data, n, a, gaussianKernel(sigma / axes[a].length()));

    openvdb::FloatGrid::Ptr blurred = openvdb::FloatGrid::create(0.0f);
    blurred->setTransform(xf.copy());
    if (const auto scale = volume.grid->getMetadata<openvdb::DoubleMetadata>(kMetaWorldScale))
        blurred->insertMeta(kMetaWorldScale, *scale);
    blurred->setName(volume.grid->getName());
    blurred->setGridClass(volume.grid->getGridClass());
    {
        auto acc = blurred->getAccessor();
        for (int k = 0; k < n[2]; ++k)
            for (int j = 0; j < n[1]; ++j)
                for (int i = 0; i < n[0]; ++i) {
                    const float v = data[(size_t(k) * n[1] + j) * n[0] + i];
                    if (v != 0.0f) acc.setValue(lo + openvdb::Coord(i, j, k), v);
                }
    }
    blurred->pruneGrid(0.0f);
    volume.grid = blurred;
}

}  // namespace lobe
