#include "render/gallery.h"

#include "core/camera.h"
#include "core/error.h"
#include "core/pixel_loop.h"
#include "figure/image_text.h"
#include "materials/registry.h"
#include "render/shading.h"

#include <map>

namespace lobe {
namespace {

// Unit sphere at the origin: nearest t > 0 of |o + t d|² = 1 (d unit), or -1.
double intersectUnitSphere(const Ray& ray) {
    const double b = ray.o.dot(ray.d);
    const double c = ray.o.length2() - 1.0;
    const double disc = b * b - c;
    if (disc < 0.0) return -1.0;
    const double root = std::sqrt(disc);
    const double t0 = -b - root;
    if (t0 > 0.0) return t0;
    const double t1 = -b + root;
    return t1 > 0.0 ? t1 : -1.0;
}

// "ward.alpha_x=0.1" settings grouped per model name.
std::map<std::string, std::vector<std::string>> groupSettings(const std::vector<std::string>& all) {
    std::map<std::string, std::vector<std::string>> grouped;
    for (const std::string& s : all) {
        const auto dot = s.find('.');
        if (dot == std::string::npos || dot == 0)
            throw Error("--set: expected MODEL.key=value, got '" + s + "'");
        findBrdfModel(s.substr(0, dot));  // unknown model → error now
        grouped[s.substr(0, dot)].push_back(s.substr(dot + 1));
    }
    return grouped;
}

}  // namespace

Gallery renderGallery(const GalleryOptions& options) {
    if (options.cellSize < 16 || options.cellSize > 4096)
        throw Error("gallery: --cell must be in [16, 4096], got " +
                    std::to_string(options.cellSize));
    if (options.samplesPerPixel < 1 || options.samplesPerPixel > 4096)
        throw Error("gallery: --spp must be in [1, 4096]");

    const auto settings = groupSettings(options.settings);
    std::vector<Material> materials;
    Gallery gallery;
    gallery.cellSize = options.cellSize;
    for (const std::string& name : specularModelNames()) {
        auto it = settings.find(name);
        Material m;
        m.specular = makeBrdf(name, it == settings.end() ? std::vector<std::string>{} : it->second);
        materials.push_back(m);
        gallery.labels.push_back(findBrdfModel(name).title);
    }
    const int rows = int((materials.size() + gallery.columns - 1) / gallery.columns);
    gallery.film = Film(gallery.columns * options.cellSize, rows * options.cellSize);

    // Camera and lights of the flux-overlap test, so the gallery shows the lobes it measures; the
    // sphere sits slightly above the cell centre to leave room for the label.
    const PinholeCamera camera(Vec3(0, -0.18, 4), Vec3(0, -0.18, 0), Vec3(0, 1, 0), 36.0, 1.0);
    const std::vector<PointLight> lights = {
        {Vec3(-3, 3, 3), Spectrum(options.lightIntensity)},
        {Vec3(3, 2, 3), Spectrum(options.lightIntensity)},
        {Vec3(0, -3, 2.5), Spectrum(options.lightIntensity)},
    };
    const int cell = options.cellSize;

    SchedulerOptions scheduler;
    scheduler.threads = options.threads;
    scheduler.progress = options.progress;
    scheduler.label = "gallery";
    const PixelSampling sampling{options.samplesPerPixel, options.seed};
    forEachPixel(gallery.film.width(), gallery.film.height(), sampling, scheduler,
                 [&](const PixelSamples& samples) {
                     const int x = samples.x(), y = samples.y();
                     const size_t index = size_t(y / cell) * gallery.columns + x / cell;
                     gallery.film.at(x, y) = samples.mean([&](const Vec2& j, Rng&) {
                         if (index >= materials.size()) return Spectrum(0.0);
                         const double u = (x % cell + j.x) / cell, v = (y % cell + j.y) / cell;
                         const Ray ray = camera.generateRay(u, v);
                         const double t = intersectUnitSphere(ray);
                         if (t < 0.0)
                             return Spectrum(0.02 + 0.03 * (1.0 - v));  // dim gradient backdrop
                         const Vec3 p = ray.at(t);
                         const Vec3 n = normalized(p);
                         // Tangent field of the flux-overlap test: world y projected, world x
                         // fallback.
                         const Frame frame =
                             Frame::fromNormalAndAxis(n, Vec3(0, 1, 0), Vec3(1, 0, 0));
                         return directLighting(materials[index], frame, p, -ray.d, lights);
                     });
                 });
    return gallery;
}

RgbImage labelledGalleryImage(const Gallery& gallery) {
    RgbImage image = filmToRgb(gallery.film);
    const int cell = gallery.cellSize;
    const int size = std::max(10, cell / 14);
    for (size_t i = 0; i < gallery.labels.size(); ++i) {
        const int cx = int(i % gallery.columns) * cell + cell / 2;
        const int cy = int(i / gallery.columns) * cell + cell - size / 2 - 2;
        drawText(image, cx, cy, gallery.labels[i], size, {0.9f, 0.9f, 0.9f}, true);
    }
    return image;
}

}  // namespace lobe
