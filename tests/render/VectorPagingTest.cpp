// A paged vector source (FeatureTiles) on lavapipe with validation: it draws what the same
// source read whole draws (Europe, across the antimeridian, around the South Pole, and closer
// than its finest pages), a click reads the feature under it and highlights it, the pages stay
// within their budget, and the scene's paging keys are checked.
#include "layers/vector/VectorLayer.h"
#include "tests/render/RenderHelpers.h"
#include "tests/render/SceneGpuTest.h"
#include "tests/render/VectorScenes.h"

#include "tests/support/GoldenImage.h"
#include "engine/scene/SceneDesc.h"

#include <cmath>
#include <iostream>
#include <set>
#include <filesystem>

namespace orbis::test {
namespace {

const std::string kCountries = std::string(ORBIS_SHARED_DATA_DIR) + "/vector/naturalearth_lowres.shp";

#define REQUIRE_DATA()                                                                                          \
    if (!std::filesystem::exists(kCountries)) GTEST_SKIP() << "../shared/data is absent: no " << kCountries;   \
    if (!std::filesystem::exists(std::string(ORBIS_SOURCE_DIR) + "/assets/generated/world-relief.tif"))         \
    GTEST_SKIP() << "assets/generated not built"

const char* kStyle = R"(, "style": {"color": [1, 0, 0], "width": 2, "fill": [1, 0.9, 0.1], "fillOpacity": 0.5})";

class VectorPaging : public SceneGpuTest {
protected:
    std::unique_ptr<scene::Scene> countries(const std::string& view, const std::string& paging, const char* style = kStyle) {
        return load(vectorSceneJson(view, worldTerrain() + "," + vectorLayerJson("Countries", kCountries, style + paging),
                                    "2026-12-21T12:00:00Z"));
    }
    static layers::VectorLayer& vectorLayer(scene::Scene& scene) {
        return dynamic_cast<layers::VectorLayer&>(*scene.resources()[1].layer);
    }
};

TEST_F(VectorPaging, APagedSourceDrawsWhatTheWholeSourceDraws) {
    REQUIRE_DATA();
    // Level-3 pages (22.5 degrees), so that every view uses pages of several levels, and the
    // closest one tiles finer than the finest page.
    const std::string paged = R"(, "paging": true, "pageLevel": 3)";
    const std::pair<const char*, const char*> views[] = {
        {"europe", R"({"lon": 10, "lat": 48, "range": 5000000})"},
        {"antimeridian", R"({"lon": 180, "lat": -17, "range": 2500000})"},
        {"south_pole", R"({"lon": 0, "lat": -90, "range": 9000000})"},
        {"close", R"({"lon": 6.5, "lat": 46.4, "range": 150000})"},
    };
    for (const auto& [name, view] : views) {
        SCOPED_TRACE(name);
        auto whole = countries(view, R"(, "paging": false)");
        auto pages = countries(view, paged);
        ASSERT_TRUE(whole && pages);
        const auto a = renderScene(*whole, 320, 240), b = renderScene(*pages, 320, 240);
        ASSERT_NE(vectorLayer(*whole).content(), nullptr);
        ASSERT_NE(vectorLayer(*pages).pages(), nullptr);
        EXPECT_EQ(vectorLayer(*pages).content(), nullptr);
        EXPECT_GT(vectorLayer(*pages).pages()->loadedCount(), 0u);
        EXPECT_TRUE(vectorLayer(*pages).pages()->errors().empty());
        // Coarse pages are simplified to half a texel before the painter simplifies: edges may
        // move by a fraction of a pixel, nothing more.
        const size_t total = size_t(a.width) * a.height;
        std::cout << name << ": " << countDifferentPixels(a, b, 24) << " pixels differ by > 24, " << countDifferentPixels(a, b, 96)
                  << " by > 96, of " << total << "\n";
        EXPECT_TRUE(imagesAgree(a, b, std::string("paging_") + name, 96));
        EXPECT_TRUE(imagesAgree(a, b, std::string("paging_") + name, 24, total / 200));
    }
}

TEST_F(VectorPaging, AClickReadsTheFeatureUnderItAndHighlightsIt) {
    REQUIRE_DATA();
    auto scene = countries(R"({"lon": 2.5, "lat": 46.5, "range": 3000000})", R"(, "paging": true, "pageLevel": 4)",
                           R"(, "style": {"color": [0, 0, 1], "width": 1, "fill": [0.1, 0.2, 1], "fillOpacity": 0.5})");
    ASSERT_TRUE(scene);
    const auto before = renderScene(*scene, 320, 240);
    auto& layer = vectorLayer(*scene);
    EXPECT_NE(layer.status().find("paged"), std::string::npos) << layer.status();
    const auto picked = layer.asPickable()->pickAt(2.5, 46.5, 10000.0);
    ASSERT_TRUE(picked.has_value());
    EXPECT_EQ(picked->layer, "Countries / naturalearth_lowres");
    bool france = false;
    for (const auto& [field, value] : picked->fields) france |= field == "name" && value == "France";
    EXPECT_TRUE(france);
    const auto highlighted = renderScene(*scene, 320, 240);
    // France turns yellow (its fill and its outline, over blue before).
    const auto yellow = [](const ImageRgba8& img) {
        size_t n = 0;
        for (size_t i = 0; i < img.pixels.size(); i += 4)
            n += int(img.pixels[i]) > int(img.pixels[i + 2]) + 40 && int(img.pixels[i + 1]) > int(img.pixels[i + 2]) + 40;
        return n;
    };
    EXPECT_GT(yellow(highlighted), yellow(before) + 100);
    EXPECT_FALSE(layer.asPickable()->pickAt(-30.0, 40.0, 10000.0).has_value());   // the Atlantic
    EXPECT_EQ(countDifferentPixels(renderScene(*scene, 320, 240), before, 8), 0u);           // the highlight went
}

TEST_F(VectorPaging, PagesStayWithinTheirBudgetAsTheViewMoves) {
    REQUIRE_DATA();
    auto scene = countries(R"({"lon": 10, "lat": 48, "range": 3000000})", R"(, "paging": true, "pageLevel": 6, "pageBudgetMB": 1)");
    ASSERT_TRUE(scene);
    auto& layer = vectorLayer(*scene);
    uint64_t reads = 0;
    for (const char* view : {R"({"lon": 10, "lat": 48, "range": 3000000})", R"({"lon": 100, "lat": 30, "range": 3000000})",
                             R"({"lon": -70, "lat": -20, "range": 3000000})", R"({"lon": 10, "lat": 48, "range": 3000000})"}) {
        Error error;
        const auto vp = scene::readViewpoint(nlohmann::json::parse(view), "test", "/viewpoint", &error);
        ASSERT_TRUE(vp.has_value());
        scene->camera().setPose(globe::poseFromViewpoint(*vp));
        renderScene(*scene, 320, 240);
        // The budget holds but for the page read last (never dropped while it is being used).
        EXPECT_LE(layer.pages()->bytes(), (1u << 20) + 1024u * 1024u);
        EXPECT_GT(layer.pages()->reads(), reads);
        reads = layer.pages()->reads();
    }
    EXPECT_TRUE(layer.pages()->errors().empty());
}

TEST_F(VectorPaging, LabelsComeFromThePagesInMemoryWithoutOverlapAndStayPut) {
    REQUIRE_DATA();
    const char* labelled = R"(, "style": {"color": [1, 0, 0], "width": 1, "fillOpacity": 0, "label": "{name}"})";
    const char* view = R"({"lon": 10, "lat": 48, "range": 5000000})";
    auto whole = countries(view, R"(, "paging": false)", labelled);
    auto paged = countries(view, R"(, "paging": true, "pageLevel": 3)", labelled);
    ASSERT_TRUE(whole && paged);
    renderScene(*whole, 640, 480);
    renderScene(*paged, 640, 480);
    const auto ids = [](const layers::VectorLayer& layer) {
        std::set<uint64_t> out;
        for (const vector::PlacedLabel& p : layer.labels()->placed()) out.insert(p.id & ((1ull << 40) - 1));   // fid (= index in a shapefile)
        return out;
    };
    const auto& pagedLayer = vectorLayer(*paged);
    ASSERT_NE(pagedLayer.labels(), nullptr);
    const std::set<uint64_t> a = ids(vectorLayer(*whole)), b = ids(pagedLayer);
    ASSERT_GT(a.size(), 10u);
    size_t common = 0;
    for (uint64_t id : b) common += a.contains(id);
    std::cout << "labels: whole " << a.size() << ", paged " << b.size() << ", in both " << common << "\n";
    // A polygon cut by pages is labelled on its largest piece in the finest page: a few labels
    // move or trade places, most are the same.
    EXPECT_GE(common * 10, a.size() * 7);
    EXPECT_NE(pagedLayer.status().find("labels"), std::string::npos) << pagedLayer.status();
    // No two drawn labels overlap.
    const auto placed = pagedLayer.labels()->placed();
    for (size_t i = 0; i < placed.size(); ++i)
        for (size_t j = i + 1; j < placed.size(); ++j)
            EXPECT_FALSE(placed[i].min.x < placed[j].max.x && placed[j].min.x < placed[i].max.x && placed[i].min.y < placed[j].max.y &&
                         placed[j].min.y < placed[i].max.y)
                << i << " and " << j << " overlap";
    // Frames that load nothing new keep the same labels.
    for (int frame = 0; frame < 3; ++frame) {
        renderOnce(*renderer_, *paged);
        EXPECT_EQ(ids(pagedLayer), b);
    }
}

TEST_F(VectorPaging, PagedBuildingsAreMeshedATileAtATimeAsTheWholeSourceIs) {
    // The buildings showcase's city (3000 buildings, generated at build time) on its hills,
    // read whole and paged: the same buildings, each once, the same picture.
    const std::string dir = std::string(ORBIS_SOURCE_DIR) + "/assets/generated/";
    if (!std::filesystem::exists(dir + "city/city.gpkg") || !std::filesystem::exists(dir + "fmv/flight-dem.tif"))
        GTEST_SKIP() << "assets/generated not built";
    const auto city = [&](const std::string& paging) {
        return load(vectorSceneJson(
            R"({"lon": 9.03, "lat": 46.019, "height": 600, "heading": 25, "pitch": -28, "range": 2600})",
            R"({"type": "terrain", "name": "Hills", "elevation": [)" + jsonString(dir + "fmv/flight-dem.tif") +
                R"(], "sky": false, "color": [0.42, 0.5, 0.36]},)" +
                vectorLayerJson("Buildings", dir + "city/city.gpkg",
                                R"(, "style": {"fill": [0.86, 0.8, 0.7], "extrude": "height", "rules": [{"when": {"kind": "tower"}, "fill": [0.9, 0.55, 0.4]}]})" +
                                    paging),
            "2026-06-21T08:00:00Z"));
    };
    auto whole = city(R"(, "paging": false)");
    auto paged = city(R"(, "paging": true)");
    ASSERT_TRUE(whole && paged);
    const auto a = renderScene(*whole, 320, 240), b = renderScene(*paged, 320, 240);
    auto& layer = vectorLayer(*paged);
    ASSERT_NE(layer.pages(), nullptr);
    ASSERT_NE(layer.mesh(), nullptr) << layer.status();
    EXPECT_TRUE(layer.hasMeshRenderer());
    // Every feature is a building: no drape (an empty one would still make the terrain refine
    // to the drape's finest level), as for the whole source.
    EXPECT_EQ(layer.drapeSource(), nullptr);
    EXPECT_EQ(vectorLayer(*whole).drapeSource(), nullptr);
    // Every building in view once: as many triangles as the whole source's (all 3000 are within
    // reach of this view), in several tiles' chunks.
    EXPECT_EQ(layer.mesh()->features, vectorLayer(*whole).mesh()->features);
    EXPECT_EQ(layer.mesh()->triangles, vectorLayer(*whole).mesh()->triangles);
    std::cout << "buildings: " << layer.status() << "\n";
    EXPECT_TRUE(imagesAgree(a, b, "paging_buildings", 24, a.width * a.height / 500));
    // A click on a building tints it (its id by fid agrees between tiles).
    const vector::Feature* building = nullptr;   // one without a courtyard, near the view's centre
    for (const vector::Feature& f : vectorLayer(*whole).content()->layers[0].data.features)
        if (f.parts.size() == 1 && std::abs(f.bounds.west - 9.03) < 0.002 && std::abs(f.bounds.south - 46.019) < 0.002) building = &f;
    ASSERT_NE(building, nullptr);
    const auto picked = layer.asPickable()->pickAt(0.5 * (building->bounds.west + building->bounds.east),
                                                   0.5 * (building->bounds.south + building->bounds.north), 1.0);
    ASSERT_TRUE(picked.has_value());
    EXPECT_EQ(picked->feature, "fid " + std::to_string(building->fid));
    const auto tinted = renderScene(*paged, 320, 240);
    EXPECT_GT(countDifferentPixels(tinted, b, 24), 10u) << "the picked building is tinted";
    // Away and back: the meshes drawn follow the view (those built stay and are drawn again).
    const auto moveTo = [&](const char* view) {
        Error error;
        const auto vp = scene::readViewpoint(nlohmann::json::parse(view), "test", "/viewpoint", &error);
        ASSERT_TRUE(vp.has_value());
        paged->camera().setPose(globe::poseFromViewpoint(*vp));
        renderScene(*paged, 320, 240);
    };
    const uint64_t triangles = layer.mesh()->triangles;
    moveTo(R"({"lon": 12.0, "lat": 46.0, "range": 2600})");
    EXPECT_EQ(layer.mesh()->triangles, 0u) << "nothing of the city in view";
    moveTo(R"({"lon": 9.03, "lat": 46.019, "height": 600, "heading": 25, "pitch": -28, "range": 2600})");
    EXPECT_EQ(layer.mesh()->triangles, triangles);
}

TEST_F(VectorPaging, BadPagingKeysNameTheKey) {
    REQUIRE_DATA();
    for (const char* extra : {R"(, "paging": "maybe")", R"(, "pageLevel": 40)", R"(, "pageBudgetMB": 0)",
                              R"(, "paging": "yes")"}) {
        auto d = scene::parseSceneText(
            vectorSceneJson(R"({"lon": 0, "lat": 0, "range": 1e7})", worldTerrain() + "," + vectorLayerJson("C", kCountries, extra), "2026-01-01T00:00:00Z"),
            "test.json", ".");
        ASSERT_TRUE(d.ok());
        auto s = scene::Scene::build(std::move(d).value(), registry_);
        ASSERT_FALSE(s.ok()) << extra;
        EXPECT_NE(s.message().find("/layers/1/pag"), std::string::npos) << s.message();
    }
}

}  // namespace
}  // namespace orbis::test
