// The "overlay" layer on lavapipe with validation: a raster draped over the terrain looks as the
// same file does as the terrain's own imagery; the same picture warped to UTM looks the same
// again; opacity 0 shows the ground; bad objects name the key and a missing file is reported.
#include "layers/analysis/OverlayLayer.h"
#include "tests/render/RenderHelpers.h"
#include "tests/render/SceneGpuTest.h"
#include "tests/render/TerrainFixtures.h"
#include "tests/render/VectorScenes.h"
#include "tests/support/ProcessTempDir.h"

#include <gdal_utils.h>

namespace orbis::test {
namespace {

class OverlayLayerTest : public SceneGpuTest {};

const char* kAbove = R"({"lon": 7.0, "lat": 46.0, "height": 2000, "heading": 0, "pitch": -89, "range": 160000})";

std::string overlay(const std::string& path, const std::string& extra = "") {
    return R"({"type": "overlay", "name": "Result", "path": )" + jsonString(path) + extra + "}";
}

/// Mean absolute difference of two images, per channel, over RGB.
double meanDifference(const ImageRgba8& a, const ImageRgba8& b) {
    double sum = 0.0;
    for (size_t i = 0; i < size_t(a.width) * a.height; ++i)
        for (int c = 0; c < 3; ++c) sum += std::abs(int(a.pixels[i * 4 + c]) - int(b.pixels[i * 4 + c]));
    return sum / (3.0 * double(a.width) * a.height);
}

TEST_F(OverlayLayerTest, ARasterDrapedLooksAsTheTerrainsOwnImageryInAnyCrs) {
    const std::string image = terrainFixtures().image;
    auto asImagery = load(vectorSceneJson(kAbove, mountainTerrain(R"(, "imagery": [)" + jsonString(image) + "]"), "2026-06-21T11:00:00Z"));
    auto asOverlay = load(vectorSceneJson(kAbove, mountainTerrain() + "," + overlay(image, R"(, "opacity": 1)"), "2026-06-21T11:00:00Z"));
    ASSERT_TRUE(asImagery && asOverlay);
    const auto reference = renderScene(*asImagery, 320, 240);
    const auto draped = renderScene(*asOverlay, 320, 240);
    auto& layer = dynamic_cast<layers::OverlayLayer&>(*asOverlay->resources()[1].layer);
    ASSERT_TRUE(layer.error().empty()) << layer.error();
    ASSERT_NE(layer.source(), nullptr);
    EXPECT_NE(layer.status().find("lon 6.0000..8.0000"), std::string::npos) << layer.status();
    const double diff = meanDifference(reference, draped);
    EXPECT_LT(diff, 3.0) << "the overlay differs from the imagery by " << diff << " of 255 on average";

    // The same picture in UTM 32N (warped here): GDAL warps it back to the tiles.
    const auto utm = processTempDir("orbis-overlay-test") / "image-utm32.tif";
    GDALAllRegister();
    GDALDatasetH src = GDALOpen(image.c_str(), GA_ReadOnly);
    ASSERT_NE(src, nullptr);
    const char* argv[] = {"-t_srs", "EPSG:32632", "-r", "bilinear", "-of", "GTiff", nullptr};
    GDALWarpAppOptions* options = GDALWarpAppOptionsNew(const_cast<char**>(argv), nullptr);
    GDALDatasetH warped = GDALWarp(utm.c_str(), nullptr, 1, &src, options, nullptr);
    GDALWarpAppOptionsFree(options);
    ASSERT_NE(warped, nullptr);
    GDALClose(warped);
    GDALClose(src);
    auto asUtm = load(vectorSceneJson(kAbove, mountainTerrain() + "," + overlay(utm.string()), "2026-06-21T11:00:00Z"));
    ASSERT_TRUE(asUtm);
    const auto fromUtm = renderScene(*asUtm, 320, 240);
    const double utmDiff = meanDifference(reference, fromUtm);
    EXPECT_LT(utmDiff, 6.0) << "warped twice (bilinear), the picture differs by " << utmDiff << " of 255 on average";

    // Opacity 0: the bare ground.
    auto bare = load(vectorSceneJson(kAbove, mountainTerrain(), "2026-06-21T11:00:00Z"));
    ASSERT_TRUE(bare);
    const auto ground = renderScene(*bare, 320, 240);
    ASSERT_TRUE(layer.setParameter("opacity", 0.0));
    EXPECT_FALSE(layer.setParameter("opacity", 1.5));
    const auto clear = renderScene(*asOverlay, 320, 240);
    EXPECT_LT(meanDifference(ground, clear), 1.0);
    EXPECT_GT(meanDifference(ground, draped), 20.0) << "the overlay shows";
}

TEST_F(OverlayLayerTest, AnOverlayAddedWhileTheSceneIsShownIsDrapedOnTheLoadedTiles) {
    const std::string image = terrainFixtures().image;
    auto reference = load(vectorSceneJson(kAbove, mountainTerrain() + "," + overlay(image), "2026-06-21T11:00:00Z"));
    auto scene = load(vectorSceneJson(kAbove, mountainTerrain(), "2026-06-21T11:00:00Z"));
    ASSERT_TRUE(reference && scene);
    const auto expected = renderScene(*reference, 320, 240);
    const auto bare = renderScene(*scene, 320, 240);
    scene::LayerDesc added;
    added.type = "overlay";
    added.name = "Result";
    added.settings = {{"path", image}};
    auto r = scene->addLayer(added, registry_);
    ASSERT_TRUE(r) << r.message();
    const auto after = renderScene(*scene, 320, 240);
    EXPECT_GT(meanDifference(bare, after), 20.0) << "the overlay shows";
    EXPECT_LT(meanDifference(expected, after), 1.0) << "as it does when the scene starts with it";
}

TEST_F(OverlayLayerTest, BadObjectsNameTheKeyAndAMissingFileIsReported) {
    const struct { const char* extra; const char* says; } cases[] = {
        {R"(, "opacity": 2)", "/layers/1/opacity"},
        {R"(, "bands": [0])", "/layers/1/bands"},
        {R"(, "scale": [5, 1])", "/layers/1/scale"},
        {R"(, "colour": 1)", "unknown key 'colour'"},
    };
    for (const auto& c : cases) {
        const std::string error = buildError(vectorSceneJson(kAbove, mountainTerrain() + "," + overlay(terrainFixtures().image, c.extra), "2026-06-21T11:00:00Z"));
        ASSERT_FALSE(error.empty()) << c.extra;
        EXPECT_NE(error.find(c.says), std::string::npos) << error;
    }
    auto missing = load(vectorSceneJson(kAbove, mountainTerrain() + "," + overlay("/no/such/result.tif"), "2026-06-21T11:00:00Z"));
    ASSERT_TRUE(missing);
    renderScene(*missing, 160, 120);
    auto& layer = dynamic_cast<layers::OverlayLayer&>(*missing->resources()[1].layer);
    EXPECT_NE(layer.error().find("/no/such/result.tif"), std::string::npos) << layer.error();
    EXPECT_EQ(layer.status().rfind("error: ", 0), 0u) << layer.status();
}

}  // namespace
}  // namespace orbis::test
