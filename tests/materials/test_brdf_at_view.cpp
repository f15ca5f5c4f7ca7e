// ModelAtView (materials/brdf.h): f(·, wo) for one viewer direction and several lights equals
// evalBrdf(brdf, wi, wo) bit for bit (tolerance 0) for every model, and the per-band sharing
// inside Ward, Ashikhmin–Shirley and He–Torrance (one exp / sqrt / D per distinct band
// parameters) gives each band the value of a model whose every band has that band's parameters.
#include "materials/he_torrance_table.h"
#include "materials/registry.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

namespace lobe {
namespace {

Vec3 direction(double thetaDeg, double phiDeg) {
    const double t = thetaDeg * kPi / 180.0, p = phiDeg * kPi / 180.0;
    return Vec3(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t));
}

bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Viewer directions from normal to grazing, light directions around them: near-mirror,
// retro-reflective, grazing, and below the horizon (f = 0).
std::vector<Vec3> viewers() {
    std::vector<Vec3> v;
    for (double t : {0.0, 20.0, 45.0, 70.0, 85.0, 89.5})
        for (double p : {0.0, 100.0, 230.0}) v.push_back(direction(t, p));
    return v;
}
std::vector<Vec3> lights() {
    std::vector<Vec3> v;
    for (double t : {0.0, 10.0, 35.0, 60.0, 80.0, 88.0, 95.0})
        for (double p : {5.0, 90.0, 180.0, 275.0}) v.push_back(direction(t, p));
    return v;
}

// Settings per model: the defaults, and per-band values with two equal bands and one different
// (A A B) and with the different one in the middle (A B A), so that sharing by the band before
// and recomputing are both exercised.
std::vector<std::vector<std::string>> settingsFor(const std::string& model) {
    if (model == "ward")
        return {{}, {"alpha_x=0.05,0.05,0.2", "alpha_y=0.3,0.3,0.1"}, {"alpha_x=0.1,0.3,0.1"}};
    if (model == "ashikhmin_shirley")
        return {{}, {"nu=10,10,200", "nv=1000,1000,50"}, {"nu=100,10,100"}};
    if (model == "he_torrance")
        return {{},
                {"sigma0_over_lambda=1,1,0.3", "tau_over_lambda=10,10,3"},
                {"sigma0_over_lambda=0.5,2,0.5", "eta=1.6,1.4,1.6"}};
    if (model == "phong")  // whole (repeated squaring), fractional, past 1024, and per band
        return {{}, {"exponent=30"}, {"exponent=12.5"}, {"exponent=2000"}, {"exponent=10,10,40"}};
    return {{}};
}

TEST(ModelAtView, EqualsEvalBrdfBitForBitForEveryModel) {
    const std::vector<Vec3> wos = viewers(), wis = lights();
    int compared = 0;
    for (const BrdfModelInfo& info : brdfModels())
        for (const std::vector<std::string>& settings : settingsFor(info.name)) {
            const Brdf brdf = makeBrdf(info.name, settings);
            for (const Vec3& wo : wos)
                // One view per viewer, reused across all lights.
                visitAtView(brdf, wo, [&](auto& view) {
                    for (const Vec3& wi : wis) {
                        const Spectrum a = view.eval(wi), b = evalBrdf(brdf, wi, wo);
                        for (int band = 0; band < kBandCount; ++band)
                            EXPECT_TRUE(sameBits(a[band], b[band]))
                                << info.name << " band " << band << ": " << a[band] << " vs "
                                << b[band];
                        ++compared;
                    }
                });
        }
    EXPECT_GT(compared, 10 * 18 * 28);
}

// He–Torrance read from its table (he_torrance_table.h), as full renders and previews read it.
TEST(ModelAtView, HeTorranceWithATableEqualsEvalBrdf) {
    HeTorrance model = std::get<HeTorrance>(makeBrdf("he_torrance", {}));
    model.table = HeTorranceTable::build(model);
    ASSERT_TRUE(model.table);
    const Brdf brdf = model;
    for (const Vec3& wo : viewers())
        visitAtView(brdf, wo, [&](auto& view) {
            for (const Vec3& wi : lights()) {
                const Spectrum a = view.eval(wi), b = evalBrdf(brdf, wi, wo);
                for (int band = 0; band < kBandCount; ++band)
                    EXPECT_TRUE(sameBits(a[band], b[band])) << a[band] << " vs " << b[band];
            }
        });
}

// "k=a,b,c" → "k=x,x,x" with x the value of `band`.
std::vector<std::string> oneBand(const std::vector<std::string>& settings, int band) {
    std::vector<std::string> out;
    for (const std::string& s : settings) {
        const size_t eq = s.find('=');
        std::vector<std::string> parts;
        size_t start = eq + 1;
        for (size_t comma; (comma = s.find(',', start)) != std::string::npos; start = comma + 1)
            parts.push_back(s.substr(start, comma - start));
        parts.push_back(s.substr(start));
        const std::string& v = parts.size() == 1 ? parts[0] : parts[size_t(band)];
        out.push_back(s.substr(0, eq + 1) + v + "," + v + "," + v);
    }
    return out;
}

TEST(BrdfAtView, SharedBandsEqualSingleParameterModels) {
    const std::vector<Vec3> wos = viewers(), wis = lights();
    for (const std::string model : {"ward", "ashikhmin_shirley", "he_torrance"})
        for (const std::vector<std::string>& settings : settingsFor(model)) {
            if (settings.empty()) continue;
            const Brdf mixed = makeBrdf(model, settings);
            for (int band = 0; band < kBandCount; ++band) {
                const Brdf single = makeBrdf(model, oneBand(settings, band));
                for (const Vec3& wo : wos)
                    for (const Vec3& wi : wis) {
                        const double a = evalBrdf(mixed, wi, wo)[band];
                        const double b = evalBrdf(single, wi, wo)[band];
                        EXPECT_TRUE(sameBits(a, b))
                            << model << " band " << band << ": " << a << " vs " << b;
                    }
            }
        }
}

}  // namespace
}  // namespace lobe
