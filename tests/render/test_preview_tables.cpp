// He–Torrance tables in renders (render/scene.cpp): with `--preview` (SceneSpec::previewBrdfTables)
// He–Torrance objects read the preview table of their parameters (materials/he_torrance_table.h),
// full renders read the fine table, and `--exact-brdf` (SceneSpec::exactBrdf) keeps the series.
// The flags are set by RenderOverrides only; each tabled image differs from the series' by at
// most its table's stated bound, errorBound·M per band and light (M the table's peak f·cos θi)
// times the light's I/d² and kd-free colour; and it is the same for 1 and 2 threads.
//
// Set-up (as tests/render/test_render_cost.cpp): a ramp whose iso-surface is a tilted plane with
// normal ∝ (0.75, 0, 1), seen from above, lit by two lights, white, Lambert kd 0.
#include "materials/he_torrance_table.h"
#include "render/render_scene.h"
#include "render/scene_file.h"
#include "render/scene_overrides.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <variant>
#include <vector>

namespace lobe {
namespace {

namespace fs = std::filesystem;

fs::path dataDir() {
    static const fs::path dir = [] {
        const fs::path d =
            fs::temp_directory_path() / ("lobe_preview_tables_" + std::to_string(getpid()));
        fs::create_directories(d);
        std::vector<float> ramp(4 * 4 * 360);
        for (int k = 0; k < 360; ++k)
            for (int j = 0; j < 4; ++j)
                for (int i = 0; i < 4; ++i) ramp[(k * 4 + j) * 4 + i] = float(k + 0.75 * i + 1.0);
        std::ofstream(d / "ramp.raw", std::ios::binary)
            .write(reinterpret_cast<const char*>(ramp.data()), std::streamsize(ramp.size() * 4));
        return d;
    }();
    return dir;
}

// One light near the mirror direction of the view (the highlight), one at 60° off it.
SceneSpec scene() {
    return parseScene(
        R"({"image": {"width": 24, "height": 16, "samples_per_pixel": 2},
            "camera": {"position": [1.5, 1.5, 200], "target": [1.5, 1.5, 0], "up": [0, 1, 0],
                       "fov_deg": 0.5},
            "lights": [{"position": [-150, 1.5, 180], "intensity": 1e5},
                       {"position": [300, 40, 120], "intensity": 1e5}],
            "backdrop": {"enabled": false},
            "objects": [{"name": "plane", "kind": "isosurface", "source": {"path": "ramp.raw",
              "dims": [4, 4, 360], "type": "float32"}, "transform": {"translate": [0, 0, -120]},
              "iso": 142.425, "color": [1, 1, 1], "kd": 0, "brdf": {"model": "he_torrance"}}]})",
        dataDir().string(), "preview-tables");
}

Film render(const SceneSpec& spec, int threads) {
    RenderOptions o;
    o.progress = false;
    o.threads = threads;
    return RenderScene(spec, false).render(o);
}

TEST(PreviewTables, OnlyPreviewsSetTheFlag) {
    SceneSpec spec = scene();
    EXPECT_FALSE(spec.previewBrdfTables);
    RenderOverrides full;
    full.width = 64;
    full.apply(spec);
    EXPECT_FALSE(spec.previewBrdfTables);
    RenderOverrides preview;
    preview.preview = true;
    preview.apply(spec);
    EXPECT_TRUE(spec.previewBrdfTables);
    EXPECT_FALSE(spec.exactBrdf);
    RenderOverrides exact;
    exact.exactBrdf = true;
    exact.apply(spec);
    EXPECT_TRUE(spec.exactBrdf);
}

// The image with tables (`tabled`) against the series' image, and thread independence.
void expectWithinBound(SceneSpec tabled, const HeTorranceTable::Resolution& res) {
    SceneSpec exactSpec = scene();
    exactSpec.exactBrdf = true;
    const Film exact = render(exactSpec, 2);
    const Film approx = render(tabled, 2);
    const Film approx1 = render(tabled, 1);
    const auto table = HeTorranceTable::build(HeTorrance{}, res);
    ASSERT_TRUE(table);
    // Σ over lights of I/d² at the plane (z ≈ 20 at x = 1.5 … the plane's points differ by far
    // less than the lights' distances; the bound below uses the nearest distance, 0.99 × each).
    double irradianceScale = 0.0;
    for (const PointLight& l : exactSpec.lights) {
        const double d = (l.position - Vec3(1.5, 1.5, 20.0)).length() * 0.99;
        irradianceScale += l.intensity[0] / (d * d);
    }
    ASSERT_EQ(exact.pixels().size(), approx.pixels().size());
    size_t differing = 0;
    double largest = 0.0, brightest = 0.0;
    for (size_t i = 0; i < exact.pixels().size(); ++i)
        for (int b = 0; b < kBandCount; ++b) {
            const double diff = std::abs(approx.pixels()[i][b] - exact.pixels()[i][b]);
            differing += diff != 0.0;
            largest = std::max(largest, diff / (table->peak()[b] * irradianceScale));
            brightest = std::max(brightest, exact.pixels()[i][b]);
            EXPECT_EQ(approx.pixels()[i][b], approx1.pixels()[i][b]);
        }
    std::printf("largest difference %.3g of M·ΣI/d² (bound %g); brightest pixel %.3g\n", largest,
                res.errorBound, brightest);
    EXPECT_GT(brightest, 0.0);
    EXPECT_GT(differing, 0u);  // the table is used
    EXPECT_LE(largest, res.errorBound);
}

TEST(PreviewTables, PreviewImageWithinTheTablesBoundAndThreadIndependent) {
    SceneSpec previewSpec = scene();
    previewSpec.previewBrdfTables = true;
    expectWithinBound(previewSpec, HeTorranceTable::kPreview);
}

TEST(PreviewTables, FullRenderReadsTheFineTableWithinItsBound) {
    expectWithinBound(scene(), HeTorranceTable::kFine);
}

}  // namespace
}  // namespace lobe
