// The model registry: every model by name in the paper's order, clear errors for unknown models,
// parameters and out-of-range values, per-band parsing, and the normative defaults.
#include "core/error.h"
#include "materials/registry.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace lobe {

TEST(Registry, KnowsEveryModelByName) {
    for (const BrdfModelInfo& model : brdfModels()) {
        EXPECT_EQ(&findBrdfModel(model.name), &model);
        const Brdf brdf = model.create(ParamValues(*model.params));
        EXPECT_EQ(std::string(brdfName(brdf)), model.name);
    }
}

// docs/models.md, "The models": the nine specular models numbered 1-9 as in the
// paper (Koldenhof 2003, Table 1 numbering), then the Lambertian term the renderer adds; the CLI,
// `lobe brdf props` and the flux-overlap ranking all iterate this list, so its content and order
// are part of the interface.
TEST(Registry, HoldsTheNineSpecularModelsInThePapersOrderThenLambert) {
    const std::vector<std::string> nine = {"phong",       "strauss",       "schlick_lewis",
                                           "ward",        "cook_torrance", "poulin_fournier",
                                           "he_torrance", "lafortune",     "ashikhmin_shirley"};
    std::vector<std::string> registered;
    for (const BrdfModelInfo& model : brdfModels()) registered.push_back(model.name);
    std::vector<std::string> expected = nine;
    expected.push_back("lambert");
    EXPECT_EQ(registered, expected);
    EXPECT_EQ(specularModelNames(), nine);
}

TEST(Registry, UnknownModelIsAClearError) {
    try {
        makeBrdf("blinn");
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("unknown BRDF model 'blinn'"), std::string::npos);
        EXPECT_NE(std::string(e.what()).find("ward"), std::string::npos);  // lists known models
    }
}

TEST(Registry, UnknownParameterAndOutOfRangeValuesAreErrors) {
    EXPECT_THROW(makeBrdf("ward", {"alpha=0.1"}), Error);
    EXPECT_THROW(makeBrdf("ward", {"alpha_x=-0.1"}), Error);
    EXPECT_THROW(makeBrdf("ward", {"alpha_x"}), Error);
    EXPECT_THROW(makeBrdf("ward", {"alpha_x=abc"}), Error);
    EXPECT_THROW(makeBrdf("ward", {"alpha_x=0.1,0.2"}), Error);
    EXPECT_THROW(makeBrdf("ward", {"alpha_x=nan"}), Error);
    try {
        makeBrdf("cook_torrance", {"m=-1"});
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("cook_torrance.m = -1 is outside its range"),
                  std::string::npos)
            << e.what();
    }
}

TEST(Registry, PerBandValuesAreParsed) {
    const Brdf brdf = makeBrdf("cook_torrance", {"eta=0.16,0.37,1.59", "ks=0.5"});
    const auto& ct = std::get<CookTorrance>(brdf);
    EXPECT_DOUBLE_EQ(ct.eta[0], 0.16);
    EXPECT_DOUBLE_EQ(ct.eta[1], 0.37);
    EXPECT_DOUBLE_EQ(ct.eta[2], 1.59);
    EXPECT_DOUBLE_EQ(ct.ks[2], 0.5);
    EXPECT_DOUBLE_EQ(ct.m[1], 0.08);  // default kept
}

TEST(Registry, DefaultsMatchTheNormativeTable) {
    // docs/models.md, "The models".
    const auto w = std::get<Ward>(makeBrdf("ward"));
    EXPECT_EQ(w.rhoS[0], 0.05);
    EXPECT_EQ(w.alphaX[0], 0.05);
    EXPECT_EQ(w.alphaY[0], 0.3);
    const auto a = std::get<AshikhminShirley>(makeBrdf("ashikhmin_shirley"));
    EXPECT_EQ(a.nu[0], 10.0);
    EXPECT_EQ(a.nv[0], 1000.0);
    const auto l = std::get<Lafortune>(makeBrdf("lafortune"));
    EXPECT_EQ(l.cz[0], 0.95);
    EXPECT_EQ(l.exponent[0], 20.0);
}

}  // namespace lobe
