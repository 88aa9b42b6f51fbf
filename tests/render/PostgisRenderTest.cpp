// PostGIS layers on lavapipe with validation, against a real PostgreSQL + PostGIS on loopback
// (tests/support/PostgresServer.h): a table draws what the same rows in a GeoPackage draw, pixel
// for pixel; with "refresh" an INSERT, UPDATE or DELETE from another connection shows in the
// next frames, drawn as a fresh read of the table draws it; a server killed while the scene
// runs is reported in the layer's status, frames go on, and once it is back the layer catches
// up; a moving point glides to its new place with its label beside it. Skipped, with the reason,
// when the packages are missing.
#include "layers/vector/VectorLayer.h"
#include "tests/render/SceneGpuTest.h"
#include "tests/render/VectorScenes.h"
#include "tests/support/GoldenImage.h"
#include "tests/support/PostgresServer.h"

#include <gdal_priv.h>
#include <ogrsf_frmts.h>
#include <unistd.h>

#include <chrono>
#include <optional>
#include <vector>
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

/// The centre of the pure red pixels (the vehicle's marker), in pixels; none when there are none.
std::optional<glm::dvec2> redCentre(const ImageRgba8& image) {
    glm::dvec2 sum(0.0);
    size_t n = 0;
    for (uint32_t y = 0; y < image.height; ++y)
        for (uint32_t x = 0; x < image.width; ++x) {
            const uint8_t* p = &image.pixels[(size_t(y) * image.width + x) * 4];
            if (p[0] > 200 && p[1] < 60 && p[2] < 60) sum += glm::dvec2(x, y), ++n;
        }
    if (n < 20) return std::nullopt;
    return sum / double(n);
}

TEST_F(PostgisRender, MovingPointsGlideToTheirNewPlacesAndTheirLabelsFollow) {
    // A vehicle in a live table, drawn as a marker on the ground ("relative") with its name; a
    // glide of 2 s, so that frames on lavapipe see it on its way.
    const auto made = db->sql("CREATE TABLE vehicles (id integer PRIMARY KEY, name text, geom geometry(Point, 4326));\n"
                              "INSERT INTO vehicles VALUES (1, 'Bus 7', ST_SetSRID(ST_MakePoint(10.010, 45.016), 4326));\n");
    ASSERT_EQ(made.exitCode, 0) << made.output;
    const auto scene = [&](const std::string& glide) {
        return load(vectorSceneJson(
            kView,
            ground() + "," + vectorLayerJson("Vehicles", db->ogrConnection(),
                                             R"(, "layers": ["vehicles"], "altitude": "relative",)"
                                             R"( "style": {"color": [1, 0, 0], "iconSize": 14, "label": "{name}", "labelSize": 14},)"
                                             R"( "refresh": {"listen": "vehicles_changed", "trigger": {"table": "vehicles"}, "glide": )" +
                                                 glide + "}"),
            "2026-06-21T12:00:00Z"));
    };
    auto live = scene("2");
    ASSERT_TRUE(live);
    const ImageRgba8 before = renderScene(*live, 256, 256);
    layers::VectorLayer& layer = vectorLayer(*live);
    ASSERT_NE(layer.motion(), nullptr);
    ASSERT_NE(layer.labels(), nullptr);
    for (int i = 0; i < 200 && !layer.listener()->listening(); ++i) std::this_thread::sleep_for(25ms);
    ASSERT_TRUE(layer.listener()->listening()) << layer.status();
    const auto from = redCentre(before);
    ASSERT_TRUE(from) << "no marker drawn";
    ASSERT_EQ(layer.labels()->placed().size(), 1u);
    const double labelGap = layer.labels()->placed()[0].min.x - from->x;

    ASSERT_EQ(db->sql("UPDATE vehicles SET geom = ST_SetSRID(ST_MakePoint(10.035, 45.016), 4326) WHERE id = 1").exitCode, 0);
    // Frames until the moved marker's tile is drawn (its glide starts), then for 3 s.
    ImageRgba8 frame = before;
    const auto end = std::chrono::steady_clock::now() + 15s;
    while (layer.motion()->glides() == 0 && std::chrono::steady_clock::now() < end) {
        frame = renderOnce(*renderer_, *live);
        std::this_thread::sleep_for(10ms);
    }
    ASSERT_EQ(layer.motion()->glides(), 1u) << layer.status();
    struct Seen {
        glm::dvec2 marker;
        std::optional<double> labelX;
    };
    std::vector<Seen> seen;
    const auto look = [&](const ImageRgba8& image) {
        const auto c = redCentre(image);
        ASSERT_TRUE(c) << "the marker went missing";
        Seen s{*c, std::nullopt};
        if (layer.labels()->placed().size() == 1) s.labelX = layer.labels()->placed()[0].min.x;
        seen.push_back(s);
    };
    look(frame);
    const auto glideEnd = std::chrono::steady_clock::now() + 3s;
    while (std::chrono::steady_clock::now() < glideEnd) look(renderOnce(*renderer_, *live));
    const ImageRgba8 settled = renderScene(*live, 256, 256);
    look(settled);

    // Where a fresh read of the table draws it.
    auto fresh = scene("0");
    ASSERT_TRUE(fresh);
    const auto to = redCentre(renderScene(*fresh, 256, 256));
    ASSERT_TRUE(to);
    const double distance = to->x - from->x;
    ASSERT_GT(distance, 40.0) << "the move is too short on the screen to follow";
    const auto fraction = [&](const Seen& s) { return (s.marker.x - from->x) / distance; };
    // No jump: the first frame drawn with the new row shows the marker where it was.
    EXPECT_LT(fraction(seen.front()), 0.1);
    // On its way: frames between, each further along, on the line between the two places.
    size_t between = 0;
    for (size_t i = 0; i < seen.size(); ++i) {
        SCOPED_TRACE(i);
        between += fraction(seen[i]) > 0.2 && fraction(seen[i]) < 0.8;
        EXPECT_NEAR(seen[i].marker.y, from->y, 1.5);
        if (i > 0) {
            EXPECT_GE(fraction(seen[i]), fraction(seen[i - 1]) - 0.03);
        }
        // The label stands beside the marker all the way (within its whole-pixel rounding).
        if (seen[i].labelX) {
            EXPECT_NEAR(*seen[i].labelX - seen[i].marker.x, labelGap, 2.0);
        }
    }
    EXPECT_GE(between, 2u) << seen.size() << " frames";
    EXPECT_NEAR(seen.back().marker.x, to->x, 0.5);
    EXPECT_NEAR(seen.back().marker.y, to->y, 0.5);
    EXPECT_TRUE(seen.back().labelX.has_value());
    EXPECT_EQ(layer.motion()->jumps(), 0u);
    EXPECT_FALSE(live->busy());
}

}  // namespace
}  // namespace orbis::test
