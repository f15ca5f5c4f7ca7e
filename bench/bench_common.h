// What every benchmark program needs, written once: wall and process CPU time, peak memory, the
// image error measure, and a small argv reader. Header-only; the benches' own numbers and
// reports stay in their files.
#pragma once

#include "core/film.h"

#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

namespace lobe::bench {

inline double wallSeconds() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
}

// User + system CPU time of the whole process (all threads), from getrusage: on a shared machine
// it moves less with other processes than wall time does.
inline double cpuSeconds() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
           1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

// Peak resident memory of the process so far, in MB (getrusage ru_maxrss: kilobytes on Linux).
inline double peakRssMb() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return double(u.ru_maxrss) / 1024.0;
}

// Wall and CPU seconds since construction.
struct Stopwatch {
    double wall0 = wallSeconds(), cpu0 = cpuSeconds();
    double wall() const { return wallSeconds() - wall0; }
    double cpu() const { return cpuSeconds() - cpu0; }
};

// RMSE of the band values of an image against a reference over all pixels; with `relative`,
// also that RMSE divided by the reference's mean band value (so it reads as a fraction of the
// image's level; 0 for a black reference).
template <class Pixels>  // std::vector<Spectrum> or FilmPixels (core/film.h)
double rmse(const Pixels& image, const Pixels& reference, double* relative = nullptr) {
    double se = 0.0, mean = 0.0;
    const size_t n = reference.size();
    for (size_t i = 0; i < n; ++i)
        for (int b = 0; b < kBandCount; ++b) {
            const double d = image[i][b] - reference[i][b];
            se += d * d;
            mean += reference[i][b];
        }
    const double count = double(kBandCount) * double(n);
    const double r = n ? std::sqrt(se / count) : 0.0;
    if (relative) *relative = mean > 0.0 ? r / (mean / count) : 0.0;
    return r;
}
// The same for one value per pixel.
inline double rmse(const std::vector<double>& image, const std::vector<double>& reference) {
    double se = 0.0;
    for (size_t i = 0; i < reference.size(); ++i)
        se += (image[i] - reference[i]) * (image[i] - reference[i]);
    return reference.empty() ? 0.0 : std::sqrt(se / double(reference.size()));
}
// The relative RMSE of two films.
inline double relativeRmse(const Film& image, const Film& reference) {
    double relative = 0.0;
    rmse(image.pixels(), reference.pixels(), &relative);
    return relative;
}

// `--name value` options: for (int i = 1; i < argc; ++i) { Args a(argc, argv, i); … }.
struct Args {
    int argc;
    char** argv;
    int& i;
    Args(int c, char** v, int& index) : argc(c), argv(v), i(index) {}
    std::string flag() const { return argv[i]; }
    std::string text() { return i + 1 < argc ? std::string(argv[++i]) : std::string(); }
    int integer() { return std::atoi(text().c_str()); }
    double number() { return std::atof(text().c_str()); }
};

}  // namespace lobe::bench
