#include "layers/vector/FeatureTiles.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <thread>

namespace orbis::vector {
namespace {

namespace fs = std::filesystem;
using globe::TileKey;

const fs::path kCountries = fs::path(ORBIS_SHARED_DATA_DIR) / "vector" / "naturalearth_lowres.shp";

#define REQUIRE_COUNTRIES() \
    if (!fs::exists(kCountries)) GTEST_SKIP() << "../shared/data is absent: no " << kCountries

FeatureTilesOptions countries() {
    FeatureTilesOptions o;
    o.content.read.source = kCountries.string();
    o.pageLevel = 4;
    return o;
}

globe::GeoExtent grownExtent(const FeatureTilesOptions& o, const TileKey& key) {
    const globe::GeoExtent e = key.extent();
    const double m = o.margin * key.sizeDeg();
    return {e.west - m, e.south - m, e.east + m, e.north + m};
}

TEST(FeatureTiles, APageHoldsItsFeaturesClippedToItsGrownTileAndIsReadOnce) {
    REQUIRE_COUNTRIES();
    FeatureTiles tiles(countries());
    const TileKey europe = TileKey::containing(10.0, 50.0, 3);
    auto page = tiles.acquire(europe);
    ASSERT_TRUE(page) << page.message();
    const VectorContent& content = *(*page)->content;
    ASSERT_EQ(content.layers.size(), 1u);
    const std::vector<Feature>& features = content.layers[0].data.features;
    EXPECT_GT(features.size(), 5u);
    EXPECT_LT(features.size(), 60u);
    const globe::GeoExtent g = grownExtent(tiles.options(), europe);
    for (const Feature& f : features) {
        for (const glm::dvec3& c : f.coords) ASSERT_TRUE(c.x >= g.west && c.x <= g.east && c.y >= g.south && c.y <= g.north);
        // Tight bounds (the drape culls by them), not the page's box.
        EXPECT_LE(f.bounds.east - f.bounds.west, g.east - g.west);
    }
    EXPECT_EQ(tiles.bytes(), (*page)->bytes);
    EXPECT_GT(tiles.bytes(), 1000u);
    // Asked again: the same page, no new read.
    auto again = tiles.acquire(europe);
    ASSERT_TRUE(again);
    EXPECT_EQ(again->get(), page->get());
    EXPECT_EQ(tiles.reads(), 1u);
}

TEST(FeatureTiles, TilesFinerThanThePageLevelShareTheirAncestorsPageWithEveryVertex) {
    REQUIRE_COUNTRIES();
    FeatureTiles tiles(countries());
    const TileKey fine = TileKey::containing(2.35, 48.85, 9);
    EXPECT_EQ(tiles.pageFor(fine), fine.ancestor(4));
    EXPECT_EQ(tiles.pageFor(fine.ancestor(2)), fine.ancestor(2));
    auto page = tiles.acquire(fine);
    ASSERT_TRUE(page);
    EXPECT_EQ((*page)->key, fine.ancestor(4));
    ASSERT_TRUE(tiles.acquire(TileKey::containing(2.5, 48.9, 10)));
    EXPECT_EQ(tiles.reads(), 1u);
    // A coarse page is simplified for its texel: the world at level 0 has far fewer vertices
    // than what the countries hold.
    auto world = tiles.acquire(TileKey{0, 0, 0});
    auto whole = loadVectorContent(tiles.options().content);
    ASSERT_TRUE(world && whole);
    EXPECT_LT((*world)->content->vertexCount, (*whole)->vertexCount / 2);
    EXPECT_GT((*world)->content->featureCount, 20u);
}

TEST(FeatureTiles, APageAcrossTheAntimeridianHoldsBothSidesOnceEach) {
    REQUIRE_COUNTRIES();
    FeatureTiles tiles(countries());
    // The level-4 tile west of 180 at Fiji: its margin reaches past the antimeridian.
    const TileKey fiji = TileKey::containing(179.0, -17.0, 4);
    auto page = tiles.acquire(fiji);
    ASSERT_TRUE(page) << page.message();
    const std::vector<Feature>& features = (*page)->content->layers[0].data.features;
    std::set<int64_t> fids;
    bool pastTheAntimeridian = false;
    const globe::GeoExtent g = grownExtent(tiles.options(), fiji);
    for (const Feature& f : features) {
        EXPECT_TRUE(fids.insert(f.fid).second) << "fid " << f.fid << " twice";
        for (const glm::dvec3& c : f.coords) {
            ASSERT_TRUE(c.x >= g.west && c.x <= g.east) << c.x;
            pastTheAntimeridian |= c.x > 180.0;
        }
    }
    EXPECT_TRUE(pastTheAntimeridian);   // Fiji's eastern islands, unwrapped
}

TEST(FeatureTiles, PastTheBudgetTheLeastRecentlyUsedPagesGoAndAreReadAgain) {
    REQUIRE_COUNTRIES();
    FeatureTilesOptions o = countries();
    o.budgetBytes = 1;   // only the page just read stays
    FeatureTiles tiles(o);
    const TileKey a = TileKey::containing(10.0, 50.0, 3), b = TileKey::containing(-60.0, -10.0, 3);
    auto held = tiles.acquire(a);
    ASSERT_TRUE(held);
    ASSERT_TRUE(tiles.acquire(b));
    EXPECT_EQ(tiles.loadedCount(), 1u);
    EXPECT_EQ(tiles.bytes(), (*tiles.acquire(b))->bytes);
    EXPECT_FALSE((*held)->content->layers[0].data.features.empty());   // a holder keeps its page
    ASSERT_TRUE(tiles.acquire(a));
    EXPECT_EQ(tiles.reads(), 3u);
}

TEST(FeatureTiles, ThreadsAskingForOnePageShareOneRead) {
    REQUIRE_COUNTRIES();
    FeatureTiles tiles(countries());
    const TileKey k = TileKey::containing(100.0, 30.0, 3);
    std::atomic<int> ok{0};
    std::vector<std::thread> threads;
    for (int i = 0; i < 6; ++i)
        threads.emplace_back([&] { ok += tiles.acquire(k) ? 1 : 0; });
    for (std::thread& t : threads) t.join();
    EXPECT_EQ(ok.load(), 6);
    EXPECT_EQ(tiles.reads(), 1u);
    EXPECT_EQ(tiles.loaded().size(), 1u);
}

TEST(FeatureTiles, AFailedPageSaysWhyAndIsNotReadAgain) {
    FeatureTilesOptions o;
    o.content.read.source = "/nonexistent/roads.gpkg";
    FeatureTiles tiles(o);
    const TileKey k = TileKey::containing(0.0, 0.0, 2);
    auto page = tiles.acquire(k);
    ASSERT_FALSE(page);
    EXPECT_NE(page.message().find("/nonexistent/roads.gpkg: no such file"), std::string::npos) << page.message();
    ASSERT_EQ(tiles.errors().size(), 1u);
    EXPECT_NE(tiles.errors()[0].find("feature tile"), std::string::npos) << tiles.errors()[0];
    EXPECT_FALSE(tiles.acquire(k));
    EXPECT_EQ(tiles.reads(), 1u);
}

TEST(FeatureTiles, ABadRuleFieldIsAnErrorOfEveryPage) {
    REQUIRE_COUNTRIES();
    FeatureTilesOptions o = countries();
    auto style = VectorStyle::read(nullptr, "scene.json", "/layers/0/style");
    ASSERT_TRUE(style);
    nlohmann::json j = {{"label", "{no_such_field}"}};
    auto bad = VectorStyle::read(&j, "scene.json", "/layers/0/style");
    ASSERT_TRUE(bad);
    o.content.style = *bad;
    FeatureTiles tiles(o);
    auto page = tiles.acquire(TileKey::containing(10.0, 50.0, 3));
    ASSERT_FALSE(page);
    EXPECT_NE(page.message().find("no_such_field"), std::string::npos) << page.message();
}

TEST(FeatureTiles, TilesCoarserThanTheSourceShareOneOverviewPage) {
    REQUIRE_COUNTRIES();
    // Only Switzerland (about 4.6 by 2 degrees): the level-5 tile around it (5.6 degrees) holds
    // it whole with its margin, a level-6 one does not; every coarser tile takes that page.
    FeatureTilesOptions o = countries();
    o.pageLevel = 6;
    o.content.read.where = "name = 'Switzerland'";
    auto swiss = readVector(o.content.read);   // (OGR's extent of a shapefile ignores the where filter)
    ASSERT_TRUE(swiss) << swiss.message();
    o.sourceBounds = swiss->layers[0].bounds;
    FeatureTiles tiles(o);
    const TileKey overview = tiles.pageFor(TileKey{0, 1, 0});
    EXPECT_EQ(overview.level, 5u);
    for (uint32_t level = 0; level <= overview.level; ++level)
        EXPECT_EQ(tiles.pageFor(TileKey::containing(8.0, 46.8, level)), overview) << level;
    // Finer tiles have their own pages.
    EXPECT_EQ(tiles.pageFor(TileKey::containing(8.0, 46.8, 6)).level, 6u);
    for (uint32_t level = 0; level <= overview.level; ++level) ASSERT_TRUE(tiles.acquire(TileKey::containing(8.0, 46.8, level)));
    EXPECT_EQ(tiles.reads(), 1u);
    auto page = tiles.acquire(TileKey{0, 0, 0});
    ASSERT_TRUE(page);
    EXPECT_EQ((*page)->content->featureCount, 1u);
}

TEST(FeatureTiles, LabelledFeaturesTakeEachFeatureOnceFromTheFinestPage) {
    REQUIRE_COUNTRIES();
    FeatureTiles tiles(countries());
    auto coarse = tiles.acquire(TileKey::containing(10.0, 50.0, 2));
    auto fine = tiles.acquire(TileKey::containing(10.0, 50.0, 3));
    ASSERT_TRUE(coarse && fine);
    nlohmann::json j = {{"label", "{name}"}, {"rules", {{{"when", {{"name", "Germany"}}}, {"visible", false}}}}};
    auto style = VectorStyle::read(&j, "scene.json", "/layers/0/style");
    ASSERT_TRUE(style) << style.message();
    const std::vector<std::shared_ptr<const FeatureTile>> pages{*coarse, *fine};
    auto merged = labelledFeatures(pages, *style);
    ASSERT_EQ(merged->layers.size(), 1u);
    const auto& features = merged->layers[0].data.features;
    std::set<int64_t> fids;
    const auto nameField = findField(merged->layers[0].data.fields, "name");
    ASSERT_TRUE(nameField);
    for (const Feature& f : features) {
        EXPECT_TRUE(fids.insert(f.fid).second) << "fid " << f.fid << " twice";
        EXPECT_NE(attributeText(f.attributes[*nameField]), "Germany");   // hidden: not labelled
        // A feature in both pages comes from the finer one.
        for (const Feature& g : (*fine)->content->layers[0].data.features)
            if (g.fid == f.fid) {
                EXPECT_EQ(f.coords.size(), g.coords.size()) << f.fid;
            }
    }
    EXPECT_GT(features.size(), 10u);
    EXPECT_EQ(merged->featureCount, features.size());
    // Switching the rule off labels Germany again.
    style->setRuleEnabled(0, false);
    auto again = labelledFeatures(pages, *style);
    EXPECT_EQ(again->featureCount, merged->featureCount + 1);
}

TEST(FeatureTiles, OwnedPagesHoldEachFeatureWholeInTheOneTileThatHoldsItsCentre) {
    REQUIRE_COUNTRIES();
    FeatureTilesOptions o = countries();
    o.owned = true;
    o.pageLevel = 1;
    auto whole = loadVectorContent(o.content);
    ASSERT_TRUE(whole) << whole.message();
    std::map<int64_t, size_t> vertices;   // fid -> vertices, over every level-1 tile
    for (uint32_t y = 0; y < TileKey::tilesY(1); ++y)
        for (uint32_t x = 0; x < TileKey::tilesX(1); ++x) {
            auto page = loadFeatureTile(o, TileKey{1, x, y});
            ASSERT_TRUE(page) << page.message();
            for (const Feature& f : page->content->layers[0].data.features) {
                EXPECT_TRUE(vertices.emplace(f.fid, f.coords.size()).second) << "fid " << f.fid << " in two tiles";
            }
        }
    const auto& features = (*whole)->layers[0].data.features;
    EXPECT_EQ(vertices.size(), features.size());
    for (const Feature& f : features) EXPECT_EQ(vertices[f.fid], f.coords.size()) << "fid " << f.fid << " cut or simplified";
}

/// A GeoJSON file of points, rewritten by the tests (a source that changes while paged).
struct PointFile {
    fs::path path;
    explicit PointFile(const std::string& name) : path(fs::temp_directory_path() / (name + "-" + std::to_string(::getpid()) + ".geojson")) {}
    ~PointFile() { fs::remove(path); }
    void write(const std::vector<std::pair<double, double>>& points) const {
        std::string text = R"({"type":"FeatureCollection","features":[)";
        for (size_t i = 0; i < points.size(); ++i)
            text += std::string(i ? "," : "") + R"({"type":"Feature","id":)" + std::to_string(i + 1) +
                    R"(,"properties":{"n":)" + std::to_string(i + 1) + R"(},"geometry":{"type":"Point","coordinates":[)" +
                    std::to_string(points[i].first) + "," + std::to_string(points[i].second) + "]}}";
        const fs::path tmp = path.string() + ".tmp";
        std::ofstream(tmp) << text << "]}";
        fs::rename(tmp, path);
    }
    FeatureTilesOptions options() const {
        FeatureTilesOptions o;
        o.content.read.source = path.string();
        o.pageLevel = 6;
        return o;
    }
};

size_t featuresIn(const FeatureTile& page) {
    size_t n = 0;
    for (const auto& layer : page.content->layers) n += layer.data.features.size();
    return n;
}

TEST(FeatureTiles, ARefreshReadsThePagesAChangeReachesAndReplacesOnlyThoseThatChanged) {
    PointFile file("orbis-refresh");
    file.write({{10.0, 45.0}, {100.0, -30.0}});
    FeatureTiles tiles(file.options());
    const TileKey europe = TileKey::containing(10.0, 45.0, 6), australia = TileKey::containing(100.0, -30.0, 6);
    auto before = tiles.acquire(europe);
    auto far = tiles.acquire(australia);
    ASSERT_TRUE(before && far) << before.message();
    EXPECT_EQ(featuresIn(**before), 1u);
    EXPECT_EQ(tiles.reads(), 2u);

    // Nothing changed: both pages read again, none replaced, no tile to paint again.
    PageRefresh same = tiles.refresh({});
    EXPECT_EQ(same.pagesRead, 2u);
    EXPECT_TRUE(same.changed.empty());
    EXPECT_EQ(tiles.acquire(europe)->get(), before->get());

    // A point added near the first: a refresh of its box reads the European page only, and
    // replaces it; whoever held the old page keeps it.
    file.write({{10.0, 45.0}, {100.0, -30.0}, {10.1, 45.1}});
    const LonLatBounds box{10.05, 45.05, 10.15, 45.15, false};
    PageRefresh changed = tiles.refresh(std::span(&box, 1));
    EXPECT_EQ(changed.pagesRead, 1u);
    ASSERT_EQ(changed.changed.size(), 1u);
    const globe::GeoExtent g = changed.changed[0];
    EXPECT_TRUE(g.west < 10.1 && g.east > 10.1 && g.south < 45.1 && g.north > 45.1);
    auto after = tiles.acquire(europe);
    ASSERT_TRUE(after);
    EXPECT_NE(after->get(), before->get());
    EXPECT_EQ(featuresIn(**after), 2u);
    EXPECT_EQ(featuresIn(**before), 1u);
    EXPECT_EQ(tiles.acquire(australia)->get(), far->get());
    EXPECT_EQ(tiles.bytes(), (*after)->bytes + (*far)->bytes);
}

TEST(FeatureTiles, ARefreshOfEverythingNamesThePagesEvictedSinceTheLast) {
    PointFile file("orbis-refresh-evicted");
    file.write({{10.0, 45.0}, {100.0, -30.0}});
    FeatureTilesOptions o = file.options();
    o.budgetBytes = 1;   // one page at a time
    FeatureTiles tiles(o);
    const TileKey europe = TileKey::containing(10.0, 45.0, 6), australia = TileKey::containing(100.0, -30.0, 6);
    ASSERT_TRUE(tiles.acquire(europe));
    ASSERT_TRUE(tiles.acquire(australia));   // Europe's page goes
    ASSERT_EQ(tiles.loadedCount(), 1u);
    PageRefresh r = tiles.refresh({});
    EXPECT_EQ(r.pagesRead, 1u);
    // Tiles painted from the evicted page may show what has changed since: painted again.
    ASSERT_EQ(r.changed.size(), 1u);
    EXPECT_TRUE(r.changed[0].west <= 10.0 && r.changed[0].east >= 10.0 && r.changed[0].south <= 45.0 && r.changed[0].north >= 45.0);
    EXPECT_TRUE(tiles.refresh({}).changed.empty());
}

TEST(FeatureTiles, AFailedPageIsReadAgainAfterTheRetryDelay) {
    PointFile file("orbis-refresh-retry");
    FeatureTiles tiles(file.options());
    const TileKey k = TileKey::containing(10.0, 45.0, 6);
    ASSERT_FALSE(tiles.acquire(k));
    EXPECT_EQ(tiles.failingCount(), 1u);
    EXPECT_NE(tiles.lastError().find("no such file"), std::string::npos) << tiles.lastError();
    file.write({{10.0, 45.0}});
    EXPECT_FALSE(tiles.acquire(k));   // not yet
    EXPECT_EQ(tiles.reads(), 1u);
    std::this_thread::sleep_for(FeatureTiles::kRetryDelay + std::chrono::milliseconds(50));
    auto page = tiles.acquire(k);
    ASSERT_TRUE(page) << page.message();
    EXPECT_EQ(featuresIn(**page), 1u);
    EXPECT_EQ(tiles.failingCount(), 0u);
}

TEST(FeatureTiles, ARefreshForgetsAFailedPageSoTheNextAskReadsIt) {
    PointFile file("orbis-refresh-failed");
    FeatureTiles tiles(file.options());
    const TileKey k = TileKey::containing(10.0, 45.0, 6);
    ASSERT_FALSE(tiles.acquire(k));
    file.write({{10.0, 45.0}});
    PageRefresh r = tiles.refresh({});
    ASSERT_EQ(r.changed.size(), 1u);   // its tiles were painted empty: again
    ASSERT_TRUE(tiles.acquire(k));
}

TEST(FeatureTiles, AnInvalidatedPageShowsItsOldContentUntilTheNextAskReadsItAgain) {
    PointFile file("orbis-invalidate");
    file.write({{10.0, 45.0}, {100.0, -30.0}});
    FeatureTilesOptions o = file.options();
    o.quickRead = std::chrono::seconds(60);   // every read counts as quick, however busy the machine
    FeatureTiles tiles(o);
    const TileKey europe = TileKey::containing(10.0, 45.0, 6), australia = TileKey::containing(100.0, -30.0, 6);
    auto before = tiles.acquire(europe);
    auto far = tiles.acquire(australia);
    ASSERT_TRUE(before && far);
    file.write({{10.0, 45.0}, {100.0, -30.0}, {10.1, 45.1}});
    const LonLatBounds box{10.1, 45.1, 10.1, 45.1, false};
    EXPECT_TRUE(tiles.invalidate(std::span(&box, 1)).empty());   // quick pages: read again at once
    EXPECT_EQ(tiles.reads(), 2u);   // nothing read yet
    // Until it is asked for, the old page is what is in memory (labels gather from it).
    bool sawOld = false;
    for (const auto& p : tiles.loaded()) sawOld |= p.get() == before->get();
    EXPECT_TRUE(sawOld);
    auto after = tiles.acquire(europe);
    ASSERT_TRUE(after);
    EXPECT_EQ(featuresIn(**after), 2u);
    EXPECT_EQ(tiles.reads(), 3u);
    EXPECT_EQ(tiles.acquire(europe)->get(), after->get());   // read once
    EXPECT_EQ(tiles.acquire(australia)->get(), far->get());  // the box did not reach it
    EXPECT_EQ(tiles.bytes(), (*after)->bytes + (*far)->bytes);

    // Outdated again, and the source gone: the old features serve, the error is reported.
    fs::remove(file.path);
    tiles.invalidate(std::span(&box, 1));
    auto served = tiles.acquire(europe);
    ASSERT_TRUE(served) << served.message();
    EXPECT_EQ(served->get(), after->get());
    EXPECT_NE(tiles.lastError().find("no such file"), std::string::npos) << tiles.lastError();
}

TEST(FeatureTiles, AnInvalidatedPageSlowToReadIsReadAgainOnlyLater) {
    PointFile file("orbis-invalidate-slow");
    file.write({{10.0, 45.0}});
    FeatureTilesOptions o = file.options();
    o.quickRead = std::chrono::microseconds(0);   // every read counts as slow
    FeatureTiles tiles(o);
    const TileKey europe = TileKey::containing(10.0, 45.0, 6);
    auto before = tiles.acquire(europe);
    ASSERT_TRUE(before);
    file.write({{10.0, 45.0}, {10.1, 45.1}});
    const LonLatBounds box{10.1, 45.1, 10.1, 45.1, false};
    const auto deferred = tiles.invalidate(std::span(&box, 1));
    ASSERT_EQ(deferred.size(), 1u);
    EXPECT_TRUE(deferred[0].extent.west <= 10.1 && deferred[0].extent.east >= 10.1);
    // Until then the old content serves, without a read.
    if (std::chrono::steady_clock::now() < deferred[0].when) {
        auto early = tiles.acquire(europe);
        ASSERT_TRUE(early);
        if (std::chrono::steady_clock::now() < deferred[0].when) {
            EXPECT_EQ(early->get(), before->get());
        }
    }
    std::this_thread::sleep_until(deferred[0].when + std::chrono::milliseconds(1));
    auto after = tiles.acquire(europe);
    ASSERT_TRUE(after);
    EXPECT_EQ(featuresIn(**after), 2u);
}

}  // namespace
}  // namespace orbis::vector
