#include "materials/brdf_common.h"

#include <gtest/gtest.h>

#include <cmath>

namespace lobe {

// Normal incidence identity of docs/models.md: F(1) = ((η−1)² + κ²)/((η+1)² + κ²).
TEST(Fresnel, NormalIncidenceIdentity) {
    const double cases[][2] = {{1.6, 0.2}, {1.5, 0.0}, {0.16, 3.5}, {2.5, 0.0}, {1.0, 0.0}};
    for (const auto& c : cases) {
        const double eta = c[0], kappa = c[1];
        const double expected =
            ((eta - 1) * (eta - 1) + kappa * kappa) / ((eta + 1) * (eta + 1) + kappa * kappa);
        EXPECT_NEAR(fresnelExact(eta, kappa, 1.0), expected, 1e-14) << eta << "+i" << kappa;
    }
}

// Dielectric η = 1.5 against the s/p-polarised Fresnel equations averaged, computed by hand:
// at θ = 45°: cos θt = sqrt(1 − sin²θ/η²) = sqrt(1 − 0.5/2.25) = 0.881917;
// rs = (cos θ − η cos θt)/(cos θ + η cos θt) = (0.707107 − 1.322876)/(0.707107 + 1.322876)
//    = −0.303337, Rs = 0.092013; rp = (η cos θ − cos θt)/(η cos θ + cos θt)
//    = (1.060660 − 0.881917)/(1.060660 + 0.881917) = 0.092013, Rp = 0.008466;
// F = (Rs + Rp)/2 = 0.050240.
TEST(Fresnel, DielectricAt45DegreesMatchesPolarisedAverage) {
    EXPECT_NEAR(fresnelExact(1.5, 0.0, std::cos(kPi / 4)), 0.050240, 2e-6);
}

TEST(Fresnel, GrazingIsTotalAndValuesStayInUnitInterval) {
    EXPECT_NEAR(fresnelExact(1.6, 0.2, 0.0), 1.0, 1e-12);
    for (double c = 0.0; c <= 1.0; c += 0.001) {
        for (double eta : {0.2, 1.0, 1.6, 4.0}) {
            const double f = fresnelExact(eta, 0.2, c);
            ASSERT_TRUE(std::isfinite(f));
            ASSERT_GE(f, 0.0);
            ASSERT_LE(f, 1.0);
        }
    }
}

TEST(Fresnel, SchlickEndpoints) {
    EXPECT_DOUBLE_EQ(fresnelSchlick(0.05, 1.0), 0.05);
    EXPECT_DOUBLE_EQ(fresnelSchlick(0.05, 0.0), 1.0);
    EXPECT_NEAR(fresnelSchlick(0.05, 0.5), 0.05 + 0.95 / 32.0, 1e-15);
}

TEST(PowerOf, WholeExponentsMatchStdPowAndOthersAreStdPow) {
    // Repeated squaring for whole exponents 0…1024 against std::pow, x over [0, 1] (cos α) and
    // a little above; a fractional or out-of-range exponent is std::pow itself.
    for (int e = 0; e <= 1024; e += (e < 70 ? 1 : 37))
        for (int i = 0; i <= 200; ++i) {
            const double x = i / 180.0;
            const double expected = std::pow(x, double(e));
            EXPECT_NEAR(powerOf(x, double(e)), expected, 1e-13 * expected + 1e-300)
                << "x " << x << " e " << e;
        }
    EXPECT_EQ(powerOf(0.0, 0.0), 1.0);
    EXPECT_EQ(powerOf(0.0, 30.0), 0.0);
    EXPECT_EQ(powerOf(0.7, 10.5), std::pow(0.7, 10.5));
    EXPECT_EQ(powerOf(0.7, 2000.0), std::pow(0.7, 2000.0));
}

}  // namespace lobe
