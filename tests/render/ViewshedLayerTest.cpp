// The "viewshed" layer on lavapipe with validation: an observer west of the fixture mountain
// sees its near slope and not what lies behind the summit, draped green and red on the terrain;
// moving the observer computes again on the same grid, moving it far samples a new grid; bad
// scene objects and a missing DEM are reported with the key or the file.
#include "layers/analysis/ViewshedLayer.h"
#include "tests/render/RenderHelpers.h"
#include "tests/render/SceneGpuTest.h"
#include "tests/render/TerrainFixtures.h"
#include "tests/render/VectorScenes.h"

namespace orbis::test {
namespace {

class ViewshedLayerTest : public SceneGpuTest {};

const char* kAbove = R"({"lon": 6.9, "lat": 46.0, "height": 2000, "heading": 0, "pitch": -89, "range": 160000})";

std::string viewshedLayer(const std::string& extra = "") {
    return R"({"type": "viewshed", "name": "Seen", "dem": )" + jsonString(terrainFixtures().dem) +
           R"(, "observer": [6.55, 46.0], "height": 10, "radius": 50000, "opacity": 1, "seen": [0, 1, 0, 1], "hidden": [1, 0, 0, 1])" + extra + "}";
}

bool green(const uint8_t* p) { return int(p[1]) - std::max(int(p[0]), int(p[2])) > 60; }
bool red(const uint8_t* p) { return int(p[0]) - std::max(int(p[1]), int(p[2])) > 60; }

std::pair<size_t, size_t> greenAndRed(const ImageRgba8& img) {
    size_t g = 0, r = 0;
    for (size_t i = 0; i < size_t(img.width) * img.height; ++i) g += green(&img.pixels[i * 4]), r += red(&img.pixels[i * 4]);
    return {g, r};
}

TEST_F(ViewshedLayerTest, TheNearSlopeIsSeenAndWhatLiesBehindTheSummitIsNot) {
    auto scene = load(vectorSceneJson(kAbove, mountainTerrain() + "," + viewshedLayer(), "2026-06-21T11:00:00Z"));
    ASSERT_TRUE(scene);
    const auto img = renderScene(*scene, 320, 240);
    auto& layer = dynamic_cast<layers::ViewshedLayer&>(*scene->resources()[1].layer);
    ASSERT_TRUE(layer.error().empty()) << layer.error();
    ASSERT_NE(layer.viewshed(), nullptr);
    const auto sight = [&](double lon, double lat) {
        const auto cell = layer.grid()->cellOf(lon, lat);
        return cell ? layer.viewshed()->at(cell->first, cell->second) : globe::Sight::OutOfRange;
    };
    EXPECT_EQ(sight(6.75, 46.0), globe::Sight::Visible) << "the foot of the slope facing the observer";
    EXPECT_EQ(sight(6.9, 46.0), globe::Sight::Hidden) << "the shoulder of the dome hides the slope above it (as the exact sight lines say)";
    EXPECT_EQ(sight(7.12, 46.0), globe::Sight::Hidden) << "behind the summit";
    EXPECT_EQ(sight(7.4, 46.0), globe::Sight::OutOfRange) << "past the radius";
    const auto [g, r] = greenAndRed(img);
    EXPECT_GT(g, img.width * img.height / 50) << "seen ground draped green";
    EXPECT_GT(r, img.width * img.height / 50) << "hidden ground draped red";
    EXPECT_NE(layer.status().find("% of"), std::string::npos) << layer.status();
    EXPECT_EQ(layer.gridsSampled(), 1);

    // A step east on the same grid: computed again, not sampled again.
    ASSERT_TRUE(layer.setParameter("observerLon", 6.6));
    renderScene(*scene, 320, 240);
    EXPECT_EQ(layer.gridsSampled(), 1);
    EXPECT_EQ(layer.computed(), 2);
    // Far away: a new grid around the new place.
    ASSERT_TRUE(layer.setParameter("observerLat", 46.6));
    renderScene(*scene, 320, 240);
    EXPECT_EQ(layer.gridsSampled(), 2);
    EXPECT_EQ(layer.computed(), 3);
    EXPECT_FALSE(layer.setParameter("observerLat", 91.0));
    EXPECT_FALSE(layer.setParameter("nothing", 1.0));

    // Hidden: nothing draped.
    auto hidden = load(vectorSceneJson(kAbove, mountainTerrain() + "," + viewshedLayer(R"(, "visible": false)"), "2026-06-21T11:00:00Z"));
    ASSERT_TRUE(hidden);
    const auto plain = renderScene(*hidden, 320, 240);
    EXPECT_EQ(greenAndRed(plain), (std::pair<size_t, size_t>{0, 0}));
}

TEST_F(ViewshedLayerTest, BadObjectsNameTheKeyAndAMissingDemIsReported) {
    const struct { const char* extra; const char* says; } cases[] = {
        {R"(, "synthetic": 3)", "exactly one of"},
        {R"(, "radius": -5)", "/layers/1/radius"},
        {R"(, "observer": [6.5])", "/layers/1/observer"},
        {R"(, "seen": [2, 0, 0, 1])", "/layers/1/seen"},
        {R"(, "cell": 0.5)", "use larger cells"},
    };
    for (const auto& c : cases) {
        const std::string error = buildError(vectorSceneJson(kAbove, mountainTerrain() + "," + viewshedLayer(c.extra), "2026-06-21T11:00:00Z"));
        ASSERT_FALSE(error.empty()) << c.extra;
        EXPECT_NE(error.find(c.says), std::string::npos) << error;
    }
    const std::string missing = R"({"type": "viewshed", "name": "Seen", "dem": "/nonexistent/dem.tif", "observer": [6.55, 46.0]})";
    auto scene = load(vectorSceneJson(kAbove, mountainTerrain() + "," + missing, "2026-06-21T11:00:00Z"));
    ASSERT_TRUE(scene);
    const auto img = renderScene(*scene, 160, 120);
    auto& layer = dynamic_cast<layers::ViewshedLayer&>(*scene->resources()[1].layer);
    EXPECT_NE(layer.error().find("/nonexistent/dem.tif"), std::string::npos) << layer.error();
    EXPECT_NE(layer.status().find("error"), std::string::npos);
    EXPECT_EQ(greenAndRed(img), (std::pair<size_t, size_t>{0, 0}));
}

}  // namespace
}  // namespace orbis::test
