// PostGIS layers on lavapipe with validation, against a real PostgreSQL + PostGIS on loopback
// (tests/support/PostgresServer.h): a table draws what the same rows in a GeoPackage draw, pixel
// for pixel; with "refresh" an INSERT, UPDATE or DELETE from another connection shows in the
// next frames, drawn as a fresh read of the table draws it; a server killed while the scene
// runs is reported in the layer's status, frames go on, and once it is back the layer catches
// up. Skipped, with the reason, when the packages are missing.
#include "layers/vector/VectorLayer.h"
#include "tests/render/SceneGpuTest.h"
#include "tests/render/VectorScenes.h"
#include "tests/support/GoldenImage.h"
#include "tests/support/PostgresServer.h"

#include <gdal_priv.h>
#include <ogrsf_frmts.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <string>
#include <thread>

namespace orbis::test {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

/// A 10 x 10 grid of 400 m parcels in Web Mercator around lon 10, lat 45: row r, column c.
std::string parcelWkt(int r, int c) {
    const double x = 1113194.9 + c * 500.0, y = 5621521.5 + r * 500.0;
    char wkt[256];
    std::snprintf(wkt, sizeof wkt, "POLYGON((%.1f %.1f,%.1f %.1f,%.1f %.1f,%.1f %.1f,%.1f %.1f))", x, y, x + 400, y, x + 400,
                  y + 400, x, y + 400, x, y);
    return wkt;
}

const char* kView = R"({"lon": 10.0225, "lat": 45.0160, "range": 9000})";
const char* kStyle = R"(, "style": {"color": [1, 0.2, 0], "width": 2, "fill": [1, 0.9, 0.1], "fillOpacity": 0.7})";

std::string ground() { return R"({"type": "terrain", "name": "Ground", "sky": false, "color": [0.3, 0.3, 0.35]})"; }

class PostgisRender : public SceneGpuTest {
protected:
    void SetUp() override {
        SceneGpuTest::SetUp();
        if (IsSkipped()) return;
        db = std::make_unique<PostgresServer>();
        if (!db->available()) GTEST_SKIP() << db->error();
        ASSERT_TRUE(db->running()) << db->error();
        std::string sql = "CREATE TABLE parcels (id integer PRIMARY KEY, geom geometry(Polygon, 3857));\n"
                          "CREATE INDEX ON parcels USING GIST (geom);\n";
        for (int r = 0; r < 10; ++r)
            for (int c = 0; c < 10; ++c)
                sql += "INSERT INTO parcels VALUES (" + std::to_string(r * 10 + c + 1) + ", ST_GeomFromText('" + parcelWkt(r, c) +
                       "', 3857));\n";
        const auto made = db->sql(sql);
        ASSERT_EQ(made.exitCode, 0) << made.output;
    }
    std::unique_ptr<scene::Scene> parcels(const std::string& extra) {
        return load(vectorSceneJson(kView, ground() + "," + vectorLayerJson("Parcels", db->ogrConnection(), std::string(kStyle) +
                                                                                  R"(, "layers": ["parcels"], "paging": true, "pageLevel": 12)" + extra),
                                    "2026-06-21T12:00:00Z"));
    }
    static layers::VectorLayer& vectorLayer(scene::Scene& scene) { return dynamic_cast<layers::VectorLayer&>(*scene.resources()[1].layer); }
    /// Renders frames until the layer has applied a change past `before` (at most 15 s), then
    /// until the scene has settled.
    ImageRgba8 afterChange(scene::Scene& scene, uint64_t before) {
        const auto end = std::chrono::steady_clock::now() + 15s;
        while (vectorLayer(scene).refreshesApplied() <= before && std::chrono::steady_clock::now() < end) {
            renderOnce(*renderer_, scene);
            std::this_thread::sleep_for(20ms);
        }
        EXPECT_GT(vectorLayer(scene).refreshesApplied(), before) << vectorLayer(scene).status();
        return renderScene(scene, 256, 256);
    }
    /// The table as it is now, read by a new scene.
    ImageRgba8 freshRead() {
        auto fresh = parcels("");
        return fresh ? renderScene(*fresh, 256, 256) : ImageRgba8{};
    }
    std::unique_ptr<PostgresServer> db;
};

TEST_F(PostgisRender, ATableDrawsWhatTheSameRowsInAGeoPackageDraw) {
    const fs::path dir = fs::temp_directory_path() / ("orbis-postgis-render-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const std::string gpkg = (dir / "parcels.gpkg").string();
    {
        GDALAllRegister();
        std::unique_ptr<GDALDataset> ds(GetGDALDriverManager()->GetDriverByName("GPKG")->Create(gpkg.c_str(), 0, 0, 0, GDT_Unknown, nullptr));
        OGRSpatialReference srs;
        srs.importFromEPSG(3857);
        OGRLayer* layer = ds->CreateLayer("parcels", &srs, wkbPolygon, nullptr);
        for (int r = 0; r < 10; ++r)
            for (int c = 0; c < 10; ++c) {
                OGRFeature f(layer->GetLayerDefn());
                f.SetFID(r * 10 + c + 1);
                OGRGeometry* g = nullptr;
                OGRGeometryFactory::createFromWkt(parcelWkt(r, c).c_str(), &srs, &g);
                f.SetGeometryDirectly(g);
                ASSERT_EQ(layer->CreateFeature(&f), OGRERR_NONE);
            }
    }
    auto fromFile = load(vectorSceneJson(kView, ground() + "," + vectorLayerJson("Parcels", gpkg, std::string(kStyle) + R"(, "paging": true, "pageLevel": 12)"),
                                         "2026-06-21T12:00:00Z"));
    auto fromServer = parcels("");
    ASSERT_TRUE(fromFile && fromServer);
    const ImageRgba8 a = renderScene(*fromFile, 256, 256), b = renderScene(*fromServer, 256, 256);
    fs::remove_all(dir);
    EXPECT_TRUE(vectorLayer(*fromServer).error().empty()) << vectorLayer(*fromServer).error();
    EXPECT_EQ(countDifferentPixels(a, b, 0), 0u) << "pixels differ: the table does not draw as the GeoPackage does";
    // Something was drawn: the parcels' yellow.
    size_t yellow = 0;
    for (size_t i = 0; i + 3 < b.pixels.size(); i += 4) yellow += b.pixels[i] > 150 && b.pixels[i + 1] > 130 && b.pixels[i + 2] < 90;
    EXPECT_GT(yellow, 1000u);
}

TEST_F(PostgisRender, ChangesFromAnotherConnectionShowInTheNextFrames) {
    auto live = parcels(R"(, "refresh": {"listen": "parcels_changed", "trigger": {"table": "parcels"}})");
    ASSERT_TRUE(live);
    const ImageRgba8 before = renderScene(*live, 256, 256);
    layers::VectorLayer& layer = vectorLayer(*live);
    ASSERT_NE(layer.listener(), nullptr);
    for (int i = 0; i < 200 && !layer.listener()->listening(); ++i) std::this_thread::sleep_for(25ms);
    ASSERT_TRUE(layer.listener()->listening()) << layer.status();
    EXPECT_NE(layer.status().find("live: listening on \"parcels_changed\""), std::string::npos) << layer.status();

    struct Step {
        const char* what;
        std::string sql;
    };
    const Step steps[] = {
        {"delete", "DELETE FROM parcels WHERE id IN (45, 46, 55, 56)"},
        {"update", "UPDATE parcels SET geom = ST_Translate(geom, 250, 250) WHERE id = 12"},
        {"insert", "INSERT INTO parcels VALUES (500, ST_Buffer(ST_SetSRID(ST_MakePoint(1115700, 5623800), 3857), 900))"},
    };
    ImageRgba8 last = before;
    for (const Step& step : steps) {
        SCOPED_TRACE(step.what);
        const uint64_t applied = layer.refreshesApplied();
        const auto r = db->sql(step.sql);
        ASSERT_EQ(r.exitCode, 0) << r.output;
        const ImageRgba8 now = afterChange(*live, applied);
        EXPECT_GT(countDifferentPixels(last, now, 0), 50u) << "the change did not show";
        EXPECT_EQ(countDifferentPixels(now, freshRead(), 0), 0u) << "the refreshed layer does not draw what a fresh read of the table draws";
        last = now;
    }
    EXPECT_TRUE(layer.error().empty()) << layer.error();
}

TEST_F(PostgisRender, AServerKilledWhileShownIsReportedAndTheLayerCatchesUpWhenItReturns) {
    auto live = parcels(R"(, "refresh": {"listen": "parcels_changed", "trigger": {"table": "parcels"}})");
    ASSERT_TRUE(live);
    const ImageRgba8 before = renderScene(*live, 256, 256);
    layers::VectorLayer& layer = vectorLayer(*live);
    for (int i = 0; i < 200 && !layer.listener()->listening(); ++i) std::this_thread::sleep_for(25ms);
    ASSERT_TRUE(layer.listener()->listening()) << layer.status();

    db->kill();
    // Frames go on (each within a bounded time: nothing waits for the server), the image stays,
    // and the status says what happened.
    for (int i = 0; i < 40 && layer.listener()->listening(); ++i) {
        const auto t0 = std::chrono::steady_clock::now();
        renderOnce(*renderer_, *live);
        EXPECT_LT(std::chrono::steady_clock::now() - t0, 5s);
        std::this_thread::sleep_for(25ms);
    }
    EXPECT_NE(layer.status().find("live: connection lost"), std::string::npos) << layer.status();
    EXPECT_EQ(countDifferentPixels(before, renderOnce(*renderer_, *live), 0), 0u);

    // Back, with a row deleted while it was away (no one was listening): the reconnection
    // reads everything in memory again.
    ASSERT_TRUE(db->start()) << db->error();
    const uint64_t applied = layer.refreshesApplied();
    // The listener reconnects on its own; the delete lands after or before, either way caught.
    ASSERT_EQ(db->sql("DELETE FROM parcels WHERE id BETWEEN 41 AND 60").exitCode, 0);
    afterChange(*live, applied);
    // The reconnection's refresh and the delete's (whichever came first): within seconds the
    // layer draws what a fresh read of the table draws.
    const ImageRgba8 expected = freshRead();
    ImageRgba8 settled = renderScene(*live, 256, 256);
    for (int i = 0; i < 30 && countDifferentPixels(settled, expected, 0) != 0; ++i) {
        std::this_thread::sleep_for(100ms);
        settled = renderScene(*live, 256, 256);
    }
    EXPECT_EQ(countDifferentPixels(settled, expected, 0), 0u) << layer.status();
    EXPECT_EQ(layer.listener()->reconnects(), 1u) << layer.status();
    EXPECT_GT(countDifferentPixels(before, settled, 0), 100u);
}

}  // namespace
}  // namespace orbis::test
